//! Learning behavior trees with the GP of Styrud et al. in the worlds of this crate.
//!
//! The GP (crate `gp`) knows nothing of bricks or PDDL: a learning problem supplies a
//! catalog of leaves, a baseline tree and a fitness. Two suppliers live here: the brick
//! tasks of Styrud et al. ([`bricks`]: symbolic or physics world) and any PDDL problem the
//! planner reads ([`strips`]: the symbolic STRIPS world, optionally disturbed by
//! external agents). A [`RunSpec`] names one run — what is learned, the variant, the
//! seed, the generations, optionally the islands of [`gp::islands`] — and [`learn`]
//! makes it. [`folder`] writes and reads the run folder that is a run's whole record.

pub mod bricks;
pub mod folder;
pub mod strips;

use std::sync::Arc;

use bt_core::{Catalog, Node};
use gp::islands::{self, IslandParams};
use gp::{Evaluation, GenerationLog, Individual, Params, Variant};
use planner::duplo::Task;

pub use bricks::{EpisodeFitness, default_generations, physics, planner_tree, symbolic};
pub use folder::{Folder, Recorded, Skipped, folder_files, read_folder};
pub use strips::{Disturbance, StripsFitness, StripsProblem};

use worlds::WorldKind;

/// What a run learns.
#[derive(Clone, Debug)]
pub enum Subject {
    /// A brick task of Styrud et al. in the symbolic or physics world.
    Brick {
        /// The task.
        task: Task,
        /// Where episodes run.
        world: WorldKind,
    },
    /// A PDDL problem in the symbolic STRIPS world.
    Strips {
        /// The problem, grounded and planned.
        problem: Arc<StripsProblem>,
        /// Ticks an episode may last.
        tick_limit: u32,
        /// External agents, if any.
        disturbance: Option<Disturbance>,
    },
}

impl Subject {
    /// The task's name, or the PDDL problem's.
    #[must_use]
    pub fn label(&self) -> String {
        match self {
            Self::Brick { task, .. } => task.name().to_string(),
            Self::Strips { problem, .. } => problem.name().to_string(),
        }
    }

    /// `symbolic`, `physics`, `strips`, or `strips-disturb<RATE>`.
    #[must_use]
    pub fn world_name(&self) -> String {
        match self {
            Self::Brick { world, .. } => world.name().to_string(),
            Self::Strips { disturbance: None, .. } => "strips".to_string(),
            Self::Strips { disturbance: Some(d), .. } => format!("strips-disturb{}", d.rate),
        }
    }

    /// The leaves GP draws from.
    #[must_use]
    pub fn catalog(&self) -> Box<dyn Catalog + '_> {
        match self {
            Self::Brick { task, .. } => Box::new(task.spec()),
            Self::Strips { problem, .. } => Box::new(problem.catalog().clone()),
        }
    }

    /// The size of a tree in GP's leaves as `learn` writes it (the image without its
    /// names section): the measure of [`gp::Fitness::size`] for this subject.
    #[must_use]
    pub fn size(&self, tree: &[Node]) -> Option<gp::Size> {
        match self {
            Self::Brick { .. } => gp::image_size(tree),
            Self::Strips { problem, .. } => problem.size(tree),
        }
    }

    /// The planner's tree in GP's leaves.
    ///
    /// # Errors
    /// The planner failing on a brick task (it does not for the shipped ones).
    pub fn planner_tree(&self, goal_sequence: bool) -> anyhow::Result<Vec<Node>> {
        match self {
            Self::Brick { task, .. } => planner_tree(*task, goal_sequence),
            Self::Strips { problem, .. } => Ok(problem.planner_tree().to_vec()),
        }
    }
}

/// One run to make.
#[derive(Clone, Debug)]
pub struct RunSpec {
    /// What is learned, and where.
    pub subject: Subject,
    /// How the planner's tree takes part.
    pub variant: Variant,
    /// The GP's seed.
    pub seed: u64,
    /// Generations (rows of the curve); with islands, each island's budget.
    pub generations: u32,
    /// Several populations at once ([`gp::islands`]), or one.
    pub islands: Option<IslandParams>,
    /// The brick tasks' baseline in the reference's form (the goal Sequence kept).
    pub goal_sequence: bool,
    /// The most the learned tree may take on the controller ([`gp::Bound`]).
    pub bound: gp::Bound,
}

impl RunSpec {
    /// The variant as it names folders and curves: `baseline`, or `baseline-islands8`.
    #[must_use]
    pub fn variant_label(&self) -> String {
        match self.islands {
            None => self.variant.name().to_string(),
            Some(i) => format!("{}-islands{}", self.variant.name(), i.islands),
        }
    }

    /// The run's folder name: `<task>-<variant>-<world>-seed<N>`.
    #[must_use]
    pub fn folder(&self) -> String {
        format!("{}-{}-{}-seed{}", self.subject.label(), self.variant_label(), self.subject.world_name(), self.seed)
    }

    /// The GP parameters of the run (Table I, the seed, variant, generations and, for
    /// the variants that use it, the planner's tree).
    ///
    /// # Errors
    /// As [`Subject::planner_tree`].
    pub fn params(&self) -> anyhow::Result<Params> {
        let baseline = match self.variant.uses_baseline() {
            true => Some(self.subject.planner_tree(self.goal_sequence)?),
            false => None,
        };
        let mut params = Params::new(self.seed, self.variant, baseline);
        params.generations = self.generations;
        params.bound = self.bound;
        Ok(params)
    }
}

/// A finished run.
#[derive(Debug)]
pub struct RunOutcome {
    /// What was run.
    pub spec: RunSpec,
    /// One row per generation.
    pub log: Vec<GenerationLog>,
    /// The best tree found.
    pub best: Individual,
    /// Episodes (unique simulations; with islands, summed over them).
    pub episodes: u64,
    /// The planner's tree's fitness in the same world.
    pub planner_fitness: f64,
    /// Restarts of stagnated islands.
    pub restarts: u32,
    /// The first row at or above the islands' `stop_at`, if any.
    pub reached: Option<GenerationLog>,
    /// Wall time of the run, s.
    pub seconds: f64,
}

/// Runs one GP run; `on_generation` sees every row as it is made.
///
/// # Errors
/// A world that cannot be built, or GP parameters the crate refuses.
pub fn learn(
    spec: &RunSpec,
    evaluation: Evaluation,
    on_generation: impl FnMut(&GenerationLog),
) -> anyhow::Result<RunOutcome> {
    let start = std::time::Instant::now();
    let params = spec.params()?;
    let baseline = spec.subject.planner_tree(spec.goal_sequence)?;
    let alphabet = gp::Alphabet::from_catalog(spec.subject.catalog().as_ref())?;
    let mut outcome = match &spec.subject {
        Subject::Brick { task, world: WorldKind::Symbolic } => {
            let f = symbolic(*task)?;
            drive(spec, alphabet, &f, f.episode(&baseline), params, evaluation, on_generation)?
        }
        Subject::Brick { task, world: WorldKind::Physics } => {
            let f = physics(*task)?;
            drive(spec, alphabet, &f, f.episode(&baseline), params, evaluation, on_generation)?
        }
        Subject::Strips { problem, tick_limit, disturbance } => {
            let f = StripsFitness::new(problem.clone(), *tick_limit, *disturbance);
            drive(spec, alphabet, &f, f.score(&baseline), params, evaluation, on_generation)?
        }
    };
    outcome.seconds = start.elapsed().as_secs_f64();
    Ok(outcome)
}

fn drive<F: gp::Fitness>(
    spec: &RunSpec,
    alphabet: gp::Alphabet,
    fitness: &F,
    planner_fitness: f64,
    params: Params,
    evaluation: Evaluation,
    on_generation: impl FnMut(&GenerationLog),
) -> anyhow::Result<RunOutcome> {
    if !planner_fitness.is_finite() {
        anyhow::bail!("the planner's tree cannot run in this world (too deep for its episodes?)");
    }
    let (log, best, episodes, restarts, reached) = match spec.islands {
        None => {
            let r = gp::run(alphabet, fitness, params, evaluation, on_generation)?;
            (r.log, r.best, r.episodes, 0, None)
        }
        Some(setup) => {
            let r = islands::run(alphabet, fitness, params, setup, on_generation)?;
            (r.log, r.best, r.episodes, r.restarts, r.reached)
        }
    };
    Ok(RunOutcome { spec: spec.clone(), log, best, episodes, planner_fitness, restarts, reached, seconds: 0.0 })
}
