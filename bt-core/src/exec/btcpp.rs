//! The kinds that stand for BehaviorTree.CPP's and Nav2's nodes, off the hot path and
//! only in the full loop: each family enters and ascends its kinds in a file of its own,
//! and this one sends each step to the family of the node's kind.
//!
//! Each kind follows its original step by step (the rules are in the module docs of
//! [`exec`](super)), including when it resets its children: a child that finishes is
//! reset at once, except where BehaviorTree.CPP keeps its status (the children a
//! `PipelineSequence` or `SequenceStar` has passed, a `WhileDoElse`'s condition, ...).
//! What each kind keeps in its [`NodeState`] (`aux`, `ext`) and its
//! [`Frame`]/[`Extra`] is in its family's file.

use super::frame::{Ascent, Entered, Extra, Frame, FrameKind, Returned};
use super::run::Run;
use super::{NodeState, oob};
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::{Family, Node, NodeKind};
use crate::status::{NodeStatus, Status};

/// What a family is given to enter a node of its kinds: the kind and its state, the
/// frame and side entry to fill in, whether the parent keeps BehaviorTree.CPP's statuses
/// (see [`Run::fresh`]), and the time.
pub(super) struct Entering<'e> {
    pub(super) kind: &'e NodeKind,
    pub(super) st: NodeState,
    pub(super) frame: &'e mut Frame,
    pub(super) x: &'e mut Extra,
    pub(super) parent_mirrors: bool,
    pub(super) now: u32,
}

/// What a family is given when a child of one of its nodes returned: the node's kind, its
/// frame and side entry, what the child returned, and the time.
pub(super) struct Ascending<'a> {
    pub(super) kind: &'a NodeKind,
    pub(super) top: &'a mut Frame,
    pub(super) x: &'a mut Extra,
    pub(super) returned: Returned,
    pub(super) now: u32,
}

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    /// Enters a node of one of these kinds: its family fills in its frame and side entry
    /// and says which child to tick first, or what the node returns.
    pub(super) fn enter_btcpp(&mut self, e: Entering<'_>) -> Result<Entered, TickError> {
        e.frame.kind = FrameKind::Btcpp;
        match e.kind.family() {
            Family::Sequences => self.enter_sequences(e),
            Family::Branches => self.enter_branches(e),
            Family::ParallelAll => self.enter_parallel_all(e),
            Family::Counting => self.enter_counting(e),
            Family::Timers => self.enter_timers(e),
            Family::Guards => self.enter_guards(e),
            Family::Loops => self.enter_loop(e),
            Family::ManualSelector => self.enter_manual_selector(e),
            Family::Scripts => self.enter_scripts(e),
            Family::Ordered | Family::Parallel | Family::Decorators | Family::Leaves => {
                Err(oob(usize::from(e.frame.node)))
            }
        }
    }

    /// Child `returned.node` returned to frame `top` of one of these kinds: its family
    /// ticks another child, or says what the node returns.
    pub(super) fn ascend_btcpp(
        &mut self,
        top: &mut Frame,
        x: &mut Extra,
        returned: Returned,
        now: u32,
    ) -> Result<Ascent, TickError> {
        let kind = *self.node(usize::from(top.node))?.kind();
        let a = Ascending { kind: &kind, top, x, returned, now };
        match kind.family() {
            Family::Sequences => self.ascend_sequences(a),
            Family::Branches => self.ascend_branches(a),
            Family::ParallelAll => self.ascend_parallel_all(a),
            Family::Counting => self.ascend_counting(a),
            Family::Timers => Ok(self.ascend_timers(a)),
            Family::Guards => self.ascend_guards(a),
            Family::Loops => Ok(self.ascend_loop(a)),
            Family::ManualSelector => Ok(self.ascend_manual_selector(a)),
            Family::Scripts | Family::Ordered | Family::Parallel | Family::Decorators | Family::Leaves => {
                Err(oob(returned.node))
            }
        }
    }

    /// Control node or decorator `i` is halted or reset: runs what BehaviorTree.CPP runs
    /// then (a `Guard`'s `_onHalted`), and says whether the node keeps its memory, as
    /// BehaviorTree.CPP's does through a reset (a `SequenceStar`'s place, a `RunOnce`'s
    /// result and a `ManualSelector`'s last selection always, a `RoundRobin`'s and a
    /// `Recovery`'s counters unless it is halted while Running).
    pub(super) fn halted(&mut self, i: usize) -> bool {
        let Some(&kind) = self.nodes.get(i).map(Node::kind) else { return false };
        let running = self.status(i) == NodeStatus::Running;
        match kind.family() {
            Family::Sequences => Self::sequences_keep(&kind, running),
            Family::Branches => Self::branches_keep(&kind, running),
            Family::Counting => Self::counting_keeps(&kind),
            Family::Guards => self.guards_halted(i, &kind),
            Family::ManualSelector => true,
            _ => false,
        }
    }

    /// The status of a control node or decorator `i` that returned Skipped: Running, as
    /// BehaviorTree.CPP leaves it (it marked itself Running before it ticked its
    /// children), except where its family says otherwise (a `Guard`, a `Precondition`, a
    /// `ManualSelector`).
    #[cold]
    #[inline(never)]
    pub(super) fn skipped_status(&self, i: usize) -> NodeStatus {
        match self.nodes.get(i).map(Node::kind) {
            Some(kind @ (NodeKind::Guard(_) | NodeKind::Precondition { .. })) => self.guards_skipped_status(i, kind),
            Some(NodeKind::ManualSelector { .. }) => self.manual_selector_skipped_status(i),
            _ => NodeStatus::Running,
        }
    }

    /// Node `i` decided Skipped without ticking a child: Idle, but a `Loop` keeps its
    /// status, as BehaviorTree.CPP's does (the only kind that may skip while Running).
    #[cold]
    #[inline(never)]
    pub(super) fn decided_skipped(&mut self, i: usize) {
        if !matches!(self.nodes.get(i).map(Node::kind), Some(NodeKind::Loop { .. })) {
            self.set_status(i, NodeStatus::Idle);
        }
    }

    /// Whether a node that BehaviorTree.CPP resets when it finishes (a
    /// `RateController`, `Gate`, `Guard`, `Loop`, `Precondition`, `ManualSelector`)
    /// starts afresh: it is Idle, or it finished under a parent that BehaviorTree.CPP
    /// would have reset it under (every parent but these kinds, which keep exactly the
    /// statuses BehaviorTree.CPP keeps).
    pub(super) fn fresh(st: NodeState, parent_mirrors: bool) -> bool {
        match st.status {
            NodeStatus::Idle => true,
            NodeStatus::Running => false,
            NodeStatus::Success | NodeStatus::Failure => !parent_mirrors,
        }
    }

    /// A node that starts afresh after finishing is Idle, as BehaviorTree.CPP's parent
    /// left it: for the kinds whose status a Skipped result keeps.
    pub(super) fn forget_result(&mut self, i: usize, st: NodeState, fresh: bool) {
        if fresh && matches!(st.status, NodeStatus::Success | NodeStatus::Failure) {
            self.set_status(i, NodeStatus::Idle);
        }
    }

    /// The number of children of a node ending at `end`, and its child number `k`
    /// (0-based), if any.
    pub(super) fn children_of(&self, node: usize, end: usize, k: u16) -> Result<(u16, Option<usize>), TickError> {
        let mut n = 0u16;
        let mut found = None;
        let mut c = node + 1;
        while c < end {
            if n == k {
                found = Some(c);
            }
            n = n.saturating_add(1);
            c = self.end_of(c)?;
        }
        Ok((n, found))
    }

    /// BehaviorTree.CPP's `haltChild`: a Running child is halted (its subtree reset);
    /// any other child only becomes Idle, keeping its memory and its own children's
    /// statuses as they are.
    pub(super) fn halt_child(&mut self, c: usize) {
        if self.status(c) == NodeStatus::Running {
            self.reset_subtree(c);
        } else {
            self.set_status(c, NodeStatus::Idle);
        }
    }

    /// [`Run::halt_child`] for every child of `node` (subtree ending at `end`), in order.
    pub(super) fn reset_children(&mut self, node: usize, end: usize) -> Result<(), TickError> {
        let mut c = node + 1;
        while c < end {
            let after = self.end_of(c)?;
            self.halt_child(c);
            c = after;
        }
        Ok(())
    }

    /// The node of frame `top` returns `r`: once it finished, its child is reset as
    /// BehaviorTree.CPP's decorators reset theirs (its status only).
    pub(super) fn finish_decorator(&mut self, top: &Frame, r: Status) -> Ascent {
        if matches!(r, Status::Success | Status::Failure) {
            self.halt_child(usize::from(top.node) + 1);
        }
        Ascent::Return(r)
    }
}
