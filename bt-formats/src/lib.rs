//! A behavior tree and its names in the notations people and tools read: the
//! deployable image with its names section ([`image`], [`names`]), the indented view
//! ([`ascii`]), Graphviz DOT ([`dot`]) and the token notation of Styrud et al.
//! ([`tokens`]).
//!
//! Every producer (the planner, genetic programming, the BehaviorTree.CPP importer)
//! hands a tree and its [`Names`] to [`image::Image`]; every consumer (`sim-host
//! inspect`, `export`, `btlog`) reads the names back from the image with
//! [`Names::of_image`] and shows the tree as its user wrote it. A [`Names`] is a
//! [`bt_core::Catalog`], so every notation takes it as it takes any behavior set.
//!
//! ```
//! use bt_core::{BehaviorInfo, Builder, Catalog, Node, Tree};
//! use bt_formats::{Names, ascii, dot, image::Image, tokens};
//!
//! // The producer: a tree over its behavior set, and the set's names.
//! const SET: [BehaviorInfo<'static>; 2] =
//!     [BehaviorInfo::condition("at goal?", 0), BehaviorInfo::action("MoveTo", 0)];
//! let mut storage = [Node::EMPTY; 3];
//! let mut b = Builder::<4>::new(&mut storage);
//! b.fallback()?.condition(0, &[])?.action(1, &[])?.end()?;
//! let nodes = b.finish()?;
//! let image = Image::new(nodes).names(&Names::of("go to the goal", &SET[..], &[])).encode(SET.fingerprint())?;
//!
//! // A consumer that knows nothing of the set: the names come with the image.
//! let names = Names::of_image(&image)?.expect("the image has names");
//! assert_eq!(names.title, "go to the goal");
//! let mut loaded = [Node::EMPTY; 3];
//! let tree: Tree<'_, 4> = bt_core::load(&image, &names, &mut loaded)?;
//! assert_eq!(ascii::to_ascii(tree.nodes(), &names)?, "[o] Fallback\n    --> at goal?\n    --> MoveTo\n");
//! assert_eq!(tokens::to_string(tree.nodes(), &names)?, "f( at goal? MoveTo! )");
//! assert!(dot::to_dot(tree.nodes(), &names).contains("n0 -> n2;"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod ascii;
pub mod constant;
pub mod dot;
pub mod image;
pub mod names;
pub mod tokens;

pub use constant::Constant;
pub use image::{Image, ImageError};
pub use names::{Names, NamesError};

/// The most levels (root and leaves included) of a tree the host tools make, load, show
/// and run: the planner emits no deeper tree, and `sim-host` (plan, inspect, export,
/// run, scenarios, learning) and `gp` load and tick trees up to this depth, so that
/// every tree one of them makes, the others take. A controller picks its own depth for
/// its own stack.
pub const DEPTH: usize = 128;
