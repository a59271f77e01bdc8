//! The control nodes whose children have parts to play: `IfThenElse` and `WhileDoElse`
//! (a condition, then a branch), and Nav2's `Recovery` (a child and its recovery).
//!
//! | kind | state | frame, side entry |
//! |---|---|---|
//! | `IfThenElse` | `aux`: the branch Running (0: none) | `a`: 0 condition, 1 branch |
//! | `WhileDoElse` | — | `a`: 0 condition, 1 branch |
//! | `Recovery` | `aux`: recoveries so far, `ext`: the child (0/1); kept unless halted Running | `a` recoveries, `ok` limit, `failed` child |

use super::btcpp::{Ascending, Entering};
use super::frame::{Ascent, Entered, Extra, Returned};
use super::oob;
use super::run::Run;
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::NodeKind;
use crate::status::Status;

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    pub(super) fn enter_branches(&mut self, e: Entering<'_>) -> Result<Entered, TickError> {
        let Entering { kind, st, frame, x, .. } = e;
        let idx = usize::from(frame.node);
        let end = usize::from(frame.end);
        let first = idx + 1;
        Ok(match *kind {
            NodeKind::IfThenElse => {
                if frame.running && st.aux != 0 {
                    frame.a = 1;
                    Entered::Child(usize::from(st.aux))
                } else {
                    frame.a = 0;
                    Entered::Child(first)
                }
            }
            NodeKind::WhileDoElse => {
                frame.a = 0;
                Entered::Child(first)
            }
            NodeKind::Recovery { retries } => {
                frame.a = st.aux;
                *x = Extra { ok: retries, failed: u16::from(st.ext), ..Extra::default() };
                if x.failed > 1 || frame.a > retries {
                    self.reset_children(idx, end)?;
                    self.set_memory(idx, 0, 0);
                    Entered::Decided(Status::Failure)
                } else {
                    let (_, c) = self.children_of(idx, end, x.failed)?;
                    Entered::Child(c.ok_or(oob(idx))?)
                }
            }
            _ => return Err(oob(idx)),
        })
    }

    pub(super) fn ascend_branches(&mut self, a: Ascending<'_>) -> Result<Ascent, TickError> {
        let Ascending { kind, top, x, returned, .. } = a;
        let Returned { node: c, end: child_end, r } = returned;
        let node = usize::from(top.node);
        let end = usize::from(top.end);
        let first = node + 1;
        let more = child_end < end;
        let done = |v| Ok(Ascent::Return(v));
        match kind {
            NodeKind::IfThenElse => {
                if top.a == 0 {
                    // The condition is the first child: `child_end` is the second.
                    let branch = match r {
                        Status::Success => child_end,
                        Status::Failure => self.end_of(child_end)?,
                        Status::Running | Status::Skipped => {
                            self.set_memory(node, 0, 0);
                            return done(r);
                        }
                    };
                    if branch >= end {
                        // Two children: the condition's Failure is the result, and
                        // BehaviorTree.CPP leaves the children as they are.
                        return done(Status::Failure);
                    }
                    top.a = 1;
                    return Ok(Ascent::Tick(branch));
                }
                if r == Status::Running {
                    self.set_memory(node, c as u16, 0);
                } else {
                    self.reset_children(node, end)?;
                    self.set_memory(node, 0, 0);
                }
                done(r)
            }
            NodeKind::WhileDoElse => {
                if top.a == 0 {
                    let third = if more { self.end_of(child_end).ok().filter(|&t| t < end) } else { None };
                    match (r, third) {
                        (Status::Running, _) => return done(Status::Running),
                        (Status::Success, third) => {
                            if let Some(t) = third {
                                self.halt_child(t);
                            }
                            top.a = 1;
                            return Ok(Ascent::Tick(child_end));
                        }
                        (Status::Failure, Some(t)) => {
                            self.halt_child(child_end);
                            top.a = 1;
                            return Ok(Ascent::Tick(t));
                        }
                        (Status::Failure, None) | (Status::Skipped, _) => {
                            self.reset_children(node, end)?;
                            return done(r);
                        }
                    }
                }
                if r != Status::Running {
                    self.reset_children(node, end)?;
                }
                done(r)
            }
            NodeKind::Recovery { .. } => {
                let second = self.end_of(first)?;
                let retries = x.ok;
                let give_up = |run: &mut Self, v| {
                    run.reset_children(node, end)?;
                    run.set_memory(node, 0, 0);
                    done(v)
                };
                if x.failed == 0 {
                    match r {
                        Status::Skipped | Status::Success => give_up(self, r),
                        Status::Running => {
                            self.set_memory(node, top.a, 0);
                            done(Status::Running)
                        }
                        Status::Failure if top.a < retries => {
                            self.halt_child(first);
                            x.failed = 1;
                            Ok(Ascent::Tick(second))
                        }
                        Status::Failure => give_up(self, Status::Failure),
                    }
                } else {
                    match r {
                        Status::Skipped => {
                            // Nav2 leaves the count of recoveries as it is here.
                            self.halt_child(second);
                            self.set_memory(node, top.a, 0);
                            done(Status::Failure)
                        }
                        Status::Running => {
                            self.set_memory(node, top.a, 1);
                            done(Status::Running)
                        }
                        Status::Success => {
                            self.halt_child(second);
                            top.a = top.a.saturating_add(1);
                            x.failed = 0;
                            if top.a <= retries { Ok(Ascent::Tick(first)) } else { give_up(self, Status::Failure) }
                        }
                        Status::Failure => give_up(self, Status::Failure),
                    }
                }
            }
            _ => Err(oob(node)),
        }
    }

    /// Whether a node of this family keeps its memory when reset: a `Recovery` unless it
    /// was Running.
    pub(super) fn branches_keep(kind: &NodeKind, running: bool) -> bool {
        matches!(kind, NodeKind::Recovery { .. }) && !running
    }
}
