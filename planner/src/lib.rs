//! Backchaining synthesis of reactive behavior trees (Colledanchise, Almeida, Ögren,
//! "Towards Blended Reactive Planning and Acting using Behavior Trees", ICRA 2019).
//!
//! Plan Example 1 of the paper offline, then run the tree in the symbolic world:
//!
//! ```
//! use std::sync::Arc;
//! use bt_core::Catalog as _;
//! use bt_formats::{ascii, image::Image};
//! use planner::{domains, plan, Options, PddlCatalog, strips::{self, StripsWorld}};
//!
//! let g = Arc::new(domains::cube_sphere()?);
//! let catalog = Arc::new(PddlCatalog::new(g.problem()));
//! let p = plan(g.clone(), catalog.clone(), Options::default())?;
//! assert_eq!(p.expansions.len(), 4); // Fig. 3 (b) to (e)
//! println!("{}", ascii::to_ascii(&p.nodes, catalog.as_ref())?);
//!
//! // The image a controller loads; the tree reaches the goal in the STRIPS world.
//! let image = Image::new(&p.nodes).encode(catalog.fingerprint())?;
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
//! [`Planner::on_failure`], from a given state by [`expand_at`] ([`run_time`]); [`strips`]
//! (the symbolic world); [`domains`] and [`duplo`] (the shipped problems). The tree and
//! its names go out through `bt-formats` (image, ASCII, DOT, tokens) and `btcpp`
//! (BehaviorTree.CPP XML), which take a [`PddlCatalog`] as any behavior set.
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
mod offline;
mod options;
pub mod pddl;
mod planner;
pub mod refine;
pub mod regress;
pub mod run_time;
pub mod search;
pub mod state;
pub mod strips;
pub mod tree;
pub mod variables;
mod wording;

pub use catalog::PddlCatalog;
pub use error::PlanError;
pub use offline::fit::{Fitted, Size};
pub use offline::{GaveUp, Made, Plan, covered_line, plan, variables_line};
pub use options::{Fit, Method, Options};
pub use planner::{ConflictStep, Expansion, Planner};
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
