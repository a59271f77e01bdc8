//! Leaves and gates: a behavior of the models' set with its ports as values, or of a
//! known set with its grounded arguments.

use std::collections::BTreeMap;

use bt_core::{BehaviorId, Catalog, Leaf, LeafKind, NodeKind};

use super::Lowerer;
use crate::error::{Fault, ImportError, Result};
use crate::xml::flatten::Inst;

impl Lowerer<'_> {
    /// The leaf of a behavior of the models' set (an Action, a Condition, or a plugin
    /// decorator's gate), its ports as values.
    pub(super) fn model_leaf(&mut self, n: &Inst) -> Result<Leaf> {
        let Some((behavior, _)) = self.catalog.lookup(&n.id) else {
            return Err(ImportError::new(&n.at, Fault::UnknownNode(n.id.clone())));
        };
        let values = self.leaf_values(n, behavior)?;
        let start = u16::try_from(self.out.values.len()).unwrap_or(u16::MAX);
        let leaf = Leaf::with_values(behavior, &values, start).map_err(|e| {
            ImportError::new(&n.at, Fault::TooLarge(format!("<{}>: {e} (the image's value table is full)", n.id)))
        })?;
        if leaf.is_extended() {
            self.out.values.extend_from_slice(&values);
        }
        Ok(leaf)
    }
}

/// A known set's behaviors by name.
pub(super) fn known_names(k: &dyn Catalog) -> BTreeMap<String, BehaviorId> {
    let mut names = BTreeMap::new();
    for id in 0..k.len() {
        let Ok(id) = BehaviorId::try_from(id) else { break };
        if let Some(info) = k.info(id) {
            names.entry(info.name.to_string()).or_insert(id);
        }
    }
    names
}

/// The leaf of behavior `behavior` of a known set, its arguments read by port name.
pub(super) fn known_leaf(k: &dyn Catalog, behavior: BehaviorId, n: &Inst) -> Result<NodeKind> {
    let values = grounded_values(k, behavior, n)?;
    let leaf = Leaf::with_args(behavior, &values)
        .map_err(|e| ImportError::new(&n.at, Fault::TooLarge(format!("<{}>: {e}", n.id))))?;
    Ok(match k.info(behavior).map(|i| i.kind) {
        Some(LeafKind::Condition) => NodeKind::Condition(leaf),
        _ => NodeKind::Action(leaf),
    })
}

/// The grounded arguments of a leaf of a known set, by port name.
fn grounded_values(k: &dyn Catalog, behavior: BehaviorId, n: &Inst) -> Result<Vec<u16>> {
    let arity = k.info(behavior).map_or(0, |i| usize::from(i.arity));
    let names: Vec<String> = (0..arity).map(|pos| crate::xml::write::port_name(k, behavior, pos)).collect();
    for b in &n.ports {
        if !names.contains(&b.port) {
            return Err(ImportError::new(
                &b.at,
                Fault::UnknownPort { node: n.id.clone(), port: b.port.clone(), declared: names.clone() },
            ));
        }
    }
    let mut values = Vec::with_capacity(arity);
    for (pos, name) in names.iter().enumerate() {
        let Some(b) = n.ports.iter().find(|b| &b.port == name) else {
            return Err(ImportError::new(
                &n.at,
                Fault::UnknownPort { node: n.id.clone(), port: format!("{name} (missing)"), declared: names.clone() },
            ));
        };
        let Some(v) = k.parse_arg(behavior, pos, &b.raw) else {
            return Err(ImportError::new(
                &b.at,
                Fault::BadLiteral {
                    node: n.id.clone(),
                    port: name.clone(),
                    value: b.raw.clone(),
                    ty: "argument of this behavior set".into(),
                },
            ));
        };
        values.push(v);
    }
    Ok(values)
}
