//! Genetic programming over reactive behavior trees, with a planner's tree as
//! baseline: the GP of Styrud et al., "Combining Planning and Learning of Behavior
//! Trees for Robotic Assembly", exactly as Section III, Table I and the
//! reference details give it.
//!
//! A run evolves a population of trees over one task's conditions and actions (an
//! [`Alphabet`] from any [`bt_core::Catalog`]); a [`Fitness`] — one episode in a world —
//! scores each tree once ([`FitnessCache`]); generations log the learning curve as
//! [`GenerationLog`] rows (`generation,episodes,best_fitness,best_length`).
//!
//! ```
//! use gp::{Alphabet, Evaluation, Gp, Params, Variant};
//! use planner::duplo::Task;
//!
//! let spec = Task::Tower.spec();
//! let alphabet = Alphabet::from_catalog(&spec)?;
//! let pick_0 = spec.id_by_name("pick 0!").unwrap();
//!
//! // A stand-in world: a tree scores well if it picks brick 0, and better the
//! // smaller it is (the 0.1-per-node penalty of Eq. 1).
//! let fitness = |tree: &[bt_core::Node]| {
//!     let picks = tree.iter().any(|n| matches!(n.kind(), bt_core::NodeKind::Action(l) if l.behavior() == pick_0));
//!     let reward = if picks { 0.0 } else { -10.0 };
//!     reward - 0.1 * tree.len() as f64
//! };
//!
//! // The planner's tree as baseline, kept in the population.
//! let baseline = bt_formats::tokens::parse("s( picked 1? pick 0! )", &spec)?;
//! let mut params = Params::new(1, Variant::Baseline, Some(baseline));
//! params.generations = 30;
//!
//! let gp = Gp::new(alphabet, &fitness, params, Evaluation::Parallel)?;
//! let result = gp.run(|row| assert!(row.episodes <= 16 + 32 * u64::from(row.generation)));
//! assert_eq!(result.log.len(), 30);
//! assert!(result.best.fitness >= -0.3, "{}", result.best.genome.to_text(&spec)?);
//! print!("{}", gp::to_csv(&result.log));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The modules, in the paper's order: [`genome`] (the token view and validity rules),
//! [`operators`] (random trees, mutation, crossover), [`selection`], [`fitness`], and
//! [`run`](mod@run) (the generation loop, with the baseline and the boosting variants);
//! beyond the paper, [`islands`] (several populations with migration and restarts, for
//! a solved tree every time).
//!
//! # A run's record
//!
//! [`Params::to_record`] writes every GP setting as `key = value` lines (seed, variant,
//! generations and the baseline in the token notation included) and
//! [`Params::from_record`] reads them back exactly; [`parse_record`] splits the same
//! syntax for the caller's own keys (task, world, version). The learning curve is a
//! CSV with the header [`CSV_HEADER`] ([`to_csv`], [`read_csv`]).
//!
//! # Where Table I and the reference leave room
//!
//! Styrud et al., its Table I and the reference details (`docs/brick-tasks.md`)
//! fix the algorithm; where they are silent, ambiguous or disagree, this crate
//! decides as follows, following the published reference code where it speaks.
//!
//! - **Generations.** `generations = N` logs generations `0..N`: the initial
//!   population and `N - 1` bred ones, as the reference counts (tower: 200).
//! - **Episodes** in a row are counted *after* that generation's evaluation: row 0
//!   shows the initial population's episodes (16). The reference logs 0 there (it
//!   counts before evaluating the initial population).
//! - **Offspring per generation.** Table I's second "mutation offspring per parent"
//!   row is read as crossover offspring per parent: 2 crossover rounds, each pairing
//!   the 8 crossover parents anew (2 children per pair), and 2 mutations per mutation
//!   parent: at most 32 new trees per generation, as Section V says.
//! - **"Mutating population and crossover offspring".** Mutation parents are drawn
//!   from the population only (the reference's settings: crossover parents may be
//!   mutated, crossover offspring may not); the crossover offspring count only in the
//!   duplicate check of the mutation offspring.
//! - **10 % of 16** is `round(1.6) = 2`, for both the old members that compete with
//!   the offspring and the elites; [`Params`] holds counts, not fractions.
//! - **Rank selection** draws without replacement (weights `n` down to 1 among those
//!   not drawn yet); asked for more than there are, it returns all.
//! - **Ties in rank** go to the later individual in the list (the reference sorts
//!   `(fitness, index)` pairs descending); lists are old population, crossover
//!   offspring, mutation offspring, so an offspring outranks an equally fit old tree.
//!   The best individual of a generation is the first in this order.
//! - **Population order** after survival: the elites best first, then the others in
//!   the order drawn, then the baseline if it was put back.
//! - **The baseline is put back** at the end of a generation rather than the start of
//!   the next (no random draw comes between, so the run is the same), so the
//!   population then has 17 members; it is boosted to the maximum of the whole
//!   population (itself included, which equals "the rest" unless it is the best).
//!   Boosting works on a copy of the scores, so nothing needs restoring.
//! - **The baseline is inserted as given**, even if it breaks a validity rule (the
//!   planner's tree); as in the reference, an invalid tree never takes part in
//!   crossover, and its mutations must be valid.
//! - **Change** draws the new node by the random-node rule (control with probability
//!   0.5, else any leaf): control by control and leaf by leaf (condition or action)
//!   in place, plus the reference's control-to-leaf and leaf-to-control rules.
//! - **Two identical children** of one crossover pair are refused (the second counts
//!   the first as an earlier offspring); the reference does not check this.
//! - **Too few candidates to fill the population** (the operators found almost
//!   nothing new): the rest of the old population fills it, best first. The
//!   reference raises an error there.
//! - **Random trees** are redrawn at most [`operators::RANDOM_TREE_ATTEMPTS`] times
//!   (the reference redraws forever; past ~25 nodes valid draws become too rare). The
//!   initial population redraws a duplicate up to 100 times, as the reference does.
//! - **A size bound** ([`Bound`], none by default; not in the paper) is one more
//!   validity rule: random trees and offspring over it are refused before they are
//!   simulated, and a baseline over it is an error ([`GpError::BaselineTooBig`]).
//! - **Offspring size**: at least `min_length` = 2 nodes (the reference counts tokens;
//!   the same for valid trees). A NaN fitness counts as `-inf`.
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod alphabet;
mod bound;
mod edit;
pub mod fitness;
pub mod genome;
pub mod islands;
mod log;
pub mod operators;
mod params;
pub mod run;
pub mod selection;

pub use alphabet::{Alphabet, AlphabetError};
pub use bound::Bound;
pub use fitness::{Fitness, FitnessCache, Size, image_size};
pub use genome::{Genome, GenomeError, Invalid, Token};
pub use log::{CSV_HEADER, CsvError, GenerationLog, read_csv, to_csv, write_csv};
pub use operators::{MutationRates, crossover, mutate, random_tree};
pub use params::{Entry, Params, ParamsError, RecordError, UnknownVariant, Variant, parse_record};
pub use run::{Evaluation, Gp, GpError, Individual, RunResult, run};
