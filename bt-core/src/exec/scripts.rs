//! BehaviorTree.CPP's leaves other than `Sleep`: `Script` and `ScriptCondition`, which
//! finish in the tick they are reached, like conditions (rule 12), and `AlwaysSuccess`
//! and `AlwaysFailure`; and running a program through the behavior set, for them and
//! for the guards and loops.

use super::btcpp::Entering;
use super::frame::Entered;
use super::oob;
use super::run::Run;
use crate::behavior::{BehaviorSet, Context, Observer, TickError};
use crate::node::{NodeId, NodeKind};
use crate::script::{Value, truth};
use crate::status::Status;

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    pub(super) fn enter_scripts(&mut self, e: Entering<'_>) -> Result<Entered, TickError> {
        let Entering { kind, frame, now, .. } = e;
        let idx = usize::from(frame.node);
        Ok(Entered::Decided(match *kind {
            NodeKind::Script(code) => {
                self.run_script(idx, code.words(self.values), now)?;
                Status::Success
            }
            NodeKind::ScriptCondition(code) => {
                if self.holds(idx, code.words(self.values), now)? {
                    Status::Success
                } else {
                    Status::Failure
                }
            }
            NodeKind::AlwaysSuccess => Status::Success,
            NodeKind::AlwaysFailure => Status::Failure,
            _ => return Err(oob(idx)),
        }))
    }

    /// Runs a script of node `idx` through the behavior set; a fault ends the tick.
    pub(super) fn run_script(&mut self, idx: usize, program: &[u16], now: u32) -> Result<Value, TickError> {
        let ctx = Context { node: idx as NodeId, now, starting: true, values: self.values };
        self.behaviors.script(program, ctx).map_err(|fault| TickError::Script { node: idx as NodeId, fault })
    }

    /// Runs a script of node `idx` and says whether its result holds.
    pub(super) fn holds(&mut self, idx: usize, program: &[u16], now: u32) -> Result<bool, TickError> {
        let v = self.run_script(idx, program, now)?;
        truth(v).map_err(|fault| TickError::Script { node: idx as NodeId, fault })
    }
}
