//! The executor's explicit stack: a [`Frame`] for each level of the path from the root to
//! the node being ticked, an [`Extra`] beside it for the kinds that count, and what
//! entering a node or returning to a frame decides.

use crate::status::Status;

/// What a frame's node is: all the ascent needs to know without reading the node.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(u8)]
pub(super) enum FrameKind {
    // The ordered kinds come first: see `is_ordered` and `goes_on_after`.
    #[default]
    Sequence = 0,
    Fallback = 1,
    SequenceWithMemory = 2,
    FallbackWithMemory = 3,
    /// A reactive Sequence or Fallback ticking its last child: see [`Frame`].
    Last,
    Parallel,
    Inverter,
    ForceSuccess,
    ForceFailure,
    Repeat,
    Retry,
    Timeout,
    /// One of BehaviorTree.CPP's and Nav2's kinds: its family ascends it, reading the
    /// node's kind (`btcpp.rs`). These reset their children as BehaviorTree.CPP does.
    Btcpp,
}

impl FrameKind {
    /// Sequence or Fallback, with or without memory.
    #[inline(always)]
    pub(super) fn is_ordered(self) -> bool {
        (self as u8) < 4
    }

    /// SequenceWithMemory or FallbackWithMemory.
    #[inline(always)]
    pub(super) fn is_memory(self) -> bool {
        matches!(self, Self::SequenceWithMemory | Self::FallbackWithMemory)
    }

    /// One of BehaviorTree.CPP's kinds, which keep a finished child's status exactly
    /// when BehaviorTree.CPP does.
    #[inline]
    pub(super) fn mirrors_btcpp(self) -> bool {
        self == Self::Btcpp
    }

    /// For an ordered kind: the status after which it ticks the next child.
    #[inline(always)]
    pub(super) fn goes_on_after(self) -> Status {
        if (self as u8) & 1 == 0 { Status::Success } else { Status::Failure }
    }
}

/// One level of the path from the root to the node being ticked. 8 bytes, so the
/// innermost frame lives in a register.
///
/// A Sequence or Fallback (either flavour) keeps the rest of what it needs in its own
/// state, which does not change before it returns: the child it returned at last time,
/// and whether it was Running. The loop writes only `node`, `end` and `kind` for it.
///
/// A reactive Sequence or Fallback ticking its *last* child gets a
/// [`FrameKind::Last`] frame, of which only `node` is read: when the child returns,
/// there is no next child, no later child to reset, and the status goes up unchanged;
/// the node only records it and the child it returned at. Rule 4 has nothing to halt in
/// it either: its previous child cannot come after its last. Trees built by
/// backchaining are mostly such tails (`Fallback[condition, Sequence[...]]`).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(8))]
pub(super) struct Frame {
    /// The control node or decorator.
    pub(super) node: u16,
    /// One past its last descendant.
    pub(super) end: u16,
    /// Repeat/Retry/Timeout: the count so far. BehaviorTree.CPP's kinds: as their
    /// family says. Otherwise unused.
    pub(super) a: u16,
    pub(super) kind: FrameKind,
    /// The node was Running when the tick reached it (not a new activation). Set for
    /// the nodes that `Run::enter_other` opens.
    pub(super) running: bool,
}

/// What a Parallel or a counting decorator needs beyond its [`Frame`], kept at the
/// same depth in a side stack so that frames stay small. BehaviorTree.CPP's kinds use
/// the fields as their family says.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Extra {
    /// Parallel: children that succeeded. Repeat/Retry/Timeout: `n`.
    pub(super) ok: u16,
    /// Parallel: children that failed.
    pub(super) failed: u16,
    /// Parallel: number of children.
    pub(super) children: u16,
    /// Parallel: success threshold.
    pub(super) success: u16,
    /// Parallel: failure threshold.
    pub(super) failure: u16,
    /// Parallel: children that returned Skipped in this tick.
    pub(super) skipped: u16,
    /// Parallel: skipped children count towards `success`.
    pub(super) count_skipped: bool,
    /// `RepeatCycles`, `RetryUntilSuccessful`: the child was Idle when ticked.
    pub(super) child_was_idle: bool,
}

/// Node `node`, whose subtree ends at `end`, returned `r` to the frame above it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Returned {
    pub(super) node: usize,
    pub(super) end: usize,
    pub(super) r: Status,
}

/// What entering a node decided.
pub(super) enum Entered {
    /// Tick this child.
    Child(usize),
    /// The node returns this without a child being ticked.
    Decided(Status),
}

/// What a frame's node does when a child returned to it.
pub(super) enum Ascent {
    /// Tick this child of the frame's node.
    Tick(usize),
    /// The frame's node returns this.
    Return(Status),
}
