//! Models for the node types a tree uses that no model declares, guessed from how the
//! tree uses them (`sim-host catalog --stub`): a starting point for the models file a
//! user then checks, not a replacement for the program's registrations.
//!
//! - **Kind.** `<Action ID>`, `<Condition ID>`, `<Decorator ID>` and `<Control ID>` say
//!   it; a node written by its type with one child is a decorator, with more a control
//!   node; a leaf is a condition when its name asks a question (`IsBatteryLow`,
//!   `HasGoal`, `GoalReached`, `...Condition`), else an action.
//! - **Ports.** Every attribute any use gives (by the rules of the document's version):
//!   an input port when some use gives it a literal, else (only blackboard keys) an
//!   in/out port; no type.
//!
//! Every model written says which parts are guessed. A declared model whose node is
//! given a port it does not declare is reported, not changed ([`Stub::missing`]).

use std::fmt::Write as _;

use crate::error::{Location, Result};
use crate::kinds;
use crate::xml::catalog::Models;
use crate::xml::document::Document;
use crate::xml::flatten::{self, Inst, Value};
use crate::xml::model::ModelKind;
use crate::xml::write::escape;

/// A model written for a node type no model declares.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StubModel {
    /// The node type.
    pub id: String,
    /// Its kind.
    pub kind: ModelKind,
    /// Whether the kind is guessed (not named by the element).
    pub guessed: bool,
    /// Its ports: name, and whether some use gives a literal (an input port).
    pub ports: Vec<(String, bool)>,
    /// Where it is first used.
    pub at: Location,
    /// How many times the tree uses it.
    pub uses: usize,
}

/// What `--stub` found.
#[derive(Clone, Debug, Default)]
pub struct Stub {
    /// Models for the undeclared node types, in first-use order.
    pub models: Vec<StubModel>,
    /// Ports used on declared node types that their model lacks: node type, port, where.
    pub missing: Vec<(String, String, Location)>,
}

/// The stub of the main tree `main` of `doc` (see the module docs).
///
/// # Errors
/// The document's models conflict, or its main tree does not flatten.
pub fn stub(doc: &Document, main: Option<&str>, models: &Models) -> Result<Stub> {
    let tree = flatten::main_tree(doc, main)?;
    let flat = flatten::flatten(doc, tree, models)?;
    let mut out = Stub::default();
    let mut stack = vec![&flat.root];
    while let Some(n) = stack.pop() {
        stack.extend(n.children.iter().rev());
        if n.is_subtree || kinds::is_builtin(&n.id) || kinds::by_id_in(&n.id, flat.version).is_some() {
            continue;
        }
        if let Some(m) = models.get(&n.id) {
            for b in n.ports.iter().filter(|b| m.port(&b.port).is_none()) {
                if !out.missing.iter().any(|(id, p, _)| *id == n.id && *p == b.port) {
                    out.missing.push((n.id.clone(), b.port.clone(), b.at.clone()));
                }
            }
            continue;
        }
        let k = match out.models.iter().position(|s| s.id == n.id) {
            Some(k) => k,
            None => {
                let (kind, guessed) = guess(n);
                out.models.push(StubModel {
                    id: n.id.clone(),
                    kind,
                    guessed,
                    ports: vec![],
                    at: n.at.clone(),
                    uses: 0,
                });
                out.models.len() - 1
            }
        };
        let s = &mut out.models[k];
        s.uses += 1;
        for b in &n.ports {
            let literal = matches!(b.value, Value::Literal(_));
            match s.ports.iter_mut().find(|(p, _)| *p == b.port) {
                Some((_, lit)) => *lit |= literal,
                None => s.ports.push((b.port.clone(), literal)),
            }
        }
    }
    Ok(out)
}

/// A node's kind: named by its element, else guessed from its children and name.
fn guess(n: &Inst) -> (ModelKind, bool) {
    if let Some(kind) = n.tag {
        return (kind, false);
    }
    let kind = match n.children.len() {
        1 => ModelKind::Decorator,
        0 if asks(&n.id) => ModelKind::Condition,
        0 => ModelKind::Action,
        _ => ModelKind::Control,
    };
    (kind, true)
}

/// Whether a node type's name asks a question, as conditions are named.
fn asks(id: &str) -> bool {
    const ASKING: [&str; 11] = ["Is", "Has", "Have", "Can", "Check", "Was", "Are", "Should", "Does", "Did", "Will"];
    const ANSWERED: [&str; 6] = ["Condition", "Reached", "Received", "Updated", "Available", "Valid"];
    let starts = ASKING.iter().any(|p| id.strip_prefix(p).is_some_and(|rest| rest.starts_with(char::is_uppercase)));
    starts || ANSWERED.iter().any(|s| id.ends_with(s))
}

impl Stub {
    /// The models as a document `import --nodes` reads, each with what was guessed.
    #[must_use]
    pub fn to_xml(&self, tree: &str) -> String {
        let mut o = String::new();
        let _ = writeln!(o, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
        // (No `--` in a comment: XML forbids it.)
        let _ = writeln!(o, "<!-- Models of the node types {} uses that no model declares, written by", comment(tree));
        let _ = writeln!(o, "     `sim-host catalog` from how the tree uses them (its stub option). Check");
        let _ = writeln!(o, "     each kind and each port's direction, add the types, then give this file");
        let _ = writeln!(o, "     to `sim-host import` as models (its nodes option). -->");
        let _ = writeln!(o, "<root>");
        let _ = writeln!(o, "  <TreeNodesModel>");
        for m in &self.models {
            let why = match (m.guessed, m.kind) {
                (false, _) => "its element names the kind",
                (true, ModelKind::Decorator) => "guessed: it has one child",
                (true, ModelKind::Control) => "guessed: it has children",
                (true, ModelKind::Condition) => "guessed from its name: check it is not an action",
                (true, _) => "guessed: a leaf not named as a question; check it is not a condition",
            };
            let uses = if m.uses == 1 { "1 use".to_string() } else { format!("{} uses", m.uses) };
            let _ =
                writeln!(o, "    <!-- {}, {uses}, first at {}: {why} -->", comment(&m.id), comment(&m.at.to_string()));
            let tag = m.kind.tag();
            if m.ports.is_empty() {
                let _ = writeln!(o, r#"    <{tag} ID="{}"/>"#, escape(&m.id));
                continue;
            }
            let _ = writeln!(o, r#"    <{tag} ID="{}">"#, escape(&m.id));
            for (port, literal) in &m.ports {
                let (element, note) = if *literal {
                    ("input_port", "given a literal")
                } else {
                    ("inout_port", "given only blackboard keys: check whether it reads, writes or both")
                };
                let _ = writeln!(o, r#"      <{element} name="{}"/> <!-- {note} -->"#, escape(port));
            }
            let _ = writeln!(o, "    </{tag}>");
        }
        let _ = writeln!(o, "  </TreeNodesModel>");
        let _ = writeln!(o, "</root>");
        o
    }
}

/// Text for inside an XML comment, which may not hold `--` (nor end in `-`).
fn comment(text: &str) -> String {
    let mut out = text.replace("--", "- -");
    if out.ends_with('-') {
        out.push(' ');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conditions_are_named_as_questions() {
        for id in ["IsBatteryLow", "HasGoal", "GoalReached", "CheckDoorCondition", "WasTriggered"] {
            assert!(asks(id), "{id}");
        }
        for id in ["Island", "Move", "ComputePathToPose", "Check"] {
            assert!(!asks(id), "{id}");
        }
    }
}
