//! BehaviorTree.CPP's and Nav2's sequences: `SequenceStar`, `SequenceStarV3`,
//! `PipelineSequence`, `RoundRobin`.
//!
//! | kind | state | frame, side entry |
//! |---|---|---|
//! | `SequenceStar` | `aux`: the child to resume at (0: the first); kept through halts | `a`: the child ticked was Idle |
//! | `SequenceStarV3` | `aux`: as `SequenceStar`'s; kept unless halted Running | — |
//! | `PipelineSequence` | `aux`: the furthest child that ran (0: the first) | `ok` that child, `skipped`, `children` |
//! | `RoundRobin` | `aux`: the next child (0-based), `ext`: failures; kept unless halted Running | `ok` next, `failed`, `skipped`, `children` |

use super::btcpp::{Ascending, Entering};
use super::frame::{Ascent, Entered, Extra, Returned};
use super::oob;
use super::run::Run;
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::NodeKind;
use crate::status::{NodeStatus, Status};

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    pub(super) fn enter_sequences(&mut self, e: Entering<'_>) -> Result<Entered, TickError> {
        let Entering { kind, st, frame, x, .. } = e;
        let idx = usize::from(frame.node);
        let end = usize::from(frame.end);
        let first = idx + 1;
        let child = |aux: u16| if aux == 0 { first } else { usize::from(aux) };
        Ok(match kind {
            NodeKind::SequenceStar | NodeKind::SequenceStarV3 => {
                let c = child(st.aux);
                frame.a = u16::from(self.status(c) == NodeStatus::Idle);
                Entered::Child(c)
            }
            NodeKind::PipelineSequence => {
                let (children, _) = self.children_of(idx, end, 0)?;
                *x = Extra {
                    ok: if frame.running { child(st.aux) as u16 } else { first as u16 },
                    children,
                    ..Extra::default()
                };
                Entered::Child(first)
            }
            NodeKind::RoundRobin => {
                let (children, c) = self.children_of(idx, end, st.aux)?;
                *x = Extra { ok: st.aux, failed: u16::from(st.ext), children, ..Extra::default() };
                match c {
                    Some(c) if x.failed < children => Entered::Child(c),
                    _ => {
                        self.reset_children(idx, end)?;
                        self.set_memory(idx, 0, 0);
                        Entered::Decided(Status::Failure)
                    }
                }
            }
            _ => return Err(oob(idx)),
        })
    }

    pub(super) fn ascend_sequences(&mut self, a: Ascending<'_>) -> Result<Ascent, TickError> {
        let Ascending { kind, top, x, returned, .. } = a;
        let Returned { node: c, end: child_end, r } = returned;
        let node = usize::from(top.node);
        let end = usize::from(top.end);
        let more = child_end < end;
        let done = |v| Ok(Ascent::Return(v));
        match kind {
            NodeKind::SequenceStar | NodeKind::SequenceStarV3 => match r {
                // Version 4's wake-up; version 3 goes on to the next child.
                Status::Success if more && top.a == 1 && *kind == NodeKind::SequenceStar => {
                    // BehaviorTree.CPP's wake-up: return, ask to be ticked again.
                    self.set_memory(node, child_end as u16, 0);
                    self.side.woken = true;
                    done(Status::Running)
                }
                Status::Success | Status::Skipped if more => {
                    top.a = u16::from(self.status(child_end) == NodeStatus::Idle);
                    Ok(Ascent::Tick(child_end))
                }
                Status::Success | Status::Skipped => {
                    let all_skipped = !self.any_child(node, end, NodeStatus::Success)? && r == Status::Skipped;
                    self.reset_children(node, end)?;
                    self.set_memory(node, 0, 0);
                    done(if all_skipped { Status::Skipped } else { Status::Success })
                }
                Status::Running => {
                    self.set_memory(node, c as u16, 0);
                    done(Status::Running)
                }
                Status::Failure => {
                    // Keeps its place: the failed child is where it resumes.
                    let mut k = c;
                    while k < end {
                        let after = self.end_of(k)?;
                        self.halt_child(k);
                        k = after;
                    }
                    self.set_memory(node, c as u16, 0);
                    done(Status::Failure)
                }
            },
            NodeKind::PipelineSequence => {
                match r {
                    Status::Failure => {
                        self.reset_children(node, end)?;
                        self.set_memory(node, 0, 0);
                        return done(Status::Failure);
                    }
                    Status::Skipped => x.skipped = x.skipped.saturating_add(1),
                    Status::Running if c >= usize::from(x.ok) => {
                        self.set_memory(node, c as u16, 0);
                        return done(Status::Running);
                    }
                    Status::Success | Status::Running => {}
                }
                if more {
                    return Ok(Ascent::Tick(child_end));
                }
                self.reset_children(node, end)?;
                self.set_memory(node, 0, 0);
                done(if x.skipped == x.children { Status::Skipped } else { Status::Success })
            }
            NodeKind::RoundRobin => {
                if r != Status::Running {
                    x.ok = if x.ok.saturating_add(1) >= x.children { 0 } else { x.ok + 1 };
                }
                match r {
                    Status::Success => {
                        self.reset_children(node, end)?;
                        self.set_memory(node, x.ok, 0);
                        return done(Status::Success);
                    }
                    Status::Failure => x.failed = x.failed.saturating_add(1),
                    Status::Skipped => x.skipped = x.skipped.saturating_add(1),
                    Status::Running => {
                        self.set_memory(node, x.ok, x.failed as u8);
                        return done(Status::Running);
                    }
                }
                if x.failed.saturating_add(x.skipped) < x.children {
                    let (_, next) = self.children_of(node, end, x.ok)?;
                    return Ok(Ascent::Tick(next.ok_or(oob(node))?));
                }
                self.reset_children(node, end)?;
                self.set_memory(node, 0, 0);
                done(if x.skipped == x.children { Status::Skipped } else { Status::Failure })
            }
            _ => Err(oob(node)),
        }
    }

    /// Whether a node of this family keeps its memory when reset: a `SequenceStar`
    /// always, a `SequenceStarV3` and a `RoundRobin` unless it was Running (halted).
    pub(super) fn sequences_keep(kind: &NodeKind, running: bool) -> bool {
        match kind {
            NodeKind::SequenceStar => true,
            NodeKind::SequenceStarV3 | NodeKind::RoundRobin => !running,
            _ => false,
        }
    }
}
