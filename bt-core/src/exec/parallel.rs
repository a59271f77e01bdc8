//! Parallel (rule 6): ticks the children that have not finished in the current
//! activation and returns as soon as a threshold is reached, halting the rest. The counts
//! are totals of the activation, as BehaviorTree.CPP keeps them; with `count_skipped`,
//! children that skip count towards success in that tick (rule 8, the full loop only).

use super::BTCPP;
use super::frame::{Ascent, Entered, Extra, Frame, FrameKind, Returned};
use super::run::Run;
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::status::{NodeStatus, Status};

impl<B: BehaviorSet, O: Observer, const DEPTH: usize, const FULL: bool> Run<'_, B, O, DEPTH, FULL> {
    /// Enters a Parallel: counts its children, and those that finished earlier in the
    /// activation, and ticks the first that has not.
    pub(super) fn enter_parallel(
        &mut self,
        success_threshold: u16,
        failure_threshold: u16,
        count_skipped: bool,
        frame: &mut Frame,
        x: &mut Extra,
    ) -> Result<Entered, TickError> {
        let idx = usize::from(frame.node);
        let end = usize::from(frame.end);
        let running = frame.running;
        frame.kind = FrameKind::Parallel;
        *x = Extra {
            ok: 0,
            failed: 0,
            children: 0,
            success: success_threshold,
            failure: failure_threshold,
            skipped: 0,
            // The plain loop keeps it too, for the full loop to read if a child skips
            // later in the tick. Without the feature the store is a constant (12 B of the
            // firmware's flash).
            count_skipped: BTCPP && count_skipped,
            child_was_idle: false,
        };
        // As BehaviorTree.CPP, the counts are totals of the activation: the children
        // that finished on earlier ticks count from the start.
        let mut c = idx + 1;
        while c < end {
            x.children = x.children.saturating_add(1);
            if running {
                match self.status(c) {
                    NodeStatus::Success => x.ok = x.ok.saturating_add(1),
                    NodeStatus::Failure => x.failed = x.failed.saturating_add(1),
                    _ => {}
                }
            }
            c = self.end_of(c)?;
        }
        match self.parallel_step(idx + 1, end, running)? {
            Some(c) => Ok(Entered::Child(c)),
            // Impossible: a Running parallel has a child that has not finished.
            None => {
                self.finish_parallel(idx, end, end)?;
                Ok(Entered::Decided(Status::Failure))
            }
        }
    }

    /// Child `returned.node` of the Parallel of frame `top` returned: count it, and
    /// return once a threshold decides or every child has been ticked.
    pub(super) fn ascend_parallel(
        &mut self,
        top: &Frame,
        x: &mut Extra,
        returned: Returned,
    ) -> Result<Ascent, TickError> {
        let Returned { end: child_end, r, .. } = returned;
        match r {
            Status::Success => x.ok = x.ok.saturating_add(1),
            Status::Failure => x.failed = x.failed.saturating_add(1),
            Status::Skipped if FULL => x.skipped = x.skipped.saturating_add(1),
            Status::Running | Status::Skipped => {}
        }
        Ok(Ascent::Return(if let Some(v) = Self::parallel_verdict(x) {
            self.finish_parallel(usize::from(top.node), usize::from(top.end), child_end)?;
            v
        } else {
            match self.parallel_step(child_end, usize::from(top.end), top.running)? {
                Some(next) => return Ok(Ascent::Tick(next)),
                None if FULL && x.skipped == x.children => Status::Skipped,
                None => Status::Running,
            }
        }))
    }

    /// Success or Failure once a parallel's thresholds decide, else `None`.
    #[inline]
    fn parallel_verdict(x: &Extra) -> Option<Status> {
        if x.ok >= x.success || (FULL && x.count_skipped && x.ok.saturating_add(x.skipped) >= x.success) {
            Some(Status::Success)
        } else if x.failed >= x.failure || x.children.saturating_sub(x.failed) < x.success {
            Some(Status::Failure)
        } else {
            None
        }
    }

    /// The next child of a parallel to tick, from `from` on: children that finished in
    /// the current activation (the parallel was Running) are passed over, their results
    /// already in the counts. `None` past the last child.
    fn parallel_step(&self, from: usize, end: usize, running: bool) -> Result<Option<usize>, TickError> {
        let mut c = from;
        while c < end {
            if !running || !matches!(self.status(c), NodeStatus::Success | NodeStatus::Failure) {
                return Ok(Some(c));
            }
            c = self.end_of(c)?;
        }
        Ok(None)
    }

    /// Parallel `node` decided: halt its Running children and reset those from
    /// `reached` on.
    fn finish_parallel(&mut self, node: usize, end: usize, reached: usize) -> Result<(), TickError> {
        let mut c = node + 1;
        while c < end {
            let after = self.end_of(c)?;
            if c >= reached || self.status(c) == NodeStatus::Running {
                self.reset_subtree(c);
            }
            c = after;
        }
        Ok(())
    }
}
