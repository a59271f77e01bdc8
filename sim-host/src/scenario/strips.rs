//! A scene over the planner's STRIPS world: its behaviors, and the events agents tell
//! into it. The cellphone is one as it is; the symbolic cube adds a rule of motion.

use std::sync::Arc;

use planner::Belief;
use planner::ground::Grounding;
use planner::state::State;
use planner::strips::StripsWorld;

use super::driver::Scene;

/// The STRIPS world of a scenario, with what happened in it in plain words.
#[derive(Debug)]
pub struct StripsScene {
    /// The world.
    pub strips: StripsWorld,
    /// The events so far.
    pub events: Vec<String>,
}

impl StripsScene {
    /// The problem's initial state, nothing happened.
    #[must_use]
    pub fn new(g: Arc<Grounding>) -> Self {
        Self { strips: StripsWorld::new(g), events: Vec::new() }
    }
}

impl bt_core::BehaviorSet for StripsScene {
    fn condition(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
        self.strips.condition(leaf, ctx)
    }

    fn action(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
        self.strips.action(leaf, ctx)
    }

    fn halt(&mut self, leaf: &bt_core::Leaf, node: bt_core::NodeId) {
        self.strips.halt(leaf, node);
    }
}

impl worlds::World for StripsScene {
    fn reset(&mut self) {
        self.strips.reset();
        self.events.clear();
    }
}

impl Scene for StripsScene {
    fn event(&self, i: usize) -> Option<&str> {
        self.events.get(i).map(String::as_str)
    }
}

/// The planner believes the STRIPS state.
impl Belief for StripsScene {
    fn belief(&mut self, g: &Grounding) -> State {
        self.strips.belief(g)
    }
}
