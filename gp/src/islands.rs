//! Several populations at once: an island model for when a single run of Styrud et al.'s GP
//! is not reliable enough (blocking at 300 generations solves about one run in three).
//!
//! `K` islands, each a full [`Gp`] run with the same [`Params`] (Table I, the variant
//! and its baseline: with `baseline` the planner's tree is kept on every island), evolve
//! side by side on rayon's thread pool. Every `migration_interval` generations they
//! stop together and:
//!
//! 1. **Migration** (a ring): island `i` sends the best of its population to island
//!    `i + 1 mod K`, where it replaces the worst member that is not the baseline
//!    ([`Gp::immigrate`]); it comes with its fitness, so nothing is simulated again.
//! 2. **Restarts**: an island whose best has not improved for `stagnation`
//!    generations starts again from a new random population (with the baseline, if
//!    the variant uses one) and a seed of its own. What it found is not lost: the
//!    result is the best tree any island ever held.
//! 3. **Stop**: if `stop_at` is set and the best of all islands has reached it.
//!
//! Each island has the whole generation budget of [`Params::generations`] (a restart's
//! new initial population counts as one generation), so islands that never stop cost
//! `K` single runs. All islands have used the same number of generations at every
//! synchronisation, so the learning curve has one row per generation: episodes summed
//! over the islands, the best fitness any island has reached so far.
//!
//! **Determinism.** Island `i` draws from its own generator, seeded from the run's
//! seed, `i` and its restart count (island 0 before any restart uses the run's seed
//! itself: one island without restarts is exactly a plain run). Islands share nothing
//! while they evolve; migration, restarts and the stop are decided at the
//! synchronisation points from all islands' states in island order. So the result
//! depends on the seed only, not on the number of threads or their timing.
//!
//! ```
//! use gp::islands::{self, IslandParams};
//! use gp::{Alphabet, Params, Variant};
//! use planner::duplo::Task;
//!
//! let spec = Task::Tower.spec();
//! let alphabet = Alphabet::from_catalog(&spec)?;
//! let pick_0 = spec.id_by_name("pick 0!").unwrap();
//! let fitness = |tree: &[bt_core::Node]| {
//!     let picks = tree.iter().any(|n| matches!(n.kind(), bt_core::NodeKind::Action(l) if l.behavior() == pick_0));
//!     (if picks { 0.0 } else { -10.0 }) - 0.1 * tree.len() as f64
//! };
//! let mut params = Params::new(1, Variant::None, None);
//! params.generations = 50;
//! let setup = IslandParams { islands: 4, stop_at: Some(-0.3), ..IslandParams::default() };
//! let result = islands::run(alphabet, &fitness, params, setup, |_| {})?;
//! assert!(result.best.fitness >= -0.3);
//! assert!(result.log.len() <= 50);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::alphabet::Alphabet;
use crate::fitness::Fitness;
use crate::log::GenerationLog;
use crate::params::Params;
use crate::run::{Evaluation, Gp, GpError, Individual};
use rayon::prelude::*;

/// How the islands are set up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IslandParams {
    /// Number of islands (populations), at least 1.
    pub islands: usize,
    /// Generations between two synchronisations (migration, restarts, the stop test),
    /// at least 1.
    pub migration_interval: u32,
    /// Restart an island whose best has not improved for this many generations;
    /// `None`: never.
    pub stagnation: Option<u32>,
    /// Stop once the best fitness of all islands is at least this.
    pub stop_at: Option<f64>,
}

impl Default for IslandParams {
    /// 16 islands, migration every 10 generations, restart after 100 generations
    /// without improvement, no early stop (`docs/results` measures this setting on the
    /// brick tasks; other settings were not compared there).
    fn default() -> Self {
        Self { islands: 16, migration_interval: 10, stagnation: Some(100), stop_at: None }
    }
}

impl IslandParams {
    /// Writes the settings as `key = value` lines of a run record (`islands`,
    /// `migration_interval`, `stagnation`, `stop_at`; `none` for an absent value).
    #[must_use]
    pub fn to_record(&self) -> String {
        let opt = |v: Option<String>| v.unwrap_or_else(|| "none".to_string());
        format!(
            "islands = {}\nmigration_interval = {}\nstagnation = {}\nstop_at = {}\n",
            self.islands,
            self.migration_interval,
            opt(self.stagnation.map(|s| s.to_string())),
            opt(self.stop_at.map(|s| format!("{s:?}"))),
        )
    }
}

/// What an island run leaves behind.
#[derive(Clone, Debug, PartialEq)]
pub struct IslandsResult {
    /// One row per generation: episodes of all islands so far, the best fitness any
    /// island has reached so far and that tree's length.
    pub log: Vec<GenerationLog>,
    /// The best tree any island ever held (ties: the lowest island, then the earliest).
    pub best: Individual,
    /// Episodes of all islands (each island simulates a tree once; two islands may
    /// both simulate the same tree).
    pub episodes: u64,
    /// Restarts made, over all islands.
    pub restarts: u32,
    /// Migrants taken in, over all islands.
    pub migrations: u32,
    /// The first row at which the best reached `stop_at`, if it did.
    pub reached: Option<GenerationLog>,
}

/// A derived seed: SplitMix64 over the run's seed, the island and its restart.
#[must_use]
pub fn island_seed(seed: u64, island: usize, restart: u32) -> u64 {
    if island == 0 && restart == 0 {
        return seed;
    }
    let mix = |mut z: u64| {
        z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    mix(mix(seed) ^ mix(((island as u64) << 32) | u64::from(restart)))
}

struct Island<'f, F: Fitness + ?Sized> {
    index: usize,
    gp: Gp<'f, F>,
    restarts: u32,
    /// Generations used, restarts' initial populations included.
    used: u32,
    /// Episodes of earlier incarnations.
    episodes_before: u64,
    /// Best ever held.
    best: Individual,
    /// `used` when `best` last improved.
    improved_at: u32,
    /// Per generation used: (episodes so far, best ever so far, its length).
    history: Vec<(u64, f64, usize)>,
}

impl<'f, F: Fitness + ?Sized> Island<'f, F> {
    fn new(
        index: usize,
        alphabet: &Alphabet,
        fitness: &'f F,
        params: &Params,
        evaluation: Evaluation,
    ) -> Result<Self, GpError> {
        let p = Params { seed: island_seed(params.seed, index, 0), ..params.clone() };
        let gp = Gp::new(alphabet.clone(), fitness, p, evaluation)?;
        let best = gp.best().clone();
        let mut island =
            Self { index, gp, restarts: 0, used: 1, episodes_before: 0, best, improved_at: 1, history: Vec::new() };
        island.note();
        Ok(island)
    }

    fn episodes(&self) -> u64 {
        self.episodes_before + self.gp.episodes()
    }

    /// Records the generation just made.
    fn note(&mut self) {
        let best = self.gp.best();
        if best.fitness > self.best.fitness {
            self.best = best.clone();
            self.improved_at = self.used;
        }
        self.history.push((self.episodes(), self.best.fitness, self.best.genome.length()));
    }

    fn advance(&mut self, generations: u32, budget: u32) {
        for _ in 0..generations {
            if self.used >= budget {
                return;
            }
            self.gp.step();
            self.used += 1;
            self.note();
        }
    }

    fn stagnant(&self, stagnation: Option<u32>) -> bool {
        stagnation.is_some_and(|s| self.used - self.improved_at >= s)
    }

    fn restart(&mut self, params: &Params, evaluation: Evaluation) -> Result<(), GpError> {
        self.restarts += 1;
        let p = Params { seed: island_seed(params.seed, self.index, self.restarts), ..params.clone() };
        let gp = Gp::new(self.gp.alphabet().clone(), self.gp.fitness(), p, evaluation)?;
        self.episodes_before += self.gp.episodes();
        self.gp = gp;
        self.used += 1;
        self.improved_at = self.used;
        self.note();
        Ok(())
    }
}

/// Runs the islands until every island has used the generation budget, or the best
/// reaches `setup.stop_at`; `on_generation` sees every row of the combined curve, in
/// order, as each synchronisation completes them.
///
/// # Errors
/// As [`Gp::new`]; [`GpError::Islands`] for zero islands or a zero interval.
pub fn run<F: Fitness + ?Sized>(
    alphabet: Alphabet,
    fitness: &F,
    params: Params,
    setup: IslandParams,
    mut on_generation: impl FnMut(&GenerationLog),
) -> Result<IslandsResult, GpError> {
    if setup.islands == 0 {
        return Err(GpError::Islands("islands must be at least 1"));
    }
    if setup.migration_interval == 0 {
        return Err(GpError::Islands("migration_interval must be at least 1"));
    }
    params.check()?;
    // Islands are the parallel unit; a lone island evaluates its offspring in parallel.
    let evaluation = if setup.islands > 1 { Evaluation::Sequential } else { Evaluation::Parallel };
    let mut islands = (0..setup.islands)
        .into_par_iter()
        .map(|i| Island::new(i, &alphabet, fitness, &params, evaluation))
        .collect::<Result<Vec<_>, _>>()?;
    let budget = params.generations;
    let mut log: Vec<GenerationLog> = Vec::new();
    let mut migrations = 0;
    let mut reached = None;
    loop {
        // Rows completed by every island so far.
        let done = islands.iter().map(|i| i.history.len()).min().unwrap_or(0);
        for g in log.len()..done {
            let row = combined_row(&islands, g);
            if reached.is_none() && setup.stop_at.is_some_and(|t| row.best_fitness >= t) {
                reached = Some(row);
            }
            on_generation(&row);
            log.push(row);
        }
        let used = islands.first().map_or(budget, |i| i.used);
        if reached.is_some() || used >= budget {
            break;
        }
        // Migration, on the populations as they are now, delivered together.
        if islands.len() > 1 {
            let migrants: Vec<Individual> = islands.iter().map(|i| i.gp.best().clone()).collect();
            let k = islands.len();
            for (from, m) in migrants.iter().enumerate() {
                migrations += u32::from(islands[(from + 1) % k].gp.immigrate(m));
            }
        }
        // Restarts (a new initial population is one generation), then the next stretch.
        let step = setup.migration_interval;
        islands
            .par_iter_mut()
            .map(|island| {
                if island.stagnant(setup.stagnation) && island.used < budget {
                    island.restart(&params, evaluation)?;
                    island.advance(step - 1, budget);
                } else {
                    island.advance(step, budget);
                }
                Ok(())
            })
            .collect::<Result<Vec<()>, GpError>>()?;
    }
    let mut best: Option<&Individual> = None;
    for island in &islands {
        if best.is_none_or(|b| island.best.fitness > b.fitness) {
            best = Some(&island.best);
        }
    }
    let best = best.cloned().ok_or(GpError::Islands("islands must be at least 1"))?;
    Ok(IslandsResult {
        log,
        best,
        episodes: islands.iter().map(Island::episodes).sum(),
        restarts: islands.iter().map(|i| i.restarts).sum(),
        migrations,
        reached,
    })
}

fn combined_row<F: Fitness + ?Sized>(islands: &[Island<'_, F>], g: usize) -> GenerationLog {
    let mut episodes = 0;
    let mut best: Option<(f64, usize)> = None;
    for island in islands {
        if let Some(&(e, f, len)) = island.history.get(g) {
            episodes += e;
            if best.is_none_or(|(b, _)| f > b) {
                best = Some((f, len));
            }
        }
    }
    let (best_fitness, best_length) = best.unwrap_or((f64::NEG_INFINITY, 0));
    GenerationLog { generation: g as u32, episodes, best_fitness, best_length }
}
