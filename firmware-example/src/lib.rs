//! The cube-and-sphere scenario of Colledanchise et al. 2019 (Fig. 1, Examples 1-2) as a controller:
//! a behavior-tree image made on the host, loaded and validated by bt-core, ticked at a
//! fixed rate against a 2-D plant model with scripted external events.
//!
//! The library is `no_std` without allocation and builds for the Cortex-M4F and for the
//! host alike: the firmware binary runs [`run`] under QEMU, the host runs the very same
//! function, and `cargo xtask qemu` compares the two traces byte for byte.
//!
//! ```no_run
//! use firmware_example::{IMAGE, Sink, run};
//! struct Stdout;
//! impl Sink for Stdout {
//!     fn line(&mut self, line: &[u8]) { println!("{}", String::from_utf8_lossy(line)) }
//! }
//! assert!(run(IMAGE, &mut Stdout, |_| {}).reached_goal());
//! ```
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]
#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing))]

#[cfg(all(target_os = "none", feature = "mps2-an386"))]
pub mod board;
pub mod catalog;
pub mod control;
pub mod link;
pub mod plant;
pub mod script;
#[cfg(target_os = "none")]
pub mod target;

pub use control::{Line, MAX_NODES, MAX_TICKS, Outcome, Ran, Sink, TickReport, run};

/// The image of the tree the firmware runs, made by `build.rs` from `gen/tree.rs`.
pub static IMAGE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/tree.img"));

/// [`IMAGE`] with one bit flipped: the loader must refuse it.
pub static CORRUPT_IMAGE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/tree-corrupt.img"));

#[cfg(test)]
mod tests;
