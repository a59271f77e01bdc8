//! Cross-crate integration tests live in `tests/tests/`: the whole pipeline, from a plan
//! or a learning run to image bytes, to the executor ticking a world.
//!
//! The library holds what the differential test against BehaviorTree.CPP shares with
//! the tool that makes its cases ([`btcpp`]).

pub mod btcpp;
