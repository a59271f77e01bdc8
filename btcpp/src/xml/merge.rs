//! Two models of one node type, made one as BehaviorTree.CPP treats them.
//!
//! BehaviorTree.CPP goes by what the C++ program registers, which the `--nodes` files
//! stand for ([`Origin::Given`]); the models in a tree file (as Groot saves them,
//! [`Origin::InFile`]) it ignores. So two models that differ only in a port's `type`,
//! `default` or description are one: the given one wins (so that the behavior set's
//! fingerprint is the one of the controller built from the `--nodes` files), else the
//! first read. Where they truly differ — the kind, a port's direction, a port one of
//! them lacks — the import stops and says which models, what differs and how to choose;
//! with `--nodes-override` ([`merge`]'s `nodes_override`) a given model wins outright
//! over a tree file's.

use crate::error::{Fault, ImportError, Result};
use crate::xml::model::{NodeModel, Origin};

/// The model of `first` and `second` (same ID; `first` read first).
///
/// # Errors
/// [`Fault::ModelConflict`] at `second`, naming what differs with both values.
pub fn merge(first: &NodeModel, second: &NodeModel, nodes_override: bool) -> Result<NodeModel> {
    // The given one wins; between two of the same origin, the first read.
    let (winner, loser) = if second.origin == Origin::Given && first.origin == Origin::InFile {
        (second, first)
    } else {
        (first, second)
    };
    let overridden = winner.origin == Origin::Given && loser.origin == Origin::InFile;
    if nodes_override && overridden {
        return Ok(winner.clone());
    }
    let conflict = |difference: String| {
        let hint = match (first.origin, second.origin) {
            (Origin::Given, Origin::Given) => {
                "; a program registers a node type once: give one model of it in the --nodes files".to_string()
            }
            (Origin::InFile, Origin::InFile) => {
                "; BehaviorTree.CPP ignores the models in tree files: give the node's model with --nodes and --nodes-override".to_string()
            }
            _ => format!(
                "; BehaviorTree.CPP goes by the program's registration, which the --nodes files stand for: --nodes-override takes the model at {} and ignores the one at {}",
                winner.at, loser.at
            ),
        };
        ImportError::new(
            &second.at,
            Fault::ModelConflict { id: second.id.clone(), first: first.at.clone(), difference, hint },
        )
    };
    if first.kind != second.kind {
        return Err(conflict(format!("its kind, {} here and {} there", second.kind.tag(), first.kind.tag())));
    }
    for p in &second.ports {
        match first.port(&p.name) {
            None => return Err(conflict(format!("port `{}`, declared here and not there", p.name))),
            Some(q) if q.direction != p.direction => {
                return Err(conflict(format!(
                    "port `{}`, {} here and {} there",
                    p.name,
                    direction(p.direction),
                    direction(q.direction)
                )));
            }
            Some(_) => {}
        }
    }
    if let Some(q) = first.ports.iter().find(|q| second.port(&q.name).is_none()) {
        return Err(conflict(format!("port `{}`, not declared here and declared there", q.name)));
    }
    Ok(winner.clone())
}

fn direction(d: bt_core::PortDirection) -> &'static str {
    match d {
        bt_core::PortDirection::Input => "an input port",
        bt_core::PortDirection::Output => "an output port",
        bt_core::PortDirection::InOut => "an in/out port",
    }
}
