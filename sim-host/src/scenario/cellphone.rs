//! The cellphone assembly of seed 000 (Section VI) in the symbolic world: the planner's
//! STRIPS semantics of `planner/domains/cellphone`, with two disturbances
//! ([`Disturbances`]).
//!
//! - While the right arm mounts the board, the board slips out of its gripper back
//!   onto the table: the tree picks it again (Problem 1, undo).
//! - While the right arm reaches for the camera, a co-worker mounts the camera on the
//!   board: the tree skips it (Problem 1, help).

use std::sync::Arc;

use bt_core::Catalog;
use planner::Belief;
use planner::ground::Grounding;
use planner::state::State;
use planner::strips::StripsWorld;
use worlds::agent::TreeState;

use super::driver::{Scene, leaf_name};

/// The cellphone world.
#[derive(Debug)]
pub struct Cellphone {
    world: StripsWorld,
    events: Vec<String>,
}

impl Cellphone {
    /// The problem's initial state.
    #[must_use]
    pub fn new(g: Arc<Grounding>) -> Self {
        Self { world: StripsWorld::new(g), events: Vec::new() }
    }

    /// The STRIPS world.
    #[must_use]
    pub fn world(&self) -> &StripsWorld {
        &self.world
    }
}

super::forward_behaviors!(Cellphone);

impl worlds::World for Cellphone {
    fn reset(&mut self) {
        self.world.reset();
        self.events.clear();
    }
}

impl Scene for Cellphone {
    fn event(&self, i: usize) -> Option<&str> {
        self.events.get(i).map(String::as_str)
    }
}

impl Belief for Cellphone {
    fn belief(&mut self, _: &Grounding) -> State {
        self.world.state().clone()
    }
}

/// The slip and the co-worker's help, each once, as the tree's running action calls
/// for them.
pub struct Disturbances {
    slipped: bool,
    helped: bool,
    /// Names the action the tree runs.
    catalog: Arc<dyn Catalog + Send + Sync>,
}

impl std::fmt::Debug for Disturbances {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Disturbances").field("slipped", &self.slipped).field("helped", &self.helped).finish()
    }
}

impl Disturbances {
    /// Neither has happened; `catalog` names the tree's actions.
    #[must_use]
    pub fn new(catalog: Arc<dyn Catalog + Send + Sync>) -> Self {
        Self { slipped: false, helped: false, catalog }
    }
}

impl worlds::Agent<Cellphone> for Disturbances {
    fn act(&mut self, _: u32, phone: &mut Cellphone, tree: &TreeState<'_>) {
        let running = tree.running_action().map(|(_, leaf)| leaf_name(self.catalog.as_ref(), leaf));
        let running = running.as_deref();
        let Cellphone { world: w, events } = phone;
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
