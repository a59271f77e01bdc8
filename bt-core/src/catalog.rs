//! What a behavior set declares about its behaviors: names, kinds, arities and ports,
//! how their values print and read back, and the 64-bit fingerprint that lets host and
//! controller agree on them without sharing code.

use crate::node::{BehaviorId, LeafKind};
use crate::port::{PortDirection, PortInfo, PortValue};

/// The declaration of one behavior.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BehaviorInfo<'a> {
    /// Human-readable name, e.g. `MoveTo` or `picked 0?`.
    pub name: &'a str,
    /// Condition or action.
    pub kind: LeafKind,
    /// Number of grounded arguments a leaf of this behavior carries.
    pub arity: u8,
}

impl<'a> BehaviorInfo<'a> {
    /// A condition with `arity` arguments.
    #[must_use]
    pub const fn condition(name: &'a str, arity: u8) -> Self {
        Self { name, kind: LeafKind::Condition, arity }
    }

    /// An action with `arity` arguments.
    #[must_use]
    pub const fn action(name: &'a str, arity: u8) -> Self {
        Self { name, kind: LeafKind::Action, arity }
    }
}

/// The behaviors a tree may use, indexed by [`BehaviorId`]: the one description of a
/// behavior set that the loader, the renderers and every format read.
///
/// Implemented for slices of [`BehaviorInfo`] and [`Behavior`]; the host implements it
/// over its own name tables (a PDDL problem, a brick task, an image's names section).
///
/// A leaf's values have two kinds of names, kept apart on purpose:
/// - **declared ports** ([`Catalog::port`]): name, direction and type, which the loader
///   checks every value against ([`PortTable::check_leaf`](crate::PortTable::check_leaf))
///   and the [fingerprint](Catalog::fingerprint) covers, so that host and controller
///   agree on them;
/// - **names for display** ([`Catalog::port_name`]): what a value is shown and written
///   as (`goal=...`, a PDDL parameter), by default the declared port's name. A set
///   whose values are grounded arguments names them here without declaring ports, so
///   naming them changes neither what loads nor the fingerprint.
pub trait Catalog {
    /// Number of behaviors; ids run from 0 to `len() - 1`.
    fn len(&self) -> usize;

    /// True when there are no behaviors.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The declaration of behavior `id`.
    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>>;

    /// Declared port `position` of behavior `id`, for behaviors that declare ports (one
    /// per value, in order; see [`port`](crate::port)): the loader checks the leaf's
    /// value against it and the default [`fingerprint`](Catalog::fingerprint) covers it.
    /// `None` by default: the behavior's values are grounded arguments.
    fn port(&self, id: BehaviorId, position: usize) -> Option<PortInfo<'_>> {
        let _ = (id, position);
        None
    }

    /// The name value `position` of a leaf of behavior `id` is shown and written under
    /// (a port name, a PDDL parameter): for display only, neither checked nor
    /// fingerprinted. By default the declared port's name, else `None`.
    fn port_name(&self, id: BehaviorId, position: usize) -> Option<&str> {
        self.port(id, position).map(|p| p.name)
    }

    /// The fingerprint of this set: see [`fingerprint`]. Covers each behavior's name,
    /// kind and arity and its declared ports ([`Catalog::port`]), never the names of
    /// [`Catalog::port_name`] alone.
    fn fingerprint(&self) -> u64 {
        let mut h = Fnv1a::new().u64(self.len() as u64);
        let mut id: BehaviorId = 0;
        while usize::from(id) < self.len() {
            if let Some(info) = self.info(id) {
                h = h.behavior(&info);
                for position in 0..usize::from(info.arity) {
                    if let Some(port) = self.port(id, position) {
                        h = h.port(&port);
                    }
                }
            }
            id = match id.checked_add(1) {
                Some(n) => n,
                None => break,
            };
        }
        h.finish()
    }

    /// Writes a whole leaf for the renderer, whose values are `args` (inline or from the
    /// tree's value table). By default `name` or `name(arg, ...)` with
    /// [`Catalog::write_arg`] for each value; a value of a declared port is written
    /// `port=value`, and left out when unset (`ComputePathToPose(goal={goal})`). Host
    /// catalogs override it to print grounded names such as `0 at pos (0.0, 0.05, 0.0)?`.
    ///
    /// # Errors
    /// Whatever the formatter returns.
    fn write_leaf(&self, f: &mut core::fmt::Formatter<'_>, leaf: &crate::Leaf, args: &[u16]) -> core::fmt::Result {
        let b = leaf.behavior();
        match self.info(b) {
            Some(info) => f.write_str(info.name)?,
            None => write!(f, "#{b}")?,
        }
        let mut first = true;
        for (pos, &a) in args.iter().enumerate() {
            let port = self.port(b, pos);
            if port.is_some() && PortValue::from_u16(a) == PortValue::Unset {
                continue;
            }
            f.write_str(if first { "(" } else { ", " })?;
            first = false;
            if let Some(p) = port {
                write!(f, "{}=", p.name)?;
            }
            self.write_arg(f, b, pos, a)?;
        }
        if !first {
            f.write_str(")")?;
        }
        Ok(())
    }

    /// Writes value `value` at `position` of a leaf of `behavior`, for the renderer and
    /// the formats. Prints the number by default; host catalogs print object names, and
    /// for declared ports a blackboard key as `{key}` and a constant as written.
    ///
    /// # Errors
    /// Whatever the formatter returns.
    fn write_arg(
        &self,
        f: &mut core::fmt::Formatter<'_>,
        behavior: BehaviorId,
        position: usize,
        value: u16,
    ) -> core::fmt::Result {
        let _ = (behavior, position);
        write!(f, "{value}")
    }

    /// The value written as `text` at `position` of a leaf of `behavior`: the inverse
    /// of [`Catalog::write_arg`] for grounded arguments (an object's name back to its
    /// index), so that a tree written as text reads back into this set. By default the
    /// number itself; `None` when `text` names no value.
    fn parse_arg(&self, behavior: BehaviorId, position: usize, text: &str) -> Option<u16> {
        let _ = (behavior, position);
        text.parse().ok()
    }
}

impl Catalog for [BehaviorInfo<'_>] {
    fn len(&self) -> usize {
        <[BehaviorInfo<'_>]>::len(self)
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        self.get(usize::from(id)).copied()
    }

    fn fingerprint(&self) -> u64 {
        fingerprint(self)
    }
}

/// A behavior and its ports: the entries of a behavior set whose behaviors declare ports
/// (as `sim-host catalog --rust` writes it from BehaviorTree.CPP models).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Behavior<'a> {
    /// Name, kind and arity (the number of ports).
    pub info: BehaviorInfo<'a>,
    /// The ports, one per value a leaf carries.
    pub ports: &'a [PortInfo<'a>],
}

impl<'a> Behavior<'a> {
    /// A behavior with its ports; its arity is taken from `ports` when `info` has none.
    #[must_use]
    pub const fn new(info: BehaviorInfo<'a>, ports: &'a [PortInfo<'a>]) -> Self {
        Self { info, ports }
    }
}

impl Catalog for [Behavior<'_>] {
    fn len(&self) -> usize {
        <[Behavior<'_>]>::len(self)
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        self.get(usize::from(id)).map(|b| b.info)
    }

    fn port(&self, id: BehaviorId, position: usize) -> Option<PortInfo<'_>> {
        self.get(usize::from(id))?.ports.get(position).copied()
    }

    fn fingerprint(&self) -> u64 {
        fingerprint_with_ports(self)
    }
}

/// An array of entries is the set its slice is (`const` tables such as
/// `[BehaviorInfo; 11]` or `[Behavior; 74]`).
impl<T, const N: usize> Catalog for [T; N]
where
    [T]: Catalog,
{
    fn len(&self) -> usize {
        N
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        self.as_slice().info(id)
    }

    fn port(&self, id: BehaviorId, position: usize) -> Option<PortInfo<'_>> {
        self.as_slice().port(id, position)
    }

    fn port_name(&self, id: BehaviorId, position: usize) -> Option<&str> {
        self.as_slice().port_name(id, position)
    }

    fn fingerprint(&self) -> u64 {
        self.as_slice().fingerprint()
    }

    fn write_leaf(&self, f: &mut core::fmt::Formatter<'_>, leaf: &crate::Leaf, args: &[u16]) -> core::fmt::Result {
        self.as_slice().write_leaf(f, leaf, args)
    }

    fn write_arg(
        &self,
        f: &mut core::fmt::Formatter<'_>,
        behavior: BehaviorId,
        position: usize,
        value: u16,
    ) -> core::fmt::Result {
        self.as_slice().write_arg(f, behavior, position, value)
    }

    fn parse_arg(&self, behavior: BehaviorId, position: usize, text: &str) -> Option<u16> {
        self.as_slice().parse_arg(behavior, position, text)
    }
}

/// [`fingerprint`] of a set whose behaviors declare ports: after each behavior's
/// fields, each of its ports (as many as its arity) in order: its direction (`0` input,
/// `1` output, `2` in/out), its type class ([`PortType`](crate::port::PortType) as a
/// byte), then its name, its declared type name and its default, each as a
/// little-endian `u64` length followed by the UTF-8 bytes (a missing default hashes as
/// the length `u64::MAX`). A behavior without ports hashes as in [`fingerprint`], so
/// the two agree on sets without ports.
#[must_use]
pub const fn fingerprint_with_ports(behaviors: &[Behavior<'_>]) -> u64 {
    let mut h = Fnv1a::new().u64(behaviors.len() as u64);
    let mut rest = behaviors;
    while let Some((first, tail)) = rest.split_first() {
        h = h.behavior(&first.info);
        let mut ports = first.ports;
        let mut left = first.info.arity;
        while let Some((port, more)) = ports.split_first() {
            if left == 0 {
                break;
            }
            h = h.port(port);
            ports = more;
            left -= 1;
        }
        rest = tail;
    }
    h.finish()
}

/// The stable 64-bit fingerprint of a behavior set.
///
/// FNV-1a (64-bit) over: the number of behaviors as a little-endian `u64`, then for each
/// behavior in id order its kind (`0` condition, `1` action), its arity, its name's
/// length in bytes as a little-endian `u64`, and the name's UTF-8 bytes (and its ports,
/// for behaviors that declare them: [`fingerprint_with_ports`]). Anyone can compute it
/// from the names alone; a `const fn`, so firmware can bake it in.
///
/// ```
/// use bt_core::{fingerprint, BehaviorInfo};
/// const SET: [BehaviorInfo<'static>; 2] =
///     [BehaviorInfo::condition("at goal?", 0), BehaviorInfo::action("MoveTo", 1)];
/// const FP: u64 = fingerprint(&SET);
/// assert_ne!(FP, fingerprint(&[BehaviorInfo::condition("at goal?", 0)]));
/// ```
#[must_use]
pub const fn fingerprint(behaviors: &[BehaviorInfo<'_>]) -> u64 {
    let mut h = Fnv1a::new().u64(behaviors.len() as u64);
    let mut rest = behaviors;
    while let Some((first, tail)) = rest.split_first() {
        h = h.behavior(first);
        rest = tail;
    }
    h.finish()
}

/// FNV-1a, 64 bit: tiny, `const`, and fixed by its published constants. Written here
/// because hashing crates' `Hasher`s are neither `const` nor promised stable.
#[derive(Clone, Copy)]
struct Fnv1a(u64);

impl Fnv1a {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;

    const fn new() -> Self {
        Self(Self::OFFSET)
    }

    const fn byte(self, b: u8) -> Self {
        Self((self.0 ^ b as u64).wrapping_mul(Self::PRIME))
    }

    const fn bytes(mut self, bytes: &[u8]) -> Self {
        let mut rest = bytes;
        while let Some((&first, tail)) = rest.split_first() {
            self = self.byte(first);
            rest = tail;
        }
        self
    }

    const fn u64(self, v: u64) -> Self {
        self.bytes(&v.to_le_bytes())
    }

    const fn behavior(self, info: &BehaviorInfo<'_>) -> Self {
        let kind = match info.kind {
            LeafKind::Condition => 0,
            LeafKind::Action => 1,
        };
        self.byte(kind).byte(info.arity).u64(info.name.len() as u64).bytes(info.name.as_bytes())
    }

    const fn str(self, s: &str) -> Self {
        self.u64(s.len() as u64).bytes(s.as_bytes())
    }

    const fn port(self, port: &PortInfo<'_>) -> Self {
        let direction = match port.direction {
            PortDirection::Input => 0,
            PortDirection::Output => 1,
            PortDirection::InOut => 2,
        };
        let h = self.byte(direction).byte(port.ty as u8).str(port.name).str(port.type_name);
        match port.default {
            Some(d) => h.str(d),
            None => h.u64(u64::MAX),
        }
    }

    const fn finish(self) -> u64 {
        self.0
    }
}
