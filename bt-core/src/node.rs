//! The node model: one flat pre-order array of [`Node`]s.
//!
//! Node `i`'s first child is `i + 1`; the next sibling of a child `c` is
//! `c + size(c)`. No pointers and no boxes: the same array is the in-memory arena, the
//! unit of validation and the payload of the image.

/// Index of a node in its tree's pre-order array.
pub type NodeId = u16;

/// Identifier of a behavior (a condition or an action) in a behavior set.
pub type BehaviorId = u16;

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

/// What a node is and does.
///
/// Control nodes have one or more children, decorators exactly one, leaves none.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NodeKind {
    /// Reactive sequence: ticks children from the first on every tick; returns the first
    /// Failure or Running, Success when all succeed.
    Sequence,
    /// Reactive fallback (selector): ticks children from the first on every tick; returns
    /// the first Success or Running, Failure when all fail.
    Fallback,
    /// Sequence with memory: resumes at the child that was Running; children that
    /// succeeded in the current activation are not ticked again.
    SequenceWithMemory,
    /// Fallback with memory: resumes at the child that was Running; children that
    /// failed in the current activation are not ticked again.
    FallbackWithMemory,
    /// Ticks all children that have not finished in the current activation; Success
    /// once `success_threshold` succeeded, Failure once `failure_threshold` failed or
    /// success can no longer be reached. The rest are halted.
    Parallel {
        /// Children that must succeed.
        success_threshold: u16,
        /// Children whose failure makes the whole node fail.
        failure_threshold: u16,
    },
    /// Swaps Success and Failure.
    Inverter,
    /// Turns Failure into Success.
    ForceSuccess,
    /// Turns Success into Failure.
    ForceFailure,
    /// Runs its child until it has succeeded `n` times (one iteration per tick);
    /// fails as soon as the child fails.
    Repeat(u16),
    /// Runs its child until it succeeds, at most `n` attempts (one per tick);
    /// fails when the `n`-th attempt fails.
    Retry(u16),
    /// Gives its child at most `n` ticks per activation: if the child is still Running
    /// after its `n`-th tick, it is halted and the node fails.
    Timeout(u16),
    /// A condition leaf.
    Condition(Leaf),
    /// An action leaf.
    Action(Leaf),
}

/// How many children a kind of node takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arity {
    /// A leaf: no children.
    Leaf,
    /// A decorator: exactly one child.
    One,
    /// A control node: one or more children.
    AtLeastOne,
}

impl NodeKind {
    /// The kind's name, as in the papers and the renderer.
    #[must_use]
    pub const fn name(&self) -> &'static str {
        match self {
            Self::Sequence => "Sequence",
            Self::Fallback => "Fallback",
            Self::SequenceWithMemory => "SequenceWithMemory",
            Self::FallbackWithMemory => "FallbackWithMemory",
            Self::Parallel { .. } => "Parallel",
            Self::Inverter => "Inverter",
            Self::ForceSuccess => "ForceSuccess",
            Self::ForceFailure => "ForceFailure",
            Self::Repeat(_) => "Repeat",
            Self::Retry(_) => "Retry",
            Self::Timeout(_) => "Timeout",
            Self::Condition(_) => "Condition",
            Self::Action(_) => "Action",
        }
    }

    /// How many children this kind takes.
    #[must_use]
    pub const fn arity(&self) -> Arity {
        match self {
            Self::Sequence
            | Self::Fallback
            | Self::SequenceWithMemory
            | Self::FallbackWithMemory
            | Self::Parallel { .. } => Arity::AtLeastOne,
            Self::Inverter
            | Self::ForceSuccess
            | Self::ForceFailure
            | Self::Repeat(_)
            | Self::Retry(_)
            | Self::Timeout(_) => Arity::One,
            Self::Condition(_) | Self::Action(_) => Arity::Leaf,
        }
    }

    /// The leaf and its kind, for leaves.
    #[must_use]
    pub const fn leaf(&self) -> Option<(LeafKind, Leaf)> {
        match *self {
            Self::Condition(l) => Some((LeafKind::Condition, l)),
            Self::Action(l) => Some((LeafKind::Action, l)),
            _ => None,
        }
    }
}

/// One node of the flat pre-order array: its kind and the size of its subtree
/// (itself included). 12 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Node {
    kind: NodeKind,
    size: u16,
}

impl Node {
    /// A placeholder to fill caller storage with (`[Node::EMPTY; N]`); a failing
    /// condition leaf of behavior 0.
    pub const EMPTY: Node = Node { kind: NodeKind::Condition(Leaf::new(0)), size: 1 };

    /// A node with the given subtree size (itself included).
    #[must_use]
    pub const fn new(kind: NodeKind, size: u16) -> Self {
        Self { kind, size }
    }

    /// What the node is.
    #[inline(always)]
    #[must_use]
    pub const fn kind(&self) -> &NodeKind {
        &self.kind
    }

    /// Size of the subtree rooted here, itself included.
    #[inline(always)]
    #[must_use]
    pub const fn size(&self) -> u16 {
        self.size
    }

    pub(crate) fn set_size(&mut self, size: u16) {
        self.size = size;
    }
}
