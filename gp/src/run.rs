//! A GP run: the generation loop of Styrud et al. (Fig. 1, Section III, Table I).
//!
//! One generation, in this order, every random draw from the run's one ChaCha8
//! generator:
//! 1. **Baseline** (variants other than `none` and `nokeep`): the planner's tree is in the
//!    population — it was put back at the end of the previous generation if it had
//!    dropped out, so the population then has `population_size + 1` members (the
//!    reference appends it at the start of the next generation; no random draw comes
//!    between, so the runs are the same, and this way [`Gp::population`] always holds
//!    it).
//! 2. **Crossover parents**: `crossover_parents` distinct individuals by rank
//!    (with `boost-crossover` and `boost-all`, the baseline's fitness counts as the
//!    population's maximum here).
//! 3. **Crossover offspring**: `crossover_rounds` rounds; each round pairs up the
//!    parents at random, and a pair whose two children are accepted is used up. A
//!    pair that fails draws again, until 100 failures in a row end the round.
//! 4. **Mutation parents**: `mutation_parents` distinct individuals of the population
//!    (not of the crossover offspring) by rank (boosted with `boost-all`).
//! 5. **Mutation offspring**: `mutation_offspring` per parent, each the first of up
//!    to 100 mutations that is accepted.
//! 6. **Episodes**: the offspring never simulated before are evaluated — in parallel,
//!    results gathered in a fixed order — and cached.
//! 7. **Survivors**: the best `survivor_parents` of the population and all offspring
//!    compete; the best `elites` stay, the rest of the population is drawn by rank.
//!
//! An offspring is **accepted** if it has at least `min_length` nodes and is not equal
//! to a member of the population or to an earlier offspring of this generation (the
//! second child of a crossover pair counts the first as earlier).

use bt_core::Node;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::alphabet::{Alphabet, draw};
use crate::bound::{Bound, RandomTrees, fits};
use crate::fitness::{Fitness, FitnessCache, Size};
use crate::genome::{Genome, GenomeError, Token, hash_tokens, length};
use crate::log::GenerationLog;
use crate::operators::{MAX_ATTEMPTS, crossover_into, mutate_into};
use crate::params::{Params, ParamsError};
use crate::selection::{rank_order, select_best, select_by_rank};

/// How a generation's episodes are run. The results are the same either way.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Evaluation {
    /// On rayon's thread pool.
    #[default]
    Parallel,
    /// On the calling thread (e.g. when runs themselves are spread over threads).
    Sequential,
}

/// A tree of the population with its fitness.
#[derive(Clone, Debug, PartialEq)]
pub struct Individual {
    /// The tree.
    pub genome: Genome,
    /// Its fitness (from the cache: never simulated twice).
    pub fitness: f64,
}

impl Individual {
    /// The tree as a bt-core node array.
    ///
    /// # Errors
    /// Only for a tree of more than 65535 nodes.
    pub fn tree(&self) -> Result<Vec<Node>, GenomeError> {
        self.genome.to_nodes()
    }
}

/// Why a run cannot start.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GpError {
    /// The parameters cannot run.
    #[error(transparent)]
    Params(#[from] ParamsError),
    /// The baseline is not a tree of this task's alphabet.
    #[error("baseline: {0}")]
    Baseline(GenomeError),
    /// No valid random tree of the initial length could be drawn.
    #[error("no valid random tree of {} could be drawn from this alphabet", crate::genome::count(*.0, "node"))]
    NoRandomTree(usize),
    /// Island settings that cannot run ([`crate::islands::IslandParams`]).
    #[error("{0}")]
    Islands(&'static str),
    /// The baseline is over the [`Bound`].
    #[error("the planner's tree (the baseline) has an image of {} and {}, over the bound of {bound}",
            crate::genome::count(size.bytes, "byte"), crate::genome::count(size.nodes, "node"))]
    BaselineTooBig {
        /// The baseline's size.
        size: Size,
        /// The bound.
        bound: Bound,
    },
    /// Not even the smallest random tree fits the [`Bound`].
    #[error("no random tree of {} or more fits {bound}", crate::genome::count(*min_length, "node"))]
    BoundTooSmall {
        /// The bound.
        bound: Bound,
        /// The smallest tree GP makes (`min_length`).
        min_length: usize,
    },
}

/// What a run leaves behind.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// One row per generation, generation 0 first.
    pub log: Vec<GenerationLog>,
    /// The best individual of the final population (ties: see [`crate::selection`]).
    pub best: Individual,
    /// The final population, elites first.
    pub population: Vec<Individual>,
    /// Episodes (unique simulations) of the whole run.
    pub episodes: u64,
}

/// A GP run in progress. [`Gp::new`] draws and evaluates the initial population
/// (generation 0); each [`Gp::step`] breeds one more generation.
pub struct Gp<'f, F: Fitness + ?Sized> {
    params: Params,
    alphabet: Alphabet,
    fitness: &'f F,
    evaluation: Evaluation,
    rng: ChaCha8Rng,
    cache: FitnessCache,
    population: Vec<Individual>,
    baseline: Option<Genome>,
    generation: u32,
    log: Vec<GenerationLog>,
    /// Members before the baseline put back, if it was.
    survivors: usize,
    // Reused buffers.
    scores: Vec<f64>,
    picks: Vec<usize>,
    child_a: Vec<Token>,
    child_b: Vec<Token>,
    nodes: Vec<Node>,
}

/// A copy of the run at this point: continuing both gives the same generations.
impl<F: Fitness + ?Sized> Clone for Gp<'_, F> {
    fn clone(&self) -> Self {
        Self {
            params: self.params.clone(),
            alphabet: self.alphabet.clone(),
            fitness: self.fitness,
            evaluation: self.evaluation,
            rng: self.rng.clone(),
            cache: self.cache.clone(),
            population: self.population.clone(),
            baseline: self.baseline.clone(),
            generation: self.generation,
            log: self.log.clone(),
            survivors: self.survivors,
            scores: Vec::new(),
            picks: Vec::new(),
            child_a: Vec::new(),
            child_b: Vec::new(),
            nodes: Vec::new(),
        }
    }
}

impl<F: Fitness + ?Sized> std::fmt::Debug for Gp<'_, F> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Gp")
            .field("variant", &self.params.variant)
            .field("seed", &self.params.seed)
            .field("generation", &self.generation)
            .field("episodes", &self.cache.episodes())
            .field("population", &self.population)
            .finish_non_exhaustive()
    }
}

impl<'f, F: Fitness + ?Sized> Gp<'f, F> {
    /// Starts a run: checks `params`, draws the initial population (the baseline
    /// replacing the first random tree) and evaluates it.
    ///
    /// # Errors
    /// [`GpError`] if the parameters cannot run or the baseline is not a tree of
    /// `alphabet`.
    pub fn new(alphabet: Alphabet, fitness: &'f F, params: Params, evaluation: Evaluation) -> Result<Self, GpError> {
        params.check()?;
        let baseline = match (&params.baseline, params.variant.uses_baseline()) {
            (Some(nodes), true) => Some(Genome::from_nodes(nodes, &alphabet).map_err(GpError::Baseline)?),
            _ => None,
        };
        if let Some(b) = &baseline {
            let size = b.to_nodes().ok().and_then(|nodes| fitness.size(&nodes));
            let size = size.unwrap_or(Size { bytes: usize::MAX, nodes: b.length() });
            if !params.bound.admits(size) {
                return Err(GpError::BaselineTooBig { size, bound: params.bound });
            }
        }
        let mut rng = ChaCha8Rng::seed_from_u64(params.seed);
        let capacity = (params.population_size + 1).saturating_add(
            (params.generations as usize).saturating_mul(offspring_per_generation(&params)).min(1 << 20),
        );
        let mut genomes: Vec<Genome> = Vec::with_capacity(params.population_size + 1);
        let mut draw = RandomTrees::new(&params);
        for _ in 0..params.population_size {
            for _ in 0..MAX_ATTEMPTS {
                let tree = draw.next(&alphabet, fitness, &mut rng)?;
                if !genomes.contains(&tree) {
                    genomes.push(tree);
                    break;
                }
            }
        }
        if let (Some(b), Some(first)) = (&baseline, genomes.first_mut()) {
            first.clone_from(b);
        }
        let mut gp = Self {
            params,
            alphabet,
            fitness,
            evaluation,
            rng,
            cache: FitnessCache::with_capacity(capacity),
            population: Vec::new(),
            baseline,
            generation: 0,
            log: Vec::new(),
            survivors: 0,
            scores: Vec::new(),
            picks: Vec::new(),
            child_a: Vec::new(),
            child_b: Vec::new(),
            nodes: Vec::new(),
        };
        let fitness = gp.evaluate(&genomes);
        gp.population =
            genomes.into_iter().zip(fitness).map(|(genome, fitness)| Individual { genome, fitness }).collect();
        gp.survivors = gp.population.len();
        gp.record();
        Ok(gp)
    }

    /// Breeds the next generation (see the [module docs](self)) and returns its row.
    pub fn step(&mut self) -> GenerationLog {
        // 1. The baseline (put back at the end of the previous generation).
        let baseline_at = self.baseline.as_ref().and_then(|b| self.population.iter().position(|i| i.genome == *b));
        // 2-3. Crossover.
        self.parent_scores(baseline_at, self.params.variant.boosts_crossover());
        let mut parents = Vec::with_capacity(self.params.crossover_parents);
        select_by_rank(&self.scores, self.params.crossover_parents, &mut self.rng, &mut parents);
        let mut offspring: Vec<Genome> = Vec::with_capacity(offspring_per_generation(&self.params));
        for _ in 0..self.params.crossover_rounds {
            self.crossover_round(&parents, &mut offspring);
        }
        // 4-5. Mutation.
        self.parent_scores(baseline_at, self.params.variant.boosts_mutation());
        select_by_rank(&self.scores, self.params.mutation_parents, &mut self.rng, &mut parents);
        for &p in &parents {
            for _ in 0..self.params.mutation_offspring {
                self.mutation(p, &mut offspring);
            }
        }
        // 6. Episodes.
        let fitness = self.evaluate(&offspring);
        let offspring: Vec<Individual> =
            offspring.into_iter().zip(fitness).map(|(genome, fitness)| Individual { genome, fitness }).collect();
        // 7. Survivors.
        self.survive(offspring);
        self.keep_baseline();
        self.generation += 1;
        self.record()
    }

    /// Runs the remaining generations up to `params.generations`, calling
    /// `on_generation` with every row (generation 0's first if it was not reported
    /// yet), and returns the result.
    pub fn run(mut self, mut on_generation: impl FnMut(&GenerationLog)) -> RunResult {
        if let Some(row) = self.log.last().filter(|_| self.generation == 0) {
            on_generation(row);
        }
        while self.generation + 1 < self.params.generations {
            let row = self.step();
            on_generation(&row);
        }
        self.finish()
    }

    /// The result so far.
    #[must_use]
    pub fn finish(self) -> RunResult {
        let best = self.best().clone();
        RunResult { log: self.log, best, population: self.population, episodes: self.cache.episodes() }
    }

    /// The current generation: 0 after [`Gp::new`].
    #[must_use]
    pub fn generation(&self) -> u32 {
        self.generation
    }

    /// Episodes (unique simulations) so far.
    #[must_use]
    pub fn episodes(&self) -> u64 {
        self.cache.episodes()
    }

    /// The population, elites first, then the rest in the order drawn, then the
    /// baseline if it was put back.
    #[must_use]
    pub fn population(&self) -> &[Individual] {
        &self.population
    }

    /// The best individual of the population (the first in rank order; see
    /// [`crate::selection`] for ties).
    #[must_use]
    pub fn best(&self) -> &Individual {
        // Ranked among the survivors: the baseline put back does not take part, as in
        // the reference, where it is put back only at the next generation's start. (It
        // cannot be better than the best survivor, only tie with it.)
        let survivors = self.population.get(..self.survivors).unwrap_or(&self.population);
        let mut order = Vec::with_capacity(survivors.len());
        let fitness: Vec<f64> = survivors.iter().map(|i| i.fitness).collect();
        rank_order(&fitness, &mut order);
        // Never empty: population_size >= 1, checked in `new`.
        &survivors[order[0]]
    }

    /// One row per generation so far.
    #[must_use]
    pub fn log(&self) -> &[GenerationLog] {
        &self.log
    }

    /// Every tree simulated so far.
    #[must_use]
    pub fn cache(&self) -> &FitnessCache {
        &self.cache
    }

    /// The baseline, as a genome.
    #[must_use]
    pub fn baseline(&self) -> Option<&Genome> {
        self.baseline.as_ref()
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The leaves drawn from.
    #[must_use]
    pub fn alphabet(&self) -> &Alphabet {
        &self.alphabet
    }

    /// The fitness the run scores trees with.
    #[must_use]
    pub fn fitness(&self) -> &'f F {
        self.fitness
    }

    /// Takes in an individual from elsewhere (a migrant of [`crate::islands`]): it
    /// replaces the worst member of the population, unless it is already a member.
    /// The baseline is never replaced; ties for the worst go to the later member. Its
    /// fitness comes with it: nothing is simulated and the episode count is unchanged.
    /// Returns whether it was taken in.
    pub fn immigrate(&mut self, migrant: &Individual) -> bool {
        if self.population.iter().any(|i| i.genome == migrant.genome) {
            return false;
        }
        let baseline = self.baseline.as_ref();
        let survivors = self.population.get(..self.survivors).unwrap_or(&self.population);
        let worst = survivors.iter().enumerate().filter(|(_, i)| baseline != Some(&i.genome)).fold(
            None::<(usize, f64)>,
            |w, (k, i)| match w {
                Some((_, f)) if f < i.fitness => w,
                _ => Some((k, i.fitness)),
            },
        );
        let Some((at, _)) = worst else { return false };
        self.population[at] = migrant.clone();
        true
    }

    /// Puts the baseline back at the end of the population if it dropped out (unless
    /// the variant is `nokeep`), and returns where it is.
    fn keep_baseline(&mut self) -> Option<usize> {
        self.survivors = self.population.len();
        let b = self.baseline.as_ref()?;
        if let Some(at) = self.population.iter().position(|i| i.genome == *b) {
            return Some(at);
        }
        if !self.params.variant.keeps_baseline() {
            return None;
        }
        let fitness = self.cache.get(b).unwrap_or(f64::NEG_INFINITY);
        self.population.push(Individual { genome: b.clone(), fitness });
        Some(self.population.len() - 1)
    }

    /// Fitness of the population for parent selection, the baseline boosted to the
    /// maximum if asked. The population's own fitness is never changed, so nothing
    /// needs restoring.
    fn parent_scores(&mut self, baseline_at: Option<usize>, boost: bool) {
        self.scores.clear();
        self.scores.extend(self.population.iter().map(|i| i.fitness));
        if boost && let Some(b) = baseline_at {
            let max = self.scores.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            if let Some(s) = self.scores.get_mut(b) {
                *s = max;
            }
        }
    }

    fn crossover_round(&mut self, parents: &[usize], offspring: &mut Vec<Genome>) {
        let mut unused = parents.to_vec();
        let mut failures = 0;
        while unused.len() >= 2 && failures < MAX_ATTEMPTS {
            let i = draw(&mut self.rng, unused.len());
            let mut j = draw(&mut self.rng, unused.len() - 1);
            if j >= i {
                j += 1;
            }
            let (a, b) = (&self.population[unused[i]].genome, &self.population[unused[j]].genome);
            let made = crossover_into(
                a.tokens(),
                b.tokens(),
                &self.alphabet,
                &mut self.rng,
                &mut self.child_a,
                &mut self.child_b,
            );
            let accepted = match made.then(|| self.accepts(&self.child_a, offspring)).flatten() {
                Some(ha) if self.child_a != self.child_b => self.accepts(&self.child_b, offspring).map(|hb| (ha, hb)),
                _ => None,
            };
            if let Some((ha, hb)) = accepted {
                offspring.push(Genome::with_hash(&self.child_a, ha));
                offspring.push(Genome::with_hash(&self.child_b, hb));
                unused.remove(i.max(j));
                unused.remove(i.min(j));
                failures = 0;
            } else {
                failures += 1;
            }
        }
    }

    fn mutation(&mut self, parent: usize, offspring: &mut Vec<Genome>) {
        for _ in 0..MAX_ATTEMPTS {
            let tokens = self.population[parent].genome.tokens();
            let made = mutate_into(tokens, &self.alphabet, &self.params.mutation, &mut self.rng, &mut self.child_a);
            if let Some(hash) = made.then(|| self.accepts(&self.child_a, offspring)).flatten() {
                offspring.push(Genome::with_hash(&self.child_a, hash));
                return;
            }
        }
    }

    /// The offspring acceptance rule; the child's hash if accepted.
    fn accepts(&self, child: &[Token], offspring: &[Genome]) -> Option<u64> {
        if length(child) < self.params.min_length || !fits(child, self.params.bound, self.fitness) {
            return None;
        }
        let hash = hash_tokens(child);
        let same = |g: &Genome| g.hash_value() == hash && g.tokens() == child;
        (!self.population.iter().any(|i| same(&i.genome)) && !offspring.iter().any(same)).then_some(hash)
    }

    /// The fitness of each genome, in order: from the cache, or from an episode for
    /// those never simulated (each once, in parallel if asked), which are then cached.
    fn evaluate(&mut self, genomes: &[Genome]) -> Vec<f64> {
        let mut new: Vec<&Genome> = Vec::with_capacity(genomes.len());
        for g in genomes {
            if !self.cache.contains(g) && !new.contains(&g) {
                new.push(g);
            }
        }
        let fitness = self.fitness;
        // A genome of the population is always a well-formed tree; were it not, it
        // would score the worst instead of reaching the world.
        let score = |nodes: &mut Vec<Node>, g: &Genome| match g.write_nodes(nodes) {
            Ok(()) => fitness.fitness(nodes),
            Err(_) => f64::NEG_INFINITY,
        };
        let scores: Vec<f64> = match self.evaluation {
            Evaluation::Parallel => new.par_iter().map_init(Vec::new, |nodes, g| score(nodes, g)).collect(),
            Evaluation::Sequential => new.iter().map(|g| score(&mut self.nodes, g)).collect(),
        };
        for (g, s) in new.into_iter().zip(scores) {
            self.cache.insert(g.clone(), s);
        }
        genomes.iter().map(|g| self.cache.get(g).unwrap_or(f64::NEG_INFINITY)).collect()
    }

    fn survive(&mut self, offspring: Vec<Individual>) {
        let size = self.params.population_size;
        let old = std::mem::take(&mut self.population);
        let old_fitness: Vec<f64> = old.iter().map(|i| i.fitness).collect();
        select_best(&old_fitness, self.params.survivor_parents, &mut self.picks);
        let mut selectable: Vec<Individual> = self.picks.iter().map(|&i| old[i].clone()).collect();
        selectable.extend(offspring);

        let fitness: Vec<f64> = selectable.iter().map(|i| i.fitness).collect();
        select_best(&fitness, self.params.elites, &mut self.picks);
        let mut chosen = vec![false; selectable.len()];
        let mut survivors: Vec<usize> = self.picks.clone();
        for &e in &survivors {
            chosen[e] = true;
        }
        let rest: Vec<usize> = (0..selectable.len()).filter(|&i| !chosen[i]).collect();
        let rest_fitness: Vec<f64> = rest.iter().map(|&i| fitness[i]).collect();
        select_by_rank(&rest_fitness, size.saturating_sub(survivors.len()), &mut self.rng, &mut self.picks);
        survivors.extend(self.picks.iter().map(|&k| rest[k]));

        let mut population: Vec<Individual> = Vec::with_capacity(size);
        let mut slots: Vec<Option<Individual>> = selectable.into_iter().map(Some).collect();
        population.extend(survivors.iter().filter_map(|&i| slots[i].take()));
        // Too few candidates (the operators found almost nothing new): fill up with
        // the rest of the old population, best first, rather than shrink.
        if population.len() < size {
            rank_order(&old_fitness, &mut self.picks);
            for &i in &self.picks {
                if population.len() >= size {
                    break;
                }
                if !population.iter().any(|p| p.genome == old[i].genome) {
                    population.push(old[i].clone());
                }
            }
        }
        self.population = population;
    }

    fn record(&mut self) -> GenerationLog {
        let best = self.best();
        let row = GenerationLog {
            generation: self.generation,
            episodes: self.cache.episodes(),
            best_fitness: best.fitness,
            best_length: best.genome.length(),
        };
        self.log.push(row);
        row
    }
}

/// Offspring slots of one generation (32 with Table I).
fn offspring_per_generation(p: &Params) -> usize {
    p.crossover_parents
        .saturating_mul(p.crossover_rounds)
        .saturating_add(p.mutation_parents.saturating_mul(p.mutation_offspring))
}

/// Runs a whole GP: [`Gp::new`] then [`Gp::run`].
///
/// # Errors
/// As [`Gp::new`].
pub fn run<F: Fitness + ?Sized>(
    alphabet: Alphabet,
    fitness: &F,
    params: Params,
    evaluation: Evaluation,
    on_generation: impl FnMut(&GenerationLog),
) -> Result<RunResult, GpError> {
    Ok(Gp::new(alphabet, fitness, params, evaluation)?.run(on_generation))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Variant;
    use planner::duplo::Task;

    #[test]
    fn boosting_lifts_the_baseline_for_selection_only() {
        let spec = Task::Tower.spec();
        let alphabet = Alphabet::from_catalog(&spec).unwrap();
        let baseline = bt_formats::tokens::parse("s( picked 0? pick 0! )", &spec).unwrap();
        // The baseline scores worst, every other tree by its length.
        let b = baseline.clone();
        let fitness = move |t: &[Node]| if t == b.as_slice() { -100.0 } else { -(t.len() as f64) };
        let params = Params::new(1, Variant::BoostAll, Some(baseline));
        let mut gp = Gp::new(alphabet, &fitness, params, Evaluation::Sequential).unwrap();
        let before: Vec<f64> = gp.population.iter().map(|i| i.fitness).collect();
        let at = gp.keep_baseline().unwrap();
        assert_eq!(before[at], -100.0);
        let max = before.iter().copied().fold(f64::NEG_INFINITY, f64::max);

        gp.parent_scores(Some(at), true);
        assert_eq!(gp.scores[at], max);
        let others = |s: &[f64]| s.iter().enumerate().filter(|(i, _)| *i != at).map(|(_, f)| *f).collect::<Vec<_>>();
        assert_eq!(others(&gp.scores), others(&before));
        gp.parent_scores(Some(at), false);
        assert_eq!(gp.scores, before);
        assert_eq!(gp.population.iter().map(|i| i.fitness).collect::<Vec<_>>(), before);
    }
}
