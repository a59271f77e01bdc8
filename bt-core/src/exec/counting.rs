//! BehaviorTree.CPP's counting decorators: `RepeatCycles` (its `Repeat`),
//! `RetryUntilSuccessful`, `KeepRunningUntilFailure` and `RunOnce`.
//!
//! | kind | state | frame, side entry |
//! |---|---|---|
//! | `RepeatCycles`, `RetryUntilSuccessful` | `aux`: the count | `a` count, `ok` limit, `child_was_idle` |
//! | `RunOnce` | `aux`: 0 not yet, 1 succeeded, 2 failed; kept for ever | — |

use super::btcpp::{Ascending, Entering};
use super::frame::{Ascent, Entered, Extra};
use super::oob;
use super::run::Run;
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::NodeKind;
use crate::status::{NodeStatus, Status};

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    pub(super) fn enter_counting(&mut self, e: Entering<'_>) -> Result<Entered, TickError> {
        let Entering { kind, st, frame, x, .. } = e;
        let idx = usize::from(frame.node);
        let first = idx + 1;
        Ok(match *kind {
            NodeKind::RepeatCycles(n) | NodeKind::RetryUntilSuccessful(n) => {
                frame.a = if frame.running { st.aux } else { 0 };
                *x = Extra { ok: n, child_was_idle: self.status(first) == NodeStatus::Idle, ..Extra::default() };
                if frame.a < n || n == NodeKind::FOREVER {
                    Entered::Child(first)
                } else {
                    self.set_memory(idx, 0, 0);
                    let repeat = matches!(kind, NodeKind::RepeatCycles(_));
                    Entered::Decided(if repeat { Status::Success } else { Status::Failure })
                }
            }
            NodeKind::RunOnce { then_skip } => match st.aux {
                0 => Entered::Child(first),
                _ if then_skip => Entered::Decided(Status::Skipped),
                1 => Entered::Decided(Status::Success),
                _ => Entered::Decided(Status::Failure),
            },
            NodeKind::KeepRunningUntilFailure => Entered::Child(first),
            _ => return Err(oob(idx)),
        })
    }

    pub(super) fn ascend_counting(&mut self, a: Ascending<'_>) -> Result<Ascent, TickError> {
        let Ascending { kind, top, x, returned, .. } = a;
        let r = returned.r;
        let node = usize::from(top.node);
        let first = node + 1;
        let done = |v| Ok(Ascent::Return(v));
        match kind {
            NodeKind::RepeatCycles(_) | NodeKind::RetryUntilSuccessful(_) => {
                let again = if matches!(kind, NodeKind::RepeatCycles(_)) { Status::Success } else { Status::Failure };
                match r {
                    Status::Running => {
                        self.set_memory(node, top.a, 0);
                        done(Status::Running)
                    }
                    Status::Skipped => {
                        self.halt_child(first);
                        self.set_memory(node, top.a, 0);
                        done(Status::Skipped)
                    }
                    r if r == again => {
                        self.halt_child(first);
                        top.a = top.a.saturating_add(1);
                        if top.a < x.ok || x.ok == NodeKind::FOREVER {
                            if x.child_was_idle {
                                // BehaviorTree.CPP's wake-up: return, ask to be ticked
                                // again. A child that had been Running goes again now.
                                self.set_memory(node, top.a, 0);
                                self.side.woken = true;
                                return done(Status::Running);
                            }
                            x.child_was_idle = true;
                            return Ok(Ascent::Tick(first));
                        }
                        self.set_memory(node, 0, 0);
                        done(r)
                    }
                    r => {
                        self.halt_child(first);
                        self.set_memory(node, 0, 0);
                        done(r)
                    }
                }
            }
            NodeKind::KeepRunningUntilFailure => match r {
                Status::Failure => {
                    self.halt_child(first);
                    done(Status::Failure)
                }
                Status::Success => {
                    self.halt_child(first);
                    done(Status::Running)
                }
                Status::Running | Status::Skipped => done(Status::Running),
            },
            NodeKind::RunOnce { .. } => {
                if matches!(r, Status::Success | Status::Failure) {
                    self.set_memory(node, if r == Status::Success { 1 } else { 2 }, 0);
                }
                Ok(self.finish_decorator(top, r))
            }
            _ => Err(oob(node)),
        }
    }

    /// Whether a node of this family keeps its memory when reset: a `RunOnce` its
    /// result, for ever.
    pub(super) fn counting_keeps(kind: &NodeKind) -> bool {
        matches!(kind, NodeKind::RunOnce { .. })
    }
}
