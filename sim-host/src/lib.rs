//! Worlds that run behavior trees: symbolic (exact, microseconds per episode) and
//! physics (rapier3d), for the scenarios of the two papers; episodes and the fitness of
//! Styrud et al.; pictures of runs.
#![forbid(unsafe_code)]
// The library returns text; the binary writes it (with errors returned, never a panic).
#![deny(clippy::print_stdout, clippy::print_stderr)]
#![warn(missing_docs)]

pub mod blend;
pub mod episode;
pub mod groot2;
pub mod input;
pub mod learn;
pub mod physics;
pub mod picture;
pub mod scenario;
pub mod session;
pub mod symbolic;
pub mod text;
pub mod world;
