//! Differential testing against BehaviorTree.CPP: the tree spec, the random cases, the
//! fixtures recorded from BehaviorTree.CPP by `tests/btcpp/record.sh`.

pub mod btlog;
pub mod case;
pub mod generate;
pub mod run;
pub mod spec;
pub mod v3;
