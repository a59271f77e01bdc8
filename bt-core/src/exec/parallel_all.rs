//! BehaviorTree.CPP's other parallels. `ParallelAll` ticks every child that has not
//! finished until all have; then Failure if at least `max_failures` of them failed,
//! else Success. `ParallelV3` (BehaviorTree.CPP 3's `Parallel`) counts anew on every
//! tick, in child order, ticking the children that have not finished and counting
//! those that have where they stand, and returns as soon as a threshold is reached.
//!
//! | kind | state | frame, side entry |
//! |---|---|---|
//! | `ParallelAll` | — | `ok` finished, `failed`, `skipped`, `children`, `failure` |
//! | `ParallelV3` | — | `ok` succeeded, `failed`, `children`, `success`, `failure` thresholds |

use super::btcpp::{Ascending, Entering};
use super::frame::{Ascent, Entered, Extra, Returned};
use super::oob;
use super::run::Run;
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::NodeKind;
use crate::status::{NodeStatus, Status};

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    pub(super) fn enter_parallel_all(&mut self, e: Entering<'_>) -> Result<Entered, TickError> {
        let Entering { kind, frame, x, .. } = e;
        let idx = usize::from(frame.node);
        if let NodeKind::ParallelV3 { success_threshold, failure_threshold } = *kind {
            let (children, _) = self.children_of(idx, usize::from(frame.end), 0)?;
            *x = Extra { children, success: success_threshold, failure: failure_threshold, ..Extra::default() };
            return self.parallel_v3_sweep(idx, usize::from(frame.end), idx + 1, frame.running, x);
        }
        let NodeKind::ParallelAll { max_failures } = *kind else {
            return Err(oob(idx));
        };
        let end = usize::from(frame.end);
        let running = frame.running;
        *x = Extra { failure: max_failures, ..Extra::default() };
        let mut next = None;
        let mut c = idx + 1;
        while c < end {
            x.children = x.children.saturating_add(1);
            match self.status(c) {
                NodeStatus::Success if running => x.ok = x.ok.saturating_add(1),
                NodeStatus::Failure if running => {
                    x.ok = x.ok.saturating_add(1);
                    x.failed = x.failed.saturating_add(1);
                }
                _ => {
                    if next.is_none() {
                        next = Some(c);
                    }
                }
            }
            c = self.end_of(c)?;
        }
        Ok(match next {
            Some(c) => Entered::Child(c),
            // Impossible for a node Running: it would have finished.
            None => Entered::Decided(self.parallel_all_done(idx, end, x)?),
        })
    }

    pub(super) fn ascend_parallel_all(&mut self, a: Ascending<'_>) -> Result<Ascent, TickError> {
        let Ascending { kind, top, x, returned, .. } = a;
        let Returned { end: child_end, r, .. } = returned;
        let node = usize::from(top.node);
        let end = usize::from(top.end);
        if matches!(kind, NodeKind::ParallelV3 { .. }) {
            if let Some(v) = Self::parallel_v3_count(x, r) {
                self.reset_children(node, end)?;
                return Ok(Ascent::Return(v));
            }
            return Ok(match self.parallel_v3_sweep(node, end, child_end, top.running, x)? {
                Entered::Child(c) => Ascent::Tick(c),
                Entered::Decided(v) => Ascent::Return(v),
            });
        }
        match r {
            Status::Success => x.ok = x.ok.saturating_add(1),
            Status::Failure => {
                x.ok = x.ok.saturating_add(1);
                x.failed = x.failed.saturating_add(1);
            }
            Status::Skipped => x.skipped = x.skipped.saturating_add(1),
            Status::Running => {}
        }
        let mut k = child_end;
        while k < end {
            let finished = matches!(self.status(k), NodeStatus::Success | NodeStatus::Failure);
            if !(top.running && finished) {
                return Ok(Ascent::Tick(k));
            }
            k = self.end_of(k)?;
        }
        Ok(Ascent::Return(self.parallel_all_done(node, end, x)?))
    }

    /// `ParallelV3` at `node` goes on from child `from`: children that finished earlier
    /// in the activation (the node was Running) are counted where they stand; the first
    /// that has not is ticked. Running past the last child.
    fn parallel_v3_sweep(
        &mut self,
        node: usize,
        end: usize,
        from: usize,
        running: bool,
        x: &mut Extra,
    ) -> Result<Entered, TickError> {
        let mut c = from;
        while c < end {
            let finished = match self.status(c) {
                NodeStatus::Success if running => Status::Success,
                NodeStatus::Failure if running => Status::Failure,
                _ => return Ok(Entered::Child(c)),
            };
            if let Some(v) = Self::parallel_v3_count(x, finished) {
                self.reset_children(node, end)?;
                return Ok(Entered::Decided(v));
            }
            c = self.end_of(c)?;
        }
        Ok(Entered::Decided(Status::Running))
    }

    /// Counts a child's result; the status once a threshold decides.
    fn parallel_v3_count(x: &mut Extra, r: Status) -> Option<Status> {
        match r {
            Status::Success => x.ok = x.ok.saturating_add(1),
            Status::Failure => x.failed = x.failed.saturating_add(1),
            Status::Running | Status::Skipped => return None,
        }
        if x.ok >= x.success {
            Some(Status::Success)
        } else if x.failed >= x.failure || x.failed > x.children.saturating_sub(x.success) {
            Some(Status::Failure)
        } else {
            None
        }
    }

    /// `ParallelAll` at `node` has ticked or passed every child this tick.
    fn parallel_all_done(&mut self, node: usize, end: usize, x: &Extra) -> Result<Status, TickError> {
        if x.skipped == x.children {
            return Ok(Status::Skipped);
        }
        if x.skipped.saturating_add(x.ok) >= x.children {
            self.reset_children(node, end)?;
            return Ok(if x.failed >= x.failure { Status::Failure } else { Status::Success });
        }
        Ok(Status::Running)
    }
}
