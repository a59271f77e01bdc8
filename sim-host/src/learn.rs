//! Learning brick tasks with the GP of seed 003 in the worlds of this crate: a
//! [`gp::Fitness`] that is one episode, runs over tasks x variants x seeds, and the run
//! folder that is a run's whole record.
//!
//! A run folder, `<task>-<variant>-<world>-seed<N>/`, holds:
//! - `run.txt`: `key = value` lines — task, world, the crate version, the planner's
//!   fitness in that world, wall time, episodes, for the physics world its settings
//!   ([`BrickParams`]), and every GP setting
//!   ([`gp::Params::to_record`]: seed, variant, generations, baseline, Table I);
//! - `curve.csv`: `generation,episodes,best_fitness,best_length`, one row per
//!   generation;
//! - `best.bt` (image), `best.txt` (ASCII) and `best.tokens`: the best tree.
//!
//! Runs are independent processes' worth of work: spread them over machines and merge
//! the folders for `sim-host plot`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use anyhow::{Context as _, anyhow, bail};
use bt_core::Node;
use gp::{Evaluation, GenerationLog, Params, Variant};
use planner::duplo::{Spec, Task};

use crate::episode::Runner;
use crate::physics::{BrickParams, PhysicsBrickWorld};
use crate::scenario::WorldKind;
use crate::symbolic::SymbolicBrickWorld;
use crate::world::BrickWorld;

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

    /// The fitness of one tree: one episode, seed 003 Eq. (1)/(2). A tree the world
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
const PHYSICS: BrickParams = BrickParams::DEFAULT;

/// The physics fitness of a task.
///
/// # Errors
/// A task the world cannot build.
pub fn physics(task: Task) -> anyhow::Result<EpisodeFitness<PhysicsBrickWorld>> {
    EpisodeFitness::new(move || Ok(Runner::new(PhysicsBrickWorld::with_params(&task.spec(), PHYSICS)?)?))
}

/// The reference's generation counts (seed 003, docs/brick-tasks.md): physics tower 200,
/// croissant 1000, balance 800, blocking 300; the fast symbolic world balance 300,
/// blocking 1000.
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

/// One run to make.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunSpec {
    /// The brick task.
    pub task: Task,
    /// How the planner's tree takes part.
    pub variant: Variant,
    /// Where episodes run.
    pub world: WorldKind,
    /// The GP's seed.
    pub seed: u64,
    /// Generations (rows of the curve).
    pub generations: u32,
}

impl RunSpec {
    /// The run's folder name.
    #[must_use]
    pub fn folder(&self) -> String {
        format!("{}-{}-{}-seed{}", self.task.name(), self.variant.name(), self.world.name(), self.seed)
    }
}

/// A finished run.
#[derive(Debug)]
pub struct RunOutcome {
    /// What was run.
    pub spec: RunSpec,
    /// The GP's result.
    pub result: gp::RunResult,
    /// The planner's tree's fitness in the same world.
    pub planner_fitness: f64,
    /// Wall time of the run, s.
    pub seconds: f64,
}

/// The planner's tree for a task (the baseline).
///
/// # Errors
/// The planner failing on the task (it does not for the shipped tasks).
pub fn planner_tree(task: Task) -> anyhow::Result<Vec<Node>> {
    Ok(planner::duplo::plan(task).with_context(|| format!("planning the {} task", task.name()))?.nodes)
}

/// Runs one GP run; `on_generation` sees every row as it is made.
///
/// # Errors
/// A world that cannot be built, or GP parameters the crate refuses.
pub fn learn(
    spec: RunSpec,
    evaluation: Evaluation,
    on_generation: impl FnMut(&GenerationLog),
) -> anyhow::Result<RunOutcome> {
    let start = Instant::now();
    let baseline = planner_tree(spec.task)?;
    let mut params = Params::new(spec.seed, spec.variant, spec.variant.uses_baseline().then(|| baseline.clone()));
    params.generations = spec.generations;
    let alphabet = gp::Alphabet::from_catalog(&spec.task.spec())?;
    let (result, planner_fitness) = match spec.world {
        WorldKind::Symbolic => {
            let f = symbolic(spec.task)?;
            let pf = f.episode(&baseline);
            (gp::run(alphabet, &f, params, evaluation, on_generation)?, pf)
        }
        WorldKind::Physics => {
            let f = physics(spec.task)?;
            let pf = f.episode(&baseline);
            (gp::run(alphabet, &f, params, evaluation, on_generation)?, pf)
        }
    };
    Ok(RunOutcome { spec, result, planner_fitness, seconds: start.elapsed().as_secs_f64() })
}

/// The files of a run's folder, by name.
///
/// # Errors
/// A best tree that cannot be encoded.
pub fn folder_files(run: &RunOutcome) -> anyhow::Result<Vec<(&'static str, Vec<u8>)>> {
    let spec = run.spec.task.spec();
    let mut params = Params::new(run.spec.seed, run.spec.variant, None);
    params.generations = run.spec.generations;
    if run.spec.variant.uses_baseline() {
        params.baseline = Some(planner_tree(run.spec.task)?);
    }
    let mut record = String::new();
    let _ = writeln!(record, "# sim-host learn: one GP run of seed 003 (Styrud et al.)");
    let _ = writeln!(record, "task = {}", run.spec.task.name());
    let _ = writeln!(record, "world = {}", run.spec.world.name());
    let _ = writeln!(record, "sim_host_version = {}", env!("CARGO_PKG_VERSION"));
    let _ = writeln!(record, "planner_fitness = {:?}", run.planner_fitness);
    let _ = writeln!(record, "best_fitness = {:?}", run.result.best.fitness);
    let _ = writeln!(record, "episodes = {}", run.result.episodes);
    let _ = writeln!(record, "wall_seconds = {:.3}", run.seconds);
    if run.spec.world == WorldKind::Physics {
        // The world's own settings: the episodes of a physics run depend on them.
        let p = PHYSICS;
        let _ = writeln!(record, "physics_steps_per_tick = {}", p.steps_per_tick);
        let _ = writeln!(record, "physics_solver_iterations = {}", p.solver_iterations);
        let _ = writeln!(record, "physics_pgs_iterations = {}", p.pgs_iterations);
        let _ = writeln!(record, "physics_gripper_speed = {}", p.speed);
        let _ = writeln!(record, "physics_travel_height = {}", p.travel_height);
    }
    record.push_str(&params.to_record(&spec)?);
    let best = run.result.best.tree()?;
    let image = planner::output::to_image(&best, &spec)?;
    let ascii = planner::output::to_ascii(&best, &spec)?;
    let mut tokens = planner::tokens::to_string(&best, &spec)?;
    tokens.push('\n');
    Ok(vec![
        ("run.txt", record.into_bytes()),
        ("curve.csv", gp::to_csv(&run.result.log).into_bytes()),
        ("best.bt", image),
        ("best.txt", ascii.into_bytes()),
        ("best.tokens", tokens.into_bytes()),
    ])
}

/// A run folder read back: what `plot` needs.
#[derive(Clone, Debug)]
pub struct Recorded {
    /// The folder.
    pub path: PathBuf,
    /// Task.
    pub task: Task,
    /// World.
    pub world: WorldKind,
    /// Variant.
    pub variant: Variant,
    /// Seed.
    pub seed: u64,
    /// The planner's fitness in that world.
    pub planner_fitness: f64,
    /// The learning curve.
    pub curve: Vec<GenerationLog>,
}

/// Reads a run folder.
///
/// # Errors
/// A missing or malformed `run.txt` or `curve.csv`, naming the file and line.
pub fn read_folder(path: &Path) -> anyhow::Result<Recorded> {
    let run_txt = path.join("run.txt");
    let text = crate::input::read_text(&run_txt, crate::input::Limit::RUN_FILE)?;
    let entries = gp::parse_record(&text).map_err(|e| anyhow!("{}: {e}", run_txt.display()))?;
    let get = |key: &str| -> anyhow::Result<&str> {
        entries
            .iter()
            .find(|e| e.key == key)
            .map(|e| e.value)
            .ok_or_else(|| anyhow!("{}: no `{key} = ...` line", run_txt.display()))
    };
    let task = Task::from_name(get("task")?).ok_or_else(|| anyhow!("{}: unknown task", run_txt.display()))?;
    let world = match get("world")? {
        "symbolic" => WorldKind::Symbolic,
        "physics" => WorldKind::Physics,
        other => bail!("{}: unknown world `{other}`", run_txt.display()),
    };
    let spec: Spec = task.spec();
    let params = Params::from_record(&text, &spec).map_err(|e| anyhow!("{}: {e}", run_txt.display()))?;
    let planner_fitness: f64 = get("planner_fitness")?
        .parse()
        .map_err(|_| anyhow!("{}: planner_fitness is not a number", run_txt.display()))?;
    let csv = path.join("curve.csv");
    let curve_text = crate::input::read_text(&csv, crate::input::Limit::RUN_FILE)?;
    let curve = gp::read_csv(&curve_text).map_err(|e| anyhow!("{}: {e}", csv.display()))?;
    if curve.is_empty() {
        bail!("{}: no rows", csv.display());
    }
    Ok(Recorded {
        path: path.to_path_buf(),
        task,
        world,
        variant: params.variant,
        seed: params.seed,
        planner_fitness,
        curve,
    })
}
