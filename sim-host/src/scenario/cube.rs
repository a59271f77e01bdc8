//! The cube-and-sphere scenario of Colledanchise et al. 2019 (Fig. 1, Examples 1-2) in a symbolic and a
//! physics world, with the same external agents ([`super::agents`]).
//!
//! The story ([`super::agents::Story`]): as the robot first carries the cube towards
//! the goal, the sphere rolls into its path: `path-free(goal)` fails and the tree is
//! expanded, the conflict resolved by IncreasePriority into the arrangement of Fig. 4
//! (Example 2); then an agent helps (puts the cube into the gripper: the tree skips the
//! pick), undoes (takes it away: the tree fetches it again), and the sphere rolls into
//! the path and away again. None of these later acts expands the tree. With a seed,
//! agents act at random instead.
//!
//! The physics world is [`MobileWorld`] itself. In the symbolic world a robot that
//! moves somewhere is no longer near anywhere else (the domain's STRIPS effects cannot
//! say so; the world does, when it steps).

use std::sync::Arc;

use planner::Belief;
use planner::ground::Grounding;
use planner::state::State;
use planner::strips::StripsWorld;

use super::agents::Acts;
use super::driver::{Points, Scene, belief_from_conditions};
use super::strips::StripsScene;
use crate::physics::mobile::{Agent, CUBE, MobileWorld, SPHERE};

/// Chance per tick that a random agent acts (with `--seed`).
pub const RANDOM_RATE: f32 = 0.04;

/// The symbolic cube world: the planner's STRIPS semantics of the cube-sphere domain,
/// with the agents acting on its atoms.
#[derive(Debug)]
pub struct SymbolicCube {
    world: StripsScene,
    /// The ground move-to actions with the location each reaches, and how often each
    /// had completed when last looked at.
    moves: Vec<(planner::ground::ActionId, String, u32)>,
}

impl SymbolicCube {
    /// The world in the problem's initial state.
    #[must_use]
    pub fn new(g: Arc<Grounding>) -> Self {
        let moves = (0..g.actions().len())
            .filter_map(|i| {
                let id = planner::ground::ActionId::try_from(i).ok()?;
                let name = g.action_name(id);
                let to = name.strip_prefix("move-to(")?.strip_suffix(')')?.to_string();
                Some((id, to, 0))
            })
            .collect();
        Self { world: StripsScene::new(g), moves }
    }

    /// The STRIPS world.
    #[must_use]
    pub fn world(&self) -> &StripsWorld {
        &self.world.strips
    }

    /// The one rule of motion STRIPS cannot state without quantified effects: a robot
    /// that moved to `l` is no longer near anywhere else.
    fn leave_other_places(&mut self) {
        let w = &mut self.world.strips;
        let mut arrived = None;
        for (id, to, seen) in &mut self.moves {
            let done = w.completions(*id);
            if done > *seen {
                *seen = done;
                arrived = Some(to.clone());
            }
        }
        if let Some(here) = arrived {
            for (_, to, _) in &self.moves {
                if *to != here {
                    w.set_named("near", &[to.as_str()], false);
                }
            }
        }
    }
}

super::forward_behaviors!(SymbolicCube);

impl worlds::World for SymbolicCube {
    fn reset(&mut self) {
        worlds::World::reset(&mut self.world);
        for m in &mut self.moves {
            m.2 = 0;
        }
    }

    fn step(&mut self) {
        self.leave_other_places();
    }
}

impl Acts for SymbolicCube {
    fn apply(&mut self, agent: Agent) -> bool {
        let w = &mut self.world.strips;
        let holding = w.holds_named("holding", &["cube"]);
        let ok = match agent {
            Agent::TakeCube if holding => {
                w.set_named("holding", &["cube"], false);
                w.set_named("hand-empty", &[], true);
                w.set_named("near", &["cube"], false);
                true
            }
            Agent::BlockPath => w.set_named("path-free", &["goal"], false),
            Agent::UnblockPath => w.set_named("path-free", &["goal"], true),
            Agent::HandCube if w.holds_named("hand-empty", &[]) => {
                w.set_named("holding", &["cube"], true);
                w.set_named("hand-empty", &[], false);
                w.set_named("at", &["cube", "goal"], false)
            }
            Agent::CubeToGoal if !holding => w.set_named("at", &["cube", "goal"], true),
            _ => false,
        };
        if ok {
            self.world.events.push(agent.describe().into());
        }
        ok
    }

    fn holding_cube(&self) -> bool {
        self.world.strips.holds_named("holding", &["cube"])
    }
}

impl Scene for SymbolicCube {
    fn event(&self, i: usize) -> Option<&str> {
        self.world.event(i)
    }
}

impl Belief for SymbolicCube {
    fn belief(&mut self, g: &Grounding) -> State {
        self.world.belief(g)
    }
}

impl Scene for MobileWorld {
    fn event(&self, i: usize) -> Option<&str> {
        self.events().get(i).map(|e| e.text.as_str())
    }

    fn points(&self) -> Points {
        let mut p = vec![("robot", self.base())];
        for (name, item) in [("cube", CUBE), ("sphere", SPHERE)] {
            if let Some(at) = self.item(item) {
                p.push((name, [at[0], at[1]]));
            }
        }
        p
    }
}

/// The planner believes what the world's conditions say.
impl Belief for MobileWorld {
    fn belief(&mut self, g: &Grounding) -> State {
        belief_from_conditions(self, g)
    }
}
