//! Plan, encode, load as a controller would, run in the STRIPS world; and the other
//! output notations.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::sync::Arc;

use bt_core::{BehaviorId, BehaviorInfo, Catalog, Node, Status, Tree};
use bt_formats::{ascii, dot, image::Image};
use btcpp::xml::to_xml;
use planner::ground::Grounding;
use planner::strips::{self, StripsWorld};
use planner::{Options, PddlCatalog, domains, plan};
use worlds::agent::BeforeTicks;

fn plan_load_run(g: Grounding) -> (Vec<Node>, Arc<PddlCatalog>, u32) {
    let g = Arc::new(g);
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let p = plan(g.clone(), c.clone(), Options::default()).unwrap();
    let image = Image::new(&p.nodes).encode(c.fingerprint()).unwrap();
    let mut storage = vec![Node::EMPTY; 1024];
    let tree: Tree<'_, 64> = bt_core::load(&image, c.as_ref(), &mut storage).unwrap();
    assert_eq!(tree.nodes(), &p.nodes[..]);
    let mut world = StripsWorld::new(g);
    let out = strips::run((tree.nodes(), &[]), c.as_ref(), &mut world, 1000, (), &mut Vec::new()).unwrap();
    assert_eq!(out.status, Status::Success);
    assert!(world.goal_reached());
    assert_eq!(Some(out.ticks), p.goal_ticks);
    (p.nodes, c, out.ticks)
}

#[test]
fn cube_domain_end_to_end() {
    let (nodes, c, ticks) = plan_load_run(domains::cube_sphere().unwrap());
    assert_eq!((nodes.len(), ticks), (19, 5));
    // The contract: behavior ids are predicates then actions; args are object indices.
    let leaf = |name: &str| nodes.iter().find_map(|n| n.kind().leaf().filter(|(_, l)| format!("{l:?}") == name));
    assert!(leaf("#0[0, 2]").is_some(), "at(cube, goal) is predicate 0 over objects 0 and 2");
    assert!(leaf("#8[0, 2]").is_some(), "place(cube, goal) is action 2, behavior 6 + 2");
    assert_eq!(c.objects(), ["cube", "sphere", "goal"]);
}

#[test]
fn blocked_cube_domain_end_to_end() {
    plan_load_run(domains::cube_sphere_blocked().unwrap());
}

#[test]
fn cellphone_assembly_end_to_end_with_regrasps() {
    let (nodes, c, _) = plan_load_run(domains::cellphone().unwrap());
    let ascii = ascii::to_ascii(&nodes, c.as_ref()).unwrap();
    assert!(ascii.contains("hand-over(left, right, chassis)"), "{ascii}");
    assert!(ascii.contains("hand-over(left, right, battery)"), "{ascii}");
    assert!(ascii.contains("-^- Inverter\n"), "negative preconditions are inverted conditions");
}

#[test]
fn blocks_world_end_to_end() {
    for n in [2, 5, 8] {
        plan_load_run(domains::blocks_world(n).unwrap());
    }
}

#[test]
fn dot_and_xml_describe_the_same_tree() {
    let g = Arc::new(domains::cellphone().unwrap());
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let p = plan(g, c.clone(), Options::default()).unwrap();
    let dot = dot::to_dot(&p.nodes, c.as_ref());
    assert_eq!(dot.matches(" -> ").count(), p.nodes.len() - 1);
    assert!(dot.contains("label=\"hand-over(left, right, chassis)\", shape=box"));
    let numbered = to_xml(&p.nodes, c.as_ref()).unwrap();
    // Every node numbered from 1 in pre-order, as BehaviorTree.CPP numbers it (`_uid`).
    let uids: Vec<usize> =
        numbered.split(" _uid=\"").skip(1).map(|r| r.split('"').next().unwrap().parse().unwrap()).collect();
    assert_eq!(uids, (1..=p.nodes.len()).collect::<Vec<_>>());
    let xml = without_uids(&numbered);
    assert!(xml.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<root BTCPP_format=\"4\""));
    assert!(xml.contains("<hand-over from=\"left\" to=\"right\" p=\"chassis\"/>"), "{xml}");
    assert!(xml.contains("<Inverter>"));
    assert!(xml.contains("<TreeNodesModel>\n    <Condition ID=\"on-table\">\n      <input_port name=\"p\""), "{xml}");
    // Balanced tags, in order.
    let mut open: Vec<&str> = Vec::new();
    for tag in xml.split('<').skip(1).map(|t| t.split('>').next().unwrap()) {
        let name = tag.trim_start_matches('/').split([' ', '/']).next().unwrap();
        if tag.starts_with('?') || tag.ends_with('/') {
            continue;
        } else if tag.starts_with('/') {
            assert_eq!(open.pop(), Some(name));
        } else {
            open.push(name);
        }
    }
    assert!(open.is_empty());
    let leaves: Vec<u16> = p.nodes.iter().filter_map(|n| n.kind().leaf()).map(|(_, l)| l.behavior()).collect();
    let mut kinds = leaves.clone();
    kinds.sort_unstable();
    kinds.dedup();
    // Every leaf type once in TreeNodesModel; every leaf in the tree in compact form.
    assert_eq!(xml.matches("<Condition ID=").count() + xml.matches("<Action ID=").count(), kinds.len());
    let tree = &xml[..xml.find("<TreeNodesModel>").unwrap()];
    assert!(!tree.contains("<Action") && !tree.contains("<Condition"), "{tree}");
    let plain = without_uids(&to_xml(&p.nodes, &Unnamed(c.as_ref())).unwrap());
    assert!(plain.contains("<hand-over arg0=\"left\" arg1=\"right\" arg2=\"chassis\"/>"));
}

#[test]
fn refinement_all_keeps_every_grounding_and_still_reaches_the_goal() {
    let g = Arc::new(domains::cube_sphere_blocked().unwrap());
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let all = Options { refinement: planner::Refinement::All, ..Options::default() };
    let p = plan(g.clone(), c.clone(), all).unwrap();
    assert!(p.goal_ticks.is_some());
    // Planned from the initial state, the hand is empty when the path is cleared; an
    // agent that puts the cube into the hand at the sphere makes `hand-empty` fail,
    // and the run-time expansion keeps every grounding that achieves it.
    let mut planner = p.planner;
    let mut world = StripsWorld::new(g);
    let mut given = false;
    let script = BeforeTicks(|_, w: &mut StripsWorld| {
        if !given && w.holds_named("near", &["sphere"]) {
            w.set_named("holding", &["cube"], true);
            w.set_named("hand-empty", &[], false);
            given = true;
        }
    });
    let out = planner::run_blended(&mut planner, c.as_ref(), &mut world, 200, script).unwrap();
    assert_eq!(out.status, Status::Success);
    let hand = out.expansions.iter().find(|e| e.1.condition == "hand-empty").unwrap();
    assert_eq!(hand.1.actions, ["place(cube, goal)", "place(sphere, goal)", "drop(cube)", "drop(sphere)"]);
}

/// A PDDL catalog whose parameters have no names: the XML names its ports `arg0`, ...
struct Unnamed<'a>(&'a PddlCatalog);

impl Catalog for Unnamed<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        self.0.info(id)
    }

    fn write_arg(&self, f: &mut std::fmt::Formatter<'_>, b: BehaviorId, position: usize, v: u16) -> std::fmt::Result {
        self.0.write_arg(f, b, position, v)
    }
}

/// The document without its ` _uid="N"` attributes.
fn without_uids(xml: &str) -> String {
    let mut out = String::new();
    let mut rest = xml;
    while let Some(at) = rest.find(" _uid=\"") {
        out.push_str(&rest[..at]);
        let after = &rest[at + 7..];
        rest = &after[after.find('"').map_or(after.len(), |q| q + 1)..];
    }
    out.push_str(rest);
    out
}
