//! Our `.btlog` against BehaviorTree.CPP's own, byte for byte but the timestamps.
//!
//! `fixtures/btlog/cases.txt` are runs in the differential harness's input form (see
//! `fixtures/btlog/README.md`); each `.btlog` is what BehaviorTree.CPP 4.10.0's
//! FileLogger2 wrote for it. The test imports each case's XML, replays it with the
//! same scripted leaves through [`Replay`], writes our log, and compares.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::collections::BTreeMap;
use std::path::Path;

use btcpp::btlog::replay::status;
use btcpp::btlog::{Leaves, Log, LogTree, LogWriter, Replay, Ticking};
use btcpp::xml::{ImportOptions, import_text};

/// One harness case.
struct Case {
    name: String,
    ticks: usize,
    /// Leaf type (`C2`, `A3`) -> script.
    scripts: BTreeMap<String, String>,
    xml: String,
    btlog: Option<String>,
}

fn cases(text: &str) -> Vec<Case> {
    let mut out = Vec::new();
    let mut c: Option<Case> = None;
    for line in text.lines() {
        let (key, rest) = line.split_once(' ').unwrap_or((line, ""));
        match key {
            "case" => {
                c = Some(Case {
                    name: rest.to_string(),
                    ticks: 0,
                    scripts: BTreeMap::new(),
                    xml: String::new(),
                    btlog: None,
                })
            }
            "ticks" => c.as_mut().unwrap().ticks = rest.parse().unwrap(),
            "leaf" => {
                let w: Vec<&str> = rest.split(' ').collect();
                c.as_mut().unwrap().scripts.insert(format!("{}{}", w[1], w[0]), w[2].to_string());
            }
            "xml" => c.as_mut().unwrap().xml = rest.to_string(),
            "btlog" => c.as_mut().unwrap().btlog = Some(rest.to_string()),
            "end" => out.push(c.take().unwrap()),
            _ => {}
        }
    }
    out
}

/// Leaves answering from their scripts, cyclically, as the harness's do.
struct Scripted<'a> {
    /// bt-core node -> (script, calls so far).
    by_node: BTreeMap<usize, (&'a str, usize)>,
}

impl Leaves for Scripted<'_> {
    fn tick(&mut self, core: usize) -> u8 {
        let (script, calls) = self.by_node.get_mut(&core).unwrap();
        let c = script.as_bytes()[*calls % script.len()];
        *calls += 1;
        match c {
            b'S' => status::SUCCESS,
            b'F' => status::FAILURE,
            _ => status::RUNNING,
        }
    }

    fn halt(&mut self, _: usize) {}
}

/// The case's XML with models for its scripted leaves (the harness registers them).
fn with_models(case: &Case) -> String {
    let models: String = case
        .scripts
        .keys()
        .map(|id| {
            let tag = if id.starts_with('C') { "Condition" } else { "Action" };
            format!("<{tag} ID=\"{id}\"/>")
        })
        .collect();
    case.xml.replace("</root>", &format!("<TreeNodesModel>{models}</TreeNodesModel></root>"))
}

#[test]
fn our_logs_equal_behaviortree_cpps_but_for_timestamps() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/btlog");
    let all = cases(&std::fs::read_to_string(dir.join("cases.txt")).unwrap());
    let mut compared = 0;
    // Cases with scripts: `the_run_of_a_tree_with_scripts_logs_as_behaviortree_cpps`.
    for case in all.iter().filter(|c| c.btlog.is_some() && !has_scripts(c)) {
        let theirs = Log::parse(&std::fs::read(dir.join(case.btlog.as_ref().unwrap())).unwrap()).unwrap();
        let imported = import_text(Path::new(&case.name), &with_models(case), &ImportOptions::default()).unwrap();
        let tree = LogTree::of_imported(&imported).unwrap();
        assert_eq!(tree.xml(), theirs.xml, "{}: the log's XML", case.name);
        let mut leaves = Scripted { by_node: BTreeMap::new() };
        for (i, m) in imported.meta.iter().enumerate() {
            if let Some(s) = case.scripts.get(&m.id) {
                leaves.by_node.insert(i, (s.as_str(), 0));
            }
        }
        let mut replay = Replay::new(&tree);
        let mut ours = LogWriter::new(&tree, theirs.first_usec);
        for tick in 0..case.ticks {
            let (_, transitions) = replay.tick(&mut leaves, tick as u32, Ticking::ExactlyOnce);
            for (uid, s) in transitions {
                ours.transition(theirs.first_usec + tick as i64 * 1000, uid, s);
            }
        }
        let ours = Log::parse(ours.bytes()).unwrap();
        let strip = |l: &Log| l.transitions.iter().map(|&(_, uid, s)| (uid, s)).collect::<Vec<_>>();
        assert_eq!(strip(&ours), strip(&theirs), "{}: transitions", case.name);
        compared += 1;
    }
    assert_eq!(compared, 3);
}

/// A controller's view of a case: scripted leaves (cyclic, as the harness's) and the
/// scripts run by `bt_core::script` on a blackboard, every call recorded as the log's
/// replay takes it (a script's run answered as a leaf's: a `Script` succeeds, the others
/// as their result holds).
struct Run<'p> {
    ports: bt_core::PortTable<'p>,
    blackboard: [Option<bt_core::script::Value>; 8],
    /// bt-core node -> (leaf script, calls so far).
    leaves: BTreeMap<usize, (String, usize)>,
    /// bt-core nodes that are `Script` nodes.
    scripts: Vec<usize>,
    calls: Vec<(usize, u8)>,
    /// Per loop over a `{key}`: the elements of the string the key held at the loop's
    /// first pop of its activation (BT.CPP reads a string entry such as `"1;2;3"` as a
    /// queue), and how many it took.
    queues: BTreeMap<usize, (Vec<i64>, usize)>,
}

impl Run<'_> {
    fn leaf(&mut self, node: bt_core::NodeId) -> bt_core::Status {
        let (script, calls) = self.leaves.get_mut(&usize::from(node)).unwrap();
        let c = script.as_bytes()[*calls % script.len()];
        *calls += 1;
        let (s, code) = match c {
            b'S' => (bt_core::Status::Success, status::SUCCESS),
            b'F' => (bt_core::Status::Failure, status::FAILURE),
            _ => (bt_core::Status::Running, status::RUNNING),
        };
        self.calls.push((usize::from(node), code));
        s
    }
}

impl bt_core::BehaviorSet for Run<'_> {
    fn condition(&mut self, _: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
        self.leaf(ctx.node)
    }
    fn action(&mut self, _: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> bt_core::Status {
        self.leaf(ctx.node)
    }
    fn halt(&mut self, _: &bt_core::Leaf, _: bt_core::NodeId) {}
    fn script(
        &mut self,
        code: &[u16],
        ctx: bt_core::Context<'_>,
    ) -> Result<bt_core::script::Value, bt_core::script::ScriptFault> {
        let v = bt_core::script::run(code, &self.ports, &mut self.blackboard)?;
        let node = usize::from(ctx.node);
        let held = self.scripts.contains(&node) || bt_core::script::truth(v).unwrap_or(false);
        self.calls.push((node, if held { status::SUCCESS } else { status::FAILURE }));
        Ok(v)
    }
    fn pop(&mut self, queue: u16, value: u16, ctx: bt_core::Context<'_>) -> Result<bool, bt_core::script::ScriptFault> {
        use bt_core::script::{ScriptFault, Value};
        let node = usize::from(ctx.node);
        if ctx.starting {
            let Some(Value::Str(k)) = self.blackboard[usize::from(queue)] else {
                return Err(ScriptFault::Unset { slot: queue });
            };
            let Some(bt_core::port::Constant::Str(text)) = self.ports.constant(k) else {
                return Err(ScriptFault::NotPermitted);
            };
            let elements = text.split(';').filter(|e| !e.is_empty()).map(|e| e.parse().unwrap()).collect();
            self.queues.insert(node, (elements, 0));
        }
        let (elements, taken) = self.queues.get_mut(&node).unwrap();
        let next = elements.get(*taken).copied();
        if let Some(v) = next {
            *taken += 1;
            self.blackboard[usize::from(value)] = Some(Value::Int(v));
        }
        self.calls.push((node, if next.is_some() { status::SUCCESS } else { status::FAILURE }));
        Ok(next.is_some())
    }
}

/// Trees with scripts (a SubTree node with scripted attributes: `_failureIf`,
/// `_onSuccess`, `_onHalted`, `_post`; a `LoopInt` over a `{key}` holding a string,
/// popped by the behavior set; one over a SubTree's key started at a literal, compiled
/// as a literal queue), run on bt-core from their image as a controller
/// runs them, logged through [`RunLog`](btcpp::btlog::RunLog) as `sim-host` logs a run:
/// the XML and every transition are BT.CPP's.
#[test]
fn the_run_of_a_tree_with_scripts_logs_as_behaviortree_cpps() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/btlog");
    let all = cases(&std::fs::read_to_string(dir.join("cases.txt")).unwrap());
    let mut compared = 0;
    for case in all.iter().filter(|c| c.btlog.is_some() && has_scripts(c)) {
        let theirs = Log::parse(&std::fs::read(dir.join(case.btlog.as_ref().unwrap())).unwrap()).unwrap();
        let imported = import_text(Path::new(&case.name), &with_models(case), &ImportOptions::default()).unwrap();
        let tree = LogTree::of_imported(&imported).unwrap();
        assert_eq!(tree.xml(), theirs.xml, "{}: the log's XML", case.name);
        let image = imported.image().unwrap();
        let mut nodes = [bt_core::Node::EMPTY; 32];
        let mut values = [0u16; 256];
        let (core, ports): (bt_core::Tree<'_, 16>, _) =
            bt_core::load_with_ports(&image, &imported.catalog, &mut nodes, &mut values).unwrap();
        let mut run = Run {
            ports,
            blackboard: [None; 8],
            leaves: BTreeMap::new(),
            scripts: vec![],
            calls: vec![],
            queues: BTreeMap::new(),
        };
        for (i, m) in imported.meta.iter().enumerate() {
            if let Some(s) = case.scripts.get(&m.id) {
                run.leaves.insert(i, (s.clone(), 0));
            }
            if m.id == "Script" {
                run.scripts.push(i);
            }
        }
        let mut state = [bt_core::NodeState::IDLE; 32];
        let mut exec = bt_core::Executor::new(core, &mut state).unwrap();
        let mut log = btcpp::btlog::RunLog::new(&tree, theirs.first_usec);
        for tick in 0..case.ticks {
            run.calls.clear();
            exec.tick(&mut run, tick as u32).unwrap();
            log.tick(tick as u32, theirs.first_usec + tick as i64 * 1000, tick as u32, &run.calls)
                .unwrap_or_else(|e| panic!("{}: tick {tick}: {e}", case.name));
        }
        let ours = Log::parse(&log.into_bytes()).unwrap();
        let strip = |l: &Log| l.transitions.iter().map(|&(_, uid, s)| (uid, s)).collect::<Vec<_>>();
        assert_eq!(strip(&ours), strip(&theirs), "{}: transitions", case.name);
        compared += 1;
    }
    assert_eq!(compared, 3);
}

/// Whether a case has scripts or loops, whose runs the log replay takes from bt-core.
fn has_scripts(case: &Case) -> bool {
    case.xml.contains("Script") || case.xml.contains("<Loop")
}

/// The `_uid` attributes of a document, in order.
fn uids(xml: &str) -> Vec<u16> {
    xml.split(" _uid=\"").skip(1).map(|r| r.split('"').next().unwrap().parse().unwrap()).collect()
}

/// What `export` and `import --format xml` write numbers every node as the log of the
/// same tree does: for an image, by position (as BehaviorTree.CPP numbers the document
/// written); for an imported document, as BehaviorTree.CPP numbers the original
/// (SubTree nodes counted). Parameters go back as the document wrote them.
#[test]
fn exported_xml_numbers_the_nodes_as_the_logs_do() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/btlog");
    let all = cases(&std::fs::read_to_string(dir.join("cases.txt")).unwrap());
    let subtree = all.iter().find(|c| c.name == "subtree").unwrap();
    let xml = with_models(subtree).replace(
        "<ForceSuccess><A4/></ForceSuccess>",
        r#"<ForceSuccess><Parallel failure_count="-1"><A4/><AlwaysSuccess/></Parallel></ForceSuccess>"#,
    );
    let imported = import_text(Path::new("subtree.xml"), &xml, &ImportOptions::default()).unwrap();
    let log = LogTree::of_imported(&imported).unwrap();
    let by_core = |t: &LogTree| {
        let mut v: Vec<(usize, u16)> = t.nodes.iter().filter_map(|n| n.core.map(|c| (c, n.uid))).collect();
        v.sort_unstable();
        v.into_iter().map(|(_, u)| u).collect::<Vec<u16>>()
    };
    let exported = imported.to_xml().unwrap();
    assert_eq!(uids(&exported), by_core(&log), "{exported}");
    // The SubTree node (uid 3) is in the log, not in the flattened export.
    assert!(log.xml().contains(r#"<SubTree ID="Sub" _fullpath="inner" _uid="3""#), "{}", log.xml());
    assert!(exported.contains(r#"<Parallel _uid="5" failure_count="-1">"#), "{exported}");
    assert!(
        log.xml().contains(r#"<Parallel name="Parallel" _uid="5" success_count="-1" failure_count="-1">"#),
        "{}",
        log.xml()
    );

    // An image's nodes: export and log number them 1, 2, ... in pre-order.
    let image_log = LogTree::new(&imported.nodes, &imported).unwrap();
    let plain = btcpp::xml::to_xml(&imported.nodes, &imported).unwrap();
    let n = u16::try_from(imported.nodes.len()).unwrap();
    assert_eq!(uids(&plain), (1..=n).collect::<Vec<_>>());
    assert_eq!(by_core(&image_log), (1..=n).collect::<Vec<_>>());
    assert_eq!(uids(&image_log.xml()), (1..=n).collect::<Vec<_>>());
}

#[test]
fn extended_leaves_take_their_ports_from_the_value_table() {
    use bt_core::{BehaviorInfo, Leaf, Node, NodeKind};
    const SET: [BehaviorInfo<'static>; 1] = [BehaviorInfo::action("drive-truck", 4)];
    let nodes = [Node::new(NodeKind::Action(Leaf::extended(0, 0, 4).unwrap()), 1)];
    let values = [7, 1, 2, 3];
    let tree = LogTree::with_values(&nodes, &values, &SET[..]).unwrap();
    let attrs: Vec<&str> = tree.nodes[0].attrs.iter().map(|(_, v)| v.as_str()).collect();
    let mut sorted = attrs.clone();
    sorted.sort_unstable();
    assert_eq!(sorted, ["1", "2", "3", "7"], "{:?}", tree.nodes[0].attrs);
    // Without the table, the leaf has no values to show.
    assert!(LogTree::new(&nodes, &SET[..]).unwrap().nodes[0].attrs.is_empty());
}
