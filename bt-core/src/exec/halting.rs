//! Halting (rules 3 and 4): resetting a subtree, halting its Running actions in
//! post-order, and halting the branches an action preempts before it starts.

use super::frame::{Frame, FrameKind};
use super::run::Run;
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::{Node, NodeId, NodeKind};
use crate::status::NodeStatus;

/// Which nodes [`Run::reset`] visits.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Scan {
    /// Skip subtrees whose root is Idle (their nodes are all Idle): between ticks, and
    /// mid-tick for subtrees off the current path.
    SkipIdle,
    /// Every node: when the state may not be consistent (a tick stopped half-way).
    All,
}

impl<B: BehaviorSet, O: Observer, const DEPTH: usize, const FULL: bool> Run<'_, B, O, DEPTH, FULL> {
    /// Rule 4: action `idx` is about to start. Halt every branch it preempts: for each
    /// reactive ancestor on the path (`frames[..depth]`) that was Running at a later
    /// child than the one being ticked, that child's subtree. Innermost first. Frames
    /// of nodes ticking their last child are passed over: nothing comes after it.
    #[cold]
    #[inline(never)]
    pub(super) fn preempt(&mut self, frames: &[Frame; DEPTH], depth: usize, idx: usize) {
        if depth == 0 {
            return;
        }
        let mut current = idx;
        for f in frames.iter().take(depth).rev() {
            if matches!(f.kind, FrameKind::Sequence | FrameKind::Fallback)
                && let Some(&st) = self.state.get(usize::from(f.node))
                && st.status == NodeStatus::Running
            {
                let old = usize::from(st.aux);
                if old > current && self.runs_an_action(old) {
                    self.reset_subtree(old);
                }
            }
            current = usize::from(f.node);
        }
    }

    /// Whether an action is Running in the subtree of `root`: a branch without one (a
    /// `Delay` waiting, a `RepeatCycles` between cycles) preempts nothing.
    fn runs_an_action(&self, root: usize) -> bool {
        let Ok(end) = self.end_of(root) else { return false };
        (root..end).any(|i| {
            self.status(i) == NodeStatus::Running
                && matches!(self.nodes.get(i).map(Node::kind), Some(NodeKind::Action(_)))
        })
    }

    /// Resets the siblings from `from` up to and including the one starting at `last`.
    #[cold]
    #[inline(never)]
    pub(super) fn reset_range(&mut self, from: usize, last: usize) -> Result<(), TickError> {
        let mut c = from;
        while c <= last {
            let after = self.end_of(c)?;
            self.reset_subtree(c);
            c = after;
        }
        Ok(())
    }

    /// Halts the Running actions under `root` (post-order) and resets the subtree to
    /// Idle. Skips subtrees that are already Idle.
    #[inline]
    pub(super) fn reset_subtree(&mut self, root: usize) {
        if self.status(root) != NodeStatus::Idle {
            self.reset(root, Scan::SkipIdle);
        }
    }

    /// Halts the Running actions under `root` in post-order (children before parents,
    /// left to right) and sets every node of the subtree to Idle.
    pub(super) fn reset(&mut self, root: usize, scan: Scan) {
        let Ok(end) = self.end_of(root) else { return };
        let mut top = 0usize;
        let mut i = root;
        loop {
            // Close the open ancestors whose subtree ends here.
            while let Some(a) = top.checked_sub(1).and_then(|t| self.side.halt.get(t)).map(|&a| usize::from(a)) {
                match self.end_of(a) {
                    Ok(a_end) if a_end <= i => {
                        top -= 1;
                        self.set_idle_halted(a);
                    }
                    _ => break,
                }
            }
            if i >= end {
                break;
            }
            let Some(node) = self.nodes.get(i).copied() else { break };
            if scan == Scan::SkipIdle && self.status(i) == NodeStatus::Idle {
                i += usize::from(node.size()).max(1);
                continue;
            }
            match node.kind() {
                NodeKind::Action(leaf) => {
                    if self.status(i) == NodeStatus::Running {
                        self.behaviors.halt(leaf, i as NodeId);
                    }
                    self.set_idle(i);
                }
                NodeKind::Condition(_) => self.set_idle(i),
                _ => match self.side.halt.get_mut(top) {
                    Some(slot) => {
                        *slot = i as u16;
                        top += 1;
                    }
                    // Deeper than DEPTH: impossible for a validated tree.
                    None => self.set_idle_halted(i),
                },
            }
            i += 1;
        }
    }

    /// Control node or decorator `i` is reset: Idle, and its memory cleared, except
    /// what BehaviorTree.CPP keeps through a reset (see `Run::halted`).
    fn set_idle_halted(&mut self, i: usize) {
        #[cfg(feature = "btcpp")]
        if FULL && self.full().halted(i) {
            return self.set_status(i, NodeStatus::Idle);
        }
        self.set_idle(i);
    }
}
