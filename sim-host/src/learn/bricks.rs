//! The brick tasks of Styrud et al. as a learning problem: GP's leaves are the task's
//! behaviors, an episode in the symbolic or physics brick world is the fitness
//! (Eq. (1)/(2)), and the planner's tree is the baseline.

use std::sync::Mutex;

use anyhow::Context as _;
use bt_core::Node;
use planner::Options;
use planner::duplo::Task;

use crate::episode::Runner;
use crate::physics::{BrickParams, PhysicsBrickWorld};
use crate::symbolic::SymbolicBrickWorld;
use crate::world::BrickWorld;
use worlds::WorldKind;

/// One episode per fitness call, in a world made by `make`. Runners are pooled, so
/// parallel evaluation reuses them and a sequential run uses one.
pub struct EpisodeFitness<W: BrickWorld> {
    make: Box<dyn Fn() -> anyhow::Result<Runner<W>> + Send + Sync>,
    pool: Mutex<Vec<Runner<W>>>,
}

impl<W: BrickWorld> std::fmt::Debug for EpisodeFitness<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EpisodeFitness").finish_non_exhaustive()
    }
}

impl<W: BrickWorld + Send> EpisodeFitness<W> {
    /// Episodes in worlds made by `make`.
    ///
    /// # Errors
    /// When `make` fails on the first world.
    pub fn new(make: impl Fn() -> anyhow::Result<Runner<W>> + Send + Sync + 'static) -> anyhow::Result<Self> {
        let first = make()?;
        Ok(Self { make: Box::new(make), pool: Mutex::new(vec![first]) })
    }

    /// The fitness of one tree: one episode, Styrud et al. Eq. (1)/(2). A tree the world
    /// cannot run scores `-inf`.
    pub fn episode(&self, tree: &[Node]) -> f64 {
        let runner = self.pool.lock().ok().and_then(|mut p| p.pop());
        let Some(mut runner) = runner.or_else(|| (self.make)().ok()) else { return f64::NEG_INFINITY };
        let fitness = runner.run_nodes(tree).map_or(f64::NEG_INFINITY, |e| e.fitness.value());
        if let Ok(mut p) = self.pool.lock() {
            p.push(runner);
        }
        fitness
    }
}

impl<W: BrickWorld + Send> gp::Fitness for EpisodeFitness<W> {
    fn fitness(&self, tree: &[Node]) -> f64 {
        self.episode(tree)
    }
}

/// The symbolic fitness of a task.
///
/// # Errors
/// A task the world cannot build.
pub fn symbolic(task: Task) -> anyhow::Result<EpisodeFitness<SymbolicBrickWorld>> {
    EpisodeFitness::new(move || Ok(Runner::new(SymbolicBrickWorld::new(&task.spec())?)?))
}

/// The physics world's settings for learning: recorded in every physics run's `run.txt`.
pub const PHYSICS: BrickParams = BrickParams::DEFAULT;

/// The physics fitness of a task.
///
/// # Errors
/// A task the world cannot build.
pub fn physics(task: Task) -> anyhow::Result<EpisodeFitness<PhysicsBrickWorld>> {
    EpisodeFitness::new(move || Ok(Runner::new(PhysicsBrickWorld::with_params(&task.spec(), PHYSICS)?)?))
}

/// The reference's generation counts (Styrud et al.): physics tower 200, croissant 1000,
/// balance 800, blocking 300; the fast symbolic world balance 300, blocking 1000.
#[must_use]
pub const fn default_generations(task: Task, world: WorldKind) -> u32 {
    match (task, world) {
        (Task::Tower, _) => 200,
        (Task::Croissant, _) => 1000,
        (Task::Balance, WorldKind::Physics) => 800,
        (Task::Balance, WorldKind::Symbolic) => 300,
        (Task::Blocking, WorldKind::Physics) => 300,
        (Task::Blocking, WorldKind::Symbolic) => 1000,
    }
}

/// The planner's tree for a task (the baseline); with `goal_sequence` in the
/// reference's form, the goal Sequence kept for a single goal.
///
/// # Errors
/// The planner failing on the task (it does not for the shipped tasks).
pub fn planner_tree(task: Task, goal_sequence: bool) -> anyhow::Result<Vec<Node>> {
    let options = Options { goal_sequence, ..Options::default() };
    Ok(planner::duplo_plan_with(task, options).with_context(|| format!("planning the {} task", task.name()))?.nodes)
}

/// The world's settings, as `run.txt` lines, for a physics run.
#[must_use]
pub fn physics_record() -> String {
    let p = PHYSICS;
    format!(
        "physics_steps_per_tick = {}\nphysics_solver_iterations = {}\nphysics_pgs_iterations = {}\n\
         physics_gripper_speed = {}\nphysics_travel_height = {}\n",
        p.steps_per_tick, p.solver_iterations, p.pgs_iterations, p.speed, p.travel_height
    )
}
