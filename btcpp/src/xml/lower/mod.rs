//! Lowering: the flattened document to bt-core nodes, leaf values, constants and
//! blackboard slots.
//!
//! BehaviorTree.CPP's built-ins and Nav2's control nodes become the bt-core kinds with
//! the same semantics, as [`crate::kinds`] maps them (submodule `builtins`; the table
//! for users is in `docs/behaviortree-cpp.md`); a plugin `<Decorator>` a model declares
//! becomes a [`NodeKind::Gate`] whose leaf is the decorator's behavior with its ports
//! (`leaves`).
//!
//! A leaf's values are its ports in model order, each a packed
//! [`PortValue`](bt_core::PortValue): constants interned in first-use order, blackboard
//! entries numbered as slots in first-use order (pre-order, then port order), unset
//! ports marked unset. A key local to a SubTree instance that only starts with a literal
//! and that no port writes is read as that literal (`values`).
//!
//! Scripts and scripted attributes are compiled into the value table (`scripts`), and
//! so are loops' queues (`loops`). This module is the driver: it walks the tree and
//! picks each node's way.

use std::collections::{BTreeMap, BTreeSet};

mod blackboard;
mod builtins;
mod leaves;
mod loops;
mod scripts;
mod values;

use bt_core::port::SlotInfo;
use bt_core::{BehaviorId, Catalog, Leaf, LeafKind, Node, NodeKind, PortDirection};

use crate::error::{Fault, ImportError, Location, Result};
use crate::kinds::{self, Shape};
use crate::xml::catalog::{Models, XmlCatalog};
use crate::xml::document::Version;
use crate::xml::flatten::{Bound, Flat, Inst, Key, Value};
use crate::xml::model::{Literal, ModelKind};
use crate::xml::script;

pub use blackboard::stoi;
pub use bt_formats::names::{NodeSource, SubtreeSource};
pub use scripts::script_name;

/// A blackboard slot of an imported tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Slot {
    /// The key's name (qualified by the SubTree instance's path for keys local to one).
    pub name: String,
    /// Its type and initial value, as the image holds them.
    pub info: SlotInfo,
    /// The C++ type of the first port that uses it.
    pub type_name: Option<String>,
}

/// Which behavior set leaves resolve against.
#[derive(Clone, Copy)]
pub enum Target<'k> {
    /// The set of the document's models ([`XmlCatalog`]).
    Models,
    /// A set the caller knows (a PDDL domain, a brick task), to import XML that
    /// [`to_xml`](crate::xml::to_xml) wrote for it back into the same set: a leaf names
    /// its behavior by its element (or its `name` attribute, which the writer adds when
    /// the behavior's name is not an XML name) and its arguments by the ports the
    /// writer names them with ([`Catalog::port_name`], else `arg0`, ...), read back with
    /// [`Catalog::parse_arg`].
    Known(&'k dyn Catalog),
}

impl std::fmt::Debug for Target<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Models => f.write_str("Models"),
            Self::Known(c) => write!(f, "Known({:#018x})", c.fingerprint()),
        }
    }
}

/// A document imported: the tree, its behavior set and everything the image holds.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The main tree's ID.
    pub main: String,
    /// The fingerprint of the behavior set the leaves refer to.
    pub fingerprint: u64,
    /// The behavior set, when it is the models' (empty for a known set).
    pub catalog: XmlCatalog,
    /// The nodes, pre-order.
    pub nodes: Vec<Node>,
    /// The value table of extended leaves.
    pub values: Vec<u16>,
    /// Blackboard slots.
    pub slots: Vec<Slot>,
    /// Constants.
    pub constants: Vec<Literal>,
    /// What the document says of each node, parallel to `nodes`.
    pub meta: Vec<NodeSource>,
    /// The SubTree nodes, in uid order.
    pub subtrees: Vec<SubtreeSource>,
    /// The scripting enums the scripts were compiled with, as given.
    pub enums: Vec<(String, i64)>,
    /// The rules the document was read by, which [`Imported::to_xml`] writes it for.
    pub version: Version,
}

impl Imported {
    /// The values of leaf `leaf` (inline or extended).
    #[must_use]
    pub fn leaf_values<'a>(&'a self, leaf: &'a Leaf) -> &'a [u16] {
        leaf.args_in(&self.values)
    }
}

/// Lowers a flattened tree against `models`.
///
/// # Errors
/// The first [`ImportError`]: unknown node types and ports, constructs without a
/// bt-core equivalent, bad literals, type conflicts on a key, trees too large.
pub fn lower(
    flat: &Flat,
    models: &Models,
    target: Target<'_>,
    enums: &[(String, i64)],
    casts: &[(String, String)],
    loops: &[String],
) -> Result<Imported> {
    let catalog = match target {
        Target::Models => models.catalog(),
        Target::Known(_) => XmlCatalog::default(),
    };
    let fingerprint = match target {
        Target::Models => catalog.fingerprint(),
        Target::Known(k) => k.fingerprint(),
    };
    let known = match target {
        Target::Models => None,
        Target::Known(k) => Some((k, leaves::known_names(k))),
    };
    let mut l = Lowerer {
        flat,
        models,
        catalog,
        known,
        enums: enums.iter().cloned().collect(),
        casts,
        loops,
        written: BTreeSet::new(),
        ported: BTreeSet::new(),
        script_slots: BTreeSet::new(),
        out: Imported {
            main: flat.main.clone(),
            fingerprint,
            catalog: XmlCatalog::default(),
            nodes: Vec::new(),
            values: Vec::new(),
            slots: Vec::new(),
            constants: Vec::new(),
            meta: Vec::new(),
            subtrees: Vec::new(),
            enums: enums.to_vec(),
            version: flat.version,
        },
        slot_ids: BTreeMap::new(),
        slot_first: Vec::new(),
        constant_ids: BTreeMap::new(),
    };
    l.collect_written(&flat.root);
    l.check_declared(&flat.root)?;
    l.node(&flat.root)?;
    l.out.subtrees.sort_by_key(|s| s.uid);
    let mut out = l.out;
    out.catalog = l.catalog;
    Ok(out)
}

struct Lowerer<'a> {
    flat: &'a Flat,
    models: &'a Models,
    catalog: XmlCatalog,
    known: Option<(&'a dyn Catalog, BTreeMap<String, BehaviorId>)>,
    /// Scripting enums: names scripts read as numbers.
    enums: BTreeMap<String, i64>,
    /// Polymorphic casts, `(derived, base)`.
    casts: &'a [(String, String)],
    /// Node types registered as loops over a type of the program's.
    loops: &'a [String],
    /// Keys some output or in/out port, or a script, writes.
    written: BTreeSet<Key>,
    /// Keys some port names (they exist before any script runs, as in BehaviorTree.CPP).
    ported: BTreeSet<Key>,
    /// Slots a script named first: a port naming them later gives them its type.
    script_slots: BTreeSet<u16>,
    out: Imported,
    slot_ids: BTreeMap<Key, u16>,
    slot_first: Vec<Location>,
    constant_ids: BTreeMap<(u8, String), u16>,
}

impl Lowerer<'_> {
    /// Refuses, at once, every node type the tree uses that is neither a built-in (of
    /// either version: the other version's are refused by name where they are lowered)
    /// nor declared by a model nor registered as a loop, with where each is first used.
    fn check_declared(&self, root: &Inst) -> Result<()> {
        let mut undeclared: Vec<(String, Location)> = Vec::new();
        let mut stack = vec![root];
        while let Some(n) = stack.pop() {
            stack.extend(n.children.iter().rev());
            if n.is_subtree || undeclared.iter().any(|(id, _)| *id == n.id) {
                continue;
            }
            let known = match &self.known {
                Some((_, names)) => {
                    names.contains_key(&n.id) || n.name.as_deref().is_some_and(|m| names.contains_key(m))
                }
                None => self.models.get(&n.id).is_some(),
            };
            let other_builtin = kinds::is_builtin(&n.id);
            let a_loop = n.id.starts_with("Loop") && n.ports.iter().any(|b| b.port == "queue");
            if !(known
                || other_builtin
                || a_loop
                || self.loops.contains(&n.id)
                || kinds::by_id_in(&n.id, self.flat.version).is_some())
            {
                undeclared.push((n.id.clone(), n.at.clone()));
            }
        }
        match undeclared.first() {
            None => Ok(()),
            Some((_, at)) => Err(ImportError::new(at, Fault::Undeclared { nodes: undeclared.clone() })),
        }
    }

    fn collect_written(&mut self, root: &Inst) {
        let mut stack = vec![root];
        while let Some(n) = stack.pop() {
            stack.extend(n.children.iter());
            for hook in &n.hooks {
                if let Ok(script) = script::parse(&hook.raw) {
                    for name in script.assigned() {
                        self.written.insert(self.flat.resolve(n.hook_scope, name));
                    }
                }
            }
            if kinds::by_id_in(&n.id, self.flat.version).is_some_and(kinds::Entry::takes_scripts)
                && let Some(code) = n.ports.iter().find(|b| b.port == "code" || b.port == "if")
                && let Ok(script) = script::parse(&code.raw)
            {
                for name in script.assigned() {
                    self.written.insert(self.flat.resolve(n.scope, name));
                }
            }
            if n.id == "SetBlackboard" && kinds::by_id_in(&n.id, self.flat.version).is_some() {
                self.written.extend(blackboard::set_blackboard_key(self, n));
                continue;
            }
            if kinds::loop_element(&n.id).is_some() || self.loops.contains(&n.id) {
                // A loop writes its `value`. Its `{queue}` it pops in place only when a
                // node's output port put a queue there (that port writes it); a string
                // it reads as a queue, without writing it.
                for b in n.ports.iter().filter(|b| b.port == "value" || b.port == "queue") {
                    if let Value::Key(k) = &b.value {
                        self.ported.insert(k.clone());
                        if b.port == "value" {
                            self.written.insert(k.clone());
                        }
                    }
                }
                continue;
            }
            let Some((_, b)) = self.catalog.lookup(&n.id) else { continue };
            if n.is_subtree {
                continue;
            }
            for p in &b.ports {
                let key = match n.ports.iter().find(|x| x.port == p.name) {
                    Some(Bound { value: Value::Key(k), .. }) => Some(k.clone()),
                    Some(_) => None,
                    None => p
                        .default
                        .as_deref()
                        .and_then(|d| self.flat.port_key(&p.name, d))
                        .map(|k| self.flat.resolve(n.scope, k)),
                };
                if let Some(k) = &key {
                    self.ported.insert(k.clone());
                }
                if p.direction != PortDirection::Input {
                    self.written.extend(key);
                }
            }
        }
    }

    fn node(&mut self, n: &Inst) -> Result<()> {
        if !n.hooks.is_empty() {
            // A guard in front of the node, holding its scripted attributes.
            let index = self.out.nodes.len();
            if index >= usize::from(u16::MAX) {
                return Err(ImportError::new(&n.at, Fault::TooLarge(format!("more than {} nodes", u16::MAX))));
            }
            self.out.nodes.push(Node::EMPTY);
            self.out.meta.push(NodeSource {
                id: "Guard".into(),
                name: None,
                uid: n.uid,
                params: Vec::new(),
                flat: None,
            });
            let kind = self.guard(n)?;
            self.node_unguarded(n)?;
            let size = u16::try_from(self.out.nodes.len() - index)
                .map_err(|_| ImportError::new(&n.at, Fault::TooLarge(format!("more than {} nodes", u16::MAX))))?;
            self.out.nodes[index] = Node::new(kind, size);
            return Ok(());
        }
        self.node_unguarded(n)
    }

    fn node_unguarded(&mut self, n: &Inst) -> Result<()> {
        if n.is_subtree {
            let attrs = n.ports.iter().map(|b| (b.port.clone(), b.raw.clone())).collect();
            self.out.subtrees.push(SubtreeSource {
                // Trees of more nodes than a u16 counts are refused later.
                node: u16::try_from(self.out.nodes.len()).unwrap_or(u16::MAX),
                uid: n.uid,
                id: n.id.clone(),
                name: n.name.clone(),
                path: n.path.clone(),
                instance: self.flat.scopes.get(n.scope).map(|s| s.path.clone()).unwrap_or_default(),
                attrs,
            });
            return match n.children.as_slice() {
                [child] => self.node(child),
                _ => Err(ImportError::new(&n.at, Fault::NoTree)),
            };
        }
        let index = self.out.nodes.len();
        if index >= usize::from(u16::MAX) {
            return Err(ImportError::new(&n.at, Fault::TooLarge(format!("more than {} nodes", u16::MAX))));
        }
        self.out.nodes.push(Node::EMPTY);
        // A built-in's parameters as written (a leaf's or a gate's ports are its values).
        let params = if kinds::by_id_in(&n.id, self.flat.version).is_some() || self.loops.contains(&n.id) {
            n.ports.iter().map(|b| (b.port.clone(), b.raw.clone())).collect()
        } else {
            Vec::new()
        };
        self.out.meta.push(NodeSource { id: n.id.clone(), name: n.name.clone(), uid: n.uid, params, flat: None });
        let (kind, shape) = self.kind(n)?;
        if !shape.fits(n.children.len()) {
            return Err(ImportError::new(
                &n.at,
                Fault::Children { node: n.id.clone(), expected: shape.rule(), found: n.children.len() },
            ));
        }
        for c in &n.children {
            self.node(c)?;
        }
        let size = u16::try_from(self.out.nodes.len() - index)
            .map_err(|_| ImportError::new(&n.at, Fault::TooLarge(format!("more than {} nodes", u16::MAX))))?;
        self.out.nodes[index] = Node::new(kind, size);
        Ok(())
    }

    /// The bt-core kind of a node and how many children it takes.
    fn kind(&mut self, n: &Inst) -> Result<(NodeKind, Shape)> {
        if let Some(entry) = kinds::by_id_in(&n.id, self.flat.version) {
            return Ok((self.builtin(n, entry)?, entry.shape));
        }
        if self.loops.contains(&n.id) {
            builtins::check_ports(n, &kinds::LOOP_PORTS)?;
            let kind = self.loop_kind(n, bt_core::script::Element::Registered)?;
            return Ok((kind, Shape::Decorator));
        }
        if let Some(m) = self.models.get(&n.id) {
            match m.kind {
                ModelKind::Control => {
                    let reason = format!(
                        "it is a plugin control node; bt-core runs the control nodes of BehaviorTree.CPP and Nav2's {}",
                        kinds::nav2_controls()
                    );
                    return Err(builtins::unsupported(&n.at, &n.id, &reason));
                }
                ModelKind::Decorator => {
                    // A plugin decorator: a gate asked through the behavior set.
                    let leaf = self.model_leaf(n)?;
                    return Ok((NodeKind::Gate(leaf), Shape::Decorator));
                }
                _ => {}
            }
        }
        if let Some((k, names)) = &self.known {
            let found = n.name.as_deref().and_then(|name| names.get(name)).or_else(|| names.get(&n.id));
            let Some(&behavior) = found else {
                return Err(ImportError::new(&n.at, Fault::UnknownNode(n.id.clone())));
            };
            return Ok((leaves::known_leaf(*k, behavior, n)?, Shape::Leaf));
        }
        if let Some((_, b)) = self.catalog.lookup(&n.id) {
            let condition = b.kind == LeafKind::Condition;
            let leaf = self.model_leaf(n)?;
            let kind = if condition { NodeKind::Condition(leaf) } else { NodeKind::Action(leaf) };
            return Ok((kind, Shape::Leaf));
        }
        if n.id.starts_with("Loop") && n.ports.iter().any(|b| b.port == "queue") {
            return Err(ImportError::new(&n.at, Fault::UnknownLoop(n.id.clone())));
        }
        Err(builtins::of_the_other_version(n, self.flat.version)
            .unwrap_or_else(|| ImportError::new(&n.at, Fault::UnknownNode(n.id.clone()))))
    }
}
