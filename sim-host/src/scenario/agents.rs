//! The external agents of the cube-and-sphere scenario (Colledanchise et al. 2019,
//! Fig. 1, Problem 1) as [`worlds::Agent`]s of any world they can act on ([`Acts`]: the
//! physics [`MobileWorld`] and the symbolic cube): at given ticks ([`ByTicks`]), at
//! random from a seed ([`Random`]), or as a story that reacts to what the robot does
//! ([`Story`]).

use std::sync::Arc;

use bt_core::Catalog;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use worlds::agent::TreeState;

use crate::physics::mobile::{Agent, CUBE, MobileWorld};

/// Names the action a tick left running, as a catalog renders it: what scripted agents
/// react to.
#[derive(Clone)]
pub struct ActionNames(pub Arc<dyn Catalog + Send + Sync>);

impl ActionNames {
    /// The action the tree runs, by name.
    #[must_use]
    pub fn running(&self, tree: &TreeState<'_>) -> Option<String> {
        tree.running_action().map(|(_, leaf)| super::driver::leaf_name(self.0.as_ref(), leaf))
    }
}

impl std::fmt::Debug for ActionNames {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ActionNames").finish_non_exhaustive()
    }
}

/// A world the cube scenario's agents act on.
pub trait Acts {
    /// Makes `agent` act now; whether the act made sense (then it is narrated).
    fn apply(&mut self, agent: Agent) -> bool;

    /// Whether the robot holds the cube.
    fn holding_cube(&self) -> bool;
}

impl Acts for MobileWorld {
    fn apply(&mut self, agent: Agent) -> bool {
        MobileWorld::apply(self, agent)
    }

    fn holding_cube(&self) -> bool {
        self.held() == Some(CUBE)
    }
}

/// Acts at given ticks: an act listed for tick `k` happens after the tree's `k`-th tick,
/// before the world's `k`-th step (the world's event carries `k`).
#[derive(Clone, Debug, Default)]
pub struct ByTicks {
    script: Vec<(u32, Agent)>,
}

impl ByTicks {
    /// Acts at the given ticks, in tick order.
    #[must_use]
    pub fn new(script: &[(u32, Agent)]) -> Self {
        let mut script = script.to_vec();
        script.sort_by_key(|&(t, _)| t);
        Self { script }
    }
}

impl<W: Acts> worlds::Agent<W> for ByTicks {
    fn act(&mut self, tick: u32, world: &mut W, _: &TreeState<'_>) {
        while let Some(&(t, agent)) = self.script.first() {
            if t > tick {
                break;
            }
            self.script.remove(0);
            let _ = world.apply(agent);
        }
    }
}

/// Acts at random: between ticks, with chance `rate`, one of the agent acts drawn
/// uniformly (it happens if it makes sense then), from a generator seeded with `seed`.
#[derive(Clone, Debug)]
pub struct Random {
    rng: ChaCha8Rng,
    rate: f32,
}

impl Random {
    /// Agents of seed `seed` acting with chance `rate` between ticks.
    #[must_use]
    pub fn new(seed: u64, rate: f32) -> Self {
        Self { rng: ChaCha8Rng::seed_from_u64(seed), rate }
    }
}

impl<W: Acts> worlds::Agent<W> for Random {
    fn act(&mut self, _: u32, world: &mut W, _: &TreeState<'_>) {
        if self.rng.random::<f32>() < self.rate
            && let Some(&agent) = Agent::ALL.get(self.rng.random_range(0..Agent::ALL.len()))
        {
            let _ = world.apply(agent);
        }
    }
}

/// The scripted story of the cube scenario, reacting to the action the tree runs and to
/// what the robot holds:
/// 1. as the robot first carries the cube towards the goal, the sphere rolls into its
///    path;
/// 2. once the robot heads back for the cube, an agent puts the cube into its gripper;
/// 3. as it carries the cube to the goal, an agent takes it from the gripper;
/// 4. the sphere rolls into the path once more and, three ticks later, away again.
///
/// Each act waits for one that makes sense in the world.
#[derive(Clone, Debug)]
pub struct Story {
    step: usize,
    since: u32,
    patience: u32,
    names: ActionNames,
}

impl Story {
    /// The story; `patience` is how many ticks an agent lets the robot carry the cube
    /// before the next act (a symbolic move-to takes one tick, a physical one many);
    /// `names` names the tree's actions.
    #[must_use]
    pub fn new(patience: u32, names: ActionNames) -> Self {
        Self { step: 0, since: 0, patience, names }
    }

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

impl<W: Acts> worlds::Agent<W> for Story {
    fn act(&mut self, _: u32, world: &mut W, tree: &TreeState<'_>) {
        let running = self.names.running(tree);
        self.since += 1;
        if let Some(agent) = self.due(running.as_deref(), world.holding_cube())
            && world.apply(agent)
        {
            self.step += 1;
            self.since = 0;
        }
    }
}

/// Who acts in the cube scenario: the story, or random agents (`--seed`).
#[derive(Clone, Debug)]
pub enum CubeAgents {
    /// The scripted story.
    Story(Story),
    /// Random agents.
    Random(Box<Random>),
}

impl<W: Acts> worlds::Agent<W> for CubeAgents {
    fn act(&mut self, tick: u32, world: &mut W, tree: &TreeState<'_>) {
        match self {
            Self::Story(s) => s.act(tick, world, tree),
            Self::Random(r) => r.act(tick, world, tree),
        }
    }
}
