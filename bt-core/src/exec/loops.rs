//! BehaviorTree.CPP's loops (`LoopInt`, `LoopBool`, `LoopDouble`, `LoopString`, and the
//! `LoopNode<T>` a program registers) as one `Loop` kind (rule 12): while its child is
//! not Running, it takes the next element of its queue into its `value` slot and ticks
//! the child.
//!
//! | kind | state | frame, side entry |
//! |---|---|---|
//! | `Loop` | `aux`: elements taken from a literal queue, `ext`: 1 while its child runs | — |

use super::btcpp::{Ascending, Entering};
use super::frame::{Ascent, Entered};
use super::oob;
use super::run::Run;
use crate::behavior::{BehaviorSet, Context, Observer, TickError};
use crate::node::{NodeId, NodeKind};
use crate::script::{Queue, ScriptFault, element, queue};
use crate::status::{NodeStatus, Status};

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    pub(super) fn enter_loop(&mut self, e: Entering<'_>) -> Result<Entered, TickError> {
        let Entering { kind, st, frame, parent_mirrors, now, .. } = e;
        let idx = usize::from(frame.node);
        let first = idx + 1;
        let NodeKind::Loop { table, if_empty } = *kind else {
            return Err(oob(idx));
        };
        // BehaviorTree.CPP's loop starts over from Idle (or finished, under a parent that
        // resets it) and pops only while its child is not Running.
        let fresh = Self::fresh(st, parent_mirrors);
        if !fresh && st.status == NodeStatus::Running && st.ext == 1 {
            return Ok(Entered::Child(first));
        }
        self.forget_result(idx, st, fresh);
        let taken = if fresh { 0 } else { st.aux };
        let fault = |fault| TickError::Script { node: idx as NodeId, fault };
        let popped = match queue(table.words(self.values)) {
            Some(Queue::Key { queue, value }) => {
                let ctx = Context { node: idx as NodeId, now, starting: fresh, values: self.values };
                self.behaviors.pop(queue, value, ctx).map_err(fault)?
            }
            Some(Queue::Literal(literal)) => match element(literal, taken) {
                Some(program) => {
                    self.run_script(idx, program, now)?;
                    true
                }
                None => false,
            },
            None => return Err(fault(ScriptFault::Malformed { at: 0 })),
        };
        if popped {
            self.set_memory(idx, taken.saturating_add(1), 0);
            Ok(Entered::Child(first))
        } else {
            self.set_memory(idx, taken, 0);
            Ok(Entered::Decided(if_empty))
        }
    }

    pub(super) fn ascend_loop(&mut self, a: Ascending<'_>) -> Ascent {
        let Ascending { top, returned, .. } = a;
        let node = usize::from(top.node);
        let first = node + 1;
        let taken = self.state.get(node).map_or(0, |s| s.aux);
        Ascent::Return(match returned.r {
            // The next element on the next tick.
            Status::Success => {
                self.halt_child(first);
                self.set_memory(node, taken, 0);
                Status::Running
            }
            Status::Failure => {
                self.halt_child(first);
                self.set_memory(node, taken, 0);
                Status::Failure
            }
            Status::Running => {
                self.set_memory(node, taken, 1);
                Status::Running
            }
            // Not finished, not Running: the next element on the next tick.
            Status::Skipped => {
                self.set_memory(node, taken, 0);
                Status::Running
            }
        })
    }
}
