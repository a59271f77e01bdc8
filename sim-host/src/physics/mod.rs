//! Physics worlds on rapier3d: the four brick tasks of Styrud et al. ([`PhysicsBrickWorld`])
//! and the mobile manipulator of Colledanchise et al. 2019 Fig. 1 ([`mobile::MobileWorld`]).
//!
//! Both are deterministic: a world is built fresh from its description (and, for the
//! mobile world, a seed), rapier3d runs single-threaded with its `enhanced-determinism`
//! feature (libm math, no SIMD lanes, ordered hash maps), and nothing reads a clock or
//! an unseeded generator. The same inputs give the same episode bit for bit, in one
//! thread or many.
//!
//! Units are SI (metres, kilograms, seconds); `z` points up and the table top is
//! `z = 0`, so a brick's reported position is the reference's: the centre of its
//! bottom face.
//!
//! ```
//! use bt_core::{Executor, NodeState, Status, Tree};
//! use planner::duplo::Task;
//! use sim_host::physics::PhysicsBrickWorld;
//! use sim_host::world::BrickWorld;
//! use worlds::World;
//!
//! let spec = Task::Tower.spec();
//! let nodes = bt_formats::tokens::parse("pick 0!", &spec)?;
//! let tree: Tree<'_, 8> = Tree::validate(&nodes, &spec)?;
//! let mut state = vec![NodeState::IDLE; nodes.len()];
//! let mut exec = Executor::new(tree, &mut state)?;
//! let mut world = PhysicsBrickWorld::new(&spec)?;
//! let mut status = Status::Running;
//! for t in 0..50 {
//!     status = exec.tick(&mut world, t)?;
//!     if status != Status::Running {
//!         break;
//!     }
//!     world.step();
//! }
//! assert_eq!(status, Status::Success);
//! assert_eq!(world.held(), Some(0));
//! assert!(world.position(0)[2] > 0.05, "lifted");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod brick_world;
mod bricks;
mod engine;
pub mod mobile;

pub use brick_world::{BrickEvent, BrickParams, PhysicsBrickWorld};
pub use bricks::{Dimensions, dimensions};

/// Why a physics world could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PhysicsError {
    /// The task description's lists do not agree.
    #[error("task {task}: {what}")]
    BadSpec {
        /// The task's name.
        task: &'static str,
        /// What is inconsistent.
        what: String,
    },
    /// A parameter outside its range.
    #[error("parameter `{name}` = {value}: {why}")]
    BadParameter {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The allowed range.
        why: &'static str,
    },
}
