//! Reactive behavior trees for robot controllers: `#![no_std]`, no allocation, no
//! recursion, no `unsafe`, no panics.
//!
//! A tree is one flat pre-order array of [`Node`]s. It becomes runnable only as a
//! validated [`Tree`] — from [`Tree::validate`] or from image bytes through [`load`] —
//! and an [`Executor`] ticks it against a [`BehaviorSet`] (the caller's conditions and
//! actions), keeping per-node state in an array the caller owns.
//!
//! ```
//! use bt_core::*;
//!
//! // The behavior set, as host and controller both declare it.
//! const BEHAVIORS: [BehaviorInfo<'static>; 2] =
//!     [BehaviorInfo::condition("at goal?", 0), BehaviorInfo::action("MoveTo", 1)];
//! const AT_GOAL: u16 = 0;
//! const MOVE_TO: u16 = 1;
//!
//! struct World { position: i32, goal: i32 }
//! impl BehaviorSet for World {
//!     fn condition(&mut self, _: &Leaf, _: Context<'_>) -> Status {
//!         if self.position == self.goal { Status::Success } else { Status::Failure }
//!     }
//!     fn action(&mut self, _: &Leaf, _: Context<'_>) -> Status {
//!         self.position += 1;
//!         Status::Running
//!     }
//!     fn halt(&mut self, _: &Leaf, _: NodeId) {}
//! }
//!
//! // Fallback[ at goal?, MoveTo(3) ], built into caller storage.
//! let mut storage = [Node::EMPTY; 3];
//! let mut b = Builder::<4>::new(&mut storage);
//! b.fallback()?.condition(AT_GOAL, &[])?.action(MOVE_TO, &[3])?.end()?;
//! let tree: Tree<'_, 4> = Tree::validate(b.finish()?, &BEHAVIORS)?;
//!
//! let mut state = [NodeState::IDLE; 3];
//! let mut exec = Executor::new(tree, &mut state)?;
//! let mut world = World { position: 0, goal: 2 };
//! assert_eq!(exec.tick(&mut world, 0)?, Status::Running);
//! assert_eq!(exec.tick(&mut world, 1)?, Status::Running);
//! assert_eq!(exec.tick(&mut world, 2)?, Status::Success);
//! assert_eq!(
//!     tree.display(&BEHAVIORS).with_states(exec.states()).to_string(),
//!     "[o] Fallback [✓]\n    --> at goal? [✓]\n    --> MoveTo(3)\n"
//! );
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The tick semantics are in [`exec`]; the image byte layout and its versioning rule in
//! [`image`].
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]
#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing))]

mod behavior;
mod builder;
mod catalog;
mod error;
pub mod exec;
pub mod image;
mod node;
pub mod port;
pub mod render;
pub mod script;
mod status;
mod tree;

pub use behavior::{BehaviorSet, Context, Observer, Selection, TickError};
pub use builder::Builder;
pub use catalog::{Behavior, BehaviorInfo, Catalog, fingerprint, fingerprint_with_ports};
pub use error::{ArgumentFault, BuildError, EncodeError, LoadError};
pub use exec::{Carry, Executor, NodeState, StateTooSmall};
pub use image::{encode, encode_with, load, load_with, load_with_ports};
pub use node::{Arity, BehaviorId, Code, Leaf, LeafError, LeafKind, MAX_ARGS, Node, NodeId, NodeKind, Span};
pub use port::{Port, PortDirection, PortInfo, PortTable, PortType, PortValue};
pub use render::Render;
pub use status::{NodeStatus, Status};
pub use tree::{Children, Tree, children};
