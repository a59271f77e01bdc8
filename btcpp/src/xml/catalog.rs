//! The behavior set of a document: its Action and Condition models, sorted by ID, with
//! their ports, as a bt-core [`Catalog`]; and the Rust table a controller compiles in.
//!
//! Behavior ids are the positions in ID order (byte order), so the set does not depend
//! on the order files are given in. Its fingerprint covers names, kinds and every port
//! (name, direction, type, default): an image imported against one set of models loads
//! only on a controller built from the same models.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use bt_core::{BehaviorId, BehaviorInfo, Catalog, LeafKind, PortInfo};

use crate::error::{Location, Result};
use crate::kinds::{self, Origin};
use crate::xml::model::{ModelKind, NodeModel, PortModel, classify};

/// One behavior: a leaf type with its ports.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Behavior {
    /// The registration ID, e.g. `ComputePathToPose`.
    pub id: String,
    /// Condition or action.
    pub kind: LeafKind,
    /// Its ports in model order: one value per port in every leaf.
    pub ports: Vec<PortModel>,
}

/// The models read, checked for conflicts: the behavior set and the other node types.
#[derive(Clone, Debug, Default)]
pub struct Models {
    /// Every non-built-in model by ID (controls, decorators, SubTrees included).
    pub by_id: BTreeMap<String, NodeModel>,
}

impl Models {
    /// Collects `models`, two of one ID made one ([`merge`](crate::xml::merge::merge):
    /// differences of a port's type or default are not refused, the `--nodes` model
    /// wins). Models of BehaviorTree.CPP's built-in nodes (which BehaviorTree.CPP itself
    /// writes into logs and Groot2 files) are skipped.
    ///
    /// # Errors
    /// [`Fault::ModelConflict`](crate::error::Fault::ModelConflict) at the second of two truly differing models.
    pub fn new(models: &[NodeModel]) -> Result<Self> {
        Self::read(models, false)
    }

    /// [`Models::new`]; with `nodes_override`, a `--nodes` model wins outright over a
    /// tree file's.
    ///
    /// # Errors
    /// As [`Models::new`].
    pub fn read(models: &[NodeModel], nodes_override: bool) -> Result<Self> {
        let mut by_id: BTreeMap<String, NodeModel> = BTreeMap::new();
        for m in models {
            if m.kind != ModelKind::SubTree && kinds::is_builtin(&m.id) {
                continue;
            }
            let merged = match by_id.get(&m.id) {
                Some(first) => crate::xml::merge::merge(first, m, nodes_override)?,
                None => m.clone(),
            };
            by_id.insert(m.id.clone(), merged);
        }
        Ok(Self { by_id })
    }

    /// The model of `id`.
    #[must_use]
    pub fn get(&self, id: &str) -> Option<&NodeModel> {
        self.by_id.get(id)
    }

    /// The behavior set: every Action and Condition model, and every plugin Decorator
    /// model (its gate, asked as an action: `bt_core::NodeKind::Gate`), by ID. Nav2's
    /// `RateController`, which bt-core has a kind for, is not a behavior.
    #[must_use]
    pub fn catalog(&self) -> XmlCatalog {
        let behaviors = self
            .by_id
            .values()
            .filter_map(|m| {
                let kind = match m.kind {
                    ModelKind::Action => LeafKind::Action,
                    ModelKind::Condition => LeafKind::Condition,
                    ModelKind::Decorator if kinds::by_id(&m.id).is_none_or(|e| e.origin != Origin::Nav2) => {
                        LeafKind::Action
                    }
                    _ => return None,
                };
                Some(Behavior { id: m.id.clone(), kind, ports: m.ports.clone() })
            })
            .collect();
        XmlCatalog { behaviors }
    }

    /// The `<SubTree>` models.
    #[must_use]
    pub fn subtree_models(&self) -> Vec<NodeModel> {
        self.by_id.values().filter(|m| m.kind == ModelKind::SubTree).cloned().collect()
    }
}

/// A behavior set read from `<TreeNodesModel>`s.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct XmlCatalog {
    behaviors: Vec<Behavior>,
}

impl XmlCatalog {
    /// A set of behaviors, sorted by ID.
    #[must_use]
    pub fn new(mut behaviors: Vec<Behavior>) -> Self {
        behaviors.sort_by(|a, b| a.id.cmp(&b.id));
        behaviors.dedup_by(|a, b| a.id == b.id);
        Self { behaviors }
    }

    /// The behaviors in id order.
    #[must_use]
    pub fn behaviors(&self) -> &[Behavior] {
        &self.behaviors
    }

    /// The behavior with this registration ID and its id.
    #[must_use]
    pub fn lookup(&self, id: &str) -> Option<(BehaviorId, &Behavior)> {
        let i = self.behaviors.binary_search_by(|b| b.id.as_str().cmp(id)).ok()?;
        Some((BehaviorId::try_from(i).ok()?, &self.behaviors[i]))
    }

    /// The Rust table a controller compiles in: one `bt_core::Behavior` per behavior
    /// with its ports, a `const` id per behavior, and the fingerprint, checked at
    /// compile time against the table.
    #[must_use]
    pub fn to_rust(&self, source: &str) -> String {
        let mut o = String::new();
        let _ = writeln!(o, "// Behavior set read from {source}: {} behaviors.", self.behaviors.len());
        let _ = writeln!(o, "// Written by `sim-host catalog --rust`; regenerate it rather than edit it.");
        let _ = writeln!(o);
        let _ = writeln!(o, "use bt_core::{{Behavior, BehaviorInfo, PortInfo, PortType}};\n");
        let _ = writeln!(o, "/// The behavior-set fingerprint images for this set carry.");
        let _ = writeln!(o, "pub const FINGERPRINT: u64 = {:#018x};\n", self.fingerprint());
        let consts = const_names(self.behaviors.iter().map(|b| b.id.as_str()));
        for (i, (b, c)) in self.behaviors.iter().zip(&consts).enumerate() {
            let _ = writeln!(o, "/// `{}`", b.id);
            let _ = writeln!(o, "pub const {c}: u16 = {i};");
        }
        let _ = writeln!(o);
        for (b, c) in self.behaviors.iter().zip(&consts) {
            let _ = writeln!(o, "/// The ports of `{}`.", b.id);
            let _ = writeln!(o, "pub const {c}_PORTS: [PortInfo<'static>; {}] = [", b.ports.len());
            for p in &b.ports {
                let ctor = match p.direction {
                    bt_core::PortDirection::Input => "input",
                    bt_core::PortDirection::Output => "output",
                    bt_core::PortDirection::InOut => "inout",
                };
                let _ = write!(
                    o,
                    "    PortInfo::{ctor}({:?}, PortType::{:?}, {:?})",
                    p.name,
                    classify(p.type_name.as_deref()),
                    p.type_name.as_deref().unwrap_or("")
                );
                if let Some(d) = &p.default {
                    let _ = write!(o, ".with_default({d:?})");
                }
                let _ = writeln!(o, ",");
            }
            let _ = writeln!(o, "];");
        }
        let _ = writeln!(o, "\n/// The behaviors, indexed by behavior id.");
        let _ = writeln!(o, "pub const BEHAVIORS: [Behavior<'static>; {}] = [", self.behaviors.len());
        for (b, c) in self.behaviors.iter().zip(&consts) {
            let kind = if b.kind == LeafKind::Condition { "condition" } else { "action" };
            let _ = writeln!(o, "    Behavior::new(BehaviorInfo::{kind}({:?}, {}), &{c}_PORTS),", b.id, b.ports.len());
        }
        let _ = writeln!(o, "];\n");
        let _ = writeln!(o, "const _: () = assert!(bt_core::fingerprint_with_ports(&BEHAVIORS) == FINGERPRINT);");
        o
    }
}

/// `SCREAMING_SNAKE_CASE` constant names for IDs, distinct.
fn const_names<'a>(ids: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for id in ids {
        let mut c = String::new();
        let mut prev_lower = false;
        for ch in id.chars() {
            if ch.is_ascii_alphanumeric() {
                if ch.is_ascii_uppercase() && prev_lower {
                    c.push('_');
                }
                prev_lower = ch.is_ascii_lowercase() || ch.is_ascii_digit();
                c.push(ch.to_ascii_uppercase());
            } else {
                if !c.ends_with('_') {
                    c.push('_');
                }
                prev_lower = false;
            }
        }
        if !c.starts_with(|ch: char| ch.is_ascii_alphabetic()) {
            c.insert_str(0, "B_");
        }
        let base = c.clone();
        let mut k = 2;
        while out.contains(&c) || c == "FINGERPRINT" || c == "BEHAVIORS" {
            c = format!("{base}_{k}");
            k += 1;
        }
        out.push(c);
    }
    out
}

impl Catalog for XmlCatalog {
    fn len(&self) -> usize {
        self.behaviors.len()
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        let b = self.behaviors.get(usize::from(id))?;
        Some(BehaviorInfo { name: &b.id, kind: b.kind, arity: u8::try_from(b.ports.len()).unwrap_or(u8::MAX) })
    }

    fn port(&self, id: BehaviorId, position: usize) -> Option<PortInfo<'_>> {
        let p = self.behaviors.get(usize::from(id))?.ports.get(position)?;
        Some(PortInfo {
            name: &p.name,
            direction: p.direction,
            ty: classify(p.type_name.as_deref()),
            type_name: p.type_name.as_deref().unwrap_or(""),
            default: p.default.as_deref(),
        })
    }
}

/// Where a model is, for errors about it.
#[must_use]
pub fn model_location(models: &Models, id: &str) -> Option<Location> {
    models.get(id).map(|m| m.at.clone())
}
