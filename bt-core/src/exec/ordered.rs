//! Sequence and Fallback (rules 2 and 6). A reactive one is the hot path: the tick loop
//! (`tick.rs`) ticks its leaf children in place, pushing a frame (here) only for a child
//! that needs one; when it returns, the children it reached last time beyond the one it
//! returned at are reset (here). The with-memory ones resume at the child that was
//! Running.

use super::frame::{Entered, Frame, FrameKind};
use super::run::Run;
use super::{NodeState, oob};
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::NodeKind;
use crate::status::Status;

impl<B: BehaviorSet, O: Observer, const DEPTH: usize, const FULL: bool> Run<'_, B, O, DEPTH, FULL> {
    /// Completes the frame at `depth` of the reactive Sequence or Fallback the child loop
    /// ticks (its `node` is set), for a child that is its last (`last`) or not.
    #[inline(always)]
    pub(super) fn push_ordered(
        frames: &mut [Frame; DEPTH],
        depth: usize,
        end: usize,
        go_on: Status,
        last: bool,
    ) -> Result<(), TickError> {
        let Some(slot) = frames.get_mut(depth) else {
            return Err(oob(end));
        };
        // The last child: a one-field frame (see `Frame`).
        slot.kind = FrameKind::Last;
        if !last {
            // What it returned at last time, and whether it was Running, are read from
            // its state when needed: that stays as it was until the node returns.
            slot.end = end as u16;
            slot.kind = if go_on == Status::Failure { FrameKind::Fallback } else { FrameKind::Sequence };
        }
        Ok(())
    }

    /// Sequence or Fallback `node` (either flavour, subtree ending at `end`) returns `r`
    /// at child `child`, whose subtree ends at `next`: reset the children it reached last
    /// time beyond `child`, remember `child`.
    #[inline(always)]
    pub(super) fn finish_ordered(
        &mut self,
        node: usize,
        end: usize,
        child: usize,
        next: usize,
        r: Status,
    ) -> Result<(), TickError> {
        // The child it returned at last time (0 for an Idle node: see `set_idle`), from
        // its state, which does not change before it returns.
        let last = self.state.get(node).map_or(0, |s| usize::from(s.aux));
        if last > child {
            // `end - 1` cannot wrap: `child` lies inside the subtree, below `end`.
            self.cold().reset_range(next, last.min(end - 1))?;
        }
        self.set_state(node, r.into(), child as u16);
        Ok(())
    }

    /// Enters a SequenceWithMemory or FallbackWithMemory: it resumes at the child that
    /// was Running.
    pub(super) fn enter_memory(&mut self, kind: &NodeKind, st: NodeState, frame: &mut Frame) -> Entered {
        frame.kind = if matches!(kind, NodeKind::SequenceWithMemory) {
            FrameKind::SequenceWithMemory
        } else {
            FrameKind::FallbackWithMemory
        };
        let idx = usize::from(frame.node);
        Entered::Child(if frame.running { usize::from(st.aux) } else { idx + 1 })
    }
}
