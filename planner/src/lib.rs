//! Backchaining synthesis of reactive behavior trees (Colledanchise, Almeida, Ögren,
//! "Towards Blended Reactive Planning and Acting using Behavior Trees", ICRA 2019 —
//! seed 000).
//!
//! Plan Example 1 of the paper offline, then run the tree in the symbolic world:
//!
//! ```
//! use std::sync::Arc;
//! use planner::{domains, output, plan, Options, PddlCatalog, strips::{self, StripsWorld}};
//!
//! let g = Arc::new(domains::cube_sphere()?);
//! let catalog = Arc::new(PddlCatalog::new(g.problem()));
//! let p = plan(g.clone(), catalog.clone(), Options::default())?;
//! assert_eq!(p.expansions.len(), 4); // Fig. 3 (b) to (e)
//! println!("{}", output::to_ascii(&p.nodes, catalog.as_ref())?);
//!
//! // The image a controller loads; the tree reaches the goal in the STRIPS world.
//! let image = output::to_image(&p.nodes, catalog.as_ref())?;
//! let mut storage = vec![bt_core::Node::EMPTY; p.nodes.len()];
//! let tree: bt_core::Tree<'_, 32> = bt_core::load(&image, catalog.as_ref(), &mut storage)?;
//! let mut world = StripsWorld::new(g);
//! let out = strips::run((tree.nodes(), &[]), catalog.as_ref(), &mut world, 100, (), &mut Vec::new())?;
//! assert_eq!(out.status, bt_core::Status::Success);
//! assert!(world.holds_named("at", &["cube", "goal"]));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The pieces: [`model`] (domains, problems, builders) and [`pddl`] (PDDL input);
//! [`ground`] (grounding, the paper's action refinement); [`algorithm`] (the steps of
//! Algorithm 1) driven by a [`Planner`], offline by [`plan`] or online by
//! [`Planner::on_failure`], from a given state by [`expand_at`] ([`run_time`]); [`strips`] (the symbolic world); [`output`] (image, ASCII,
//! DOT, BehaviorTree.CPP XML) and [`tokens`]; [`domains`] and [`duplo`] (the shipped
//! problems).
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod algorithm;
mod catalog;
pub mod coverage;
pub mod domains;
pub mod duplo;
mod duplo_plan;
mod error;
pub mod ground;
pub mod guide;
pub mod model;
pub mod names;
mod offline;
pub mod output;
pub mod pddl;
mod planner;
pub mod refine;
pub mod regress;
pub mod run_time;
pub mod search;
pub mod state;
pub mod strips;
pub mod tokens;
pub mod tree;
pub mod variables;
mod wording;

pub use catalog::{NoPorts, PddlCatalog, Ports};
pub use error::PlanError;
pub use offline::{GaveUp, Made, Plan, covered_line, plan, variables_line};
pub use planner::{ConflictStep, Expansion, Method, Options, Planner};
pub use refine::Refinement;
pub use run_time::{AtRunTime, Belief, Blended, Change, ChangeError, Expanding, expand_at, parse_changes, run_blended};
pub use tree::DEPTH;

/// Plans a brick task with explicit [`Options`] (see [`duplo::plan`]).
///
/// # Errors
/// As [`plan`].
pub fn duplo_plan_with(task: duplo::Task, options: Options) -> Result<Plan<duplo::Spec>, PlanError> {
    duplo_plan::plan(task, options)
}
