//! The behaviors a written tree uses, each with a distinct type ID, and the
//! `<TreeNodesModel>` section that declares them.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use bt_core::{BehaviorId, Catalog, LeafKind};

use super::names::{behavior_name, escape, port_name, type_id};

/// The behaviors declared so far.
#[derive(Default)]
pub(super) struct Declared {
    /// Per behavior: its kind, arity and type ID (distinct: numbered on collision).
    used: BTreeMap<BehaviorId, (LeafKind, usize, String)>,
    /// The type IDs given.
    taken: BTreeSet<String>,
    /// Behaviors used as plugin decorators (gates): declared as `<Decorator>`.
    gates: BTreeSet<BehaviorId>,
}

impl Declared {
    /// Declares behavior `b` (once) and gives its type ID.
    pub fn declare<C: Catalog + ?Sized>(&mut self, catalog: &C, b: BehaviorId, kind: LeafKind, argc: usize) -> String {
        let taken = &mut self.taken;
        self.used
            .entry(b)
            .or_insert_with(|| {
                let base = type_id(&behavior_name(catalog, b));
                let mut id = base.clone();
                let mut k = 2;
                while !taken.insert(id.clone()) {
                    id = format!("{base}_{k}");
                    k += 1;
                }
                (kind, argc, id)
            })
            .2
            .clone()
    }

    /// Declares behavior `b` as a gate and gives its type ID.
    pub fn declare_gate<C: Catalog + ?Sized>(&mut self, catalog: &C, b: BehaviorId, argc: usize) -> String {
        let id = self.declare(catalog, b, LeafKind::Action, argc);
        self.gates.insert(b);
        id
    }

    /// Declares every behavior of the catalog, in id order.
    pub fn declare_all<C: Catalog + ?Sized>(&mut self, catalog: &C) {
        for b in 0..catalog.len() {
            let Ok(b) = BehaviorId::try_from(b) else { break };
            if let Some(info) = catalog.info(b) {
                self.declare(catalog, b, info.kind, usize::from(info.arity));
            }
        }
    }

    /// The `<TreeNodesModel>` section: each behavior declared with its ports.
    pub fn write<C: Catalog + ?Sized>(&self, catalog: &C, out: &mut String) {
        out.push_str("  <TreeNodesModel>\n");
        for (&b, &(kind, argc, ref name)) in &self.used {
            let tag = match kind {
                _ if self.gates.contains(&b) => "Decorator",
                LeafKind::Condition => "Condition",
                LeafKind::Action => "Action",
            };
            if argc == 0 {
                let _ = writeln!(out, "    <{tag} ID=\"{name}\"/>");
                continue;
            }
            let _ = writeln!(out, "    <{tag} ID=\"{name}\">");
            for pos in 0..argc {
                let _ = match catalog.port(b, pos) {
                    Some(p) => {
                        let ty = if p.type_name.is_empty() {
                            String::new()
                        } else {
                            format!(" type=\"{}\"", escape(p.type_name))
                        };
                        let default = p.default.map_or(String::new(), |d| format!(" default=\"{}\"", escape(d)));
                        writeln!(out, "      <{} name=\"{}\"{ty}{default}/>", p.direction.tag(), p.name)
                    }
                    None => {
                        writeln!(
                            out,
                            "      <input_port name=\"{}\" type=\"std::string\"/>",
                            port_name(catalog, b, pos)
                        )
                    }
                };
            }
            let _ = writeln!(out, "    </{tag}>");
        }
        out.push_str("  </TreeNodesModel>\n");
    }
}
