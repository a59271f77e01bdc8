//! A tree as BehaviorTree.CPP instantiates it: its nodes with their uids, registration
//! IDs, instance names and port attributes, SubTree nodes included. Made from bt-core
//! nodes (and, for imported trees, what the import kept of the document).

use bt_core::{Catalog, Node, NodeKind, PortValue};

use crate::btlog::stdmap;
use crate::kinds::{self, SCRIPT_ATTRIBUTES};
use crate::xml::Imported;
use crate::xml::write::type_id;

/// What a node does, in BehaviorTree.CPP's terms.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `Sequence`.
    Sequence,
    /// `SequenceWithMemory`.
    SequenceWithMemory,
    /// `Fallback`.
    Fallback,
    /// `ReactiveSequence`.
    ReactiveSequence,
    /// `ReactiveFallback`.
    ReactiveFallback,
    /// `Parallel`.
    Parallel {
        /// `success_count`.
        success: i32,
        /// `failure_count`.
        failure: i32,
    },
    /// `ParallelAll`.
    ParallelAll {
        /// `max_failures`.
        max_failures: i32,
    },
    /// `IfThenElse`.
    IfThenElse,
    /// `WhileDoElse`.
    WhileDoElse,
    /// `Inverter`.
    Inverter,
    /// `ForceSuccess`.
    ForceSuccess,
    /// `ForceFailure`.
    ForceFailure,
    /// `Repeat`.
    Repeat(i32),
    /// `RetryUntilSuccessful`.
    Retry(i32),
    /// `KeepRunningUntilFailure`.
    KeepRunningUntilFailure,
    /// `RunOnce`.
    RunOnce {
        /// `then_skip`.
        then_skip: bool,
    },
    /// `Timeout`: its `msec`.
    Timeout(u32),
    /// `Delay`: its `delay_msec`.
    Delay(u32),
    /// Nav2's `RateController`: its period in milliseconds.
    RateController(u32),
    /// Nav2's `PipelineSequence`.
    PipelineSequence,
    /// Nav2's `RecoveryNode`: its `number_of_retries`.
    Recovery(i32),
    /// Nav2's `RoundRobin`.
    RoundRobin,
    /// `AlwaysSuccess`.
    AlwaysSuccess,
    /// `AlwaysFailure`.
    AlwaysFailure,
    /// A `<SubTree>` node.
    SubTree,
    /// A condition leaf.
    Condition,
    /// An action leaf.
    Action,
    /// `Script`: a leaf whose run answers as a condition (its result consumed, Success).
    Script,
    /// `ScriptCondition`: a leaf whose run answers Success or Failure.
    ScriptCondition,
    /// `Precondition`: its `else` status; its script's result is asked as a leaf's.
    Precondition(u8),
    /// `Sleep`: its `msec`.
    Sleep(u32),
    /// `ManualSelector`: its `repeat_last_selection`.
    ManualSelector {
        /// `repeat_last_selection`.
        repeat_last: bool,
    },
    /// `LoopInt`, ..., or a loop the program registers: the number of elements of a
    /// literal queue (`None`: a blackboard queue, whose pops are asked as a leaf's) and
    /// its `if_empty` status.
    Loop {
        /// Elements of a literal queue.
        elements: Option<u16>,
        /// The status when the queue is empty.
        if_empty: u8,
    },
    /// BehaviorTree.CPP 3's `SequenceStar`.
    SequenceStarV3,
    /// BehaviorTree.CPP 3's `Parallel`: `success_threshold`, `failure_threshold`.
    ParallelV3 {
        /// `success_threshold`.
        success: i32,
        /// `failure_threshold`.
        failure: i32,
    },
    /// `Repeat` or `RetryUntilSuccessful` with a count read from the blackboard, or
    /// BehaviorTree.CPP 3's (whose cycles run within the tick).
    Cycles {
        /// The count (-1: no limit); `None` when read from the blackboard.
        count: Option<i32>,
        /// `RetryUntilSuccessful`.
        retry: bool,
        /// BehaviorTree.CPP 3's.
        v3: bool,
    },
    /// BehaviorTree.CPP 3's `BlackboardCheck*`: its `return_on_mismatch` status; its
    /// comparison's result is asked as a leaf's.
    Check(u8),
    /// A plugin decorator a model declares (bt-core's `Gate`: Nav2's
    /// `DistanceController`, `GoalUpdater`, ...): its answer is asked as a leaf's.
    Gate,
}

impl Kind {
    /// Whether it has exactly one child.
    #[must_use]
    pub const fn is_decorator(self) -> bool {
        matches!(
            self,
            Self::Inverter
                | Self::ForceSuccess
                | Self::ForceFailure
                | Self::Repeat(_)
                | Self::Retry(_)
                | Self::KeepRunningUntilFailure
                | Self::RunOnce { .. }
                | Self::Timeout(_)
                | Self::Delay(_)
                | Self::RateController(_)
                | Self::SubTree
                | Self::Precondition(_)
                | Self::Loop { .. }
                | Self::Cycles { .. }
                | Self::Check(_)
                | Self::Gate
        )
    }
}

/// One node as BehaviorTree.CPP has it.
#[derive(Clone, Debug)]
pub struct LogNode {
    /// Its uid (creation order from 1).
    pub uid: u16,
    /// The element name BehaviorTree.CPP writes: the registration ID, `SubTree` for a
    /// SubTree node.
    pub element: String,
    /// The instance name (`name` attribute, else the registration ID); for a SubTree
    /// node, the subtree's ID.
    pub name: String,
    /// Its semantics.
    pub kind: Kind,
    /// Children, as indices into [`LogTree::nodes`].
    pub children: Vec<usize>,
    /// Port attributes in the order BehaviorTree.CPP writes them.
    pub attrs: Vec<(String, String)>,
    /// The bt-core node it is (none for a SubTree node).
    pub core: Option<usize>,
    /// For a SubTree node: the node's `_fullpath` and the instance's path.
    pub subtree: Option<(String, String)>,
    /// Its scripted attributes (`_skipIf`, `_onSuccess`, ...), when it has any.
    pub hooks: Option<Hooks>,
}

/// A node's scripted attributes: bt-core's guard in front of the node runs them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Hooks {
    /// The guard's bt-core node (the run's script calls of the hooks are its).
    pub core: usize,
    /// Which attributes it has: bit `k` for [`SCRIPT_ATTRIBUTES`]`[k]`
    /// ([`bt_core::script::Hook`] order).
    pub mask: u8,
}

impl Hooks {
    /// Whether it has attribute `hook`.
    #[must_use]
    pub fn has(self, hook: bt_core::script::Hook) -> bool {
        self.mask & (1 << hook as u8) != 0
    }
}

/// A leaf type's model, as registered in the factory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LeafModel {
    /// `Action`, `Condition`, or `Decorator` (a plugin decorator's).
    pub tag: &'static str,
    /// Registration ID.
    pub id: String,
    /// Ports in the order the model declares them: tag (`input_port`, ...), name,
    /// type, default.
    pub ports: Vec<(&'static str, String, String, Option<String>)>,
}

/// The whole tree, pre-order, the root first.
#[derive(Clone, Debug)]
pub struct LogTree {
    /// The main tree's ID.
    pub main: String,
    /// The nodes, in uid order.
    pub nodes: Vec<LogNode>,
    /// The leaf types registered (all of the behavior set).
    pub models: Vec<LeafModel>,
}

/// Why a tree has no BehaviorTree.CPP form.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("node {node} is a {kind}, which BehaviorTree.CPP has no exact equivalent for")]
pub struct NotExpressible {
    /// The bt-core node.
    pub node: usize,
    /// Its kind.
    pub kind: &'static str,
}

/// A loop's kind and registration ID (`None` for one the program registers, whose ID
/// the document gives), from its table in `values`.
fn loop_kind(table: bt_core::Code, if_empty: bt_core::Status, values: &[u16]) -> Option<(Kind, Option<&'static str>)> {
    use bt_core::script::{Queue, queue, queue_element};
    let words = table.words(values);
    let element = kinds::loop_entry(queue_element(words)?.0).map(|e| e.id);
    let elements = match queue(words)? {
        Queue::Literal(l) => Some(l.first().copied()?),
        Queue::Key { .. } => None,
    };
    Some((Kind::Loop { elements, if_empty: kinds::status_code(if_empty).0 }, element))
}

/// The attribute order BehaviorTree.CPP prints for ports given in `given` order (all
/// inputs), after adding the defaults.
fn attr_order(given: Vec<(String, String)>, defaults: &[(&str, &str)]) -> Vec<(String, String)> {
    // The attributes go into one map in document order, which is then walked to fill
    // the node's input map, after which absent defaults are added.
    let remap = stdmap::order(given.iter().map(|(k, _)| k.as_str()));
    inputs_order(&remap, &given, defaults)
}

/// [`attr_order`] from the attribute map's order (`remap`, inputs only).
fn inputs_order(remap: &[String], given: &[(String, String)], defaults: &[(&str, &str)]) -> Vec<(String, String)> {
    let mut inputs: Vec<&str> = remap.iter().map(String::as_str).collect();
    for (k, _) in defaults {
        if !inputs.contains(k) {
            inputs.push(k);
        }
    }
    let order = stdmap::order(inputs.iter().copied());
    order
        .into_iter()
        .map(|k| {
            let v = given
                .iter()
                .find(|(g, _)| *g == k)
                .map(|(_, v)| v.clone())
                .or_else(|| defaults.iter().find(|(d, _)| *d == k).map(|(_, v)| (*v).to_string()))
                .unwrap_or_default();
            (k, v)
        })
        .collect()
}

impl LogTree {
    /// The tree of bt-core `nodes` whose leaves `catalog` names (their values as ports
    /// named by [`Catalog::port_name`]), numbered as BehaviorTree.CPP numbers the XML
    /// [`to_xml`](crate::xml::to_xml) writes for it. For a tree without a value table
    /// (no extended leaves); otherwise [`LogTree::with_values`].
    ///
    /// # Errors
    /// [`NotExpressible`] for kinds BehaviorTree.CPP has no equivalent of.
    pub fn new<C: Catalog + ?Sized>(nodes: &[Node], catalog: &C) -> Result<Self, NotExpressible> {
        Self::with_values(nodes, &[], catalog)
    }

    /// [`LogTree::new`] for a tree with a value table (`values`, as
    /// [`Tree::values`](bt_core::Tree::values) gives it): extended leaves (more than
    /// [`bt_core::MAX_ARGS`] arguments) get their port attributes from it, as
    /// [`to_xml_with`](crate::xml::to_xml_with) writes them.
    ///
    /// # Errors
    /// [`NotExpressible`] for kinds BehaviorTree.CPP has no equivalent of.
    pub fn with_values<C: Catalog + ?Sized>(
        nodes: &[Node],
        values: &[u16],
        catalog: &C,
    ) -> Result<Self, NotExpressible> {
        let uids: Vec<u16> = (1..=nodes.len()).map(|u| u16::try_from(u).unwrap_or(u16::MAX)).collect();
        let names: Vec<Option<String>> = vec![None; nodes.len()];
        Self::build(nodes, values, catalog, "MainTree", &uids, &names, &[], &[], &[], |leaf| {
            leaf.args_in(values).to_vec()
        })
    }

    /// The tree of an imported document, SubTree nodes and names included.
    ///
    /// # Errors
    /// [`NotExpressible`] for kinds BehaviorTree.CPP has no equivalent of.
    pub fn of_imported(imported: &Imported) -> Result<Self, NotExpressible> {
        let uids: Vec<u16> = imported.meta.iter().map(|m| m.uid).collect();
        let names: Vec<Option<String>> = imported.meta.iter().map(|m| m.name.clone()).collect();
        let params: Vec<Option<&[(String, String)]>> =
            imported.meta.iter().map(|m| Some(m.params.as_slice())).collect();
        let ids: Vec<&str> = imported.meta.iter().map(|m| m.id.as_str()).collect();
        Self::build(
            &imported.nodes,
            &imported.values,
            imported,
            &imported.main,
            &uids,
            &names,
            &params,
            &imported.subtrees,
            &ids,
            |leaf| imported.leaf_values(leaf).to_vec(),
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn build<C: Catalog + ?Sized>(
        nodes: &[Node],
        table: &[u16],
        catalog: &C,
        main: &str,
        uids: &[u16],
        names: &[Option<String>],
        params: &[Option<&[(String, String)]>],
        subtrees: &[bt_formats::names::SubtreeSource],
        ids: &[&str],
        values: impl Fn(&bt_core::Leaf) -> Vec<u16>,
    ) -> Result<Self, NotExpressible> {
        let mut out: Vec<LogNode> = Vec::with_capacity(nodes.len() + subtrees.len());
        // A guard's attributes, until the node it guards is made.
        let mut pending: Option<Pending> = None;
        // Open nodes: (index in out, end of its bt-core subtree).
        let mut open: Vec<(usize, usize)> = Vec::new();
        for (i, n) in nodes.iter().enumerate() {
            while open.last().is_some_and(|&(_, end)| end <= i) {
                open.pop();
            }
            // SubTree nodes whose subtree's root is node i, outermost first.
            for s in subtrees.iter().filter(|s| usize::from(s.node) == i) {
                let idx = out.len();
                if let Some(&(p, _)) = open.last() {
                    out[p].children.push(idx);
                }
                let attrs = stdmap::order(s.attrs.iter().map(|(k, _)| k.as_str()))
                    .into_iter()
                    .map(|k| {
                        let v = s.attrs.iter().find(|(a, _)| *a == k).map(|(_, v)| v.clone()).unwrap_or_default();
                        (k, v)
                    })
                    .collect();
                out.push(LogNode {
                    uid: s.uid,
                    element: "SubTree".into(),
                    name: s.id.clone(),
                    kind: Kind::SubTree,
                    children: Vec::new(),
                    attrs,
                    core: None,
                    subtree: Some((s.path.clone(), s.instance.clone())),
                    hooks: None,
                });
                attach(&mut out, &mut pending);
                open.push((idx, i + usize::from(n.size())));
            }
            if let NodeKind::Guard(_) = n.kind() {
                // No node of its own: its attributes go on the node it guards (the next
                // one made, with its uid: a SubTree node, or the bt-core node after it).
                let written = params.get(i).copied().flatten().filter(|w| !w.is_empty());
                let Some(written) = written else {
                    return Err(NotExpressible { node: i, kind: n.kind().name() });
                };
                let mut mask = 0u8;
                let mut attrs = Vec::new();
                for (bit, name) in SCRIPT_ATTRIBUTES.iter().enumerate() {
                    if let Some((_, text)) = written.iter().find(|(k, _)| k == name) {
                        mask |= 1 << bit;
                        attrs.push((name.to_string(), text.clone()));
                    }
                }
                // One guard's attributes wait at a time: the node it guards comes next.
                if let Some(p) = pending.replace(Pending {
                    uid: uids.get(i).copied().unwrap_or(0),
                    hooks: Hooks { core: i, mask },
                    attrs,
                }) {
                    return Err(NotExpressible { node: p.hooks.core, kind: n.kind().name() });
                }
                continue;
            }
            let idx = out.len();
            if let Some(&(p, _)) = open.last() {
                out[p].children.push(idx);
            }
            let (kind, element, attrs, default_name) = match n.kind() {
                NodeKind::Condition(leaf) | NodeKind::Action(leaf) | NodeKind::Gate(leaf) => {
                    let b = leaf.behavior();
                    let name = catalog.info(b).map_or_else(|| format!("behavior{b}"), |i| i.name.to_string());
                    let element = type_id(&name);
                    let vals = values(leaf);
                    let given: Vec<(String, String)> = vals
                        .iter()
                        .enumerate()
                        .filter(|&(pos, &v)| {
                            catalog.port(b, pos).is_none() || PortValue::from_u16(v) != PortValue::Unset
                        })
                        .map(|(pos, &v)| {
                            (
                                crate::xml::write::port_name(catalog, b, pos),
                                crate::xml::write::arg_text(catalog, b, pos, v),
                            )
                        })
                        .collect();
                    let kind = match n.kind() {
                        NodeKind::Condition(_) => Kind::Condition,
                        NodeKind::Gate(_) => Kind::Gate,
                        _ => Kind::Action,
                    };
                    let default_name = if element == name { None } else { Some(name) };
                    (kind, element, attr_order(given, &[]), default_name)
                }
                &NodeKind::Loop { table: t, if_empty } => {
                    let Some((kind, element)) = loop_kind(t, if_empty, table) else {
                        return Err(NotExpressible { node: i, kind: "Loop" });
                    };
                    // Its attributes only as the document wrote them (an image keeps
                    // elements as programs); one the program registers has its ID there.
                    let (Some(written), Some(element)) =
                        (params.get(i).copied().flatten(), element.or_else(|| ids.get(i).copied()))
                    else {
                        return Err(NotExpressible { node: i, kind: "Loop" });
                    };
                    // The inputs as BehaviorTree.CPP orders them, then the output `value`.
                    let remap = stdmap::order(written.iter().map(|(k, _)| k.as_str()));
                    let inputs: Vec<String> = remap.into_iter().filter(|k| k != "value").collect();
                    let mut attrs = inputs_order(&inputs, written, kinds::LOOP_LOG_DEFAULTS);
                    attrs.extend(written.iter().filter(|(k, _)| k == "value").cloned());
                    (kind, element.to_string(), attrs, None)
                }
                other => {
                    let children = u16::try_from(i).map_or(0, |id| bt_core::children(nodes, id).count());
                    let Some((entry, canonical)) = kinds::written(other, children) else {
                        return Err(NotExpressible { node: i, kind: other.name() });
                    };
                    // The attributes as the document wrote them (`failure_count="-1"`),
                    // else as the kind gives them back.
                    let given = match params.get(i).copied().flatten() {
                        Some(written) => written.to_vec(),
                        None => canonical.params.into_iter().map(|(k, v)| (k.to_string(), v)).collect(),
                    };
                    (canonical.log, entry.id.to_string(), attr_order(given, entry.log_defaults), None)
                }
            };
            let name = names.get(i).cloned().flatten().or(default_name).unwrap_or_else(|| element.clone());
            out.push(LogNode {
                uid: uids.get(i).copied().unwrap_or(0),
                element,
                name,
                kind,
                children: Vec::new(),
                attrs,
                core: Some(i),
                subtree: None,
                hooks: None,
            });
            attach(&mut out, &mut pending);
            if n.size() > 1 {
                open.push((idx, i + usize::from(n.size())));
            }
        }
        // A guard whose node never came (numbered otherwise) has no BehaviorTree.CPP form.
        if let Some(p) = pending {
            return Err(NotExpressible { node: p.hooks.core, kind: "Guard" });
        }
        let mut models = Vec::new();
        // The behaviors gates ask are the plugin decorators' models.
        let gates: Vec<u16> = nodes
            .iter()
            .filter_map(|n| if let NodeKind::Gate(leaf) = n.kind() { Some(leaf.behavior()) } else { None })
            .collect();
        for b in 0..catalog.len() {
            let Ok(b) = u16::try_from(b) else { break };
            let Some(info) = catalog.info(b) else { continue };
            let tag = if gates.contains(&b) {
                "Decorator"
            } else if info.kind == bt_core::LeafKind::Condition {
                "Condition"
            } else {
                "Action"
            };
            let ports = (0..usize::from(info.arity))
                .map(|pos| match catalog.port(b, pos) {
                    Some(p) => (
                        p.direction.tag(),
                        p.name.to_string(),
                        if p.type_name.is_empty() { "BT::AnyTypeAllowed".to_string() } else { p.type_name.to_string() },
                        p.default.map(str::to_string),
                    ),
                    None => ("input_port", crate::xml::write::port_name(catalog, b, pos), "std::string".into(), None),
                })
                .collect();
            models.push(LeafModel { tag, id: type_id(info.name), ports });
        }
        Ok(Self { main: main.to_string(), nodes: out, models })
    }
}

/// A guard's attributes waiting for their node.
struct Pending {
    uid: u16,
    hooks: Hooks,
    /// The attributes in the order BehaviorTree.CPP writes them (its condition maps'
    /// order, which is [`SCRIPT_ATTRIBUTES`]'), with the scripts as written.
    attrs: Vec<(String, String)>,
}

/// Gives the node just made (the last of `out`) the pending attributes if they are its.
fn attach(out: &mut [LogNode], pending: &mut Option<Pending>) {
    if let Some(node) = out.last_mut()
        && pending.as_ref().is_some_and(|p| p.uid == node.uid)
        && let Some(p) = pending.take()
    {
        node.hooks = Some(p.hooks);
        node.attrs.extend(p.attrs);
    }
}
