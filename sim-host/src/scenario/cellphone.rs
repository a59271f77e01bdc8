//! The cellphone assembly of seed 000 (Section VI) in the symbolic world: the planner's
//! STRIPS semantics of `planner/domains/cellphone`, with two disturbances.
//!
//! - While the right arm mounts the board, the board slips out of its gripper back
//!   onto the table: the tree picks it again (Problem 1, undo).
//! - While the right arm reaches for the camera, a co-worker mounts the camera on the
//!   board: the tree skips it (Problem 1, help).

use std::sync::Arc;

use planner::ground::Grounding;
use planner::state::State;
use planner::strips::StripsWorld;

use super::driver::Live;

/// The cellphone world with its scripted disturbances.
#[derive(Debug)]
pub struct Cellphone {
    world: StripsWorld,
    slipped: bool,
    helped: bool,
    events: Vec<String>,
}

impl Cellphone {
    /// The problem's initial state.
    #[must_use]
    pub fn new(g: Arc<Grounding>) -> Self {
        Self { world: StripsWorld::new(g), slipped: false, helped: false, events: Vec::new() }
    }

    /// The STRIPS world.
    #[must_use]
    pub fn world(&self) -> &StripsWorld {
        &self.world
    }
}

super::forward_behaviors!(Cellphone);

impl Live for Cellphone {
    fn advance(&mut self, _tick: u32, running: Option<&str>) {
        let w = &mut self.world;
        if !self.slipped && running == Some("mount(right, board, chassis)") {
            self.slipped = true;
            w.set_named("holding", &["right", "board"], false);
            w.set_named("by-back", &["board"], false);
            w.set_named("free", &["right"], true);
            w.set_named("on-table", &["board"], true);
            self.events.push("the board slips out of the right gripper back onto the table".into());
        }
        if !self.helped && running.is_some_and(|r| r.ends_with(", camera)") && !r.starts_with("mount")) {
            self.helped = true;
            w.set_named("on-table", &["camera"], false);
            w.set_named("mounted", &["camera"], true);
            self.events.push("a co-worker mounts the camera on the board".into());
        }
    }

    fn drain_events(&mut self) -> Vec<String> {
        std::mem::take(&mut self.events)
    }

    fn belief(&mut self, _g: &Grounding) -> State {
        self.world.state().clone()
    }
}
