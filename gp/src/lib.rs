//! Genetic programming over reactive behavior trees, with a planner's tree as
//! baseline: the GP of Styrud et al., "Combining Planning and Learning of Behavior
//! Trees for Robotic Assembly" (seed 003), exactly as Section III, Table I and the
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
//! let baseline = planner::tokens::parse("s( picked 1? pick 0! )", &spec)?;
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
//! [`run`] (the generation loop, with the baseline and the boosting variants).
//! Decisions where Table I and the reference leave room are listed in `gp/README.md`.
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod alphabet;
mod edit;
pub mod fitness;
pub mod genome;
mod log;
pub mod operators;
mod params;
pub mod run;
pub mod selection;

pub use alphabet::{Alphabet, AlphabetError};
pub use fitness::{Fitness, FitnessCache};
pub use genome::{Genome, GenomeError, Invalid, Token};
pub use log::{CSV_HEADER, CsvError, GenerationLog, read_csv, to_csv, write_csv};
pub use operators::{MutationRates, crossover, mutate, random_tree};
pub use params::{Entry, Params, ParamsError, RecordError, UnknownVariant, Variant, parse_record};
pub use run::{Evaluation, Gp, GpError, Individual, RunResult, run};
