//! BehaviorTree.CPP's `ManualSelector`, with the choice made by the behavior set
//! ([`BehaviorSet::select`], rule 13).
//!
//! | kind | state | frame, side entry |
//! |---|---|---|
//! | `ManualSelector` | `aux`: the last selection ([`remembered`]); kept for ever | `a`: 1 when it asked on this tick |

use super::btcpp::{Ascending, Entering};
use super::frame::{Ascent, Entered};
use super::oob;
use super::run::Run;
use crate::behavior::{BehaviorSet, Context, Observer, Selection, TickError};
use crate::node::{NodeId, NodeKind};
use crate::status::{NodeStatus, Status};

/// A `ManualSelector`'s last selection as its `aux` keeps it: 0 none, `1 + k` child
/// `k`, `0x101` to `0x103` Success, Failure, Running.
const fn selection_aux(s: Selection) -> u16 {
    match s {
        Selection::Child(k) => 1 + k as u16,
        Selection::Success => 0x101,
        Selection::Failure => 0x102,
        Selection::Running => 0x103,
    }
}

/// The selection [`selection_aux`] kept, if any.
const fn remembered(aux: u16) -> Option<Selection> {
    match aux {
        0 => None,
        0x101 => Some(Selection::Success),
        0x102 => Some(Selection::Failure),
        0x103 => Some(Selection::Running),
        1..=0x100 => Some(Selection::Child((aux - 1) as u8)),
        _ => None,
    }
}

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    pub(super) fn enter_manual_selector(&mut self, e: Entering<'_>) -> Result<Entered, TickError> {
        let Entering { kind, st, frame, parent_mirrors, now, .. } = e;
        let idx = usize::from(frame.node);
        let end = usize::from(frame.end);
        let first = idx + 1;
        let NodeKind::ManualSelector { repeat_last } = *kind else {
            return Err(oob(idx));
        };
        let fresh = Self::fresh(st, parent_mirrors);
        self.forget_result(idx, st, fresh);
        let (count, _) = self.children_of(idx, end, 0)?;
        // At most 255 children: validation refuses more.
        let children = u8::try_from(count).map_err(|_| oob(idx))?;
        let (selection, asked) = match remembered(st.aux) {
            Some(s) if repeat_last && children > 0 => (s, false),
            _ => {
                let ctx = Context { node: idx as NodeId, now, starting: fresh, values: self.values };
                let s = self
                    .behaviors
                    .select(children, ctx)
                    .map_err(|fault| TickError::Script { node: idx as NodeId, fault })?;
                (s, true)
            }
        };
        frame.a = u16::from(asked);
        let chosen = match selection {
            Selection::Child(k) => match self.children_of(idx, end, u16::from(k))? {
                (_, Some(c)) => Some(c),
                (_, None) => return Err(TickError::NoSuchChild { node: idx as NodeId, child: k, children }),
            },
            _ => None,
        };
        // BehaviorTree.CPP remembers what it was told only when it has children.
        if children > 0 {
            self.set_memory(idx, selection_aux(selection), 0);
        }
        // Halt before start: a child still Running that was not chosen is halted first
        // (BehaviorTree.CPP leaves it Running), and so is one under a node that finishes
        // now. Returning Running leaves it as it is.
        if selection != Selection::Running {
            let mut c = first;
            while c < end {
                let after = self.end_of(c)?;
                if Some(c) != chosen && self.status(c) == NodeStatus::Running {
                    self.reset_subtree(c);
                }
                c = after;
            }
        }
        Ok(match (chosen, selection) {
            (Some(c), _) => Entered::Child(c),
            (None, Selection::Success) => Entered::Decided(Status::Success),
            (None, Selection::Failure) => Entered::Decided(Status::Failure),
            (None, _) => Entered::Decided(Status::Running),
        })
    }

    pub(super) fn ascend_manual_selector(&mut self, a: Ascending<'_>) -> Ascent {
        let Ascending { top, returned, .. } = a;
        // BehaviorTree.CPP's node marks itself Running before it asks, so a child that
        // skips leaves it Running; when it repeats its last selection without asking, it
        // keeps its status (see `manual_selector_skipped_status`). Its children keep
        // what they returned, as BehaviorTree.CPP's do.
        if returned.r == Status::Skipped && top.a == 1 {
            self.set_status(usize::from(top.node), NodeStatus::Running);
        }
        Ascent::Return(returned.r)
    }

    /// A `ManualSelector` that returned Skipped keeps its status: one that asked has
    /// marked itself Running on the way up.
    pub(super) fn manual_selector_skipped_status(&self, i: usize) -> NodeStatus {
        self.status(i)
    }
}
