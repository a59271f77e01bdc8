//! How BehaviorTree.CPP 3.8's nodes that 4.10 changed tick (`SequenceStar`, `Parallel`,
//! `Repeat`, `RetryUntilSuccessful`, `BlackboardCheck*`), a count read from the
//! blackboard, and the plugin decorators the run asked (bt-core's `Gate`): what
//! [`Replay`] runs for them.

use super::status::{FAILURE, IDLE, RUNNING, SUCCESS};
use super::{Leaves, Replay};
use crate::btlog::tree::Kind;

impl Replay<'_> {
    pub(super) fn tick_v3(&mut self, i: usize, leaves: &mut dyn Leaves) -> u8 {
        let node = &self.tree.nodes[i];
        let n = node.children.len();
        match node.kind {
            // 3.8's SequenceStar: no wake-up; a halt sends it back to its first child
            // (`halt_only`), a Failure keeps its place.
            Kind::SequenceStarV3 => {
                self.set_status(i, RUNNING);
                while self.rt[i].idx < n {
                    let k = self.rt[i].idx;
                    match self.execute(self.child(i, k), leaves) {
                        RUNNING => return RUNNING,
                        FAILURE => {
                            for j in k..n {
                                self.halt_child(i, j, leaves);
                            }
                            return FAILURE;
                        }
                        _ => self.rt[i].idx += 1,
                    }
                }
                self.reset_children(i, leaves);
                self.rt[i].idx = 0;
                SUCCESS
            }
            // 3.8's Parallel: counts anew each tick, in child order, finished children
            // where they stand.
            Kind::ParallelV3 { success, failure } => {
                let threshold = |t: i32| if t < 0 { (n as i32 + t + 1).max(0) } else { t };
                let (need, fail) = (threshold(success), threshold(failure));
                self.set_status(i, RUNNING);
                let (mut ok, mut failed) = (0, 0);
                for k in 0..n {
                    let c = self.child(i, k);
                    let s = if self.rt[i].done[k] { self.rt[c].status } else { self.execute(c, leaves) };
                    match s {
                        SUCCESS => ok += 1,
                        FAILURE => failed += 1,
                        _ => continue,
                    }
                    self.rt[i].done[k] = true;
                    if ok == need || failed > n as i32 - need || failed == fail {
                        self.rt[i].done.iter_mut().for_each(|d| *d = false);
                        self.reset_children(i, leaves);
                        return if ok == need { SUCCESS } else { FAILURE };
                    }
                }
                RUNNING
            }
            Kind::Cycles { count: None, .. } => {
                self.refuse(i, "reads its count from the blackboard, which a run's leaf results do not give");
                FAILURE
            }
            // 3.8's Repeat and RetryUntilSuccessful: every cycle within the tick.
            Kind::Cycles { count: Some(cycles), retry, .. } => {
                let (again, stop) = if retry { (FAILURE, SUCCESS) } else { (SUCCESS, FAILURE) };
                self.set_status(i, RUNNING);
                while self.rt[i].count < cycles || cycles == -1 {
                    let s = self.execute(self.child(i, 0), leaves);
                    if s == RUNNING {
                        return RUNNING;
                    }
                    self.halt_child(i, 0, leaves);
                    if s == again {
                        self.rt[i].count += 1;
                    } else {
                        self.rt[i].count = 0;
                        return stop;
                    }
                }
                self.rt[i].count = 0;
                again
            }
            // Asks its comparison (as a leaf) on every tick; a mismatch halts a Running
            // child.
            Kind::Check(otherwise) => {
                self.set_status(i, RUNNING);
                if node.core.is_some_and(|c| leaves.tick(c) == SUCCESS) {
                    return self.execute(self.child(i, 0), leaves);
                }
                let c = self.child(i, 0);
                if self.rt[c].status == RUNNING {
                    self.halt_child(i, 0, leaves);
                }
                otherwise
            }
            // A plugin decorator: its answer is the run's (asked as a leaf's); a child
            // that runs is ticked whatever it says, else Success lets the child go.
            Kind::Gate => {
                self.set_status(i, RUNNING);
                let answer = node.core.map_or(FAILURE, |c| leaves.tick(c));
                let c = self.child(i, 0);
                if self.rt[c].status == RUNNING || answer == SUCCESS {
                    return self.execute(c, leaves);
                }
                answer
            }
            _ => IDLE,
        }
    }
}
