//! The borrowed pieces of one tick ([`Run`]), what the executor keeps beside the node
//! states ([`Side`]), and the reads and writes of node states that every family uses.

use super::frame::Frame;
use super::{NodeState, oob};
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::{Node, NodeId};
use crate::status::{NodeStatus, Status};

/// What the executor keeps beside its frames and the node states: the halt stack, and
/// what a tick leaves besides statuses. Behind one pointer in [`Run`], which the tick
/// loop keeps in a register.
#[derive(Debug)]
pub(super) struct Side<const DEPTH: usize> {
    /// The open ancestors while [`Run::reset`] walks a subtree.
    pub(super) halt: [u16; DEPTH],
    /// A node asked to be ticked again at once: see
    /// [`Executor::woken`](super::Executor::woken).
    pub(super) woken: bool,
    /// A fault of a script run while halting (a `Guard`'s `_onHalted`), which the tick
    /// returns.
    #[cfg(feature = "btcpp")]
    pub(super) fault: Option<TickError>,
    /// Tick with the full loop (`FULL`): the tree has one of BehaviorTree.CPP's kinds, or
    /// a leaf has returned Skipped. Never cleared: the plain loop knows nothing of what
    /// Skipped leaves behind (rule 8).
    #[cfg(feature = "btcpp")]
    pub(super) full: bool,
}

impl<const DEPTH: usize> Side<DEPTH> {
    pub(super) const fn new(full: bool) -> Self {
        let _ = full;
        Self {
            halt: [0; DEPTH],
            woken: false,
            #[cfg(feature = "btcpp")]
            fault: None,
            #[cfg(feature = "btcpp")]
            full,
        }
    }
}

/// The borrowed pieces of one tick, split so that the hot loop sees plain slices.
///
/// `FULL` is false for the *plain* loop, which ticks the papers' kinds and knows nothing
/// of BehaviorTree.CPP's (their families, Skipped, the wake-up signal): the compiler
/// leaves all of that out of it. A tree of the papers' kinds runs the plain loop until a
/// leaf returns Skipped; from there on it runs the full one (`Run::leaf_odd`).
pub(super) struct Run<'r, B, O, const DEPTH: usize, const FULL: bool> {
    pub(super) nodes: &'r [Node],
    /// The tree's value table, handed to behaviors in their
    /// [`Context`](crate::Context).
    pub(super) values: &'r [u16],
    pub(super) state: &'r mut [NodeState],
    pub(super) side: &'r mut Side<DEPTH>,
    pub(super) behaviors: &'r mut B,
    pub(super) observer: &'r mut O,
    /// An action that was Running and runs on ends the tick: every ancestor was Running
    /// at the child on the path to it and stays so, with nothing to reset (an ancestor's
    /// later children were reset when it last returned there). True when the tree has
    /// no `Parallel`, `ParallelAll` or `PipelineSequence`, which go on to tick other
    /// children, and no `Timeout`, which counts the tick; the other decorators return
    /// Running unchanged, and the clocked ones decide on the way down.
    pub(super) still_running: bool,
}

impl<B: BehaviorSet, O: Observer, const DEPTH: usize, const FULL: bool> Run<'_, B, O, DEPTH, FULL> {
    /// The same pieces, reborrowed for a call out of the tick loop. Built where the call
    /// is made, so that the loop keeps its pieces in registers instead of laying out a
    /// `Run` in memory on every tick for calls that are rarely made.
    #[inline(always)]
    pub(super) fn cold(&mut self) -> Run<'_, B, O, DEPTH, FULL> {
        self.with::<FULL>()
    }

    /// The same pieces for the full loop (`FULL`), where BehaviorTree.CPP's kinds run.
    #[inline(always)]
    pub(super) fn full(&mut self) -> Run<'_, B, O, DEPTH, true> {
        self.with::<true>()
    }

    #[inline(always)]
    fn with<const M: bool>(&mut self) -> Run<'_, B, O, DEPTH, M> {
        Run {
            nodes: self.nodes,
            values: self.values,
            state: &mut *self.state,
            side: &mut *self.side,
            behaviors: &mut *self.behaviors,
            observer: &mut *self.observer,
            still_running: self.still_running,
        }
    }

    #[inline(always)]
    pub(super) fn node(&self, i: usize) -> Result<&Node, TickError> {
        self.nodes.get(i).ok_or(oob(i))
    }

    #[inline(always)]
    pub(super) fn end_of(&self, i: usize) -> Result<usize, TickError> {
        Ok(i + usize::from(self.node(i)?.size()))
    }

    #[inline(always)]
    pub(super) fn status(&self, i: usize) -> NodeStatus {
        self.state.get(i).map_or(NodeStatus::Idle, NodeState::status)
    }

    #[inline(always)]
    pub(super) fn set_status(&mut self, i: usize, new: NodeStatus) {
        if let Some(s) = self.state.get_mut(i) {
            let old = s.status;
            s.status = new;
            if O::ENABLED && old != new {
                self.observer.on_change(i as NodeId, old, new);
            }
        }
    }

    /// Sets status and `aux` at once.
    #[inline(always)]
    pub(super) fn set_state(&mut self, i: usize, new: NodeStatus, aux: u16) {
        if let Some(s) = self.state.get_mut(i) {
            let old = s.status;
            *s = NodeState { status: new, aux, ext: 0 };
            if O::ENABLED && old != new {
                self.observer.on_change(i as NodeId, old, new);
            }
        }
    }

    /// Sets a node Idle and its `aux` to 0: the tick relies on an Idle node's `aux`
    /// being 0 (no child returned at, no count).
    #[inline(always)]
    pub(super) fn set_idle(&mut self, i: usize) {
        self.set_state(i, NodeStatus::Idle, 0);
    }

    #[inline(always)]
    pub(super) fn set_aux(&mut self, i: usize, aux: u16) {
        if let Some(s) = self.state.get_mut(i) {
            s.aux = aux;
        }
    }

    /// Sets `aux` and `ext`, leaving the status as it is.
    #[inline]
    pub(super) fn set_memory(&mut self, i: usize, aux: u16, ext: u8) {
        if let Some(s) = self.state.get_mut(i) {
            s.aux = aux;
            s.ext = ext;
        }
    }

    /// Control node or decorator `i` returns `r`. One that returns Skipped stays
    /// Running, as BehaviorTree.CPP leaves it (it marked itself Running before it ticked
    /// its children), except where its family says otherwise.
    #[inline]
    pub(super) fn set_returned(&mut self, i: usize, r: Status) {
        #[cfg(feature = "btcpp")]
        if FULL && r == Status::Skipped {
            let new = self.full().skipped_status(i);
            return self.set_status(i, new);
        }
        self.set_status(i, r.into());
    }

    /// Records `node` as the reactive Sequence or Fallback whose children the child loop
    /// ticks at `depth`: it goes in the frame it pushes if a child needs one.
    #[inline(always)]
    pub(super) fn ticking(frames: &mut [Frame; DEPTH], depth: usize, node: usize) -> Result<(), TickError> {
        match frames.get_mut(depth) {
            Some(slot) => {
                slot.node = node as u16;
                Ok(())
            }
            None => Err(oob(node)),
        }
    }
}
