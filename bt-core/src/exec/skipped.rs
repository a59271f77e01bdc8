//! Skipped in Sequence and Fallback (rule 8), the full loop only: a child that skipped
//! is passed over (a reactive node resets it), and a node none of whose children
//! returned what it goes on after skips itself.

use super::frame::{Ascent, Frame};
use super::run::Run;
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::NodeKind;
use crate::status::{NodeStatus, Status};

impl<B: BehaviorSet, O: Observer, const DEPTH: usize, const FULL: bool> Run<'_, B, O, DEPTH, FULL> {
    /// True when a child of `node` (subtree ending at `end`) has status `s`.
    pub(super) fn any_child(&self, node: usize, end: usize, s: NodeStatus) -> Result<bool, TickError> {
        let mut c = node + 1;
        while c < end {
            if self.status(c) == s {
                return Ok(true);
            }
            c = self.end_of(c)?;
        }
        Ok(false)
    }

    /// Reactive or memory Sequence/Fallback `node` (subtree ending at `end`) got
    /// Skipped from its last child `child`: it returns `go_on`, or Skipped when no child
    /// returned `go_on` in this activation (children that skipped are Idle or Running).
    /// A node that returns Skipped stays Running, resuming at its first child.
    #[cold]
    #[inline(never)]
    fn finish_skipped(
        &mut self,
        node: usize,
        end: usize,
        child: usize,
        go_on: Status,
        memory: bool,
    ) -> Result<Status, TickError> {
        let any = self.any_child(node, end, go_on.into())?;
        if memory {
            // Finished: BehaviorTree.CPP resets all children, here those still Running.
            self.reset_running(node + 1, end);
        }
        if any {
            self.set_state(node, go_on.into(), child as u16);
            Ok(go_on)
        } else {
            self.set_state(node, NodeStatus::Running, if memory { node as u16 + 1 } else { child as u16 });
            Ok(Status::Skipped)
        }
    }

    /// A reactive Sequence or Fallback ticking its last child `child` (a
    /// [`FrameKind::Last`](super::frame::FrameKind::Last) frame) got Skipped from it.
    #[cold]
    #[inline(never)]
    pub(super) fn last_skipped(&mut self, node: usize, child: usize) -> Result<Status, TickError> {
        // BehaviorTree.CPP halts a reactive node's child that skipped.
        self.reset_subtree(child);
        let go_on = match self.node(node)?.kind() {
            NodeKind::Fallback => Status::Failure,
            _ => Status::Success,
        };
        let end = self.end_of(node)?;
        self.finish_skipped(node, end, child, go_on, false)
    }

    /// An ordered frame `f` got Skipped from child `c` (ending at `child_end`): go on
    /// to the next child, or finish.
    #[cold]
    #[inline(never)]
    pub(super) fn ordered_skipped(&mut self, f: &Frame, c: usize, child_end: usize) -> Result<Ascent, TickError> {
        let memory = f.kind.is_memory();
        if !memory {
            self.reset_subtree(c);
        }
        if child_end < usize::from(f.end) {
            return Ok(Ascent::Tick(child_end));
        }
        let r = self.finish_skipped(usize::from(f.node), usize::from(f.end), c, f.kind.goes_on_after(), memory)?;
        Ok(Ascent::Return(r))
    }

    /// Resets the siblings from `from` up to (not including) `to` that are Running: the
    /// children that skipped before a SequenceWithMemory or FallbackWithMemory finishes.
    #[cold]
    #[inline(never)]
    pub(super) fn reset_running(&mut self, from: usize, to: usize) {
        let mut c = from;
        while c < to {
            let Ok(after) = self.end_of(c) else { return };
            if self.status(c) == NodeStatus::Running {
                self.reset_subtree(c);
            }
            c = after;
        }
    }
}
