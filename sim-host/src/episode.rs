//! Episodes and the fitness of Styrud et al., Eq. (1) and (2), over any [`BrickWorld`].
//!
//! An *episode* ticks the tree (a [`bt_core::Executor`]), then steps the world, once per
//! tick, from the task's start state. It "is aborted if the root returns Failure or if it
//! returns Success twice in a row", or ends by timeout at the world's tick limit (30 in
//! the symbolic world, 200 in the physics world). Its fitness is
//!
//! ```text
//! F  = - sum over bricks with a goal of 1000 * max(0, |o - g| - δ) - λ L - τ T - ϕ F   (1)
//! F' = F - η H                                                                         (2)
//! ```
//!
//! with δ = 0.0004 m, λ = 0.1 per node (control nodes included), τ = 10 if the episode
//! ended by timeout, ϕ = 50 if it ended in Failure, and, for the balance task only,
//! η = 100 if the gripper still holds a brick at the end ([`FitnessParams`]).
//!
//! # Which episodes end by timeout
//!
//! As in the reference implementation, an episode ends by timeout when it ran all the
//! ticks of the limit, whatever the last tick returned: Success twice in a row exactly on
//! the last tick, or Failure on the last tick, also pays τ (the latter pays ϕ too). Its
//! [`End`] is what the root did ([`End::Failure`], [`End::Success`]) or
//! [`End::Timeout`] when it did neither; [`Episode::timed_out`] says whether τ applies.
//!
//! # Cost
//!
//! [`Runner`] runs episodes on the one runner of [`worlds`], with the end rules above
//! ([`Failures::first`], [`SuccessTwice`]); the world moves on after every tick, the
//! last one too, before it is scored. It keeps the world (reset in place), the per-node
//! state and the goals between episodes: an episode allocates nothing. A
//! [`worlds::Recorder`] sees every tick ([`Trace`] for pictures); `()` records nothing
//! and compiles to nothing.

use bt_core::{LoadError, Node, NodeState, NodeStatus, Status, TickError, Tree};
use planner::duplo::Task;
use worlds::agent::TreeState;
use worlds::end::{Failures, SuccessTwice};
use worlds::{Clock, Recorder, Settings, Stop};

use crate::world::{BrickWorld, MAX_BRICKS};

/// Most levels a tree may have in [`Runner::run_nodes`]: the host tools' shared
/// [`planner::DEPTH`].
pub const DEPTH: usize = planner::DEPTH;

/// Milliseconds of simulated time per tick: the `now` bt-core gets on tick `k` (from
/// 0) is `k * TICK_MS` ([`Clock::TENTHS`]). Ten ticks a second, the rate of the worlds
/// and of the example firmware, so that an imported BehaviorTree.CPP tree's `Timeout`,
/// `Delay` and `RateController` (milliseconds) last what they say. The kinds of seed
/// 003 count ticks and never read `now`.
pub const TICK_MS: u32 = Clock::TENTHS.ms_per_tick;

/// The constants of Eq. (1) and (2), Table I of Styrud et al.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitnessParams {
    /// λ: cost per node of the tree, control nodes included.
    pub length: f64,
    /// Cost per metre a brick ends beyond the allowed error from its goal (1 per mm).
    pub completion: f64,
    /// δ: metres of each brick's distance to its goal that cost nothing.
    pub allowed_error: f64,
    /// ϕ: cost of ending in Failure.
    pub failure: f64,
    /// τ: cost of ending by timeout.
    pub timeout: f64,
    /// η: cost of holding a brick at the end (the balance task only; 0 otherwise).
    pub held: f64,
}

impl FitnessParams {
    /// The published constants for `task`.
    #[must_use]
    pub fn for_task(task: Task) -> Self {
        Self {
            length: 0.1,
            completion: 1000.0,
            allowed_error: 0.0004,
            failure: 50.0,
            timeout: 10.0,
            held: if task == Task::Balance { 100.0 } else { 0.0 },
        }
    }
}

/// How an episode ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum End {
    /// The root returned Failure.
    Failure,
    /// The root returned Success on two consecutive ticks.
    Success,
    /// Neither, within the tick limit.
    Timeout,
}

impl End {
    /// Lowercase name, as printed.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Failure => "failure",
            Self::Success => "success",
            Self::Timeout => "timeout",
        }
    }
}

/// Each term of the cost (the fitness is its negative), in the order they are summed.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Fitness {
    /// λ L.
    pub length: f64,
    /// Per brick (by index): `completion * max(0, |pos - goal| - δ)`, 0 for bricks
    /// without a goal.
    pub distance: [f64; MAX_BRICKS],
    /// ϕ F.
    pub failure: f64,
    /// τ T.
    pub timeout: f64,
    /// η H.
    pub held: f64,
}

impl Fitness {
    /// The distance terms summed, in brick order.
    #[must_use]
    pub fn distance_total(&self) -> f64 {
        self.distance.iter().sum()
    }

    /// The cost: every term, summed in a fixed order (length, distances in brick order,
    /// failure, timeout, held), so the same episode gives the same bits.
    #[must_use]
    pub fn cost(&self) -> f64 {
        let mut c = self.length;
        for d in self.distance {
            c += d;
        }
        c + self.failure + self.timeout + self.held
    }

    /// The fitness, `-cost`: higher is better, 0 is a perfect empty tree.
    #[must_use]
    pub fn value(&self) -> f64 {
        -self.cost()
    }

    /// The terms by name, in the order they are summed (the distances as one).
    #[must_use]
    pub fn terms(&self) -> [(&'static str, f64); 5] {
        [
            ("length", self.length),
            ("distance", self.distance_total()),
            ("failure", self.failure),
            ("timeout", self.timeout),
            ("held", self.held),
        ]
    }

    /// The terms as `length 0.400`, ... joined by `sep`.
    #[must_use]
    pub fn terms_text(&self, sep: &str) -> String {
        self.terms().iter().map(|(name, v)| format!("{name} {v:.3}")).collect::<Vec<_>>().join(sep)
    }
}

/// Everything one episode produced. `Copy`, no heap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Episode {
    /// How it ended.
    pub end: End,
    /// Ticks run (the last one included).
    pub ticks: u32,
    /// It ran all the ticks of the limit: τ applies (see the module docs).
    pub timed_out: bool,
    /// The fitness terms.
    pub fitness: Fitness,
    /// Nodes in the tree.
    pub nodes: usize,
    /// Number of bricks; `final_positions[..bricks]` are meaningful.
    pub bricks: usize,
    /// Final position of each brick.
    pub final_positions: [[f32; 3]; MAX_BRICKS],
    /// The brick held at the end.
    pub held: Option<u8>,
}

impl Episode {
    /// Final brick positions, by brick index.
    #[must_use]
    pub fn positions(&self) -> &[[f32; 3]] {
        self.final_positions.get(..self.bricks).unwrap_or(&[])
    }
}

/// The world and the tree after one tick.
#[derive(Clone, Debug, PartialEq)]
pub struct TickRecord {
    /// What the root returned.
    pub root: Status,
    /// Each node's status after the tick (Idle: not ticked in this activation, or halted).
    pub nodes: Vec<NodeStatus>,
    /// Brick positions after the world stepped.
    pub positions: Vec<[f32; 3]>,
    /// The brick held after the tick.
    pub held: Option<u8>,
}

/// A whole episode, tick by tick: what pictures and narration are made from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// Brick positions before the first tick.
    pub start: Vec<[f32; 3]>,
    /// One record per tick.
    pub ticks: Vec<TickRecord>,
}

impl Trace {
    /// Brick `brick`'s position before the first tick (index 0) and after each tick.
    pub fn path(&self, brick: usize) -> impl Iterator<Item = [f32; 3]> + '_ {
        self.start.get(brick).into_iter().chain(self.ticks.iter().filter_map(move |t| t.positions.get(brick))).copied()
    }
}

impl<W: BrickWorld + ?Sized> Recorder<W> for Trace {
    fn start(&mut self, world: &W, _: &TreeState<'_>) {
        self.ticks.clear();
        self.start = (0..world.spec().bricks.len()).map(|b| world.position(b)).collect();
    }

    fn stepped(&mut self, _: u32, root: Status, states: &[NodeState], world: &W) {
        self.ticks.push(TickRecord {
            root,
            nodes: states.iter().map(NodeState::status).collect(),
            positions: (0..world.spec().bricks.len()).map(|b| world.position(b)).collect(),
            held: world.held(),
        });
    }
}

/// Why [`Runner::new`] refused a world.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RunnerError {
    /// The task has more bricks than an episode keeps.
    #[error("task {task}: {}, episodes keep at most {MAX_BRICKS}", crate::text::count(*.count, "brick"))]
    TooManyBricks {
        /// The task's name.
        task: &'static str,
        /// Its bricks.
        count: usize,
    },
}

/// Why [`Runner::run_nodes`] could not run a node array.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum EpisodeError {
    /// The nodes are not a valid tree for the task.
    #[error("invalid tree: {0}")]
    Invalid(#[from] LoadError),
    /// A behavior broke the tick rules.
    #[error(transparent)]
    Tick(#[from] TickError),
}

/// Runs episodes of one world, keeping everything between them.
///
/// ```
/// use planner::duplo::Task;
/// use sim_host::episode::{End, Runner};
/// use sim_host::symbolic::SymbolicBrickWorld;
///
/// let spec = Task::Tower.spec();
/// let mut runner = Runner::new(SymbolicBrickWorld::new(&spec)?)?;
/// let nodes = bt_formats::tokens::parse("s( pick 0! place on 1! apply force 0! )", &spec)?;
/// let episode = runner.run_nodes(&nodes)?;
/// // `pick 0!` starts again right after the place, so the press never happens.
/// assert_eq!(episode.end, End::Timeout);
/// assert_eq!(episode.fitness.length, 0.1 * 4.0);
/// assert_eq!(episode.fitness.timeout, 10.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// A runner is `Send` and, when its world is, `Clone`: parallel fitness evaluation gives
/// each worker its own (e.g. rayon's `map_init`), and results do not depend on which
/// worker ran which tree.
#[derive(Clone, Debug)]
pub struct Runner<W> {
    world: W,
    runner: worlds::Runner,
    params: FitnessParams,
    goals: [Option<[f32; 3]>; MAX_BRICKS],
    bricks: usize,
}

/// Styrud et al.'s episodes: tick `k` (from 0) at `k * TICK_MS`, the world steps after
/// every tick, the last one too, and nothing is halted at the end.
fn settings(tick_limit: u32) -> Settings {
    Settings::new(tick_limit, Clock::TENTHS)
}

impl<W: BrickWorld> Runner<W> {
    /// A runner of `world` with the published constants of its task and its tick limit.
    ///
    /// # Errors
    /// [`RunnerError::TooManyBricks`] for tasks with more than [`MAX_BRICKS`] bricks.
    pub fn new(world: W) -> Result<Self, RunnerError> {
        let spec = world.spec();
        let bricks = spec.bricks.len();
        if bricks > MAX_BRICKS {
            return Err(RunnerError::TooManyBricks { task: spec.task.name(), count: bricks });
        }
        let mut goals = [None; MAX_BRICKS];
        for (slot, g) in goals.iter_mut().zip(&spec.goal) {
            *slot = *g;
        }
        let params = FitnessParams::for_task(spec.task);
        let runner = worlds::Runner::new(settings(world.tick_limit()));
        Ok(Self { world, runner, params, goals, bricks })
    }

    /// Uses other fitness constants.
    #[must_use]
    pub fn with_params(mut self, params: FitnessParams) -> Self {
        self.params = params;
        self
    }

    /// Uses another tick limit (at least 1).
    #[must_use]
    pub fn with_tick_limit(mut self, ticks: u32) -> Self {
        self.runner.settings_mut().limit = ticks.max(1);
        self
    }

    /// The world, as the last episode left it.
    pub fn world(&self) -> &W {
        &self.world
    }

    /// The world, to inspect or set up by hand.
    pub fn world_mut(&mut self) -> &mut W {
        &mut self.world
    }

    /// The fitness constants.
    pub fn params(&self) -> &FitnessParams {
        &self.params
    }

    /// Ticks an episode may last.
    pub fn tick_limit(&self) -> u32 {
        self.runner.settings().limit
    }

    /// Each node's state after the last tick of the last episode (parallel to its tree's
    /// nodes; entries past them are left over from larger trees).
    pub fn states(&self) -> &[NodeState] {
        self.runner.states()
    }

    /// Validates `nodes` against the task (at most [`DEPTH`] levels) and runs one
    /// episode.
    ///
    /// # Errors
    /// [`EpisodeError::Invalid`] for nodes that are not a valid tree of the task's
    /// behaviors; [`EpisodeError::Tick`] as [`Runner::run`].
    pub fn run_nodes(&mut self, nodes: &[Node]) -> Result<Episode, EpisodeError> {
        let tree: Tree<'_, DEPTH> = Tree::validate(nodes, self.world.spec())?;
        Ok(self.run(tree)?)
    }

    /// Runs one episode of `tree` from the task's start state.
    ///
    /// # Errors
    /// [`TickError`] when a behavior of the world breaks the tick rules (a condition
    /// returning Running); the symbolic world never does.
    #[inline]
    pub fn run<const D: usize>(&mut self, tree: Tree<'_, D>) -> Result<Episode, TickError> {
        self.run_recorded(tree, &mut ())
    }

    /// As [`Runner::run`], showing every tick to `recorder`.
    ///
    /// # Errors
    /// As [`Runner::run`].
    #[inline]
    pub fn run_recorded<const D: usize, R: Recorder<W>>(
        &mut self,
        tree: Tree<'_, D>,
        recorder: &mut R,
    ) -> Result<Episode, TickError> {
        self.world.reset();
        let mut ends = (Failures::first(), SuccessTwice::default());
        let out = self.runner.run(tree, &mut self.world, &mut ends, &mut (), recorder)?;
        let end = match out.stop {
            Stop::Failure => End::Failure,
            Stop::Success => End::Success,
            _ => End::Timeout,
        };
        Ok(self.score(tree.len(), end, out.ticks))
    }

    /// The fitness terms of the world as it is now.
    fn score(&self, nodes: usize, end: End, ticks: u32) -> Episode {
        let p = &self.params;
        let timed_out = ticks >= self.tick_limit();
        let mut final_positions = [[0.0; 3]; MAX_BRICKS];
        let mut distance = [0.0; MAX_BRICKS];
        for b in 0..self.bricks {
            let pos = self.world.position(b);
            final_positions[b] = pos;
            if let Some(goal) = self.goals[b] {
                let d = distance_f64(pos, goal);
                distance[b] = p.completion * (d - p.allowed_error).max(0.0);
            }
        }
        let held = self.world.held();
        let fitness = Fitness {
            length: p.length * nodes as f64,
            distance,
            failure: if end == End::Failure { p.failure } else { 0.0 },
            timeout: if timed_out { p.timeout } else { 0.0 },
            held: if held.is_some() { p.held } else { 0.0 },
        };
        Episode { end, ticks, timed_out, fitness, nodes, bricks: self.bricks, final_positions, held }
    }
}

/// Euclidean distance, in `f64` as the reference computes it.
fn distance_f64(a: [f32; 3], b: [f32; 3]) -> f64 {
    let d = |i: usize| f64::from(a[i]) - f64::from(b[i]);
    let (dx, dy, dz) = (d(0), d(1), d(2));
    (dx * dx + dy * dy + dz * dz).sqrt()
}

#[cfg(test)]
mod tests;
