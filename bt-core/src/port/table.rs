//! The ports section of an image (tag 3), read in place and written.
//!
//! # Body
//!
//! | field | encoding |
//! |---|---|
//! | slot count `s` | varint `u16` |
//! | `s` slots | each: type ([`PortType`] as one byte), initial value (varint `u16`: 0 none, `k + 1` constant `k`) |
//! | constant count `c` | varint `u16` |
//! | `c` offsets | each a little-endian `u16`: where constant `i` starts, counted from the first constant |
//! | `c` constants | each a varint tag and its value: 0 int (zigzag varint `i64`), 1 double (8 bytes, little-endian IEEE 754), 2 bool (one byte, 0 or 1), 3 string (varint length, UTF-8 bytes) |
//!
//! Varints are LEB128 as postcard writes them. The offsets make reading constant `i` one
//! lookup; [`PortTable::parse`] checks every offset and every constant once, so reads
//! after it cannot fail on a table it accepted.

use super::{Constant, MAX_CONSTANTS, MAX_SLOTS, PortDirection, PortFault, PortType, PortValue, SlotInfo};
use crate::catalog::Catalog;

/// The ports section of an image, read in place: blackboard slots and constants.
///
/// Made by [`PortTable::parse`], which checks the whole section; [`PortTable::EMPTY`]
/// for images without one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PortTable<'a> {
    slots: &'a [u8],
    slot_count: u16,
    offsets: &'a [u8],
    data: &'a [u8],
    constant_count: u16,
}

fn varint_u16(bytes: &[u8]) -> Option<(u16, &[u8])> {
    postcard::take_from_bytes::<u16>(bytes).ok()
}

impl<'a> PortTable<'a> {
    /// No slots and no constants.
    pub const EMPTY: PortTable<'static> =
        PortTable { slots: &[], slot_count: 0, offsets: &[], data: &[], constant_count: 0 };

    /// Reads and checks a ports section body (see the module docs).
    ///
    /// # Errors
    /// [`PortFault::Malformed`] or [`PortFault::BadInitial`].
    pub fn parse(body: &'a [u8]) -> Result<Self, PortFault> {
        let at = |rest: &[u8]| PortFault::Malformed { offset: body.len() - rest.len() };
        let (slot_count, mut rest) = varint_u16(body).ok_or(PortFault::Malformed { offset: 0 })?;
        if slot_count > MAX_SLOTS {
            return Err(PortFault::Malformed { offset: 0 });
        }
        let slots_start = body.len() - rest.len();
        for _ in 0..slot_count {
            let (&ty, tail) = rest.split_first().ok_or_else(|| at(rest))?;
            if PortType::from_u8(ty).is_none() {
                return Err(at(rest));
            }
            let (_, tail) = varint_u16(tail).ok_or_else(|| at(tail))?;
            rest = tail;
        }
        let slots = body.get(slots_start..body.len() - rest.len()).unwrap_or(&[]);
        let (constant_count, tail) = varint_u16(rest).ok_or_else(|| at(rest))?;
        if constant_count > MAX_CONSTANTS {
            return Err(at(rest));
        }
        let n = usize::from(constant_count);
        let (offsets, data) = tail.split_at_checked(2 * n).ok_or_else(|| at(tail))?;
        let table = Self { slots, slot_count, offsets, data, constant_count };
        // Every constant decodes, they follow one another, and nothing is left over.
        let mut expected = 0usize;
        let data_start = body.len() - data.len();
        for i in 0..constant_count {
            let offset = usize::from(table.offset(i));
            if offset != expected {
                return Err(PortFault::Malformed { offset: data_start + offset.min(data.len()) });
            }
            let item = data.get(offset..).ok_or(PortFault::Malformed { offset: data_start })?;
            let (_, after) = postcard::take_from_bytes::<Constant<'_>>(item)
                .map_err(|_| PortFault::Malformed { offset: data_start + offset })?;
            expected = data.len() - after.len();
        }
        if expected != data.len() {
            return Err(PortFault::Malformed { offset: data_start + expected });
        }
        for slot in 0..slot_count {
            if let Some(SlotInfo { ty, initial: Some(c) }) = table.slot(slot) {
                match table.constant(c) {
                    Some(k) if k.kind() == ty.constant_kind() => {}
                    _ => return Err(PortFault::BadInitial { slot, constant: c }),
                }
            }
        }
        Ok(table)
    }

    fn offset(&self, i: u16) -> u16 {
        let at = 2 * usize::from(i);
        match self.offsets.get(at..at + 2) {
            Some(&[lo, hi]) => u16::from_le_bytes([lo, hi]),
            _ => u16::MAX,
        }
    }

    /// Number of blackboard slots.
    #[must_use]
    pub const fn slot_count(&self) -> u16 {
        self.slot_count
    }

    /// Number of constants.
    #[must_use]
    pub const fn constant_count(&self) -> u16 {
        self.constant_count
    }

    /// Constant `i`. Walks nothing: one offset lookup and one decode.
    #[must_use]
    pub fn constant(&self, i: u16) -> Option<Constant<'a>> {
        if i >= self.constant_count {
            return None;
        }
        let item = self.data.get(usize::from(self.offset(i))..)?;
        postcard::take_from_bytes::<Constant<'a>>(item).ok().map(|(c, _)| c)
    }

    /// Slot `i`'s declaration. Walks the slot list (a few bytes per slot).
    #[must_use]
    pub fn slot(&self, i: u16) -> Option<SlotInfo> {
        if i >= self.slot_count {
            return None;
        }
        let mut rest = self.slots;
        let mut k = 0u16;
        loop {
            let (&ty, tail) = rest.split_first()?;
            let (initial, tail) = varint_u16(tail)?;
            if k == i {
                let initial = initial.checked_sub(1);
                return Some(SlotInfo { ty: PortType::from_u8(ty)?, initial });
            }
            rest = tail;
            k += 1;
        }
    }

    /// Checks one leaf's values against its behavior's ports ([`Catalog::port`]): every
    /// constant and slot present and of the port's type, no constant on an output port.
    /// Behaviors that declare no ports take any values (grounded arguments); the number
    /// of values is the behavior's arity, which [`Tree::validate`](crate::Tree::validate)
    /// checks.
    ///
    /// # Errors
    /// The first [`PortFault`] found.
    pub fn check_leaf<C: Catalog + ?Sized>(&self, catalog: &C, behavior: u16, values: &[u16]) -> Result<(), PortFault> {
        for (position, &v) in values.iter().enumerate() {
            let Some(port) = catalog.port(behavior, position) else {
                return Ok(());
            };
            let position = position.min(255) as u8;
            match PortValue::from_u16(v) {
                PortValue::Unset => {}
                PortValue::Constant(index) => {
                    if port.direction == PortDirection::Output {
                        return Err(PortFault::OutputConstant { position });
                    }
                    let Some(c) = self.constant(index) else {
                        return Err(PortFault::NoSuchConstant { position, index, count: self.constant_count });
                    };
                    let expected = port.ty.constant_kind();
                    if c.kind() != expected {
                        return Err(PortFault::ConstantType { position, index, expected, found: c.kind() });
                    }
                }
                PortValue::Slot(index) => {
                    let Some(slot) = self.slot(index) else {
                        return Err(PortFault::NoSuchSlot { position, index, count: self.slot_count });
                    };
                    if !port.ty.fits_slot(slot.ty) {
                        return Err(PortFault::SlotType { position, index, port: port.ty, slot: slot.ty });
                    }
                }
            }
        }
        Ok(())
    }

    /// The value of port `position` of a leaf whose values are `values` (from
    /// [`Context::args`](crate::Context::args)), resolved against this table.
    #[must_use]
    pub fn port(&self, values: &[u16], position: usize) -> Option<Port<'a>> {
        let v = *values.get(position)?;
        Some(match PortValue::from_u16(v) {
            PortValue::Unset => Port::Unset,
            PortValue::Slot(s) => Port::Slot(s),
            PortValue::Constant(c) => Port::Constant(self.constant(c)?),
        })
    }
}

/// A port's value as a behavior reads it: a constant, a blackboard slot to read or
/// write, or unset (use the default).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Port<'a> {
    /// A constant from the tree.
    Constant(Constant<'a>),
    /// A blackboard slot the behavior set owns.
    Slot(u16),
    /// Not given in the tree.
    Unset,
}

impl<'a> Port<'a> {
    /// The integer constant, if this is one.
    #[must_use]
    pub const fn int(&self) -> Option<i64> {
        match self {
            Self::Constant(Constant::Int(v)) => Some(*v),
            _ => None,
        }
    }

    /// The floating-point constant, if this is one.
    #[must_use]
    pub const fn double(&self) -> Option<f64> {
        match self {
            Self::Constant(Constant::Double(v)) => Some(*v),
            _ => None,
        }
    }

    /// The boolean constant, if this is one.
    #[must_use]
    pub const fn bool(&self) -> Option<bool> {
        match self {
            Self::Constant(Constant::Bool(v)) => Some(*v),
            _ => None,
        }
    }

    /// The string constant, if this is one.
    #[must_use]
    pub const fn str(&self) -> Option<&'a str> {
        match self {
            Self::Constant(Constant::Str(v)) => Some(v),
            _ => None,
        }
    }

    /// The blackboard slot, if this is one.
    #[must_use]
    pub const fn slot(&self) -> Option<u16> {
        match self {
            Self::Slot(s) => Some(*s),
            _ => None,
        }
    }
}

/// Writes a ports section body (host side; see the module docs). `slots` are the slot
/// declarations, `constants` the constants in index order.
///
/// # Errors
/// [`PortFault::Malformed`] with the offset reached when `out` is too small, or more
/// slots or constants than a section holds.
pub fn encode_table(slots: &[SlotInfo], constants: &[Constant<'_>], out: &mut [u8]) -> Result<usize, PortFault> {
    if slots.len() > usize::from(MAX_SLOTS) || constants.len() > usize::from(MAX_CONSTANTS) {
        return Err(PortFault::Malformed { offset: 0 });
    }
    let mut w = Writer { out, used: 0 };
    w.varint(slots.len() as u16)?;
    for slot in slots {
        w.bytes(&[slot.ty as u8])?;
        w.varint(slot.initial.map_or(0, |c| c.saturating_add(1)))?;
    }
    w.varint(constants.len() as u16)?;
    let offsets_at = w.used;
    w.used += 2 * constants.len();
    let data_at = w.used;
    for (i, c) in constants.iter().enumerate() {
        let offset = u16::try_from(w.used - data_at).map_err(|_| PortFault::Malformed { offset: w.used })?;
        let at = offsets_at + 2 * i;
        w.out.get_mut(at..at + 2).ok_or(PortFault::Malformed { offset: at })?.copy_from_slice(&offset.to_le_bytes());
        let rest = w.out.get_mut(w.used..).ok_or(PortFault::Malformed { offset: w.used })?;
        let written = postcard::to_slice(c, rest).map_err(|_| PortFault::Malformed { offset: w.used })?.len();
        w.used += written;
    }
    Ok(w.used)
}

/// Bytes written into a caller's buffer, failing with the offset reached.
struct Writer<'o> {
    out: &'o mut [u8],
    used: usize,
}

impl Writer<'_> {
    fn bytes(&mut self, b: &[u8]) -> Result<(), PortFault> {
        let at = self.used;
        self.out.get_mut(at..at + b.len()).ok_or(PortFault::Malformed { offset: at })?.copy_from_slice(b);
        self.used += b.len();
        Ok(())
    }

    fn varint(&mut self, v: u16) -> Result<(), PortFault> {
        let mut buf = [0u8; 3];
        let b = postcard::to_slice(&v, &mut buf).map_err(|_| PortFault::Malformed { offset: self.used })?;
        let b: &[u8] = b;
        let mut copy = [0u8; 3];
        let n = b.len();
        copy.get_mut(..n).ok_or(PortFault::Malformed { offset: self.used })?.copy_from_slice(b);
        self.bytes(copy.get(..n).unwrap_or(&[]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::port::{PortInfo, UNSET};
    use crate::{Behavior, BehaviorInfo};

    fn table(slots: &[SlotInfo], constants: &[Constant<'_>]) -> ([u8; 256], usize) {
        let mut out = [0u8; 256];
        let n = encode_table(slots, constants, &mut out).unwrap();
        (out, n)
    }

    #[test]
    fn a_table_reads_back_what_was_written() {
        let slots = [SlotInfo { ty: PortType::Other, initial: None }, SlotInfo { ty: PortType::Int, initial: Some(0) }];
        let constants = [Constant::Int(-7), Constant::Double(1.5), Constant::Bool(true), Constant::Str("GridBased")];
        let mut out = [0u8; 64];
        let n = encode_table(&slots, &constants, &mut out).unwrap();
        let t = PortTable::parse(&out[..n]).unwrap();
        assert_eq!((t.slot_count(), t.constant_count()), (2, 4));
        assert_eq!(t.slot(1), Some(slots[1]));
        assert_eq!(t.slot(2), None);
        for (i, c) in constants.iter().enumerate() {
            assert_eq!(t.constant(i as u16).as_ref(), Some(c));
        }
        assert_eq!(t.constant(4), None);
        let values = [0x8001, 3, UNSET];
        assert_eq!(t.port(&values, 0), Some(Port::Slot(1)));
        assert_eq!(t.port(&values, 1).and_then(|p| p.str()), Some("GridBased"));
        assert_eq!(t.port(&values, 2), Some(Port::Unset));
        assert_eq!(t.port(&values, 3), None);
    }

    #[test]
    fn every_truncation_and_corruption_is_refused_or_consistent() {
        let slots = [SlotInfo { ty: PortType::Double, initial: Some(1) }];
        let constants = [Constant::Str("a"), Constant::Double(2.0)];
        let mut out = [0u8; 64];
        let n = encode_table(&slots, &constants, &mut out).unwrap();
        assert!(PortTable::parse(&out[..n]).is_ok());
        for cut in 0..n {
            assert!(PortTable::parse(&out[..cut]).is_err(), "cut at {cut}");
        }
        let mut longer = out;
        longer[n] = 0;
        assert!(PortTable::parse(&longer[..=n]).is_err());
        // Every single-byte corruption either is refused or gives a table whose reads
        // do not fail.
        for at in 0..n {
            for b in [0u8, 1, 0x7F, 0x80, 0xFF] {
                let mut bad = out;
                bad[at] = b;
                if let Ok(t) = PortTable::parse(&bad[..n]) {
                    for i in 0..t.constant_count() {
                        assert!(t.constant(i).is_some());
                    }
                    for i in 0..t.slot_count() {
                        assert!(t.slot(i).is_some());
                    }
                }
            }
        }
    }

    #[test]
    fn a_slot_starting_with_a_constant_of_another_type_is_refused() {
        let (out, n) = table(&[SlotInfo { ty: PortType::Int, initial: Some(0) }], &[Constant::Str("x")]);
        assert_eq!(PortTable::parse(&out[..n]), Err(PortFault::BadInitial { slot: 0, constant: 0 }));
    }

    #[test]
    fn leaves_are_checked_against_their_ports() {
        const PORTS: [PortInfo<'static>; 2] = [
            PortInfo::input("distance", PortType::Double, "double"),
            PortInfo::output("path", PortType::Other, "nav_msgs::msg::Path"),
        ];
        let catalog = [Behavior::new(BehaviorInfo::action("Plan", 2), &PORTS)];
        let slots = [SlotInfo { ty: PortType::Other, initial: None }, SlotInfo { ty: PortType::Int, initial: None }];
        let (out, end) = table(&slots, &[Constant::Double(1.0), Constant::Str("x")]);
        let t = PortTable::parse(&out[..end]).unwrap();
        assert_eq!(t.check_leaf(&catalog[..], 0, &[0, 0x8000]), Ok(()));
        assert_eq!(t.check_leaf(&catalog[..], 0, &[UNSET, UNSET]), Ok(()));
        assert!(matches!(t.check_leaf(&catalog[..], 0, &[1, 0x8000]), Err(PortFault::ConstantType { .. })));
        assert!(matches!(t.check_leaf(&catalog[..], 0, &[2, 0x8000]), Err(PortFault::NoSuchConstant { .. })));
        assert!(matches!(t.check_leaf(&catalog[..], 0, &[0, 0x8002]), Err(PortFault::NoSuchSlot { .. })));
        assert!(matches!(t.check_leaf(&catalog[..], 0, &[0x8001, 0x8000]), Err(PortFault::SlotType { .. })));
        assert_eq!(t.check_leaf(&catalog[..], 0, &[0, 0]), Err(PortFault::OutputConstant { position: 1 }));
    }
}
