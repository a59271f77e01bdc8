//! Predicates and actions with more than three parameters become extended leaves:
//! their values live in the tree's value table, the image carries it, and a controller
//! that loads the image with `load_with` runs the same tree.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::sync::Arc;

use bt_core::Catalog as _;
use bt_core::{Node, NodeKind, Status, Tree};
use bt_formats::{ascii, image::Image};
use planner::ground::Grounding;
use planner::pddl::{parse_domain, parse_problem};
use planner::strips::{self, StripsWorld};
use planner::{Options, PddlCatalog, plan};

/// A truck drives between cities of a region (`drive ?t ?from ?to ?region`, four
/// parameters) and the goal names four places at once (`route`, five).
const DOMAIN: &str = "(define (domain trucks)
  (:requirements :strips :typing)
  (:types truck place region)
  (:predicates (at ?t - truck ?p - place) (in ?p - place ?r - region)
               (route ?t - truck ?a - place ?b - place ?c - place ?r - region))
  (:action drive
    :parameters (?t - truck ?from - place ?to - place ?r - region)
    :precondition (and (at ?t ?from) (in ?from ?r) (in ?to ?r))
    :effect (and (at ?t ?to) (not (at ?t ?from))))
  (:action record
    :parameters (?t - truck ?a - place ?b - place ?c - place ?r - region)
    :precondition (and (at ?t ?c) (in ?a ?r) (in ?b ?r))
    :effect (route ?t ?a ?b ?c ?r)))";

const PROBLEM: &str = "(define (problem p) (:domain trucks)
  (:objects t1 - truck a b c - place north - region)
  (:init (at t1 a) (in a north) (in b north) (in c north))
  (:goal (and (route t1 a b c north) (at t1 c))))";

#[test]
fn leaves_with_four_and_five_arguments_plan_encode_load_and_run() {
    let d = parse_domain("trucks.pddl", DOMAIN).unwrap();
    let p = parse_problem("p.pddl", PROBLEM, &d).unwrap();
    let g = Arc::new(Grounding::new(&p).unwrap());
    let c = Arc::new(PddlCatalog::new(&p));
    let plan = plan(g.clone(), c.clone(), Options::default()).unwrap();

    let extended = plan
        .nodes
        .iter()
        .filter(|n| matches!(n.kind(), NodeKind::Condition(l) | NodeKind::Action(l) if l.argc() > 3))
        .count();
    assert!(extended > 0, "no extended leaf in the tree");
    assert!(!plan.values.is_empty());

    let ascii = ascii::to_ascii_with(&plan.nodes, &plan.values, c.as_ref()).unwrap();
    assert!(ascii.contains("route(t1, a, b, c, north)"), "{ascii}");
    assert!(ascii.contains("drive(t1, "), "{ascii}");

    let image = Image::new(&plan.nodes).values(&plan.values).encode(c.fingerprint()).unwrap();
    let mut storage = vec![Node::EMPTY; plan.nodes.len()];
    let mut values = vec![0u16; plan.values.len()];
    let tree: Tree<'_, 64> = bt_core::load_with(&image, c.as_ref(), &mut storage, &mut values).unwrap();
    assert_eq!(tree.nodes(), &plan.nodes[..]);
    assert_eq!(tree.values(), &plan.values[..]);

    let mut world = StripsWorld::new(g);
    let out = strips::run((&plan.nodes, &plan.values), c.as_ref(), &mut world, 100, (), &mut Vec::new()).unwrap();
    assert_eq!(out.status, Status::Success);
    assert!(world.goal_reached());
    assert_eq!(world.executed(), &plan.executed[..]);
}
