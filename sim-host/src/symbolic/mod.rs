//! Symbolic worlds: exact state machines with no physics, microseconds per episode.
//!
//! [`SymbolicBrickWorld`] is the fast brick world of Styrud et al., in which GP evaluates
//! hundreds of thousands of trees per second.
//!
//! ```
//! use bt_core::Tree;
//! use planner::duplo::Task;
//! use sim_host::episode::{End, Runner};
//! use sim_host::symbolic::SymbolicBrickWorld;
//!
//! let spec = Task::Tower.spec();
//! let nodes = bt_formats::tokens::parse(
//!     "s( f( 0 at pos (0.0, 0.05, 0.0)? s( pick 0! place at (0.0, 0.05, 0.0)! ) ) )",
//!     &spec,
//! )?;
//! let tree: Tree<'_, 8> = Tree::validate(&nodes, &spec)?;
//! let mut runner = Runner::new(SymbolicBrickWorld::new(&spec)?)?;
//! let episode = runner.run(tree)?;
//! assert_eq!(episode.end, End::Success);
//! // Tick 1 starts `pick 0!`, tick 2 picks and starts the place, tick 3 places (the
//! // pick succeeds at once: it holds brick 0) and the root succeeds, as on tick 4.
//! assert_eq!(episode.ticks, 4);
//! assert_eq!(episode.positions()[0], [0.0, 0.05, 0.0]);
//! // Bricks 1 and 2 are still 0.15 m or more from their goals.
//! assert!(episode.fitness.value() < -290.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod bricks;

pub use bricks::{
    BALANCE_TIP, BLOCKING_CONE_LIFT, BLOCKING_CONE_REACH, CROISSANT_CLEARANCE, HaltRule, NOT_PRESSED_GAP,
    ON_TOP_MARGIN, PICK_HEIGHT, POSITION_MARGIN, SymbolicBrickWorld, SymbolicError,
};
