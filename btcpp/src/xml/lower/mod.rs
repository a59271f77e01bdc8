//! Lowering: the flattened document to bt-core nodes, leaf values, constants and
//! blackboard slots.
//!
//! BehaviorTree.CPP's built-ins and Nav2's control nodes become the bt-core kinds with
//! the same semantics (the table is in `docs/behaviortree-cpp.md`); a plugin
//! `<Decorator>` a model declares becomes a [`NodeKind::Gate`] whose leaf is the
//! decorator's behavior with its ports.
//!
//! A leaf's values are its ports in model order, each a packed
//! [`PortValue`]: constants interned in first-use order, blackboard
//! entries numbered as slots in first-use order (pre-order, then port order), unset
//! ports marked unset. A key local to a SubTree instance that only starts with a literal
//! and that no port writes is read as that literal.

use std::collections::{BTreeMap, BTreeSet};

use bt_core::port::{SlotInfo, UNSET};
use bt_core::{BehaviorId, Catalog, Code, Leaf, LeafKind, Node, NodeKind, PortDirection, PortType, PortValue, Span};

use crate::error::{Fault, ImportError, Location, Result};
use crate::xml::builtin::{LOOP_PORTS, SCRIPT_ATTRIBUTES, Shape, builtin, loop_element, nav2};
use crate::xml::catalog::{Models, XmlCatalog};
use crate::xml::flatten::{Bound, Flat, Inst, Key, Value, blackboard_key, resolve};
use crate::xml::model::{Literal, ModelKind, convert};
use crate::xml::script;

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

/// What BehaviorTree.CPP knows about a node that the bt-core node does not keep.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NodeMeta {
    /// Registration ID (`Sequence`, `ComputePathToPose`).
    pub id: String,
    /// The `name` attribute.
    pub name: Option<String>,
    /// BehaviorTree.CPP's node id.
    pub uid: u16,
    /// A built-in node's parameters as written (`num_cycles="-1"`), in document order:
    /// what BehaviorTree.CPP writes back into its logs, where bt-core keeps only the
    /// resolved value. Empty for leaves and plugin decorators (their ports are values).
    pub params: Vec<(String, String)>,
    /// For a script node or a guard: its attributes as the XML of the flattened tree
    /// writes them, each script with every key as that tree names it (a key a SubTree
    /// remaps becomes its parent's, a SubTree's local key its [`script_name`]; a
    /// guard's attributes go on the node it guards). `None` for other nodes, whose
    /// `params` are written as they are.
    pub flat: Option<Vec<(String, String)>>,
}

/// A `<SubTree>` node of the document: BehaviorTree.CPP keeps it as a node (with a uid
/// and status), bt-core does not.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SubtreeMeta {
    /// The bt-core node its subtree's root became.
    pub node: usize,
    /// BehaviorTree.CPP's node id.
    pub uid: u16,
    /// The subtree's ID.
    pub id: String,
    /// The `name` attribute.
    pub name: Option<String>,
    /// The node's `_fullpath`.
    pub path: String,
    /// The instance's path (the `_fullpath` of its `<BehaviorTree>`).
    pub instance: String,
    /// Its port attributes as written.
    pub attrs: Vec<(String, String)>,
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
    /// Per node, parallel to `nodes`.
    pub meta: Vec<NodeMeta>,
    /// The SubTree nodes, in uid order.
    pub subtrees: Vec<SubtreeMeta>,
    /// The scripting enums the scripts were compiled with, as given.
    pub enums: Vec<(String, i64)>,
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
        Target::Known(k) => Some((k, known_names(k))),
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
        },
        slot_ids: BTreeMap::new(),
        slot_first: Vec::new(),
        constant_ids: BTreeMap::new(),
    };
    l.collect_written(&flat.root);
    l.node(&flat.root)?;
    l.out.subtrees.sort_by_key(|s| s.uid);
    let mut out = l.out;
    out.catalog = l.catalog;
    Ok(out)
}

/// Whether a value of type `from` may be read as `to` through `casts`
/// (`(derived, base)`): upwards through any number of casts, or down one, as
/// BehaviorTree.CPP's polymorphic cast registry allows.
fn converts(casts: &[(String, String)], from: &str, to: &str) -> bool {
    if casts.iter().any(|(derived, base)| derived == to && base == from) {
        return true;
    }
    // Upwards: the bases reachable from `from` (a cycle of casts ends when no type is new).
    let mut reached = vec![from];
    let mut next = 0;
    while let Some(&t) = reached.get(next) {
        if t == to {
            return true;
        }
        for (derived, base) in casts {
            if derived == t && !reached.contains(&base.as_str()) {
                reached.push(base);
            }
        }
        next += 1;
    }
    false
}

/// The name a slot has in the XML of the flattened tree, where scripts name it too: its
/// key when that is a script identifier, else (a SubTree's local key, `MySub::3/x`)
/// every run of other characters made one `_` (`MySub_3_x`), with a `_` in front of a
/// digit.
#[must_use]
pub fn script_name(name: &str) -> std::borrow::Cow<'_, str> {
    let word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    if name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') && name.chars().all(word) {
        return name.into();
    }
    let mut out = String::with_capacity(name.len() + 1);
    if !name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        out.push('_');
    }
    for c in name.chars() {
        if word(c) {
            out.push(c);
        } else if !out.ends_with('_') {
            out.push('_');
        }
    }
    out.into()
}

/// A known set's behaviors by name.
fn known_names(k: &dyn Catalog) -> BTreeMap<String, BehaviorId> {
    let mut names = BTreeMap::new();
    for id in 0..k.len() {
        let Ok(id) = BehaviorId::try_from(id) else { break };
        if let Some(info) = k.info(id) {
            names.entry(info.name.to_string()).or_insert(id);
        }
    }
    names
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

/// What a port of a node reads: the attribute, or the model's default.
enum Given<'b> {
    Attr(&'b Bound),
    Default(String),
    Unset,
}

impl Lowerer<'_> {
    fn collect_written(&mut self, root: &Inst) {
        let mut stack = vec![root];
        while let Some(n) = stack.pop() {
            stack.extend(n.children.iter());
            for hook in &n.hooks {
                if let Ok(script) = script::parse(&hook.raw) {
                    for name in script.assigned() {
                        self.written.insert(resolve(&self.flat.scopes, n.hook_scope, name));
                    }
                }
            }
            if matches!(n.id.as_str(), "Script" | "ScriptCondition" | "Precondition")
                && let Some(code) = n.ports.iter().find(|b| b.port == "code" || b.port == "if")
                && let Ok(script) = script::parse(&code.raw)
            {
                for name in script.assigned() {
                    self.written.insert(resolve(&self.flat.scopes, n.scope, name));
                }
            }
            if loop_element(&n.id).is_some() || self.loops.contains(&n.id) {
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
                    None => {
                        p.default.as_deref().and_then(blackboard_key).map(|k| resolve(&self.flat.scopes, n.scope, k))
                    }
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
            self.out.meta.push(NodeMeta { id: "Guard".into(), name: None, uid: n.uid, params: Vec::new(), flat: None });
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
            self.out.subtrees.push(SubtreeMeta {
                node: self.out.nodes.len(),
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
        let params = if builtin(&n.id).or_else(|| nav2(&n.id)).is_some() || self.loops.contains(&n.id) {
            n.ports.iter().map(|b| (b.port.clone(), b.raw.clone())).collect()
        } else {
            Vec::new()
        };
        self.out.meta.push(NodeMeta { id: n.id.clone(), name: n.name.clone(), uid: n.uid, params, flat: None });
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
        if let Some(b) = builtin(&n.id).or_else(|| nav2(&n.id)) {
            if let Some(reason) = b.refused {
                return Err(unsupported(&n.at, &n.id, reason));
            }
            check_ports(n, b.ports)?;
            if b.id == "Precondition" {
                let code = self.script_code(n, "if")?;
                let otherwise = self.status_param(n, "else", bt_core::Status::Failure)?;
                return Ok((NodeKind::Precondition { code, otherwise }, Shape::Decorator));
            }
            if let Some(element) = loop_element(b.id) {
                return Ok((self.loop_kind(n, element)?, Shape::Decorator));
            }
            if matches!(b.id, "Script" | "ScriptCondition") {
                let code = self.script_code(n, "code")?;
                let kind = if b.id == "Script" { NodeKind::Script(code) } else { NodeKind::ScriptCondition(code) };
                return Ok((kind, Shape::Leaf));
            }
            let kind = self.builtin_kind(n, b.id)?;
            return Ok((kind, Shape::of(&kind)));
        }
        if self.loops.contains(&n.id) {
            check_ports(n, &LOOP_PORTS)?;
            return Ok((self.loop_kind(n, bt_core::script::Element::Registered)?, Shape::Decorator));
        }
        if let Some(m) = self.models.get(&n.id) {
            match m.kind {
                ModelKind::Control => {
                    return Err(unsupported(
                        &n.at,
                        &n.id,
                        "it is a plugin control node; bt-core runs the control nodes of BehaviorTree.CPP and Nav2's PipelineSequence, RecoveryNode and RoundRobin",
                    ));
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
            let k = *k;
            let values = grounded_values(k, behavior, n)?;
            let leaf = Leaf::with_args(behavior, &values)
                .map_err(|e| ImportError::new(&n.at, Fault::TooLarge(format!("<{}>: {e}", n.id))))?;
            let kind = match k.info(behavior).map(|i| i.kind) {
                Some(LeafKind::Condition) => NodeKind::Condition(leaf),
                _ => NodeKind::Action(leaf),
            };
            return Ok((kind, Shape::Leaf));
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
        Err(ImportError::new(&n.at, Fault::UnknownNode(n.id.clone())))
    }

    /// A `Script`'s or `ScriptCondition`'s program, in the value table: keys become slots
    /// (of no type unless a port gives them one), strings constants.
    fn script_code(&mut self, n: &Inst, port: &'static str) -> Result<Code> {
        let Some(bound) = n.ports.iter().find(|b| b.port == port) else {
            return Err(ImportError::new(&n.at, Fault::MissingAttribute { element: n.id.clone(), attribute: port }));
        };
        let (words, flat) = self.compile_script(n, bound, n.scope)?;
        if let Some(meta) = self.out.meta.last_mut() {
            let written = |text: &String| {
                meta.params.iter().map(|(k, v)| (k.clone(), if k == port { text.clone() } else { v.clone() })).collect()
            };
            meta.flat = Some(written(&flat));
        }
        self.place(n, &words)
    }

    /// Words appended to the value table, as a [`Code`].
    fn place(&mut self, n: &Inst, words: &[u16]) -> Result<Code> {
        let start = u16::try_from(self.out.values.len()).ok();
        let len = u16::try_from(words.len()).ok();
        let full = || ImportError::new(&n.at, Fault::TooLarge("the image's value table is full".into()));
        let (Some(start), Some(len)) = (start, len) else {
            return Err(full());
        };
        if start.checked_add(len).is_none() {
            return Err(full());
        }
        self.out.values.extend_from_slice(words);
        Ok(Code { start, len })
    }

    /// A script attribute of `n` (`bound`) compiled with its keys read in `scope`: its
    /// program, and its text with every key as the flattened tree names it.
    fn compile_script(&mut self, n: &Inst, bound: &Bound, scope: usize) -> Result<(Vec<u16>, String)> {
        let fault = |e: script::ScriptError| {
            let mut code: String = bound.raw.chars().take(80).collect();
            if code.len() < bound.raw.len() {
                code.push_str("...");
            }
            ImportError::new(
                &bound.at,
                Fault::Script {
                    node: n.id.clone(),
                    attribute: bound.port.clone(),
                    code,
                    message: e.message,
                    offset: e.offset,
                },
            )
        };
        let parsed = script::parse(&bound.raw).map_err(fault)?;
        let (words, mut keys) = {
            let mut symbols = ScriptSymbols { l: self, n, scope, at: &bound.at, failed: None, keys: Vec::new() };
            let compiled = parsed.compile(&mut symbols);
            if let Some(e) = symbols.failed {
                return Err(e);
            }
            (compiled.map_err(fault)?, symbols.keys)
        };
        // The script as the flattened tree names its keys.
        let mut flat = bound.raw.clone();
        keys.sort_by_key(|k| std::cmp::Reverse(k.0));
        for (offset, written, slot) in keys {
            let name = script_name(&self.out.slots[usize::from(slot)].name);
            if *name != written && flat.get(offset..offset + written.len()) == Some(written.as_str()) {
                flat.replace_range(offset..offset + written.len(), &name);
            }
        }
        Ok((words, flat))
    }

    /// The guard of a node with scripted attributes: their table (a mask, then each
    /// hook's length and program, in [`bt_core::script::Hook`] order) in the value table.
    fn guard(&mut self, n: &Inst) -> Result<NodeKind> {
        let mut mask = 0u16;
        let mut table = vec![0u16];
        let mut flat = Vec::new();
        for (bit, name) in SCRIPT_ATTRIBUTES.iter().enumerate() {
            let Some(bound) = n.hooks.iter().find(|b| b.port == *name) else { continue };
            let (words, text) = self.compile_script(n, bound, n.hook_scope)?;
            mask |= 1 << bit;
            let len = u16::try_from(words.len())
                .map_err(|_| ImportError::new(&bound.at, Fault::TooLarge("a script longer than 65535 words".into())))?;
            table.push(len);
            table.extend_from_slice(&words);
            flat.push((name.to_string(), text));
        }
        table[0] = mask;
        if let Some(meta) = self.out.meta.last_mut() {
            meta.params = n.hooks.iter().map(|b| (b.port.clone(), b.raw.clone())).collect();
            meta.flat = Some(flat);
        }
        Ok(NodeKind::Guard(self.place(n, &table)?))
    }

    /// The leaf of a behavior of the models' set (an Action, a Condition, or a plugin
    /// decorator's gate), its ports as values.
    fn model_leaf(&mut self, n: &Inst) -> Result<Leaf> {
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

    /// The kind of a BehaviorTree.CPP built-in or a Nav2 control node, its parameters
    /// read as BehaviorTree.CPP and Nav2 read them.
    fn builtin_kind(&self, n: &Inst, id: &str) -> Result<NodeKind> {
        let children = n.children.len();
        Ok(match id {
            "ReactiveSequence" => NodeKind::Sequence,
            "ReactiveFallback" => NodeKind::Fallback,
            "Sequence" => NodeKind::SequenceWithMemory,
            "Fallback" => NodeKind::FallbackWithMemory,
            "SequenceWithMemory" => NodeKind::SequenceStar,
            "IfThenElse" => NodeKind::IfThenElse,
            "WhileDoElse" => NodeKind::WhileDoElse,
            "Inverter" => NodeKind::Inverter,
            "ForceSuccess" => NodeKind::ForceSuccess,
            "ForceFailure" => NodeKind::ForceFailure,
            "KeepRunningUntilFailure" => NodeKind::KeepRunningUntilFailure,
            "Sleep" => NodeKind::Sleep(self.span_param(n, "msec")?),
            "AlwaysSuccess" => NodeKind::AlwaysSuccess,
            "AlwaysFailure" => NodeKind::AlwaysFailure,
            "PipelineSequence" => NodeKind::PipelineSequence,
            "RoundRobin" => {
                if let Some(b) = n.ports.iter().find(|b| b.port == "wrap_around") {
                    return Err(unsupported_construct(
                        &b.at,
                        format!("<RoundRobin wrap_around=\"{}\">", b.raw),
                        "bt-core's RoundRobin is Nav2's classic one (Nav2 jazzy): it fails once every child has failed in turn and goes on from the first; leave wrap_around out",
                    ));
                }
                NodeKind::RoundRobin
            }
            "Parallel" => {
                let s = self.int_param(n, "success_count", Some(-1))?;
                let f = self.int_param(n, "failure_count", Some(1))?;
                let resolve = |t: i64| if t < 0 { (children as i64 + t + 1).max(0) } else { t };
                let (rs, rf) = (resolve(s), resolve(f));
                for (port, v) in [("success_count", rs), ("failure_count", rf)] {
                    if v < 1 || v > children as i64 {
                        return Err(unsupported_construct(
                            &n.at,
                            format!("<Parallel {port}> of {v} with {children} children"),
                            "the threshold must be between 1 and the number of children",
                        ));
                    }
                }
                NodeKind::Parallel { success_threshold: rs as u16, failure_threshold: rf as u16, count_skipped: s < 0 }
            }
            "ParallelAll" => {
                let m = self.int_param(n, "max_failures", Some(1))?;
                let resolved = if m < 0 { (children as i64 + m + 1).max(0) } else { m };
                if resolved > children as i64 {
                    return Err(unsupported_construct(
                        &n.at,
                        format!("<ParallelAll max_failures=\"{m}\"> with {children} children"),
                        "it could never fail (BehaviorTree.CPP refuses it when ticked)",
                    ));
                }
                NodeKind::ParallelAll { max_failures: resolved as u16 }
            }
            "Repeat" => NodeKind::RepeatCycles(self.cycles_param(n, "num_cycles")?),
            "RetryUntilSuccessful" => NodeKind::RetryUntilSuccessful(self.cycles_param(n, "num_attempts")?),
            "RunOnce" => NodeKind::RunOnce { then_skip: self.bool_param(n, "then_skip", true)? },
            "ManualSelector" => {
                if children > usize::from(u8::MAX) {
                    return Err(unsupported_construct(
                        &n.at,
                        format!("<ManualSelector> with {children} children"),
                        "the behavior set chooses a child by a number from 0 to 254: at most 255 children",
                    ));
                }
                NodeKind::ManualSelector { repeat_last: self.bool_param(n, "repeat_last_selection", false)? }
            }
            "Timeout" => NodeKind::TimeLimit(self.span_param(n, "msec")?),
            "Delay" => NodeKind::Delay(self.span_param(n, "delay_msec")?),
            "RecoveryNode" => {
                let r = self.int_param(n, "number_of_retries", Some(1))?;
                let retries = u16::try_from(r).map_err(|_| {
                    unsupported_construct(
                        &n.at,
                        format!("<RecoveryNode number_of_retries=\"{r}\">"),
                        "the number of retries must be between 0 and 65535",
                    )
                })?;
                NodeKind::Recovery { retries }
            }
            "RateController" => {
                let (text, at) =
                    self.param_text(n, "hz", Some("10.0"))?.unwrap_or_else(|| ("10.0".to_string(), n.at.clone()));
                let hz = match convert(Some("double"), &text) {
                    Some(Literal::Double(v)) => v,
                    _ => {
                        return Err(ImportError::new(
                            &at,
                            Fault::BadLiteral {
                                node: n.id.clone(),
                                port: "hz".into(),
                                value: text,
                                ty: "double".into(),
                            },
                        ));
                    }
                };
                // The period in milliseconds, rounded up so the rate is never exceeded.
                // (Less a hair, so that the rate written for a period reads back as it.)
                let ms = if hz > 0.0 { (1000.0 / hz * (1.0 - 1e-12)).ceil() } else { f64::INFINITY };
                let span = (ms.is_finite() && ms <= f64::from(Span::MAX))
                    .then(|| Span::new(ms as u32))
                    .flatten()
                    .ok_or_else(|| {
                        unsupported_construct(
                            &at,
                            format!("<RateController hz=\"{text}\">"),
                            "the rate must be above 0 and its period at most 16,777,215 ms",
                        )
                    })?;
                NodeKind::RateController(span)
            }
            other => return Err(unsupported(&n.at, other, "bt-core has no node kind with its semantics")),
        })
    }

    /// The literal text of a built-in's parameter (its default when absent).
    fn param_text(&self, n: &Inst, port: &str, default: Option<&str>) -> Result<Option<(String, Location)>> {
        let Some(b) = n.ports.iter().find(|b| b.port == port) else {
            return Ok(default.map(|d| (d.to_string(), n.at.clone())));
        };
        match &b.value {
            Value::Literal(v) => Ok(Some((v.clone(), b.at.clone()))),
            Value::Key(k) => match self.initial_literal(k) {
                Some(v) => Ok(Some((v, b.at.clone()))),
                None => Err(ImportError::new(
                    &b.at,
                    Fault::ParameterFromBlackboard { node: n.id.clone(), port: port.into(), value: b.raw.clone() },
                )),
            },
        }
    }

    fn int_param(&self, n: &Inst, port: &str, default: Option<i64>) -> Result<i64> {
        let d = default.map(|d| d.to_string());
        let Some((text, at)) = self.param_text(n, port, d.as_deref())? else {
            return Err(ImportError::new(
                &n.at,
                Fault::MissingAttribute { element: n.id.clone(), attribute: leak(port) },
            ));
        };
        match convert(Some("int"), &text) {
            Some(Literal::Int(v)) => Ok(v),
            _ => Err(ImportError::new(
                &at,
                Fault::BadLiteral { node: n.id.clone(), port: port.into(), value: text, ty: "int".into() },
            )),
        }
    }

    /// `num_cycles` / `num_attempts`: -1 is forever, other negative counts are 0 (the
    /// child is not ticked), as BehaviorTree.CPP reads them.
    fn cycles_param(&self, n: &Inst, port: &str) -> Result<u16> {
        let v = self.int_param(n, port, None)?;
        match v {
            -1 => Ok(NodeKind::FOREVER),
            v if v < 0 => Ok(0),
            v => u16::try_from(v).ok().filter(|&v| v != NodeKind::FOREVER).ok_or_else(|| {
                let at = n.ports.iter().find(|b| b.port == port).map_or(&n.at, |b| &b.at);
                unsupported_construct(
                    at,
                    format!("<{} {port}=\"{v}\">", n.id),
                    "the count must be -1 (forever) or between 0 and 65534",
                )
            }),
        }
    }

    /// A span in milliseconds (`msec`, `delay_msec`).
    fn span_param(&self, n: &Inst, port: &str) -> Result<Span> {
        let v = self.int_param(n, port, None)?;
        u32::try_from(v).ok().and_then(Span::new).ok_or_else(|| {
            let at = n.ports.iter().find(|b| b.port == port).map_or(&n.at, |b| &b.at);
            unsupported_construct(
                at,
                format!("<{} {port}=\"{v}\">", n.id),
                "milliseconds must be between 0 and 16,777,215 (4 h 39 min)",
            )
        })
    }

    fn bool_param(&self, n: &Inst, port: &str, default: bool) -> Result<bool> {
        let d = if default { "true" } else { "false" };
        let Some((text, at)) = self.param_text(n, port, Some(d))? else {
            return Ok(default);
        };
        match convert(Some("bool"), &text) {
            Some(Literal::Bool(b)) => Ok(b),
            _ => Err(ImportError::new(
                &at,
                Fault::BadLiteral { node: n.id.clone(), port: port.into(), value: text, ty: "bool".into() },
            )),
        }
    }

    /// A status parameter (`else`, `if_empty`): SUCCESS, FAILURE, RUNNING or SKIPPED.
    fn status_param(&self, n: &Inst, port: &str, default: bt_core::Status) -> Result<bt_core::Status> {
        let Some((text, at)) = self.param_text(n, port, None)? else {
            return Ok(default);
        };
        Ok(match text.trim() {
            "SUCCESS" => bt_core::Status::Success,
            "FAILURE" => bt_core::Status::Failure,
            "RUNNING" => bt_core::Status::Running,
            "SKIPPED" => bt_core::Status::Skipped,
            _ => {
                return Err(ImportError::new(
                    &at,
                    Fault::BadLiteral {
                        node: n.id.clone(),
                        port: port.into(),
                        value: text,
                        ty: "status (SUCCESS, FAILURE, RUNNING or SKIPPED)".into(),
                    },
                ));
            }
        })
    }

    /// A loop (`LoopInt`, ..., or one the program registers): its queue's table in the
    /// value table ([`bt_core::script::queue`]). A literal queue (`"1;2;3"`, split at
    /// `;` as BehaviorTree.CPP splits it, or a SubTree-local key that starts with one)
    /// becomes one assignment program per element; a `{key}` the slots
    /// [`BehaviorSet::pop`](bt_core::BehaviorSet::pop) is given.
    fn loop_kind(&mut self, n: &Inst, element: bt_core::script::Element) -> Result<NodeKind> {
        use bt_core::script::{Element, QUEUE_KEY};
        use script::Push;
        let if_empty = self.status_param(n, "if_empty", bt_core::Status::Success)?;
        let (ty, type_name) = match element {
            Element::Int => (PortType::Int, Some("int")),
            Element::Bool => (PortType::Bool, Some("bool")),
            Element::Double => (PortType::Double, Some("double")),
            Element::String => (PortType::String, Some("std::string")),
            Element::Registered => (PortType::Any, None),
        };
        let mut flat = Vec::new();
        // The `value` port: a key (BehaviorTree.CPP drops the elements without one).
        let value = match n.ports.iter().find(|b| b.port == "value") {
            None => None,
            Some(b) => match &b.value {
                Value::Literal(text) => {
                    return Err(ImportError::new(
                        &b.at,
                        Fault::OutputLiteral { node: n.id.clone(), port: "value".into(), value: text.clone() },
                    ));
                }
                Value::Key(k) => {
                    let v = self.slot_value(k, (ty, PortDirection::Output), type_name, &b.at, n, "value")?;
                    match PortValue::from_u16(v) {
                        PortValue::Slot(id) => Some(id),
                        _ => return Err(ImportError::new(&b.at, Fault::TooLarge("no slot for `value`".into()))),
                    }
                }
            },
        };
        let Some(queue) = n.ports.iter().find(|b| b.port == "queue") else {
            return Err(ImportError::new(&n.at, Fault::MissingAttribute { element: n.id.clone(), attribute: "queue" }));
        };
        let registered = |l: &mut Self, at: &Location| match element {
            Element::Registered => l.intern(Literal::Str(n.id.clone()), at),
            _ => Ok(u16::MAX),
        };
        let literal = match &queue.value {
            Value::Literal(text) => Ok(text.clone()),
            Value::Key(k) => self.initial_literal(k).ok_or(k),
        };
        let table;
        match literal {
            Ok(text) => {
                if element == Element::Registered {
                    return Err(unsupported_construct(
                        &queue.at,
                        format!("<{} queue=\"{}\">", n.id, queue.raw),
                        "BehaviorTree.CPP reads a literal queue only for LoopInt, LoopBool, LoopDouble and LoopString",
                    ));
                }
                let name = registered(self, &queue.at)?;
                // BehaviorTree.CPP's splitString: no element after a final `;`.
                let mut parts: Vec<&str> = text.split(';').collect();
                if parts.last() == Some(&"") {
                    parts.pop();
                }
                let mut programs = Vec::with_capacity(parts.len());
                for part in parts {
                    let bad = || {
                        ImportError::new(
                            &queue.at,
                            Fault::BadLiteral {
                                node: n.id.clone(),
                                port: "queue".into(),
                                value: part.into(),
                                ty: type_name.unwrap_or("any").into(),
                            },
                        )
                    };
                    let push = match convert(type_name, part).ok_or_else(bad)? {
                        Literal::Int(v) => Push::Int(v),
                        Literal::Double(v) => Push::Double(v),
                        // A string the slot's type converts (`true` for a boolean slot).
                        Literal::Bool(v) => Push::Str(self.intern(Literal::Str(v.to_string()), &queue.at)?),
                        Literal::Str(v) => Push::Str(self.intern(Literal::Str(v), &queue.at)?),
                    };
                    programs.push(script::element_program(push, value));
                }
                table = script::literal_queue(element, name, &programs).ok_or_else(|| {
                    ImportError::new(&queue.at, Fault::TooLarge("a queue of more than 65535 elements".into()))
                })?;
                flat.push(("queue".to_string(), text));
            }
            Err(k) => {
                let v = self.slot_value(k, (PortType::Any, PortDirection::InOut), None, &queue.at, n, "queue")?;
                let PortValue::Slot(slot) = PortValue::from_u16(v) else {
                    return Err(ImportError::new(&queue.at, Fault::TooLarge("no slot for `queue`".into())));
                };
                table = vec![QUEUE_KEY | element as u16, registered(self, &queue.at)?, slot, value.unwrap_or(u16::MAX)];
                flat.push((
                    "queue".to_string(),
                    format!("{{{}}}", script_name(&self.out.slots[usize::from(slot)].name)),
                ));
            }
        }
        if let Some(b) = n.ports.iter().find(|b| b.port == "if_empty") {
            flat.push(("if_empty".to_string(), b.raw.clone()));
        }
        if let Some(slot) = value {
            flat.push(("value".to_string(), format!("{{{}}}", script_name(&self.out.slots[usize::from(slot)].name))));
        }
        if let Some(meta) = self.out.meta.last_mut() {
            meta.flat = Some(flat);
        }
        Ok(NodeKind::Loop { table: self.place(n, &table)?, if_empty })
    }

    /// The literal a key starts with, when it is a SubTree-local entry no port writes.
    fn initial_literal(&self, k: &Key) -> Option<String> {
        if self.written.contains(k) {
            return None;
        }
        self.flat.scopes.get(k.scope)?.initial.get(&k.name).map(|(v, _)| v.clone())
    }

    fn leaf_values(&mut self, n: &Inst, behavior: u16) -> Result<Vec<u16>> {
        let model = self.catalog.behaviors()[usize::from(behavior)].clone();
        for b in &n.ports {
            if !model.ports.iter().any(|p| p.name == b.port) {
                return Err(ImportError::new(
                    &b.at,
                    Fault::UnknownPort {
                        node: n.id.clone(),
                        port: b.port.clone(),
                        declared: model.ports.iter().map(|p| p.name.clone()).collect(),
                    },
                ));
            }
        }
        let mut values = Vec::with_capacity(model.ports.len());
        for (position, p) in model.ports.iter().enumerate() {
            let info = self.catalog.port(behavior, position).map(|i| (i.ty, i.direction));
            let (ty, direction) = info.unwrap_or((PortType::Any, PortDirection::Input));
            let given = match n.ports.iter().find(|b| b.port == p.name) {
                Some(b) => Given::Attr(b),
                None => match &p.default {
                    Some(d) => Given::Default(d.clone()),
                    None => Given::Unset,
                },
            };
            let v = match given {
                Given::Unset => UNSET,
                Given::Default(d) => match blackboard_key(&d) {
                    Some(k) => {
                        let key = resolve(&self.flat.scopes, n.scope, k);
                        self.slot_value(&key, (ty, direction), p.type_name.as_deref(), &n.at, n, &p.name)?
                    }
                    // The behavior applies a literal default itself.
                    None => UNSET,
                },
                Given::Attr(b) => match &b.value {
                    Value::Literal(text) => {
                        if direction == PortDirection::Output {
                            return Err(ImportError::new(
                                &b.at,
                                Fault::OutputLiteral { node: n.id.clone(), port: p.name.clone(), value: text.clone() },
                            ));
                        }
                        self.constant(text, p.type_name.as_deref(), &b.at, n, &p.name)?
                    }
                    Value::Key(k) => match self.initial_literal(k) {
                        Some(text) if direction == PortDirection::Input => {
                            self.constant(&text, p.type_name.as_deref(), &b.at, n, &p.name)?
                        }
                        _ => self.slot_value(k, (ty, direction), p.type_name.as_deref(), &b.at, n, &p.name)?,
                    },
                },
            };
            values.push(v);
        }
        Ok(values)
    }

    fn constant(&mut self, text: &str, type_name: Option<&str>, at: &Location, n: &Inst, port: &str) -> Result<u16> {
        let Some(lit) = convert(type_name, text) else {
            return Err(ImportError::new(
                at,
                Fault::BadLiteral {
                    node: n.id.clone(),
                    port: port.into(),
                    value: text.into(),
                    ty: type_name.unwrap_or("any").into(),
                },
            ));
        };
        let id = self.intern(lit, at)?;
        Ok(PortValue::Constant(id).to_u16().unwrap_or(UNSET))
    }

    fn intern(&mut self, lit: Literal, at: &Location) -> Result<u16> {
        let key = lit.key();
        if let Some(&id) = self.constant_ids.get(&key) {
            return Ok(id);
        }
        let id = u16::try_from(self.out.constants.len())
            .ok()
            .filter(|&i| i < bt_core::port::MAX_CONSTANTS)
            .ok_or_else(|| ImportError::new(at, Fault::TooLarge("more constants than a ports section holds".into())))?;
        self.out.constants.push(lit);
        self.constant_ids.insert(key, id);
        Ok(id)
    }

    #[allow(clippy::too_many_arguments)]
    fn slot_value(
        &mut self,
        key: &Key,
        (ty, direction): (PortType, PortDirection),
        type_name: Option<&str>,
        at: &Location,
        n: &Inst,
        port: &str,
    ) -> Result<u16> {
        if let Some(&id) = self.slot_ids.get(key) {
            // A slot a script named first takes the type of the first port that names it.
            if self.script_slots.contains(&id) && port != SCRIPT_PORT {
                self.script_slots.remove(&id);
                let slot = &mut self.out.slots[usize::from(id)];
                slot.info.ty = ty;
                slot.type_name = type_name.map(str::to_string);
                return Ok(PortValue::Slot(id).to_u16().unwrap_or(UNSET));
            }
            let slot = &self.out.slots[usize::from(id)];
            // BehaviorTree.CPP's rule: two typed ports on one key must agree, unless the
            // key was first created as a string.
            let first = slot.info.ty;
            let conflict = ty != PortType::Any
                && first != PortType::Any
                && first != PortType::String
                && (ty != first || (ty == PortType::Other && slot.type_name.as_deref() != type_name))
                // An input port may read through a registered polymorphic cast.
                && !(direction == PortDirection::Input
                    && slot.type_name.as_deref().zip(type_name).is_some_and(|(from, to)| converts(self.casts, from, to)));
            if conflict {
                return Err(ImportError::new(
                    at,
                    Fault::KeyTypeConflict {
                        key: slot.name.clone(),
                        first: slot.type_name.clone().unwrap_or_else(|| "any".into()),
                        second: type_name.unwrap_or("any").into(),
                        at: self.slot_first[usize::from(id)].clone(),
                    },
                ));
            }
            return Ok(PortValue::Slot(id).to_u16().unwrap_or(UNSET));
        }
        let id =
            u16::try_from(self.out.slots.len()).ok().filter(|&i| i < bt_core::port::MAX_SLOTS).ok_or_else(|| {
                ImportError::new(at, Fault::TooLarge("more blackboard keys than a ports section holds".into()))
            })?;
        let scope = self.flat.scopes.get(key.scope);
        let initial = match scope.and_then(|s| s.initial.get(&key.name)) {
            Some((text, lit_at)) => {
                let Some(lit) = convert(type_name, text) else {
                    return Err(ImportError::new(
                        lit_at,
                        Fault::BadLiteral {
                            node: n.id.clone(),
                            port: key.name.clone(),
                            value: text.clone(),
                            ty: type_name.unwrap_or("any").into(),
                        },
                    ));
                };
                Some(self.intern(lit, lit_at)?)
            }
            None => None,
        };
        let name = match scope {
            Some(s) if key.scope != 0 => format!("{}/{}", s.path, key.name),
            _ => key.name.clone(),
        };
        self.out.slots.push(Slot { name, info: SlotInfo { ty, initial }, type_name: type_name.map(str::to_string) });
        self.slot_first.push(at.clone());
        self.slot_ids.insert(key.clone(), id);
        if port == SCRIPT_PORT {
            self.script_slots.insert(id);
        }
        Ok(PortValue::Slot(id).to_u16().unwrap_or(UNSET))
    }
}

/// The port name [`Lowerer::slot_value`] is given for a script's keys.
const SCRIPT_PORT: &str = "code";

/// Keys and strings of a script, as [`Lowerer`] numbers them.
struct ScriptSymbols<'l, 'a, 'n> {
    l: &'l mut Lowerer<'a>,
    n: &'n Inst,
    at: &'n Location,
    /// The scope its keys are read in.
    scope: usize,
    /// An import error (a key conflict, a full table) met while compiling.
    failed: Option<ImportError>,
    /// Each key as written (its byte offset and text) and its slot.
    keys: Vec<(usize, String, u16)>,
}

impl script::Symbols for ScriptSymbols<'_, '_, '_> {
    fn slot(&mut self, name: &str, offset: usize) -> std::result::Result<(u16, bool), script::ScriptError> {
        let key = resolve(&self.l.flat.scopes, self.scope, name);
        let declared = self.l.ported.contains(&key)
            || self.l.flat.scopes.get(key.scope).is_some_and(|s| s.initial.contains_key(&key.name));
        match self.l.slot_value(&key, (PortType::Any, PortDirection::InOut), None, self.at, self.n, SCRIPT_PORT) {
            Ok(v) => match PortValue::from_u16(v) {
                PortValue::Slot(id) => {
                    self.keys.push((offset, name.to_string(), id));
                    Ok((id, declared))
                }
                _ => Err(script::ScriptError { offset, message: format!("no slot for `{name}`") }),
            },
            Err(e) => {
                let message = e.to_string();
                self.failed = Some(e);
                Err(script::ScriptError { offset, message })
            }
        }
    }

    fn enum_value(&self, name: &str) -> Option<f64> {
        self.l.enums.get(name).map(|&v| v as f64)
    }

    fn string(&mut self, text: &str) -> std::result::Result<u16, script::ScriptError> {
        match self.l.intern(Literal::Str(text.to_string()), self.at) {
            Ok(k) => Ok(k),
            Err(e) => {
                let message = e.to_string();
                self.failed = Some(e);
                Err(script::ScriptError { offset: 0, message })
            }
        }
    }
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

/// Refuses a port the node type does not have.
fn check_ports(n: &Inst, ports: &[crate::xml::builtin::BuiltinPort]) -> Result<()> {
    for p in &n.ports {
        if !ports.iter().any(|(name, _, _)| *name == p.port) {
            return Err(ImportError::new(
                &p.at,
                Fault::UnknownPort {
                    node: n.id.clone(),
                    port: p.port.clone(),
                    declared: ports.iter().map(|(name, _, _)| (*name).to_string()).collect(),
                },
            ));
        }
    }
    Ok(())
}

fn unsupported(at: &Location, id: &str, reason: &str) -> ImportError {
    unsupported_construct(at, format!("<{id}>"), reason)
}

fn unsupported_construct(at: &Location, construct: String, reason: &str) -> ImportError {
    ImportError::new(at, Fault::Unsupported { construct, reason: reason.into() })
}

/// Attribute names in errors are `&'static str`; parameters are few and fixed.
fn leak(port: &str) -> &'static str {
    match port {
        "num_cycles" => "num_cycles",
        "num_attempts" => "num_attempts",
        "success_count" => "success_count",
        "failure_count" => "failure_count",
        "max_failures" => "max_failures",
        "msec" => "msec",
        "delay_msec" => "delay_msec",
        "number_of_retries" => "number_of_retries",
        _ => "a parameter",
    }
}
