//! BehaviorTree.CPP's counting decorators: `RepeatCycles` (its `Repeat`),
//! `RetryUntilSuccessful`, `Cycles` (either, with a count read from a slot or version
//! 3's loop), `KeepRunningUntilFailure` and `RunOnce`.
//!
//! | kind | state | frame, side entry |
//! |---|---|---|
//! | `RepeatCycles`, `RetryUntilSuccessful`, `Cycles` | `aux`: the count | `a` count, `ok` limit, `child_was_idle`, `children` cycles in this tick |
//! | `RunOnce` | `aux`: 0 not yet, 1 succeeded, 2 failed; kept for ever | — |

use super::btcpp::{Ascending, Entering};
use super::frame::{Ascent, Entered, Extra};
use super::oob;
use super::run::Run;
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::{NodeId, NodeKind};
use crate::script::{ScriptFault, Value, op};
use crate::status::{NodeStatus, Status};

/// A count as BehaviorTree.CPP reads it from the blackboard: -1 is no limit, other
/// negative counts are 0; `None` past 65,534 or for a value that is no integer.
fn count_of(v: Value) -> Option<u16> {
    let i = match v {
        Value::Int(i) => i,
        Value::Bool(b) => i64::from(b),
        Value::Double(d) if (-1e15..1e15).contains(&d) && d == (d as i64) as f64 => d as i64,
        Value::Double(_) | Value::Str(_) => return None,
    };
    match i {
        -1 => Some(NodeKind::FOREVER),
        i if i < 0 => Some(0),
        i => u16::try_from(i).ok().filter(|&n| n != NodeKind::FOREVER),
    }
}

/// Most cycles a `Cycles` of version 3 runs within one tick: every count it can be
/// given (up to 65,534) completes in one tick, as in BehaviorTree.CPP 3.8, and a loop
/// for ever over a child that finishes at once, where 3.8 never returns, yields here
/// (Running, with a wake-up).
pub const V3_CYCLES_PER_TICK: u16 = u16::MAX;

/// Whether a counting kind is a retry: a Failure counts a cycle.
const fn retries(kind: &NodeKind) -> bool {
    matches!(kind, NodeKind::RetryUntilSuccessful(_) | NodeKind::Cycles { retry: true, .. })
}

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    pub(super) fn enter_counting(&mut self, e: Entering<'_>) -> Result<Entered, TickError> {
        let Entering { kind, st, frame, x, now, .. } = e;
        let idx = usize::from(frame.node);
        let first = idx + 1;
        let limit = match *kind {
            NodeKind::RepeatCycles(n) | NodeKind::RetryUntilSuccessful(n) => Some(n),
            // Read on every tick, as BehaviorTree.CPP reads its port.
            NodeKind::Cycles { count: slot, from_slot: true, .. } => {
                let v = self.run_script(idx, &[op::LOAD, slot], now)?;
                let fault = ScriptFault::Conversion { slot };
                Some(count_of(v).ok_or(TickError::Script { node: idx as NodeId, fault })?)
            }
            NodeKind::Cycles { count, .. } => Some(count),
            _ => None,
        };
        Ok(match (*kind, limit) {
            (_, Some(n)) => {
                frame.a = if frame.running { st.aux } else { 0 };
                *x = Extra { ok: n, child_was_idle: self.status(first) == NodeStatus::Idle, ..Extra::default() };
                if frame.a < n || n == NodeKind::FOREVER {
                    Entered::Child(first)
                } else {
                    // Done without ticking the child (a count read from a slot fell to
                    // what it has done): a child still Running is halted first.
                    if self.status(first) == NodeStatus::Running {
                        self.halt_child(first);
                    }
                    self.set_memory(idx, 0, 0);
                    Entered::Decided(if retries(kind) { Status::Failure } else { Status::Success })
                }
            }
            (NodeKind::RunOnce { then_skip }, None) => match st.aux {
                0 => Entered::Child(first),
                _ if then_skip => Entered::Decided(Status::Skipped),
                1 => Entered::Decided(Status::Success),
                _ => Entered::Decided(Status::Failure),
            },
            (NodeKind::KeepRunningUntilFailure, None) => Entered::Child(first),
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
            NodeKind::RepeatCycles(_) | NodeKind::RetryUntilSuccessful(_) | NodeKind::Cycles { .. } => {
                let again = if retries(kind) { Status::Failure } else { Status::Success };
                let v3 = matches!(kind, NodeKind::Cycles { v3: true, .. });
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
                            // Cycles in this tick: version 3's loop yields after
                            // `V3_CYCLES_PER_TICK` (its only end when it repeats for ever
                            // over a child that finishes at once).
                            x.children = x.children.saturating_add(1);
                            let yields = if v3 { x.children == V3_CYCLES_PER_TICK } else { x.child_was_idle };
                            if yields {
                                // BehaviorTree.CPP 4's wake-up: return, ask to be ticked
                                // again. A child that had been Running goes again now,
                                // and in version 3 any child.
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
