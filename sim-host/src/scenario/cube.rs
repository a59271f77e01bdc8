//! The cube-and-sphere scenario of seed 000 (Fig. 1, Examples 1-2) in a symbolic and a
//! physics world, with the same external agents.
//!
//! The story (scripted agents, reacting to what the robot does):
//! 1. as the robot first carries the cube towards the goal, the sphere rolls into its
//!    path: `path-free(goal)` fails and the tree is expanded, the conflict resolved by
//!    IncreasePriority into the arrangement of Fig. 4 (Example 2);
//! 2. once the path is cleared and the robot heads back for the cube it dropped, an
//!    agent puts the cube into its gripper: the tree skips the pick (Problem 1, help);
//! 3. as it carries the cube to the goal, an agent takes it from the gripper: the tree
//!    fetches it again (Problem 1, undo);
//! 4. the sphere rolls into the path once more and, three ticks later, away again: the
//!    tree turns to the sphere and back without clearing it.
//!
//! None of 2-4 expands the tree. With a seed, agents act at random instead.
//!
//! In the symbolic world a robot that moves somewhere is no longer near anywhere else
//! (the domain's STRIPS effects cannot say so; the world does).

use std::sync::Arc;

use planner::ground::Grounding;
use planner::state::State;
use planner::strips::StripsWorld;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::driver::Live;
use crate::physics::mobile::{Agent, MobileWorld};

/// Chance per tick that a random agent acts (with `--seed`).
pub const RANDOM_RATE: f32 = 0.04;

/// Who acts on the world: the story above, or random agents from a seed.
#[derive(Debug)]
pub enum Agents {
    /// The scripted story.
    Story(Story),
    /// Random agents.
    Random(Box<ChaCha8Rng>),
}

impl Agents {
    /// The scripted story; `patience` is how many ticks an agent lets the robot carry
    /// the cube before the next act (a symbolic move-to takes one tick, a physical one
    /// many).
    #[must_use]
    pub fn story(patience: u32) -> Self {
        Self::Story(Story { patience, ..Story::default() })
    }

    /// Random agents from `seed`.
    #[must_use]
    pub fn random(seed: u64) -> Self {
        Self::Random(Box::new(ChaCha8Rng::seed_from_u64(seed)))
    }

    /// The agent act due now, given the action the tree left running and whether the
    /// robot holds the cube; `act` performs it in the world and says whether it made
    /// sense there (the story waits for one that does).
    fn step(&mut self, running: Option<&str>, holding_cube: bool, act: impl FnOnce(Agent) -> bool) {
        match self {
            Self::Story(s) => {
                s.since += 1;
                if let Some(agent) = s.due(running, holding_cube)
                    && act(agent)
                {
                    s.step += 1;
                    s.since = 0;
                }
            }
            Self::Random(rng) => {
                if rng.random::<f32>() < RANDOM_RATE
                    && let Some(&agent) = Agent::ALL.get(rng.random_range(0..Agent::ALL.len()))
                {
                    let _ = act(agent);
                }
            }
        }
    }
}

/// Progress through the scripted story.
#[derive(Debug, Default)]
pub struct Story {
    step: usize,
    since: u32,
    patience: u32,
}

impl Story {
    fn due(&self, running: Option<&str>, holding: bool) -> Option<Agent> {
        let to_goal = running == Some("move-to(goal)");
        Some(match self.step {
            0 if to_goal && holding => Agent::BlockPath,
            1 if running == Some("move-to(cube)") => Agent::HandCube,
            2 if to_goal && holding && self.since >= self.patience => Agent::TakeCube,
            3 if to_goal && holding && self.since >= self.patience => Agent::BlockPath,
            4 if self.since >= 2 => Agent::UnblockPath,
            _ => return None,
        })
    }

    /// Whether the whole story happened.
    #[must_use]
    pub fn finished(&self) -> bool {
        self.step >= 5
    }
}

/// The symbolic cube world: the planner's STRIPS semantics of the cube-sphere domain,
/// with the agents acting on its atoms.
#[derive(Debug)]
pub struct SymbolicCube {
    world: StripsWorld,
    /// The ground move-to actions with the location each reaches, and how often each
    /// had completed when last looked at.
    moves: Vec<(planner::ground::ActionId, String, u32)>,
    agents: Agents,
    events: Vec<String>,
    /// Events in the order they happened, for tests.
    pub acted: Vec<Agent>,
}

impl SymbolicCube {
    /// The world in the problem's initial state.
    #[must_use]
    pub fn new(g: Arc<Grounding>, agents: Agents) -> Self {
        let moves = (0..g.actions().len())
            .filter_map(|i| {
                let id = planner::ground::ActionId::try_from(i).ok()?;
                let name = g.action_name(id);
                let to = name.strip_prefix("move-to(")?.strip_suffix(')')?.to_string();
                Some((id, to, 0))
            })
            .collect();
        Self { world: StripsWorld::new(g), moves, agents, events: Vec::new(), acted: Vec::new() }
    }

    /// The STRIPS world.
    #[must_use]
    pub fn world(&self) -> &StripsWorld {
        &self.world
    }

    fn act(&mut self, agent: Agent) -> bool {
        let w = &mut self.world;
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
            self.events.push(describe(agent).into());
            self.acted.push(agent);
        }
        ok
    }
}

super::forward_behaviors!(SymbolicCube);

impl SymbolicCube {
    /// The one rule of motion STRIPS cannot state without quantified effects: a robot
    /// that moved to `l` is no longer near anywhere else.
    fn leave_other_places(&mut self) {
        let mut arrived = None;
        for (id, to, seen) in &mut self.moves {
            let done = self.world.completions(*id);
            if done > *seen {
                *seen = done;
                arrived = Some(to.clone());
            }
        }
        if let Some(here) = arrived {
            for (_, to, _) in &self.moves {
                if *to != here {
                    self.world.set_named("near", &[to.as_str()], false);
                }
            }
        }
    }
}

impl Live for SymbolicCube {
    fn advance(&mut self, _tick: u32, running: Option<&str>) {
        self.leave_other_places();
        let holding = self.world.holds_named("holding", &["cube"]);
        let mut agents = std::mem::replace(&mut self.agents, Agents::story(0));
        agents.step(running, holding, |agent| self.act(agent));
        self.agents = agents;
    }

    fn drain_events(&mut self) -> Vec<String> {
        std::mem::take(&mut self.events)
    }

    fn belief(&mut self, _g: &Grounding) -> State {
        self.world.state().clone()
    }
}

/// The physics cube world (rapier3d, [`MobileWorld`]) with the same agents.
#[derive(Debug)]
pub struct PhysicsCube {
    world: MobileWorld,
    agents: Agents,
    seen: usize,
    /// Events in the order they happened, for tests.
    pub acted: Vec<Agent>,
}

impl PhysicsCube {
    /// Example 1's start.
    #[must_use]
    pub fn new(agents: Agents) -> Self {
        Self { world: MobileWorld::new(), agents, seen: 0, acted: Vec::new() }
    }

    /// The physics world.
    #[must_use]
    pub fn world(&self) -> &MobileWorld {
        &self.world
    }
}

super::forward_behaviors!(PhysicsCube);

impl Live for PhysicsCube {
    fn advance(&mut self, _tick: u32, running: Option<&str>) {
        let holding = self.world.held() == Some(crate::physics::mobile::CUBE);
        let (world, acted) = (&mut self.world, &mut self.acted);
        self.agents.step(running, holding, |agent| {
            let ok = world.apply(agent);
            if ok {
                acted.push(agent);
            }
            ok
        });
        self.world.step();
    }

    fn drain_events(&mut self) -> Vec<String> {
        let events = self.world.events();
        let new = events.get(self.seen..).unwrap_or(&[]).iter().map(|e| e.text.clone()).collect();
        self.seen = events.len();
        new
    }

    fn points(&self) -> super::driver::Points {
        let mut p = vec![("robot", self.world.base())];
        for (name, item) in [("cube", crate::physics::mobile::CUBE), ("sphere", crate::physics::mobile::SPHERE)] {
            if let Some(at) = self.world.item(item) {
                p.push((name, [at[0], at[1]]));
            }
        }
        p
    }
}

/// An agent's act in words (the physics world says the same).
fn describe(agent: Agent) -> &'static str {
    match agent {
        Agent::TakeCube => "an agent takes the cube from the gripper",
        Agent::BlockPath => "an agent rolls the sphere into the path to the goal",
        Agent::UnblockPath => "an agent rolls the sphere out of the way",
        Agent::HandCube => "an agent puts the cube into the gripper",
        Agent::CubeToGoal => "an agent puts the cube on the goal",
    }
}
