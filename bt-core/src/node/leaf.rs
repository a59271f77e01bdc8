//! Leaves: a behavior and its values (grounded arguments or port references), kept
//! inline in the node or, past [`MAX_ARGS`], in the tree's value table.

use super::BehaviorId;

/// Most values (grounded arguments, ports) a leaf carries inline, in its node.
///
/// A leaf with more is *extended*: its values live in the tree's value table (see
/// [`Leaf::extended`]), so every node keeps its 12 bytes.
pub const MAX_ARGS: usize = 3;

/// Marks an unused argument slot inside a [`Leaf`]; never a valid argument value.
const NO_ARG: u16 = u16::MAX;

/// In the last slot, marks an extended leaf: the first two slots are the start and
/// length of its values in the tree's value table. Never a valid inline value.
const EXTENDED: u16 = u16::MAX - 1;

/// A leaf's behavior and its values: grounded arguments (object, position, ... ids) or
/// port references.
///
/// Up to [`MAX_ARGS`] values are kept inline; the values `0xFFFF` and `0xFFFE` are
/// reserved there. A leaf with more values refers to a range of the tree's value table
/// ([`Leaf::extended`]); behaviors read the values of either kind with
/// [`Context::args`](crate::Context::args).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Leaf {
    behavior: BehaviorId,
    args: [u16; MAX_ARGS],
}

/// Why a [`Leaf`] could not be made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LeafError {
    /// More than [`MAX_ARGS`] arguments inline; use [`Leaf::extended`].
    #[error("a leaf carries at most {MAX_ARGS} arguments inline, got {0}")]
    TooManyArgs(usize),
    /// An inline argument equal to 65535 or 65534, which are reserved.
    #[error("argument {0} is 65534 or 65535, values reserved inside a leaf")]
    ReservedValue(usize),
    /// An extended leaf whose range ends beyond 65535 or has fewer than
    /// [`MAX_ARGS`]` + 1` values.
    #[error(
        "an extended leaf takes {0} values from {1}: the range must hold more than {MAX_ARGS} and end within 65535"
    )]
    BadRange(u16, u16),
}

impl Leaf {
    /// A leaf without arguments.
    #[must_use]
    pub const fn new(behavior: BehaviorId) -> Self {
        Self { behavior, args: [NO_ARG; MAX_ARGS] }
    }

    /// A leaf with the given arguments.
    ///
    /// # Errors
    /// [`LeafError`] if there are more than [`MAX_ARGS`] arguments or one is `u16::MAX`.
    pub fn with_args(behavior: BehaviorId, args: &[u16]) -> Result<Self, LeafError> {
        if args.len() > MAX_ARGS {
            return Err(LeafError::TooManyArgs(args.len()));
        }
        let mut leaf = Self::new(behavior);
        for (i, (slot, &a)) in leaf.args.iter_mut().zip(args).enumerate() {
            if a >= EXTENDED {
                return Err(LeafError::ReservedValue(i));
            }
            *slot = a;
        }
        Ok(leaf)
    }

    /// A leaf whose `len` values are `values[start..start + len]` of the value table of
    /// the tree it belongs to ([`Tree::validate_with`](crate::Tree::validate_with)
    /// checks the range). `len` must be more than [`MAX_ARGS`]: fewer values go inline.
    ///
    /// # Errors
    /// [`LeafError::BadRange`] when `len <= MAX_ARGS` or the range ends past 65535.
    pub fn extended(behavior: BehaviorId, start: u16, len: u16) -> Result<Self, LeafError> {
        if usize::from(len) <= MAX_ARGS || start.checked_add(len).is_none() {
            return Err(LeafError::BadRange(len, start));
        }
        Ok(Self { behavior, args: [start, len, EXTENDED] })
    }

    /// A leaf with the given values: inline when they fit, else extended with its values
    /// at `start` of the value table (which the caller fills with `values`).
    ///
    /// # Errors
    /// As [`Leaf::with_args`] and [`Leaf::extended`].
    pub fn with_values(behavior: BehaviorId, values: &[u16], start: u16) -> Result<Self, LeafError> {
        if values.len() <= MAX_ARGS {
            return Self::with_args(behavior, values);
        }
        let len = u16::try_from(values.len()).map_err(|_| LeafError::TooManyArgs(values.len()))?;
        Self::extended(behavior, start, len)
    }

    /// Whether the values are in the tree's value table rather than inline.
    #[inline(always)]
    #[must_use]
    pub const fn is_extended(&self) -> bool {
        self.args[MAX_ARGS - 1] == EXTENDED
    }

    /// For an extended leaf, the start and length of its values in the value table.
    #[inline]
    #[must_use]
    pub const fn range(&self) -> Option<(u16, u16)> {
        if self.is_extended() { Some((self.args[0], self.args[1])) } else { None }
    }

    /// The behavior this leaf runs.
    #[inline(always)]
    #[must_use]
    pub const fn behavior(&self) -> BehaviorId {
        self.behavior
    }

    /// Number of values, inline or extended.
    #[inline]
    #[must_use]
    pub fn argc(&self) -> usize {
        match self.range() {
            Some((_, len)) => usize::from(len),
            None => self.inline_count(),
        }
    }

    fn inline_count(&self) -> usize {
        self.args.iter().take_while(|&&a| a != NO_ARG).count()
    }

    /// The inline values, in order; empty for an extended leaf, whose values only its
    /// tree knows: read values with [`Context::args`](crate::Context::args) or
    /// [`Tree::args`](crate::Tree::args), which handle both.
    #[inline]
    #[must_use]
    pub fn args(&self) -> &[u16] {
        if self.is_extended() {
            return &[];
        }
        self.args.get(..self.inline_count()).unwrap_or(&[])
    }

    /// Inline value `i`, if present (`None` for an extended leaf).
    #[inline]
    #[must_use]
    pub fn arg(&self, i: usize) -> Option<u16> {
        if self.is_extended() {
            return None;
        }
        self.args.get(i).copied().filter(|&a| a != NO_ARG)
    }

    /// The leaf's values, taken from `values` (its tree's value table) when extended.
    /// Empty when the range lies outside `values`, which a validated tree rules out.
    #[inline]
    #[must_use]
    pub fn args_in<'v>(&'v self, values: &'v [u16]) -> &'v [u16] {
        match self.range() {
            Some((start, len)) => {
                let start = usize::from(start);
                values.get(start..start + usize::from(len)).unwrap_or(&[])
            }
            None => self.args(),
        }
    }
}

impl core::fmt::Debug for Leaf {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.range() {
            Some((start, len)) => write!(f, "#{}[values {start}..+{len}]", self.behavior),
            None => write!(f, "#{}{:?}", self.behavior, self.args()),
        }
    }
}

/// Whether a behavior is a condition or an action.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LeafKind {
    /// Checks the world; Success or Failure, never Running.
    Condition,
    /// Acts on the world; may take several ticks (Running) and can be halted.
    Action,
}
