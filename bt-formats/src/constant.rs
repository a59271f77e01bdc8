//! A leaf's port value as people write it: a constant as its text, a blackboard slot as
//! `{key}`.

use std::fmt;

use bt_core::PortValue;
use bt_core::port::Constant as Borrowed;

/// A constant of a tree's ports section, owned: what a producer interns and what a
/// reader of an image gets back ([`bt_core::port::Constant`] borrows the image).
#[derive(Clone, Debug, PartialEq)]
pub enum Constant {
    /// An integer.
    Int(i64),
    /// A floating-point number.
    Double(f64),
    /// A boolean.
    Bool(bool),
    /// A string.
    Str(String),
}

impl Constant {
    /// The bt-core constant borrowing this one.
    #[must_use]
    pub fn as_constant(&self) -> Borrowed<'_> {
        match self {
            Self::Int(v) => Borrowed::Int(*v),
            Self::Double(v) => Borrowed::Double(*v),
            Self::Bool(v) => Borrowed::Bool(*v),
            Self::Str(s) => Borrowed::Str(s),
        }
    }

    /// A key for interning: equal constants (bit-equal doubles) share one entry.
    #[must_use]
    pub fn key(&self) -> (u8, String) {
        match self {
            Self::Int(v) => (0, v.to_string()),
            Self::Double(v) => (1, v.to_bits().to_string()),
            Self::Bool(v) => (2, v.to_string()),
            Self::Str(s) => (3, s.clone()),
        }
    }

    /// The constant as BehaviorTree.CPP XML writes it back (a double keeps enough
    /// digits to read back the same bits).
    #[must_use]
    pub fn text(&self) -> String {
        Text(self.as_constant()).to_string()
    }
}

impl From<Borrowed<'_>> for Constant {
    fn from(c: Borrowed<'_>) -> Self {
        match c {
            Borrowed::Int(v) => Self::Int(v),
            Borrowed::Double(v) => Self::Double(v),
            Borrowed::Bool(v) => Self::Bool(v),
            Borrowed::Str(s) => Self::Str(s.to_string()),
        }
    }
}

/// A constant's text: `3`, `0.5`, `true`, `GridBased`.
struct Text<'a>(Borrowed<'a>);

impl fmt::Display for Text<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Borrowed::Int(v) => write!(f, "{v}"),
            Borrowed::Double(v) => write!(f, "{v:?}"),
            Borrowed::Bool(v) => write!(f, "{v}"),
            Borrowed::Str(s) => f.write_str(s),
        }
    }
}

/// Writes a leaf value of a declared port as its user wrote it: a constant as its text
/// (from `constant`), a blackboard slot as `{key}` (its name from `slot`), nothing when
/// unset. A constant or slot that `constant` or `slot` does not know is written by its
/// number, `#const3` or `{#slot3}`.
///
/// # Errors
/// Whatever the formatter returns.
pub fn write_port_value<'a>(
    f: &mut fmt::Formatter<'_>,
    value: u16,
    slot: impl FnOnce(u16) -> Option<&'a str>,
    constant: impl FnOnce(u16) -> Option<Borrowed<'a>>,
) -> fmt::Result {
    match PortValue::from_u16(value) {
        PortValue::Constant(i) => match constant(i) {
            Some(c) => write!(f, "{}", Text(c)),
            None => write!(f, "#const{i}"),
        },
        PortValue::Slot(i) => match slot(i) {
            Some(name) => write!(f, "{{{name}}}"),
            None => write!(f, "{{#slot{i}}}"),
        },
        PortValue::Unset => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_print_as_written_and_read_back_the_same_bits() {
        assert_eq!(Constant::Double(1.0).text(), "1.0");
        assert_eq!(Constant::Double(0.1).text().parse::<f64>().unwrap().to_bits(), 0.1f64.to_bits());
        assert_eq!(Constant::Int(-3).text(), "-3");
        assert_eq!(Constant::Bool(true).text(), "true");
        assert_eq!(Constant::Str("GridBased".into()).text(), "GridBased");
        let c = Constant::Str("x".into());
        assert_eq!(Constant::from(c.as_constant()), c);
        assert_ne!(Constant::Double(0.0).key(), Constant::Double(-0.0).key());
    }
}
