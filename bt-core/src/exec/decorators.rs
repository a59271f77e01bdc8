//! The papers' decorators: Inverter, ForceSuccess, ForceFailure, and Repeat, Retry and
//! Timeout, which count ticks and activations, never `now` (rule 7).

use super::NodeState;
use super::frame::{Entered, Extra, Frame, FrameKind, Returned};
use super::run::Run;
use crate::behavior::{BehaviorSet, Observer};
use crate::node::NodeKind;
use crate::status::Status;

impl<B: BehaviorSet, O: Observer, const DEPTH: usize, const FULL: bool> Run<'_, B, O, DEPTH, FULL> {
    /// Enters a decorator: its one child is ticked; a counting one resumes its count
    /// when it was Running.
    pub(super) fn enter_decorator(
        &mut self,
        kind: &NodeKind,
        st: NodeState,
        frame: &mut Frame,
        x: &mut Extra,
    ) -> Entered {
        match *kind {
            NodeKind::Repeat(n) | NodeKind::Retry(n) | NodeKind::Timeout(n) => {
                frame.kind = match kind {
                    NodeKind::Repeat(_) => FrameKind::Repeat,
                    NodeKind::Retry(_) => FrameKind::Retry,
                    _ => FrameKind::Timeout,
                };
                x.ok = n;
                frame.a = if frame.running { st.aux } else { 0 };
            }
            NodeKind::ForceSuccess => frame.kind = FrameKind::ForceSuccess,
            NodeKind::ForceFailure => frame.kind = FrameKind::ForceFailure,
            _ => frame.kind = FrameKind::Inverter,
        }
        Entered::Child(usize::from(frame.node) + 1)
    }

    /// The child of decorator frame `top` returned: what the decorator returns. Skipped
    /// goes through unchanged (rule 8).
    pub(super) fn ascend_decorator(&mut self, top: &Frame, x: &Extra, returned: Returned) -> Status {
        let Returned { node: c, r, .. } = returned;
        let node = usize::from(top.node);
        match top.kind {
            FrameKind::Inverter => match r {
                Status::Success => Status::Failure,
                Status::Failure => Status::Success,
                Status::Running | Status::Skipped => r,
            },
            FrameKind::ForceSuccess if r == Status::Failure => Status::Success,
            FrameKind::ForceFailure if r == Status::Success => Status::Failure,
            FrameKind::Repeat | FrameKind::Retry => {
                let again = if top.kind == FrameKind::Repeat { Status::Success } else { Status::Failure };
                if r == again {
                    let count = top.a.saturating_add(1);
                    if count < x.ok {
                        self.set_aux(node, count);
                        Status::Running
                    } else {
                        r
                    }
                } else {
                    if r == Status::Running {
                        self.set_aux(node, top.a);
                    }
                    r
                }
            }
            FrameKind::Timeout if r == Status::Running => {
                let count = top.a.saturating_add(1);
                if count >= x.ok {
                    self.reset_subtree(c);
                    Status::Failure
                } else {
                    self.set_aux(node, count);
                    Status::Running
                }
            }
            _ => r,
        }
    }
}
