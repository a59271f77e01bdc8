//! Worlds that run behavior trees: symbolic (exact, microseconds per episode) and
//! physics (rapier3d), for the scenarios of the two papers.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod physics;
pub mod world;
