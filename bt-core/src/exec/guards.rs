//! The decorators that decide whether their child runs (rules 9 and 12): a `Guard`
//! (BehaviorTree.CPP's scripted attributes around one node), a `Precondition` (its
//! `if` script), a `Gate` (a behavior of the set: Nav2's `DistanceController`,
//! `SpeedController`, ...), and a `Check` (BehaviorTree.CPP 3's `BlackboardCheck*`).
//!
//! | kind | state | frame, side entry |
//! |---|---|---|
//! | `Guard` | — | — |
//! | `Precondition` | `aux`: 1 while its child is under way; kept for ever | — |
//! | `Gate` | — | — |
//! | `Check` | — | — |

use super::btcpp::{Ascending, Entering};
use super::frame::{Ascent, Entered};
use super::oob;
use super::run::Run;
use crate::behavior::{BehaviorSet, Context, Observer, TickError};
use crate::node::{Code, NodeId, NodeKind};
use crate::script::{Hook, hook, truth};
use crate::status::{NodeStatus, Status};

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    pub(super) fn enter_guards(&mut self, e: Entering<'_>) -> Result<Entered, TickError> {
        let Entering { kind, st, frame, parent_mirrors, now, .. } = e;
        let idx = usize::from(frame.node);
        let first = idx + 1;
        Ok(match *kind {
            NodeKind::Guard(table) => {
                let decided = if Self::fresh(st, parent_mirrors) {
                    self.guard_before(idx, table, now)?
                } else if frame.running {
                    // `_while` is the one hook asked while the node runs.
                    match hook(table.words(self.values), Hook::While) {
                        Some(p) if !self.holds(idx, p, now)? => {
                            self.reset_subtree(first);
                            self.run_hook(idx, table, Hook::OnHalted, now)?;
                            Some(Status::Skipped)
                        }
                        _ => None,
                    }
                } else {
                    None
                };
                match decided {
                    Some(d) => {
                        self.guard_after(idx, table, d, now)?;
                        Entered::Decided(d)
                    }
                    None => Entered::Child(first),
                }
            }
            NodeKind::Precondition { code, otherwise } => {
                self.forget_result(idx, st, Self::fresh(st, parent_mirrors));
                if st.aux == 1 {
                    Entered::Child(first)
                } else if self.holds(idx, code.words(self.values), now)? {
                    self.set_memory(idx, 1, 0);
                    Entered::Child(first)
                } else {
                    Entered::Decided(otherwise)
                }
            }
            NodeKind::Check { code, otherwise } => {
                // A fault (a key not set yet) is a mismatch, as a failed `getInput`.
                let holds = self.run_script(idx, code.words(self.values), now).is_ok_and(|v| truth(v) == Ok(true));
                if holds {
                    Entered::Child(first)
                } else {
                    if self.status(first) == NodeStatus::Running {
                        self.halt_child(first);
                    }
                    Entered::Decided(otherwise)
                }
            }
            NodeKind::Gate(ref leaf) => {
                let starting = Self::fresh(st, parent_mirrors);
                let open =
                    self.behaviors.action(leaf, Context { node: idx as NodeId, now, starting, values: self.values });
                if self.status(first) == NodeStatus::Running {
                    Entered::Child(first)
                } else {
                    match open {
                        Status::Success => Entered::Child(first),
                        other => Entered::Decided(other),
                    }
                }
            }
            _ => return Err(oob(idx)),
        })
    }

    pub(super) fn ascend_guards(&mut self, a: Ascending<'_>) -> Result<Ascent, TickError> {
        let Ascending { kind, top, returned, now, .. } = a;
        let node = usize::from(top.node);
        let r = returned.r;
        match *kind {
            NodeKind::Guard(table) => {
                self.guard_after(node, table, r, now)?;
                // The guard now holds the node's result; the node is reset as its parent
                // in BehaviorTree.CPP resets a finished child: its status only.
            }
            NodeKind::Precondition { .. } => {
                if matches!(r, Status::Success | Status::Failure) {
                    self.set_memory(node, 0, 0);
                }
            }
            NodeKind::Gate(_) | NodeKind::Check { .. } => {}
            _ => return Err(oob(node)),
        }
        Ok(self.finish_decorator(top, r))
    }

    /// A node of this family is halted or reset: a `Guard` that was Running runs its
    /// `_onHalted`; a `Precondition` keeps its memory (whether it let its child go), as
    /// BehaviorTree.CPP's does. Whether it keeps its memory.
    pub(super) fn guards_halted(&mut self, i: usize, kind: &NodeKind) -> bool {
        match *kind {
            NodeKind::Guard(table) => {
                self.guard_halted(i, table);
                false
            }
            NodeKind::Precondition { .. } => true,
            _ => false,
        }
    }

    /// The status of a node of this family that returned Skipped: a `Guard` takes the
    /// status its child kept (BehaviorTree.CPP's node keeps its own when it skips), and
    /// a `Precondition` keeps its own (BehaviorTree.CPP's does not mark itself Running).
    pub(super) fn guards_skipped_status(&self, i: usize, kind: &NodeKind) -> NodeStatus {
        match kind {
            NodeKind::Guard(_) => self.status(i + 1),
            _ => self.status(i),
        }
    }

    /// Runs hook `h` of the guard at `idx`, if it has one.
    fn run_hook(&mut self, idx: usize, table: Code, h: Hook, now: u32) -> Result<(), TickError> {
        if let Some(program) = hook(table.words(self.values), h) {
            self.run_script(idx, program, now)?;
        }
        Ok(())
    }

    /// A guard's checks before its node starts: `_failureIf`, `_successIf`, `_skipIf`,
    /// then `_while`, as BehaviorTree.CPP asks them; the status they decide, if any.
    fn guard_before(&mut self, idx: usize, table: Code, now: u32) -> Result<Option<Status>, TickError> {
        let t = table.words(self.values);
        for (h, then) in
            [(Hook::FailureIf, Status::Failure), (Hook::SuccessIf, Status::Success), (Hook::SkipIf, Status::Skipped)]
        {
            if let Some(p) = hook(t, h)
                && self.holds(idx, p, now)?
            {
                return Ok(Some(then));
            }
        }
        match hook(t, Hook::While) {
            Some(p) if !self.holds(idx, p, now)? => Ok(Some(Status::Skipped)),
            _ => Ok(None),
        }
    }

    /// A guard's hooks after its node returned `r`: `_onSuccess` or `_onFailure`, then
    /// `_post`, when it finished.
    fn guard_after(&mut self, idx: usize, table: Code, r: Status, now: u32) -> Result<(), TickError> {
        match r {
            Status::Success => self.run_hook(idx, table, Hook::OnSuccess, now)?,
            Status::Failure => self.run_hook(idx, table, Hook::OnFailure, now)?,
            _ => return Ok(()),
        }
        self.run_hook(idx, table, Hook::Post, now)
    }

    /// The guard at `idx`, Running, is halted: its `_onHalted`, after its subtree (its
    /// script is told `now` 0: halts have no clock). A fault is kept for the tick to
    /// return.
    #[cold]
    #[inline(never)]
    fn guard_halted(&mut self, idx: usize, table: Code) {
        if self.status(idx) != NodeStatus::Running {
            return;
        }
        if let Err(e) = self.run_hook(idx, table, Hook::OnHalted, 0)
            && self.side.fault.is_none()
        {
            self.side.fault = Some(e);
        }
    }

    /// The tick's result, or the fault of a guard's `_onHalted` that failed while the
    /// tick halted its node (which it clears).
    #[cold]
    #[inline(never)]
    pub(super) fn guard_fault(&mut self, result: Result<Status, TickError>) -> Result<Status, TickError> {
        match self.side.fault.take() {
            Some(f) if result.is_ok() => Err(f),
            _ => result,
        }
    }
}
