//! Pictures of runs, as standalone SVG documents: what people would rather look at than
//! read.
//!
//! - [`bricks`]: a brick episode (`sim-host run --svg`): the bricks' paths over the
//!   table, their heights against ticks, the tree's statuses tick by tick;
//! - [`scenario`]: a scenario run (`sim-host scenario --svg`): every body's path, the
//!   events and expansions where they happened, the tree at chosen moments.
//!
//! One writer draws both: the document, escaping, labels that keep clear of each
//! other, and one look for a node's status and kind.

pub mod bricks;
pub mod scenario;
mod tree;
mod writer;

pub use bricks::{MAX_COLUMNS, Run, svg};
