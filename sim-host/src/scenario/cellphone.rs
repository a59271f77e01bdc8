//! The cellphone assembly of Colledanchise et al. 2019 (Section VI) in the symbolic world: the planner's
//! STRIPS semantics of `planner/domains/cellphone` ([`StripsScene`]), with two
//! disturbances ([`Disturbances`]).
//!
//! - While the right arm mounts the board, the board slips out of its gripper back
//!   onto the table: the tree picks it again (Problem 1, undo).
//! - While the right arm reaches for the camera, a co-worker mounts the camera on the
//!   board: the tree skips it (Problem 1, help).

use worlds::agent::TreeState;

use super::agents::ActionNames;
use super::strips::StripsScene;

/// The slip and the co-worker's help, each once, as the tree's running action calls
/// for them.
#[derive(Debug)]
pub struct Disturbances {
    slipped: bool,
    helped: bool,
    names: ActionNames,
}

impl Disturbances {
    /// Neither has happened; `names` names the tree's actions.
    #[must_use]
    pub fn new(names: ActionNames) -> Self {
        Self { slipped: false, helped: false, names }
    }
}

impl worlds::Agent<StripsScene> for Disturbances {
    fn act(&mut self, _: u32, phone: &mut StripsScene, tree: &TreeState<'_>) {
        let running = self.names.running(tree);
        let running = running.as_deref();
        let StripsScene { strips: w, events } = phone;
        if !self.slipped && running == Some("mount(right, board, chassis)") {
            self.slipped = true;
            w.set_named("holding", &["right", "board"], false);
            w.set_named("by-back", &["board"], false);
            w.set_named("free", &["right"], true);
            w.set_named("on-table", &["board"], true);
            events.push("the board slips out of the right gripper back onto the table".into());
        }
        if !self.helped && running.is_some_and(|r| r.ends_with(", camera)") && !r.starts_with("mount")) {
            self.helped = true;
            w.set_named("on-table", &["camera"], false);
            w.set_named("mounted", &["camera"], true);
            events.push("a co-worker mounts the camera on the board".into());
        }
    }
}
