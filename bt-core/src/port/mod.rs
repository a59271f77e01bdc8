//! Ports: the named, typed values a leaf receives, as BehaviorTree.CPP declares them.
//!
//! A behavior may declare its ports ([`Catalog::port`](crate::Catalog::port)): each has a name, a direction
//! and a type. A leaf of such a behavior carries one value per
//! declared port, in declaration order (inline or in the tree's value table, as any leaf
//! value), and each value is a [`PortValue`] packed into a `u16`:
//!
//! | `u16` value | meaning |
//! |---|---|
//! | `0x0000..=0x7FFE` | constant `v` of the image's port table |
//! | `0x7FFF` | unset: the behavior uses the port's default |
//! | `0x8000..=0xFFFD` | blackboard slot `v - 0x8000` |
//!
//! Constants (numbers, booleans, strings written in the tree) are interned once in the
//! image's *ports section* (tag 3), typed as the port that reads them declares; a
//! blackboard key (`{goal}` in BehaviorTree.CPP XML) becomes a slot id that the behavior
//! set owns, so nothing is allocated on the controller. [`PortTable`] reads that section
//! in place, without copying it, and [`PortTable::check_leaf`] is what the loader
//! ([`load_with_ports`](crate::load_with_ports)) runs on every leaf: every constant and slot a leaf
//! names exists, has its port's type, and no output port is given a constant.
//!
//! A controller keeps the table [`load_with_ports`](crate::load_with_ports) returns beside
//! the tree, and a
//! behavior reads port `i` of a leaf as `table.port(ctx.args(leaf), i)`: a typed
//! constant ([`Port::double`], [`Port::int`], [`Port::bool`], [`Port::str`]), a slot of
//! its blackboard ([`Port::slot`]), or unset (the port's default, which the catalog's
//! [`PortInfo::default`] states).
//!
//! The section's encoding, and [`PortTable`] which reads it, are in `table.rs`.

mod table;

pub use table::{Port, PortTable, encode_table};

use serde::{Deserialize, Serialize};

/// Which way data flows through a port.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PortDirection {
    /// The behavior reads it.
    Input,
    /// The behavior writes it (a blackboard slot, or unset).
    Output,
    /// The behavior reads and writes it.
    InOut,
}

impl PortDirection {
    /// The direction as BehaviorTree.CPP's model tags name it: `input_port`,
    /// `output_port`, `inout_port`.
    #[must_use]
    pub const fn tag(self) -> &'static str {
        match self {
            Self::Input => "input_port",
            Self::Output => "output_port",
            Self::InOut => "inout_port",
        }
    }
}

/// The type of a port's value, as far as the controller needs to know it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum PortType {
    /// No type declared: anything goes; constants are strings.
    Any = 0,
    /// A signed or unsigned integer (`int`, `unsigned`, `uint16`, milliseconds, ...).
    Int = 1,
    /// A floating-point number (`double`, `float`).
    Double = 2,
    /// `bool`.
    Bool = 3,
    /// `std::string`.
    String = 4,
    /// Another type (a message, a vector, ...): opaque to bt-core; constants are
    /// strings, which the behavior converts.
    Other = 5,
}

impl PortType {
    /// The type for its byte in the ports section.
    #[must_use]
    pub const fn from_u8(b: u8) -> Option<Self> {
        Some(match b {
            0 => Self::Any,
            1 => Self::Int,
            2 => Self::Double,
            3 => Self::Bool,
            4 => Self::String,
            5 => Self::Other,
            _ => return None,
        })
    }

    /// The kind of constant a port of this type takes.
    #[must_use]
    pub const fn constant_kind(self) -> ConstantKind {
        match self {
            Self::Int => ConstantKind::Int,
            Self::Double => ConstantKind::Double,
            Self::Bool => ConstantKind::Bool,
            Self::Any | Self::String | Self::Other => ConstantKind::Str,
        }
    }

    /// Whether a port of this type may share a blackboard slot of type `slot`:
    /// equal types, or either untyped, or a string slot (which BehaviorTree.CPP
    /// converts from when read).
    #[must_use]
    pub const fn fits_slot(self, slot: PortType) -> bool {
        matches!(self, Self::Any) || matches!(slot, Self::Any | Self::String) || self as u8 == slot as u8
    }
}

/// The declaration of one port of a behavior.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PortInfo<'a> {
    /// The port's name, e.g. `goal`.
    pub name: &'a str,
    /// Input, output or both.
    pub direction: PortDirection,
    /// The type class the controller reads.
    pub ty: PortType,
    /// The type as the model writes it (`double`, `geometry_msgs::msg::PoseStamped`);
    /// empty when none is declared.
    pub type_name: &'a str,
    /// The default value's text when the model declares one.
    pub default: Option<&'a str>,
}

impl<'a> PortInfo<'a> {
    /// An input port of type `ty` named as its C++ type `type_name`, without default.
    #[must_use]
    pub const fn input(name: &'a str, ty: PortType, type_name: &'a str) -> Self {
        Self { name, direction: PortDirection::Input, ty, type_name, default: None }
    }

    /// An output port.
    #[must_use]
    pub const fn output(name: &'a str, ty: PortType, type_name: &'a str) -> Self {
        Self { name, direction: PortDirection::Output, ty, type_name, default: None }
    }

    /// An input-output port.
    #[must_use]
    pub const fn inout(name: &'a str, ty: PortType, type_name: &'a str) -> Self {
        Self { name, direction: PortDirection::InOut, ty, type_name, default: None }
    }

    /// The same port with a default value.
    #[must_use]
    pub const fn with_default(mut self, default: &'a str) -> Self {
        self.default = Some(default);
        self
    }
}

/// Marks a port that the tree leaves unset.
pub const UNSET: u16 = 0x7FFF;
/// The first value that names a blackboard slot.
pub const SLOT_BASE: u16 = 0x8000;
/// Most constants a ports section holds.
pub const MAX_CONSTANTS: u16 = UNSET;
/// Most blackboard slots a ports section holds (values up to `0xFFFD`; `0xFFFE` and
/// `0xFFFF` are reserved by [`Leaf`](crate::Leaf)).
pub const MAX_SLOTS: u16 = 0xFFFE - SLOT_BASE;

/// What one leaf value of a behavior with ports stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PortValue {
    /// Constant `i` of the ports section.
    Constant(u16),
    /// Blackboard slot `i`.
    Slot(u16),
    /// Not given: the behavior uses the port's default.
    Unset,
}

impl PortValue {
    /// Decodes a leaf value.
    #[must_use]
    pub const fn from_u16(v: u16) -> Self {
        if v == UNSET {
            Self::Unset
        } else if v < SLOT_BASE {
            Self::Constant(v)
        } else {
            Self::Slot(v - SLOT_BASE)
        }
    }

    /// Encodes it as a leaf value; `None` when the index is beyond [`MAX_CONSTANTS`] or
    /// [`MAX_SLOTS`].
    #[must_use]
    pub const fn to_u16(self) -> Option<u16> {
        match self {
            Self::Unset => Some(UNSET),
            Self::Constant(i) if i < MAX_CONSTANTS => Some(i),
            Self::Slot(i) if i < MAX_SLOTS => Some(SLOT_BASE + i),
            _ => None,
        }
    }
}

/// What kind of value a constant holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ConstantKind {
    /// An integer.
    Int,
    /// A floating-point number.
    Double,
    /// A boolean.
    Bool,
    /// A string.
    Str,
}

/// A constant of the ports section, borrowed from the image bytes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Constant<'a> {
    /// An integer.
    Int(i64),
    /// A floating-point number.
    Double(f64),
    /// A boolean.
    Bool(bool),
    /// A string.
    Str(&'a str),
}

impl Constant<'_> {
    /// Its kind.
    #[must_use]
    pub const fn kind(&self) -> ConstantKind {
        match self {
            Self::Int(_) => ConstantKind::Int,
            Self::Double(_) => ConstantKind::Double,
            Self::Bool(_) => ConstantKind::Bool,
            Self::Str(_) => ConstantKind::Str,
        }
    }
}

/// A blackboard slot as the ports section declares it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SlotInfo {
    /// The type of the ports that share it.
    pub ty: PortType,
    /// The constant it starts with, if any (a SubTree remapping a literal to a key its
    /// nodes also write).
    pub initial: Option<u16>,
}

/// Why a ports section or a leaf's port values were refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PortFault {
    /// The section's bytes do not decode: a bad varint, an offset or a constant that
    /// runs past the end, a bad type byte, a string that is not UTF-8, bytes left over.
    #[error("the ports section is malformed at byte {offset} of its body")]
    Malformed {
        /// Byte offset in the section body.
        offset: usize,
    },
    /// A slot's initial value names a constant that does not exist or has another type.
    #[error("slot {slot} starts with constant {constant}, which is missing or not of the slot's type")]
    BadInitial {
        /// The slot.
        slot: u16,
        /// The constant.
        constant: u16,
    },
    /// A value names a constant beyond the table.
    #[error("port {position} names constant {index}; the image has {count}")]
    NoSuchConstant {
        /// Port position.
        position: u8,
        /// The constant.
        index: u16,
        /// Constants in the image.
        count: u16,
    },
    /// A value names a slot beyond the table.
    #[error("port {position} names blackboard slot {index}; the image has {count}")]
    NoSuchSlot {
        /// Port position.
        position: u8,
        /// The slot.
        index: u16,
        /// Slots in the image.
        count: u16,
    },
    /// A constant of another type than the port's.
    #[error("port {position} is of type {expected:?}, its constant {index} is {found:?}")]
    ConstantType {
        /// Port position.
        position: u8,
        /// The constant.
        index: u16,
        /// What the port takes.
        expected: ConstantKind,
        /// What the constant is.
        found: ConstantKind,
    },
    /// A slot whose type the port's type cannot share.
    #[error("port {position} is of type {port:?}, its blackboard slot {index} holds {slot:?}")]
    SlotType {
        /// Port position.
        position: u8,
        /// The slot.
        index: u16,
        /// The port's type.
        port: PortType,
        /// The slot's type.
        slot: PortType,
    },
    /// An output port given a constant: there is nothing to write to.
    #[error("port {position} is an output port but is given a constant")]
    OutputConstant {
        /// Port position.
        position: u8,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_pack_into_u16() {
        for v in [
            PortValue::Constant(0),
            PortValue::Constant(0x7FFE),
            PortValue::Slot(0),
            PortValue::Slot(0x7FFD),
            PortValue::Unset,
        ] {
            assert_eq!(PortValue::from_u16(v.to_u16().unwrap()), v);
        }
        assert_eq!(PortValue::Constant(0x7FFF).to_u16(), None);
        assert_eq!(PortValue::Slot(0x7FFE).to_u16(), None);
        assert_eq!(PortValue::Slot(0x7FFD).to_u16(), Some(0xFFFD));
    }
}
