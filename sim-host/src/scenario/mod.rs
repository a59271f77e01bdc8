//! The papers' scenarios, narrated: the blended planning-and-acting demo of Colledanchise et al. 2019
//! (cube and sphere, Examples 1-2), the two-armed cellphone assembly (Colledanchise et al. 2019,
//! Section VI), and the four brick tasks of Styrud et al. with the planner's tree.
//!
//! Every run goes through the one episode runner of [`worlds`] ([`driver`]): the world
//! is a [`driver::Scene`], the agents are [`worlds::Agent`]s ([`agents`]), the
//! narration is a [`worlds::Recorder`] ([`narrate`]).
//!
//! ```
//! use sim_host::scenario::{self, Scenario};
//! use worlds::WorldKind;
//! let run = scenario::run(Scenario::Cube, WorldKind::Symbolic, None)?;
//! assert_eq!(run.record.status, Some(bt_core::Status::Success));
//! assert!(run.narration.contains("IncreasePriority"));
//! # Ok::<(), anyhow::Error>(())
//! ```

/// Implements `bt_core::BehaviorSet` for a scenario's world by handing every call to its
/// `world` field: the scenario's world adds what the behaviors' world does not know.
macro_rules! forward_behaviors {
    ($t:ty $(where $g:ident: $bound:path)?) => {
        impl$(<$g: $bound>)? bt_core::BehaviorSet for $t {
            fn condition(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
                bt_core::BehaviorSet::condition(&mut self.world, leaf, ctx)
            }
            fn action(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
                bt_core::BehaviorSet::action(&mut self.world, leaf, ctx)
            }
            fn halt(&mut self, leaf: &bt_core::Leaf, node: bt_core::NodeId) {
                bt_core::BehaviorSet::halt(&mut self.world, leaf, node);
            }
        }
    };
}
pub(crate) use forward_behaviors;

pub mod agents;
pub mod cellphone;
pub mod cube;
pub mod driver;
pub mod narrate;
pub mod strips;

use std::fmt::Write as _;
use std::sync::Arc;

use anyhow::Context as _;
use bt_core::Status;
use planner::duplo::{Spec, Task};
use planner::{Expanding, Options, PddlCatalog, Planner, domains};
use worlds::{Fixed, WorldKind};

use crate::groot2::Watch;
use crate::physics::PhysicsBrickWorld;
use crate::physics::mobile::MobileWorld;
use crate::symbolic::SymbolicBrickWorld;
use crate::text::count;
use crate::world::BrickWorld;
use agents::{ActionNames, CubeAgents, Random, Story};
use driver::{Points, Record, Scene};

/// A scenario of the papers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Scenario {
    /// Colledanchise et al. 2019, Fig. 1 and Examples 1-2: the blended demo.
    Cube,
    /// Colledanchise et al. 2019, Section VI: the cellphone assembly with two arms.
    Cellphone,
    /// A brick task of Styrud et al. with the planner's tree.
    Bricks(Task),
}

impl Scenario {
    /// Every scenario, in the order `--list` shows them.
    pub const ALL: [Scenario; 6] = [
        Scenario::Cube,
        Scenario::Cellphone,
        Scenario::Bricks(Task::Tower),
        Scenario::Bricks(Task::Croissant),
        Scenario::Bricks(Task::Balance),
        Scenario::Bricks(Task::Blocking),
    ];

    /// The name on the command line.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Cube => "cube",
            Self::Cellphone => "cellphone",
            Self::Bricks(t) => t.name(),
        }
    }

    /// The scenario with that name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The worlds it runs in.
    #[must_use]
    pub const fn worlds(self) -> &'static [WorldKind] {
        match self {
            Self::Cube | Self::Bricks(_) => &[WorldKind::Symbolic, WorldKind::Physics],
            Self::Cellphone => &[WorldKind::Symbolic],
        }
    }

    /// What it shows, in one line.
    #[must_use]
    pub const fn about(self) -> &'static str {
        match self {
            Self::Cube => {
                "Colledanchise et al. 2019 Fig. 1, Examples 1-2: the tree grows from the goal as the robot acts; a \
                 sphere blocks the path (expansion + conflict resolution, Fig. 4); agents help and \
                 undo, and the tree copes without replanning"
            }
            Self::Cellphone => {
                "Colledanchise et al. 2019 Section VI: two arms assemble a cellphone, handing parts over to regrasp \
                 them; a part slips and a co-worker helps, without replanning"
            }
            Self::Bricks(Task::Tower) => "Styrud et al. task 1: the planner's tree stacks and presses three bricks",
            Self::Bricks(Task::Croissant) => {
                "Styrud et al. task 2: the planner's tree fails: the long brick blocks the side bricks"
            }
            Self::Bricks(Task::Balance) => {
                "Styrud et al. task 3: the planner's tree fails: the unbalanced brick tips off a narrow base"
            }
            Self::Bricks(Task::Blocking) => {
                "Styrud et al. task 4: the planner's tree fails: the bricks block each other's places"
            }
        }
    }
}

/// A finished scenario run.
pub struct Run {
    /// The narration, ready to print.
    pub narration: String,
    /// What happened, for pictures and tests.
    pub record: Record,
    /// Object names for the picture's legend (the leaves' catalog renders names).
    pub catalog: Arc<dyn bt_core::Catalog + Send + Sync>,
    /// The goal region, for the top view, if the world has one.
    pub goal_region: Option<([f32; 2], [f32; 2])>,
}

impl std::fmt::Debug for Run {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Run").field("record", &self.record).finish_non_exhaustive()
    }
}

/// A scenario that stopped with an error part way: the error (naming the tick) and the
/// narration up to it, for the reader to see what led there.
#[derive(Debug, thiserror::Error)]
#[error("{error:#}")]
pub struct Interrupted {
    /// The narration up to the error.
    pub narration: String,
    /// What went wrong.
    pub error: anyhow::Error,
}

fn interrupted(out: &str, error: anyhow::Error) -> anyhow::Error {
    anyhow::Error::new(Interrupted { narration: out.to_string(), error })
}

/// Most ticks of a scenario run.
pub const MAX_TICKS: u32 = 600;

/// Runs a scenario. `seed` switches the cube scenario to random agents.
///
/// # Errors
/// A world the scenario does not offer, or a failure of the planner or the tree (an
/// [`Interrupted`] with the narration so far, the error naming the tick).
pub fn run(scenario: Scenario, world: WorldKind, seed: Option<u64>) -> anyhow::Result<Run> {
    run_watched(scenario, world, seed, &mut Watch::off())
}

/// [`run`], served to Groot2 as it runs through `watch`: each tree, each status change,
/// each tick at its time.
///
/// # Errors
/// As [`run`].
pub fn run_watched(scenario: Scenario, world: WorldKind, seed: Option<u64>, watch: &mut Watch) -> anyhow::Result<Run> {
    if !scenario.worlds().contains(&world) {
        anyhow::bail!(
            "scenario `{}` has no {} world (it runs in: {})",
            scenario.name(),
            world.name(),
            scenario.worlds().iter().map(|w| w.name()).collect::<Vec<_>>().join(", ")
        );
    }
    let mut out = String::new();
    let _ = writeln!(out, "scenario {} ({} world): {}", scenario.name(), world.name(), scenario.about());
    match scenario {
        Scenario::Cube => {
            let g = Arc::new(domains::cube_sphere().context("loading the cube/sphere domain")?);
            let catalog = Arc::new(PddlCatalog::new(g.problem()));
            watch.names(catalog.clone());
            let mut planner = Planner::new(g.clone(), Options::default())?;
            let mut agents = match seed {
                Some(s) => {
                    let _ = writeln!(out, "agents: random, seed {s}");
                    CubeAgents::Random(Box::new(Random::new(s, cube::RANDOM_RATE)))
                }
                None => {
                    let patience = if world == WorldKind::Physics { 5 } else { 1 };
                    CubeAgents::Story(Story::new(patience, ActionNames(catalog.clone())))
                }
            };
            let _ = writeln!(
                out,
                "goal: at(cube, goal). The tree starts as the goal condition alone (Fig. 3a) and is \
                 expanded whenever it fails (Algorithm 1, at run time).\n"
            );
            let mut trees = Expanding::new(&mut planner, catalog.as_ref());
            let record = match world {
                WorldKind::Symbolic => {
                    let mut w = cube::SymbolicCube::new(g);
                    driver::run(&mut w, &mut trees, catalog.as_ref(), &mut agents, MAX_TICKS, &mut out, watch)
                }
                WorldKind::Physics => {
                    let mut w = MobileWorld::new();
                    driver::run(&mut w, &mut trees, catalog.as_ref(), &mut agents, MAX_TICKS, &mut out, watch)
                }
            }
            .map_err(|e| interrupted(&out, e))?;
            summary(&mut out, &record);
            let goal = crate::physics::mobile::GOAL;
            let half = crate::physics::mobile::GOAL_SIZE / 2.0;
            let region = (world == WorldKind::Physics).then_some(([goal[0] - half, goal[1] - half], [half * 2.0; 2]));
            Ok(Run { narration: out, record, catalog, goal_region: region })
        }
        Scenario::Cellphone => {
            let g = Arc::new(domains::cellphone().context("loading the cellphone domain")?);
            let catalog = Arc::new(PddlCatalog::new(g.problem()));
            watch.names(catalog.clone());
            let mut planner = Planner::new(g.clone(), Options::default())?;
            let _ = writeln!(
                out,
                "goal: every part mounted. The tree starts as the goal conditions in a Sequence and is \
                 expanded whenever it fails.\n"
            );
            let mut w = strips::StripsScene::new(g);
            let mut trees = Expanding::new(&mut planner, catalog.as_ref());
            let mut agents = cellphone::Disturbances::new(ActionNames(catalog.clone()));
            let record = driver::run(&mut w, &mut trees, catalog.as_ref(), &mut agents, MAX_TICKS, &mut out, watch)
                .map_err(|e| interrupted(&out, e))?;
            summary(&mut out, &record);
            Ok(Run { narration: out, record, catalog, goal_region: None })
        }
        Scenario::Bricks(task) => {
            let plan = planner::duplo::plan(task).with_context(|| format!("planning the {} task", task.name()))?;
            let spec = task.spec();
            watch.names(Arc::new(spec.clone()));
            let _ = writeln!(
                out,
                "the planner's tree ({}, planned offline from the goal conditions) runs in the \
                 {} world; episodes end as in Styrud et al. (first Failure, or the tick limit).\n",
                count(plan.nodes.len(), "node"),
                world.name()
            );
            let mut tree = Fixed { nodes: &plan.nodes, values: &[], catalog: &spec };
            let record = match world {
                WorldKind::Symbolic => {
                    let mut w = Bricks::new(SymbolicBrickWorld::new(&spec)?);
                    let limit = w.0.tick_limit();
                    driver::run(&mut w, &mut tree, &spec, &mut (), limit, &mut out, watch)
                }
                WorldKind::Physics => {
                    let mut w = Bricks::new(PhysicsBrickWorld::new(&spec)?);
                    let limit = w.0.tick_limit();
                    driver::run(&mut w, &mut tree, &spec, &mut (), limit, &mut out, watch)
                }
            }
            .map_err(|e| interrupted(&out, e))?;
            brick_summary(&mut out, &spec, &record);
            Ok(Run { narration: out, record, catalog: Arc::new(spec), goal_region: None })
        }
    }
}

/// Whether a world event is an external agent's (not the robot's own doing).
#[must_use]
pub fn is_external(event: &str) -> bool {
    event.starts_with("an agent") || event.starts_with("a co-worker") || event.starts_with("the board slips")
}

fn summary(out: &mut String, r: &Record) {
    let _ = writeln!(out);
    let verdict = match r.status {
        Some(Status::Success) => "goal reached",
        Some(Status::Failure) => "the tree failed",
        _ => "stopped before the goal",
    };
    let external: Vec<u32> = r.events.iter().filter(|(_, e)| is_external(e)).map(|(t, _)| *t).collect();
    let _ = writeln!(
        out,
        "summary: {verdict} after {}, {}, {}, {} halted",
        count(r.ticks, "tick"),
        count(r.expansions.len(), "expansion"),
        count(external.len(), "external event"),
        count(r.halts.len(), "action")
    );
    let after_last = r.expansions.last().map_or(0, |e| e.0);
    let coped = external.iter().filter(|&&t| t > after_last).count();
    let which = match (coped, external.len()) {
        (0, _) => None,
        (1, 1) => Some("the external event came after the last expansion: the tree handled it".to_string()),
        (1, _) => Some("1 of the external events came after the last expansion: the tree handled it".to_string()),
        (n, _) => Some(format!("{n} of the external events came after the last expansion: the tree handled them")),
    };
    if let Some(which) = which {
        let _ = writeln!(out, "         {which} as it was, without replanning");
    }
}

fn brick_summary(out: &mut String, spec: &Spec, r: &Record) {
    let _ = writeln!(out);
    let verdict = match r.status {
        Some(Status::Success) => "the tree succeeded",
        Some(Status::Failure) => "the tree failed",
        _ => "the tick limit ran out",
    };
    let _ = writeln!(out, "summary: {verdict} after {}", count(r.ticks, "tick"));
    if let Some((_, last)) = r.frames.last() {
        for (i, goal) in spec.goal.iter().enumerate() {
            if let (Some(g), Some((name, p))) = (goal, last.get(i)) {
                let d = ((p[0] - g[0]).powi(2) + (p[1] - g[1]).powi(2)).sqrt();
                let _ = writeln!(out, "         {name}: {:.1} mm from its goal in the plane", d * 1000.0);
            }
        }
    }
    let _ = writeln!(out, "         `sim-host run --task {}` gives the fitness of Styrud et al.", spec.task.name());
}

/// Names of bricks for the top view.
const BRICK_NAMES: [&str; 4] = ["brick 0", "brick 1", "brick 2", "brick 3"];

/// A brick world as a scene: no events, the bricks in the top view.
#[derive(Debug)]
struct Bricks<W>(W);

impl<W: BrickWorld> Bricks<W> {
    fn new(mut world: W) -> Self {
        world.reset();
        Self(world)
    }
}

impl<W: BrickWorld> bt_core::BehaviorSet for Bricks<W> {
    fn condition(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> Status {
        self.0.condition(leaf, ctx)
    }
    fn action(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> Status {
        self.0.action(leaf, ctx)
    }
    fn halt(&mut self, leaf: &bt_core::Leaf, node: bt_core::NodeId) {
        self.0.halt(leaf, node);
    }
}

impl<W: BrickWorld> worlds::World for Bricks<W> {
    fn reset(&mut self) {
        self.0.reset();
    }

    fn step(&mut self) {
        self.0.step();
    }
}

impl<W: BrickWorld> Scene for Bricks<W> {
    fn event(&self, _: usize) -> Option<&str> {
        None
    }

    fn points(&self) -> Points {
        (0..self.0.spec().bricks.len())
            .filter_map(|i| {
                let p = self.0.position(i);
                BRICK_NAMES.get(i).map(|&n| (n, [p[0], p[1]]))
            })
            .collect()
    }
}
