//! The kinds that read the clock (rule 10): `TimeLimit` (BehaviorTree.CPP's `Timeout`),
//! `Delay`, Nav2's `RateController`, and the `Sleep` leaf; and what their timers did
//! between two ticks.
//!
//! | kind | state | frame, side entry |
//! |---|---|---|
//! | `TimeLimit`, `Delay`, `RateController`, `Sleep` | `aux` + `ext`: start time (24 bits of `now`) | — |

use super::btcpp::{Ascending, Entering};
use super::frame::{Ascent, Entered};
use super::run::Run;
use super::{NodeState, oob};
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::{NodeKind, Span};
use crate::status::{NodeStatus, Status};

/// Start times are kept in 24 bits.
const TIME_MASK: u32 = Span::MAX;

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    fn start_time(st: NodeState) -> u32 {
        u32::from(st.aux) | u32::from(st.ext) << 16
    }

    fn set_start(&mut self, i: usize, now: u32) {
        self.set_memory(i, now as u16, (now >> 16) as u8);
    }

    fn elapsed(st: NodeState, now: u32) -> u32 {
        now.wrapping_sub(Self::start_time(st)) & TIME_MASK
    }

    /// Before a tick of a tree with clocked kinds: what BehaviorTree.CPP's timers did
    /// since the last tick. A `TimeLimit` whose span has passed while its child runs
    /// halts the child now (the tick then finds it expired and fails it), and asks for a
    /// tick; a `Delay` whose span has passed asks for one, as does a Running `Sleep`
    /// whose span has passed. Pre-order.
    #[cold]
    #[inline(never)]
    pub(super) fn timers(&mut self, now: u32) {
        for i in 0..self.nodes.len() {
            let Some(&node) = self.nodes.get(i) else { return };
            let st = self.state.get(i).copied().unwrap_or_default();
            if st.status != NodeStatus::Running {
                continue;
            }
            let first = i + 1;
            match *node.kind() {
                NodeKind::TimeLimit(d)
                    if d.get() > 0
                        && Self::elapsed(st, now) >= d.get()
                        && self.status(first) == NodeStatus::Running =>
                {
                    self.reset_subtree(first);
                    self.side.woken = true;
                }
                NodeKind::Delay(d) if Self::elapsed(st, now) >= d.get() && self.status(first) == NodeStatus::Idle => {
                    self.side.woken = true;
                }
                NodeKind::Sleep(d) if Self::elapsed(st, now) >= d.get() => self.side.woken = true,
                _ => {}
            }
        }
    }

    pub(super) fn enter_timers(&mut self, e: Entering<'_>) -> Result<Entered, TickError> {
        let Entering { kind, st, frame, parent_mirrors, now, .. } = e;
        let idx = usize::from(frame.node);
        let first = idx + 1;
        let running = frame.running;
        Ok(match *kind {
            NodeKind::TimeLimit(d) => {
                if !running {
                    self.set_start(idx, now);
                    Entered::Child(first)
                } else if d.get() > 0 && Self::elapsed(st, now) >= d.get() {
                    // Expired: its child was halted before the tick (see `timers`).
                    self.halt_child(first);
                    Entered::Decided(Status::Failure)
                } else {
                    Entered::Child(first)
                }
            }
            NodeKind::Delay(d) => {
                let elapsed = if running { Self::elapsed(st, now) } else { 0 };
                if !running {
                    self.set_start(idx, now);
                }
                if elapsed >= d.get() || self.status(first) == NodeStatus::Running {
                    Entered::Child(first)
                } else {
                    Entered::Decided(Status::Running)
                }
            }
            NodeKind::RateController(d) => {
                let fresh = Self::fresh(st, parent_mirrors);
                if fresh {
                    self.set_start(idx, now);
                }
                if fresh || self.status(first) == NodeStatus::Running || Self::elapsed(st, now) >= d.get() {
                    Entered::Child(first)
                } else {
                    Entered::Decided(Status::Running)
                }
            }
            NodeKind::Sleep(d) => {
                if !running {
                    if d.get() == 0 {
                        return Ok(Entered::Decided(Status::Success));
                    }
                    self.set_start(idx, now);
                    Entered::Decided(Status::Running)
                } else if Self::elapsed(st, now) >= d.get() {
                    Entered::Decided(Status::Success)
                } else {
                    Entered::Decided(Status::Running)
                }
            }
            _ => return Err(oob(idx)),
        })
    }

    pub(super) fn ascend_timers(&mut self, a: Ascending<'_>) -> Ascent {
        let Ascending { kind, top, returned, now, .. } = a;
        if matches!(kind, NodeKind::RateController(_)) && returned.r == Status::Success {
            self.set_start(usize::from(top.node), now);
        }
        self.finish_decorator(top, returned.r)
    }
}
