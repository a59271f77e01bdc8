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
//! Other kinds map to their BehaviorTree.CPP counterparts: `SequenceWithMemory` to
//! `Sequence` (which resumes at the running child), `FallbackWithMemory` to `Fallback`,
//! `Parallel` with `success_count`/`failure_count`, `Inverter`, `ForceSuccess`,
//! `ForceFailure`, `Repeat(num_cycles)`, `Retry` to `RetryUntilSuccessful`. `Timeout`
//! counts ticks here and milliseconds there, so it is refused.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use bt_core::{BehaviorId, Catalog, LeafKind, Node, NodeKind, PortValue};

/// An argument as the catalog renders it, e.g. `cube`.
pub(crate) fn arg_text<C: Catalog + ?Sized>(catalog: &C, behavior: u16, position: usize, value: u16) -> String {
    struct A<'a, C: ?Sized>(&'a C, u16, usize, u16);
    impl<C: Catalog + ?Sized> std::fmt::Display for A<'_, C> {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            self.0.write_arg(f, self.1, self.2, self.3)
        }
    }
    A(catalog, behavior, position, value).to_string()
}

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
    /// A key a SubTree instance starts at a literal, which a tree without that SubTree
    /// cannot write.
    #[error(
        "blackboard key `{key}` (slot {slot}) starts at {value}, given by its SubTree; \
         the flattened tree has no SubTree to give it"
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

/// Attributes as written: ` key="value"` each.
fn attr_text(written: &[(String, String)]) -> String {
    written.iter().map(|(k, v)| format!(" {k}=\"{}\"", escape(v))).collect()
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

fn escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&apos;"),
            c => o.push(c),
        }
    }
    o
}

/// Whether the writer uses `p` as a port name as it is (after `-` becomes `_`).
pub(crate) fn is_port_name(p: &str) -> bool {
    p.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && p.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        && p != "name"
        && p != "ID"
}

/// The port value `position` of `behavior` is written as: a declared port's name as it
/// is; a grounded argument's name ([`Catalog::port_name`]) when BehaviorTree.CPP accepts
/// it (a letter first, not `name` or `ID`; `-` becomes `_`), else `arg{position}`.
pub(crate) fn port_name<C: Catalog + ?Sized>(catalog: &C, behavior: BehaviorId, position: usize) -> String {
    if let Some(p) = catalog.port(behavior, position) {
        return p.name.to_string();
    }
    match catalog.port_name(behavior, position) {
        Some(p) if is_port_name(p) => p.replace('-', "_"),
        _ => format!("arg{position}"),
    }
}

fn behavior_name<C: Catalog + ?Sized>(catalog: &C, id: BehaviorId) -> String {
    catalog.info(id).map_or_else(|| format!("behavior{id}"), |i| i.name.to_string())
}

/// The values of a leaf, inline or from `values`.
fn leaf_values<'a>(leaf: &'a bt_core::Leaf, values: &'a [u16]) -> &'a [u16] {
    leaf.args_in(values)
}

/// A node type ID usable as an XML element name: letters, digits, `_` and `-`,
/// starting with a letter; other characters become `_` (one per run, none at the ends).
/// A name that already is one is kept as it is.
pub(crate) fn type_id(name: &str) -> String {
    if name.starts_with(|c: char| c.is_ascii_alphabetic())
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        return name.to_string();
    }
    let mut id = String::with_capacity(name.len() + 1);
    for c in name.chars() {
        if c.is_ascii_alphanumeric() || c == '-' {
            id.push(c);
        } else if !id.is_empty() && !id.ends_with('_') {
            id.push('_');
        }
    }
    while id.ends_with('_') {
        id.pop();
    }
    if !id.starts_with(|c: char| c.is_ascii_alphabetic()) {
        id.insert(0, 'b');
    }
    id
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
    let mut out = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<root BTCPP_format=\"4\" main_tree_to_execute=\"{tree_id}\">\n  <BehaviorTree ID=\"{tree_id}\">\n",
    );
    let mut open: Vec<(usize, String)> = Vec::new();
    // Behaviors used as plugin decorators (gates): declared as `<Decorator>`.
    let mut gates: BTreeSet<BehaviorId> = BTreeSet::new();
    // Per behavior used: its kind, arity and type ID (distinct: numbered on collision).
    let mut used: BTreeMap<BehaviorId, (LeafKind, usize, String)> = BTreeMap::new();
    let mut taken = BTreeSet::new();
    let mut declare =
        |b: BehaviorId, kind: LeafKind, argc: usize, used: &mut BTreeMap<BehaviorId, (LeafKind, usize, String)>| {
            used.entry(b)
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
        };
    if options.all_behaviors {
        for b in 0..catalog.len() {
            let Ok(b) = BehaviorId::try_from(b) else { break };
            if let Some(info) = catalog.info(b) {
                declare(b, info.kind, usize::from(info.arity), &mut used);
            }
        }
    }
    let indent = |depth: usize| "  ".repeat(depth + 2);
    // A guard's attributes, for the node it guards (the next one).
    let mut carried: Option<String> = None;
    for (i, n) in nodes.iter().enumerate() {
        while let Some((end, tag)) = open.last() {
            if *end > i {
                break;
            }
            let tag = tag.clone();
            open.pop();
            let _ = writeln!(out, "{}</{tag}>", indent(open.len()));
        }
        let end = i + usize::from(n.size());
        if n.size() == 0 || end > nodes.len() || open.last().is_some_and(|(e, _)| end > *e) {
            return Err(XmlError::Malformed { node: i });
        }
        let pad = indent(open.len());
        let mut meta = String::new();
        let named = matches!(options.names.get(i), Some(Some(_)));
        if let Some(Some(name)) = options.names.get(i) {
            let _ = write!(meta, " name=\"{}\"", escape(name));
        }
        // BehaviorTree.CPP numbers the nodes of a document with one tree and no SubTree
        // nodes in pre-order from 1: the uids its logs (and ours) show.
        match options.uids.get(i) {
            Some(uid) => {
                let _ = write!(meta, " _uid=\"{uid}\"");
            }
            None if options.uids.is_empty() => {
                let _ = write!(meta, " _uid=\"{}\"", i + 1);
            }
            None => {}
        }
        if let Some(c) = carried.take() {
            meta.push_str(&c);
        }
        let (tag, attrs): (&'static str, String) = match *n.kind() {
            // A guard is its node's scripted attributes: written on the node.
            NodeKind::Guard(_) => {
                carried = Some(script_attrs(options, i, n)?);
                continue;
            }
            NodeKind::Sequence => ("ReactiveSequence", String::new()),
            NodeKind::Fallback => ("ReactiveFallback", String::new()),
            NodeKind::SequenceWithMemory => ("Sequence", String::new()),
            NodeKind::FallbackWithMemory => ("Fallback", String::new()),
            NodeKind::SequenceStar => ("SequenceWithMemory", String::new()),
            NodeKind::Parallel { success_threshold, failure_threshold, count_skipped } => {
                // A success count that counts skipped children was negative in the XML.
                let children = bt_core::children(nodes, u16::try_from(i).unwrap_or(u16::MAX)).count();
                let success = if count_skipped {
                    i64::from(success_threshold) - i64::try_from(children).unwrap_or(i64::MAX) - 1
                } else {
                    i64::from(success_threshold)
                };
                ("Parallel", format!(" success_count=\"{success}\" failure_count=\"{failure_threshold}\""))
            }
            NodeKind::ParallelAll { max_failures } => ("ParallelAll", format!(" max_failures=\"{max_failures}\"")),
            NodeKind::IfThenElse => ("IfThenElse", String::new()),
            NodeKind::WhileDoElse => ("WhileDoElse", String::new()),
            NodeKind::Inverter => ("Inverter", String::new()),
            NodeKind::ForceSuccess => ("ForceSuccess", String::new()),
            NodeKind::ForceFailure => ("ForceFailure", String::new()),
            NodeKind::RepeatCycles(k) => ("Repeat", format!(" num_cycles=\"{}\"", count(k))),
            NodeKind::RetryUntilSuccessful(k) => ("RetryUntilSuccessful", format!(" num_attempts=\"{}\"", count(k))),
            NodeKind::KeepRunningUntilFailure => ("KeepRunningUntilFailure", String::new()),
            NodeKind::RunOnce { then_skip } => ("RunOnce", format!(" then_skip=\"{then_skip}\"")),
            NodeKind::TimeLimit(span) => ("Timeout", format!(" msec=\"{}\"", span.get())),
            NodeKind::Delay(span) => ("Delay", format!(" delay_msec=\"{}\"", span.get())),
            NodeKind::PipelineSequence => ("PipelineSequence", String::new()),
            NodeKind::Recovery { retries } => ("RecoveryNode", format!(" number_of_retries=\"{retries}\"")),
            NodeKind::RoundRobin => ("RoundRobin", String::new()),
            NodeKind::ManualSelector { repeat_last } => {
                ("ManualSelector", format!(" repeat_last_selection=\"{repeat_last}\""))
            }
            // The period is whole milliseconds; the rate that gives it back.
            NodeKind::RateController(span) => ("RateController", format!(" hz=\"{}\"", 1000.0 / f64::from(span.get()))),
            // Our tick-counting kinds count ticks, not cycles or milliseconds: no
            // BehaviorTree.CPP node does what they do.
            NodeKind::Repeat(_) => return Err(XmlError::NotExpressible { node: i, kind: "Repeat" }),
            NodeKind::Retry(_) => return Err(XmlError::NotExpressible { node: i, kind: "Retry" }),
            NodeKind::Timeout(_) => return Err(XmlError::NotExpressible { node: i, kind: "Timeout" }),
            // The image keeps a script's program, not its text: written only where the
            // document's attributes are known (an imported tree).
            NodeKind::Script(_) | NodeKind::ScriptCondition(_) | NodeKind::Precondition { .. } => {
                let tag = n.kind().name();
                let attrs = script_attrs(options, i, n)?;
                if matches!(n.kind(), NodeKind::Precondition { .. }) {
                    let _ = writeln!(out, "{pad}<{tag}{meta}{attrs}>");
                    open.push((end, tag.to_string()));
                } else {
                    let _ = writeln!(out, "{pad}<{tag}{meta}{attrs}/>");
                }
                continue;
            }
            // Written from the document's attributes, as scripts are.
            NodeKind::Loop { table, .. } => {
                use bt_core::script::Element;
                let tag = match bt_core::script::queue_element(table.words(options.values)) {
                    Some((Element::Int, _)) => "LoopInt",
                    Some((Element::Bool, _)) => "LoopBool",
                    Some((Element::Double, _)) => "LoopDouble",
                    Some((Element::String, _)) => "LoopString",
                    Some((Element::Registered, _)) => match options.ids.get(i) {
                        Some(id) => id,
                        None => {
                            return Err(XmlError::NotExpressible {
                                node: i,
                                kind: "Loop over a type of the program's",
                            });
                        }
                    },
                    None => return Err(XmlError::Malformed { node: i }),
                };
                let attrs = script_attrs(options, i, n)?;
                let _ = writeln!(out, "{pad}<{tag}{meta}{attrs}>");
                open.push((end, tag.to_string()));
                continue;
            }
            NodeKind::Sleep(span) => {
                let _ = writeln!(out, "{pad}<Sleep{meta} msec=\"{}\"/>", span.get());
                continue;
            }
            NodeKind::AlwaysSuccess | NodeKind::AlwaysFailure => {
                let tag = if matches!(n.kind(), NodeKind::AlwaysSuccess) { "AlwaysSuccess" } else { "AlwaysFailure" };
                let _ = writeln!(out, "{pad}<{tag}{meta}/>");
                continue;
            }
            NodeKind::Gate(leaf) => {
                let b = leaf.behavior();
                let values = leaf_values(&leaf, options.values);
                let tag = declare(b, LeafKind::Action, values.len(), &mut used);
                gates.insert(b);
                let a = port_attrs(catalog, b, values);
                let _ = writeln!(out, "{pad}<{tag}{meta}{a}>");
                open.push((end, tag));
                continue;
            }
            NodeKind::Condition(leaf) | NodeKind::Action(leaf) => {
                let kind =
                    if matches!(n.kind(), NodeKind::Condition(_)) { LeafKind::Condition } else { LeafKind::Action };
                let b = leaf.behavior();
                let name = behavior_name(catalog, b);
                let values = leaf_values(&leaf, options.values);
                let tag = declare(b, kind, values.len(), &mut used);
                let mut a = String::new();
                if !named && tag != name {
                    let _ = write!(a, " name=\"{}\"", escape(&name));
                }
                a.push_str(&meta);
                a.push_str(&port_attrs(catalog, b, values));
                let _ = writeln!(out, "{pad}<{tag}{a}/>");
                continue;
            }
        };
        let attrs = match options.params.get(i) {
            Some(written) => attr_text(written),
            None => attrs,
        };
        let _ = writeln!(out, "{pad}<{tag}{meta}{attrs}>");
        open.push((end, tag.to_string()));
    }
    while let Some((_, tag)) = open.pop() {
        let _ = writeln!(out, "{}</{tag}>", indent(open.len()));
    }
    out.push_str("  </BehaviorTree>\n  <TreeNodesModel>\n");
    for (&b, &(kind, argc, ref name)) in &used {
        let tag = match kind {
            _ if gates.contains(&b) => "Decorator",
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
                    writeln!(out, "      <input_port name=\"{}\" type=\"std::string\"/>", port_name(catalog, b, pos))
                }
            };
        }
        let _ = writeln!(out, "    </{tag}>");
    }
    out.push_str("  </TreeNodesModel>\n</root>\n");
    Ok(out)
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

/// `num_cycles` / `num_attempts` as BehaviorTree.CPP writes them: -1 for no limit.
fn count(n: u16) -> i32 {
    if n == NodeKind::FOREVER { -1 } else { i32::from(n) }
}

#[cfg(test)]
mod tests {
    use super::type_id;

    #[test]
    fn type_ids_are_xml_names() {
        assert_eq!(type_id("place"), "place");
        assert_eq!(type_id("hand-over"), "hand-over");
        assert_eq!(type_id("put 0 on 1!"), "put_0_on_1");
        assert_eq!(type_id("0 at pos (0.0, 0.05, 0.0)?"), "b0_at_pos_0_0_0_05_0_0");
        assert_eq!(type_id("?!"), "b");
    }
}
