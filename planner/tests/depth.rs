//! The planner emits trees up to exactly `planner::DEPTH` levels, the depth every host
//! tool loads, and refuses deeper ones.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::sync::Arc;

use bt_core::Tree;
use planner::{DEPTH, Options, PddlCatalog, PlanError, pddl, plan};

/// A chain: `p0` needs `a0`, which needs `p1`, ... `a{n}` needs nothing. With
/// `negative_end`, the last action needs `(not q)` (an Inverter over a Condition: one
/// level more).
fn chain(n: usize, negative_end: bool) -> Result<planner::Plan<PddlCatalog>, PlanError> {
    let preds: String = (0..=n).map(|i| format!("(p{i}) ")).collect();
    let mut d =
        format!("(define (domain chain) (:requirements :strips :negative-preconditions) (:predicates {preds}(q))\n");
    for i in 0..n {
        d += &format!("(:action a{i} :parameters () :precondition (p{}) :effect (p{i}))\n", i + 1);
    }
    let pre = if negative_end { "(not (q))" } else { "()" };
    d += &format!("(:action a{n} :parameters () :precondition {pre} :effect (p{n})))\n");
    let domain = pddl::parse_domain("chain.pddl", &d).unwrap();
    let problem =
        pddl::parse_problem("p.pddl", "(define (problem c) (:domain chain) (:init) (:goal (p0)))", &domain).unwrap();
    let g = Arc::new(planner::ground::Grounding::new(&problem).unwrap());
    let catalog = Arc::new(PddlCatalog::new(&problem));
    plan(g, catalog, Options::default())
}

fn levels(p: &planner::Plan<PddlCatalog>) -> usize {
    Tree::<'_, DEPTH>::validate(&p.nodes, p.catalog.as_ref()).unwrap().depth()
}

#[test]
fn trees_of_exactly_depth_levels_are_planned_and_deeper_ones_refused() {
    // Each link adds two levels (Fallback, Sequence) under the root's.
    let base = levels(&chain(1, false).unwrap());
    let step = levels(&chain(2, false).unwrap()) - base;
    assert_eq!(step, 2);
    // The deepest chain within DEPTH, with the one extra level of a negative condition
    // where it lands exactly on DEPTH.
    let n = 1 + (DEPTH - base) / step;
    let deepest = chain(n, false).unwrap();
    assert!(levels(&deepest) <= DEPTH);
    let negative = (DEPTH - levels(&deepest)) == 1;
    let exact = chain(n, negative);
    let exact = exact.unwrap_or_else(|e| panic!("{} levels refused: {e}", levels(&deepest) + usize::from(negative)));
    assert_eq!(levels(&exact), DEPTH, "a tree of exactly DEPTH levels");
    // One link more: Algorithm 1's tree would be too deep. The planner either refuses it
    // or makes a shallower tree another way; it never hands out a deeper tree.
    match chain(n + 1, false) {
        Err(PlanError::TooDeep { limit, .. }) => assert_eq!(limit, DEPTH),
        Ok(p) => assert!(levels(&p) <= DEPTH),
        Err(e) => panic!("one link more: {e}"),
    }
}
