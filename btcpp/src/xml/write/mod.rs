//! BehaviorTree.CPP v4 XML: `ReactiveSequence` / `ReactiveFallback` for the reactive
//! controls, leaves in the compact form `<place i="cube" s="goal"/>` whose values are
//! ports (declared ports as declared, grounded arguments as input ports named by the
//! catalog's [`Catalog::port_name`], else `arg0`, `arg1`, ...), and a `TreeNodesModel`
//! section declaring every leaf type (`<Action ID="place">`) and its ports, so Groot2
//! shows the tree without the C++ registrations.
//!
//! The compact form is the one BehaviorTree.CPP and Groot2 write themselves, and the
//! only one releases 4.7 to 4.10 load under a `ReactiveSequence`: their check of a
//! reactive sequence's children looks `<Action ID="...">` up by its element name
//! (checked against 4.10.0). An element name must be an XML name, so a behavior name
//! that is not one (the brick tasks' `put 0 on 1!`) becomes its type ID with every run
//! of other characters turned into `_` (`put_0_on_1`), numbered if two collide; the
//! full name stays on each node as its `name`.
//!
//! Other kinds map to their BehaviorTree.CPP counterparts as [`crate::kinds`] says:
//! `SequenceWithMemory` to `Sequence` (which resumes at the running child),
//! `FallbackWithMemory` to `Fallback`, `Parallel` with `success_count`/`failure_count`,
//! `RepeatCycles` to `Repeat(num_cycles)`, and so on. bt-core's `Repeat`, `Retry` and
//! `Timeout` count ticks, where BehaviorTree.CPP's count cycles or milliseconds, so they
//! are refused.

mod models;
mod names;

use std::fmt::Write as _;

use bt_core::{BehaviorId, Catalog, Leaf, LeafKind, Node, NodeKind, PortValue};

pub(crate) use names::{arg_text, escape, port_name, type_id};

use crate::kinds::{self, Attrs, Shape};
use crate::xml::document::Version;
use models::Declared;
use names::{attr_text, behavior_name};

/// `a` or `an` and the kind's name, by its first letter's sound: `an Inverter`.
fn article(word: &str) -> String {
    let vowel = word.chars().next().is_some_and(|c| "aeiouAEIOU".contains(c));
    format!("{} {word}", if vowel { "an" } else { "a" })
}

/// Why a tree cannot be written as BehaviorTree.CPP XML.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum XmlError {
    /// A kind without an exact BehaviorTree.CPP equivalent.
    #[error("node {node} is {}, which BehaviorTree.CPP has no exact equivalent for", article(kind))]
    NotExpressible {
        /// Index of the node.
        node: usize,
        /// Its kind.
        kind: &'static str,
    },
    /// A script node whose text cannot be written.
    #[error("node {node} is a {kind} whose script cannot be written: {why}")]
    ScriptText {
        /// Index of the node.
        node: usize,
        /// Its kind.
        kind: &'static str,
        /// Why.
        why: String,
    },
    /// A key a SubTree instance starts at a literal that a SubTree attribute cannot
    /// give (`{x}` reads as a key, an empty one as nothing).
    #[error(
        "blackboard key `{key}` (slot {slot}) starts at `{value}`, given by its SubTree, \
         which a SubTree attribute would read as a key"
    )]
    StartValue {
        /// Its slot.
        slot: usize,
        /// The key.
        key: String,
        /// The literal it starts at.
        value: String,
    },
    /// Two blackboard keys that the XML would write with one name.
    #[error("blackboard keys `{first}` and `{second}` (slot {slot}) would both be written as `{name}`")]
    SameKey {
        /// The second key's slot.
        slot: usize,
        /// The name both would have.
        name: String,
        /// The first key.
        first: String,
        /// The second key.
        second: String,
    },
    /// Subtree sizes that do not nest.
    #[error("node {node}: subtree size does not fit inside its parent")]
    Malformed {
        /// Index of the node.
        node: usize,
    },
}

/// What else [`to_xml_with`] writes.
#[derive(Clone, Copy, Debug, Default)]
pub struct XmlOptions<'a> {
    /// The tree's value table, where extended leaves keep their values.
    pub values: &'a [u16],
    /// Declare every behavior of the catalog in `<TreeNodesModel>`, in id order, not
    /// only those the tree uses: importing the document then gives the same behavior
    /// set (and fingerprint) back.
    pub all_behaviors: bool,
    /// Per node, a `name` attribute.
    pub names: &'a [Option<String>],
    /// Per node, BehaviorTree.CPP's node id, written as `_uid` (as Groot2 logs show it);
    /// when empty, the node's position from 1, which is how BehaviorTree.CPP numbers the
    /// document written (and how [`LogTree::new`](crate::btlog::LogTree::new) numbers
    /// the logs of these nodes).
    pub uids: &'a [u16],
    /// Per node, the parameters of a built-in as its document wrote them
    /// (`failure_count="-1"`), written instead of those the kind gives back; when
    /// empty, every node's are the kind's.
    pub params: &'a [&'a [(String, String)]],
    /// The tree's ID (`MainTree` when empty).
    pub tree_id: &'a str,
    /// Per node, its registration ID as the document wrote it: the tag of a loop over a
    /// type the program registers (`LoopPose`).
    pub ids: &'a [&'a str],
    /// The rules the document is written for: version 4's (`BTCPP_format="4"`), or
    /// version 3's for a tree imported from a version 3 document (no `BTCPP_format`, no
    /// `_uid`s, which BehaviorTree.CPP 3 would read as ports).
    pub version: Version,
    /// Keys the tree starts at a literal, as `(key, text)`: a SubTree gave them, so
    /// the tree is written as the subtree `ID.body` of a main tree whose one SubTree
    /// node gives them (with `_autoremap`; in version 3 a `SubTreePlus` with
    /// `__autoremap`), every other key shared.
    pub starting: &'a [(String, String)],
}

/// The tree as a BehaviorTree.CPP v4 document with one tree, `MainTree`.
///
/// # Errors
/// [`XmlError`] for `Timeout` nodes and malformed arrays.
pub fn to_xml<C: Catalog + ?Sized>(nodes: &[Node], catalog: &C) -> Result<String, XmlError> {
    to_xml_with(nodes, catalog, &XmlOptions::default())
}

/// [`to_xml`] with a value table, node names and uids, and optionally the whole
/// behavior set declared.
///
/// # Errors
/// [`XmlError`] for kinds without an equivalent and malformed arrays.
pub fn to_xml_with<C: Catalog + ?Sized>(
    nodes: &[Node],
    catalog: &C,
    options: &XmlOptions<'_>,
) -> Result<String, XmlError> {
    let tree_id = if options.tree_id.is_empty() { "MainTree" } else { options.tree_id };
    let tree_id = escape(tree_id);
    let format = if options.version == Version::V4 { " BTCPP_format=\"4\"" } else { "" };
    let mut out = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<root{format} main_tree_to_execute=\"{tree_id}\">\n  <BehaviorTree ID=\"{tree_id}\">\n",
    );
    if !options.starting.is_empty() {
        let (tag, autoremap) =
            if options.version == Version::V4 { ("SubTree", "_autoremap") } else { ("SubTreePlus", "__autoremap") };
        let _ = write!(out, "    <{tag} ID=\"{tree_id}.body\" {autoremap}=\"true\"");
        for (key, text) in options.starting {
            let _ = write!(out, " {}=\"{}\"", escape(key), escape(text));
        }
        let _ = write!(out, "/>\n  </BehaviorTree>\n  <BehaviorTree ID=\"{tree_id}.body\">\n");
    }
    let mut w = Writer { nodes, catalog, options, out, open: Vec::new(), declared: Declared::default(), carried: None };
    if options.all_behaviors {
        w.declared.declare_all(catalog);
    }
    for (i, n) in nodes.iter().enumerate() {
        w.close(i);
        w.node(i, n)?;
    }
    w.close(usize::MAX);
    w.out.push_str("  </BehaviorTree>\n");
    w.declared.write(catalog, &mut w.out);
    w.out.push_str("</root>\n");
    Ok(w.out)
}

/// A document being written, node by node in pre-order.
struct Writer<'a, C: ?Sized> {
    nodes: &'a [Node],
    catalog: &'a C,
    options: &'a XmlOptions<'a>,
    out: String,
    /// Elements open: the end of their subtree and their tag.
    open: Vec<(usize, String)>,
    /// The behaviors of the leaves and gates written.
    declared: Declared,
    /// A guard's attributes, for the node it guards (the next one).
    carried: Option<String>,
}

impl<C: Catalog + ?Sized> Writer<'_, C> {
    /// The indentation of an element inside `depth` open ones.
    fn indent(depth: usize) -> String {
        "  ".repeat(depth + 2)
    }

    /// Closes the open elements whose subtrees end at or before node `i`.
    fn close(&mut self, i: usize) {
        while let Some((end, tag)) = self.open.last() {
            if *end > i {
                break;
            }
            let tag = tag.clone();
            self.open.pop();
            let _ = writeln!(self.out, "{}</{tag}>", Self::indent(self.open.len()));
        }
    }

    /// Writes an element: `<tag attrs/>` for a leaf, else opened until its subtree ends.
    fn element(&mut self, tag: &str, attrs: &str, leaf: bool, end: usize) {
        let pad = Self::indent(self.open.len());
        if leaf {
            let _ = writeln!(self.out, "{pad}<{tag}{attrs}/>");
        } else {
            let _ = writeln!(self.out, "{pad}<{tag}{attrs}>");
            self.open.push((end, tag.to_string()));
        }
    }

    /// Node `i`'s `name` and `_uid`, and the attributes a guard in front of it carried.
    fn meta(&mut self, i: usize) -> String {
        let mut meta = String::new();
        if let Some(Some(name)) = self.options.names.get(i) {
            let _ = write!(meta, " name=\"{}\"", escape(name));
        }
        // BehaviorTree.CPP numbers the nodes of a document with one tree and no SubTree
        // nodes in pre-order from 1: the uids its logs (and ours) show.
        match self.options.uids.get(i) {
            _ if self.options.version == Version::V3 => {}
            Some(uid) => {
                let _ = write!(meta, " _uid=\"{uid}\"");
            }
            None if self.options.uids.is_empty() => {
                let _ = write!(meta, " _uid=\"{}\"", i + 1);
            }
            None => {}
        }
        if let Some(c) = self.carried.take() {
            meta.push_str(&c);
        }
        meta
    }

    fn node(&mut self, i: usize, n: &Node) -> Result<(), XmlError> {
        let end = i + usize::from(n.size());
        if n.size() == 0 || end > self.nodes.len() || self.open.last().is_some_and(|(e, _)| end > *e) {
            return Err(XmlError::Malformed { node: i });
        }
        let meta = self.meta(i);
        match *n.kind() {
            // A guard is its node's scripted attributes: written on the node.
            NodeKind::Guard(_) => {
                self.carried = Some(script_attrs(self.options, i, n)?);
                Ok(())
            }
            NodeKind::Condition(leaf) => self.leaf(i, &leaf, LeafKind::Condition, &meta),
            NodeKind::Action(leaf) => self.leaf(i, &leaf, LeafKind::Action, &meta),
            NodeKind::Gate(leaf) => {
                let b = leaf.behavior();
                let values = leaf.args_in(self.options.values);
                let tag = self.declared.declare_gate(self.catalog, b, values.len());
                let a = port_attrs(self.catalog, b, values);
                self.element(&tag, &format!("{meta}{a}"), false, end);
                Ok(())
            }
            // Written from the document's attributes, as scripts are.
            NodeKind::Loop { table, .. } => {
                use bt_core::script::Element;
                let tag = match bt_core::script::queue_element(table.words(self.options.values)) {
                    Some((Element::Registered, _)) => match self.options.ids.get(i) {
                        Some(id) => id,
                        None => {
                            return Err(XmlError::NotExpressible {
                                node: i,
                                kind: "Loop over a type of the program's",
                            });
                        }
                    },
                    Some((element, _)) => kinds::loop_entry(element).ok_or(XmlError::Malformed { node: i })?.id,
                    None => return Err(XmlError::Malformed { node: i }),
                };
                let attrs = script_attrs(self.options, i, n)?;
                self.element(tag, &format!("{meta}{attrs}"), false, end);
                Ok(())
            }
            ref kind => self.builtin(i, n, kind, &meta, end),
        }
    }

    /// A leaf in the compact form, its values as ports.
    fn leaf(&mut self, i: usize, leaf: &Leaf, kind: LeafKind, meta: &str) -> Result<(), XmlError> {
        let b = leaf.behavior();
        let name = behavior_name(self.catalog, b);
        let values = leaf.args_in(self.options.values);
        let tag = self.declared.declare(self.catalog, b, kind, values.len());
        let mut a = String::new();
        let named = matches!(self.options.names.get(i), Some(Some(_)));
        if !named && tag != name {
            let _ = write!(a, " name=\"{}\"", escape(&name));
        }
        a.push_str(meta);
        a.push_str(&port_attrs(self.catalog, b, values));
        self.element(&tag, &a, true, i + 1);
        Ok(())
    }

    /// A node of a BehaviorTree.CPP or Nav2 type, as [`kinds::written`] names it.
    fn builtin(&mut self, i: usize, n: &Node, kind: &NodeKind, meta: &str, end: usize) -> Result<(), XmlError> {
        let children = bt_core::children(self.nodes, u16::try_from(i).unwrap_or(u16::MAX)).count();
        let id = self.options.ids.get(i).copied();
        let Some((entry, written)) = kinds::written_as(kind, children, id) else {
            return Err(XmlError::NotExpressible { node: i, kind: kind.name() });
        };
        let attrs = match entry.map {
            kinds::Map::Params { attrs: Attrs::Kind, .. } => attr_text(&written.params),
            kinds::Map::Params { attrs: Attrs::Script, .. } => script_attrs(self.options, i, n)?,
            _ => match self.options.params.get(i) {
                Some(document) => attr_text(document),
                None => attr_text(&written.params),
            },
        };
        self.element(entry.id, &format!("{meta}{attrs}"), entry.shape == Shape::Leaf, end);
        Ok(())
    }
}

/// The attributes of script node or guard `i`: known only for an imported tree.
fn script_attrs(options: &XmlOptions<'_>, i: usize, n: &Node) -> Result<String, XmlError> {
    match options.params.get(i) {
        Some(written) => Ok(attr_text(written)),
        None => Err(XmlError::ScriptText {
            node: i,
            kind: n.kind().name(),
            why: "an image keeps its program, not its text (export the imported document: \
                  sim-host import TREE.xml --format xml)"
                .into(),
        }),
    }
}

/// ` port="value"` for each value of a leaf, unset ports left out.
fn port_attrs<C: Catalog + ?Sized>(catalog: &C, b: BehaviorId, values: &[u16]) -> String {
    let mut a = String::new();
    for (pos, &v) in values.iter().enumerate() {
        if catalog.port(b, pos).is_some() && PortValue::from_u16(v) == PortValue::Unset {
            continue;
        }
        let _ = write!(a, " {}=\"{}\"", port_name(catalog, b, pos), escape(&arg_text(catalog, b, pos, v)));
    }
    a
}
