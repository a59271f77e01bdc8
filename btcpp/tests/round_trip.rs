//! Exported XML imported again gives the same tree and the same image: random trees of
//! every kind that has a BehaviorTree.CPP or Nav2 equivalent (all but our own `Repeat`,
//! `Retry` and `Timeout`, which count ticks), plugin decorators (gates) and
//! `ManualSelector`s without children included.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::fmt;
use std::path::Path;

use bt_core::{BehaviorId, BehaviorInfo, Catalog, Leaf, LeafKind, Node, NodeKind};
use btcpp::xml::{ImportOptions, import_text, to_xml};
use proptest::prelude::*;

/// A behavior set like the planner's: conditions and actions with grounded object
/// arguments, names that are and are not XML names.
struct Objects;

const BEHAVIORS: [(&str, LeafKind, u8); 6] = [
    ("at", LeafKind::Condition, 2),
    ("hand empty?", LeafKind::Condition, 0),
    ("holding", LeafKind::Condition, 1),
    ("move-to", LeafKind::Action, 1),
    ("pick up!", LeafKind::Action, 1),
    ("place", LeafKind::Action, 3),
];
const OBJECTS: [&str; 4] = ["cube", "sphere", "goal", "table"];

impl Catalog for Objects {
    fn len(&self) -> usize {
        BEHAVIORS.len()
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        BEHAVIORS.get(usize::from(id)).map(|&(name, kind, arity)| BehaviorInfo { name, kind, arity })
    }

    fn port_name(&self, behavior: BehaviorId, position: usize) -> Option<&str> {
        (behavior == 5).then(|| ["what", "where", "on-top"][position])
    }

    fn write_arg(&self, f: &mut fmt::Formatter<'_>, _: BehaviorId, _: usize, value: u16) -> fmt::Result {
        f.write_str(OBJECTS[usize::from(value)])
    }

    fn parse_arg(&self, _: BehaviorId, _: usize, text: &str) -> Option<u16> {
        OBJECTS.iter().position(|o| *o == text).map(|i| i as u16)
    }
}

/// A random tree from a seed: pre-order nodes, every kind but Timeout.
fn tree(seed: u64) -> Vec<Node> {
    let mut s = seed | 1;
    let mut next = move |n: u64| {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s % n
    };
    let mut out: Vec<Node> = Vec::new();
    // (index, children left to make, depth)
    fn make(out: &mut Vec<Node>, depth: u32, next: &mut dyn FnMut(u64) -> u64) {
        let at = out.len();
        out.push(Node::EMPTY);
        // 0..=8 controls, 9..=10 two or three children, 11 two, 12..=21 decorators,
        // 22..=25 leaves, 26 a ManualSelector (any number of children, none included).
        let pick = if depth >= 5 { 22 + next(4) } else { next(27) };
        let children = match pick {
            0..=8 => 1 + next(4) as usize,
            26 => next(4) as usize,
            9..=10 => 2 + next(2) as usize,
            11 => 2,
            12..=21 => 1,
            _ => 0,
        };
        for _ in 0..children {
            make(out, depth + 1, next);
        }
        let c = children as u64;
        let count = |r: u64| match r % 8 {
            0 => NodeKind::FOREVER,
            1 => 0,
            r => r as u16 * 61,
        };
        let span = |r: u64| bt_core::Span::new([0, 1, 3, 7, 250, 1000, 60_000, 16_777_215][(r % 8) as usize]).unwrap();
        let kind = match pick {
            0 => NodeKind::Sequence,
            1 => NodeKind::Fallback,
            2 => NodeKind::SequenceWithMemory,
            3 => NodeKind::FallbackWithMemory,
            4 => NodeKind::SequenceStar,
            5 => NodeKind::Parallel {
                success_threshold: 1 + next(c) as u16,
                failure_threshold: 1 + next(c) as u16,
                count_skipped: next(2) == 0,
            },
            6 => NodeKind::ParallelAll { max_failures: next(c + 1) as u16 },
            7 => NodeKind::PipelineSequence,
            8 => NodeKind::RoundRobin,
            9 => NodeKind::IfThenElse,
            10 => NodeKind::WhileDoElse,
            11 => NodeKind::Recovery { retries: next(7) as u16 },
            12 => NodeKind::Inverter,
            13 => NodeKind::ForceSuccess,
            14 => NodeKind::ForceFailure,
            15 => NodeKind::RepeatCycles(count(next(64))),
            16 => NodeKind::RetryUntilSuccessful(count(next(64))),
            17 => NodeKind::KeepRunningUntilFailure,
            18 => NodeKind::RunOnce { then_skip: next(2) == 0 },
            19 => NodeKind::TimeLimit(span(next(8))),
            20 => NodeKind::Delay(span(next(8))),
            21 => NodeKind::RateController(span(1 + next(7))),
            22 => NodeKind::AlwaysSuccess,
            23 => NodeKind::AlwaysFailure,
            26 => NodeKind::ManualSelector { repeat_last: next(2) == 0 },
            _ => {
                let b = next(BEHAVIORS.len() as u64) as u16;
                let (_, kind, arity) = BEHAVIORS[usize::from(b)];
                let args: Vec<u16> = (0..arity).map(|_| next(OBJECTS.len() as u64) as u16).collect();
                let leaf = Leaf::with_args(b, &args).unwrap();
                if kind == LeafKind::Condition { NodeKind::Condition(leaf) } else { NodeKind::Action(leaf) }
            }
        };
        out[at] = Node::new(kind, (out.len() - at) as u16);
    }
    make(&mut out, 0, &mut next);
    out
}

fn image<C: Catalog + ?Sized>(nodes: &[Node], catalog: &C) -> Vec<u8> {
    let mut buf = vec![0u8; bt_core::image::max_image_len(nodes.len())];
    let n = bt_core::encode(nodes, catalog.fingerprint(), &mut buf).unwrap();
    buf.truncate(n);
    buf
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// A tree we make, written as XML and read back into its behavior set.
    #[test]
    fn exported_trees_import_to_the_same_image(seed in any::<u64>()) {
        let nodes = tree(seed);
        let tree: bt_core::Tree<'_, 16> = bt_core::Tree::validate(&nodes, &Objects).unwrap();
        let xml = to_xml(tree.nodes(), &Objects).unwrap();
        let options = ImportOptions { known: Some(&Objects), ..ImportOptions::default() };
        let back = import_text(Path::new("exported.xml"), &xml, &options).unwrap_or_else(|e| panic!("{e}\n{xml}"));
        prop_assert_eq!(&back.nodes, &nodes);
        prop_assert_eq!(back.fingerprint, Objects.fingerprint());
        prop_assert_eq!(image(&back.nodes, &Objects), image(&nodes, &Objects));
    }

    /// An imported tree (ports, constants, blackboard slots, names), written as XML and
    /// imported again.
    #[test]
    fn imported_trees_export_and_import_unchanged(seed in any::<u64>()) {
        let doc = document(seed);
        let first = import_text(Path::new("t.xml"), &doc, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}\n{doc}"));
        let xml = first.to_xml().unwrap();
        let second = import_text(Path::new("t.xml"), &xml, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}\n{xml}"));
        prop_assert_eq!(&second.nodes, &first.nodes);
        prop_assert_eq!(&second.values, &first.values);
        prop_assert_eq!(&second.constants, &first.constants);
        prop_assert_eq!(&second.slots, &first.slots);
        prop_assert_eq!(&second.meta, &first.meta);
        prop_assert_eq!(second.fingerprint, first.fingerprint);
        prop_assert_eq!(second.image().unwrap(), first.image().unwrap());
    }
}

/// A random document over a catalog with typed ports: the tree of [`tree`] with its
/// leaves replaced by ported ones.
fn document(seed: u64) -> String {
    let nodes = tree(seed);
    let mut s = seed.rotate_left(17) | 1;
    let mut next = move |n: u64| {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s % n
    };
    let mut xml = String::from("<root BTCPP_format=\"4\"><BehaviorTree ID=\"T\">");
    let mut open: Vec<(usize, &str)> = Vec::new();
    for (i, n) in nodes.iter().enumerate() {
        while open.last().is_some_and(|&(end, _)| end <= i) {
            xml.push_str(&format!("</{}>", open.pop().unwrap().1));
        }
        let name = if next(4) == 0 { format!(" name=\"n{i}\"") } else { String::new() };
        let count = |k: u16| if k == NodeKind::FOREVER { -1 } else { i32::from(k) };
        let (tag, attrs) = match *n.kind() {
            NodeKind::Sequence => ("ReactiveSequence", String::new()),
            NodeKind::Fallback => ("ReactiveFallback", String::new()),
            NodeKind::SequenceWithMemory => ("Sequence", String::new()),
            NodeKind::FallbackWithMemory => ("Fallback", String::new()),
            NodeKind::SequenceStar => ("SequenceWithMemory", String::new()),
            NodeKind::Parallel { success_threshold, failure_threshold, count_skipped } => {
                let children = bt_core::children(&nodes, i as u16).count() as i32;
                let s = if count_skipped {
                    i32::from(success_threshold) - children - 1
                } else {
                    i32::from(success_threshold)
                };
                ("Parallel", format!(" success_count=\"{s}\" failure_count=\"{failure_threshold}\""))
            }
            NodeKind::ParallelAll { max_failures } => ("ParallelAll", format!(" max_failures=\"{max_failures}\"")),
            NodeKind::PipelineSequence => ("PipelineSequence", String::new()),
            NodeKind::RoundRobin => ("RoundRobin", String::new()),
            NodeKind::IfThenElse => ("IfThenElse", String::new()),
            NodeKind::WhileDoElse => ("WhileDoElse", String::new()),
            NodeKind::Recovery { retries } => ("RecoveryNode", format!(" number_of_retries=\"{retries}\"")),
            // Half the Inverters become a plugin decorator (a gate) with a port.
            NodeKind::Inverter if next(2) == 0 => {
                ("Throttle", format!(" every=\"{}\"", ["0.5", "2", "{period}"][next(3) as usize]))
            }
            NodeKind::Inverter => ("Inverter", String::new()),
            NodeKind::ForceSuccess => ("ForceSuccess", String::new()),
            NodeKind::ForceFailure => ("ForceFailure", String::new()),
            NodeKind::RepeatCycles(k) => ("Repeat", format!(" num_cycles=\"{}\"", count(k))),
            NodeKind::RetryUntilSuccessful(k) => ("RetryUntilSuccessful", format!(" num_attempts=\"{}\"", count(k))),
            NodeKind::KeepRunningUntilFailure => ("KeepRunningUntilFailure", String::new()),
            NodeKind::RunOnce { then_skip } => ("RunOnce", format!(" then_skip=\"{then_skip}\"")),
            // The parameter left out half the time when it is the default.
            NodeKind::ManualSelector { repeat_last: false } if next(2) == 0 => ("ManualSelector", String::new()),
            NodeKind::ManualSelector { repeat_last } => {
                ("ManualSelector", format!(" repeat_last_selection=\"{repeat_last}\""))
            }
            NodeKind::TimeLimit(t) => ("Timeout", format!(" msec=\"{}\"", t.get())),
            NodeKind::Delay(t) => ("Delay", format!(" delay_msec=\"{}\"", t.get())),
            // Rates as people write them; the period is what is compared.
            NodeKind::RateController(t) => ("RateController", format!(" hz=\"{}\"", 1000.0 / f64::from(t.get()))),
            NodeKind::AlwaysSuccess => {
                xml.push_str(&format!("<AlwaysSuccess{name}/>"));
                continue;
            }
            NodeKind::AlwaysFailure => {
                xml.push_str(&format!("<AlwaysFailure{name}/>"));
                continue;
            }
            _ => {
                let leaf = match next(3) {
                    0 => {
                        format!("<Near target=\"{{t{}}}\" within=\"{}\"/>", next(3), [0.5, 1.0, 2.25][next(3) as usize])
                    }
                    1 => String::from("<Idle/>"),
                    _ => {
                        let mut a = format!("<Go goal=\"{{g{}}}\"", next(2));
                        if next(2) == 0 {
                            a.push_str(&format!(" speed=\"{}\"", next(4)));
                        }
                        if next(2) == 0 {
                            a.push_str(" done=\"{done}\"");
                        }
                        if next(2) == 0 {
                            a.push_str(&format!(
                                " note=\"{}\" tries=\"{}\"",
                                ["a", "b&amp;c", "x y"][next(3) as usize],
                                next(3)
                            ));
                        }
                        a.push_str("/>");
                        if next(2) == 0 {
                            a = format!("<Say label=\"{}\"/>", ["a", "b&amp;c", "x y"][next(3) as usize]);
                        }
                        a
                    }
                };
                xml.push_str(&leaf.replacen("/>", &format!("{name}/>"), 1));
                continue;
            }
        };
        xml.push_str(&format!("<{tag}{name}{attrs}>"));
        open.push((i + usize::from(n.size()), tag));
    }
    while let Some((_, tag)) = open.pop() {
        xml.push_str(&format!("</{tag}>"));
    }
    xml.push_str(
        "</BehaviorTree><TreeNodesModel>\
         <Condition ID=\"Near\"><input_port name=\"target\" type=\"Pose\"/><input_port name=\"within\" type=\"double\" default=\"1.0\"/></Condition>\
         <Condition ID=\"Idle\"/>\
         <Action ID=\"Go\"><input_port name=\"goal\" type=\"Pose\"/><input_port name=\"speed\" type=\"unsigned int\" default=\"2\"/>\
         <output_port name=\"done\" type=\"bool\"/><input_port name=\"note\" type=\"std::string\"/>\
         <input_port name=\"tries\" type=\"unsigned int\" default=\"2\"/></Action>\
         <Action ID=\"Say\"><input_port name=\"label\" type=\"std::string\"/></Action>\
         <Decorator ID=\"Throttle\"><input_port name=\"every\" type=\"double\"/></Decorator>\
         </TreeNodesModel></root>",
    );
    xml
}
