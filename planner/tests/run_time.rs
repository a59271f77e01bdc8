//! Expansion at run time from a given state (`expand_at`, `parse_changes`), and the
//! trees that planning errors carry for the caller to show.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::sync::Arc;

use planner::pddl::{parse_domain, parse_problem};
use planner::{Method, Options, PddlCatalog, PlanError, domains, expand_at, parse_changes, plan};

#[test]
fn changes_read_the_notation_of_the_trees_conditions() {
    let g = domains::cube_sphere().unwrap();
    let c = parse_changes(&g, "holding(CUBE) ,not   hand-empty, NOT path-free( goal )").unwrap();
    let named: Vec<(String, bool)> = c.iter().map(|c| (g.atom_name(c.atom), c.value)).collect();
    assert_eq!(
        named,
        [("holding(cube)".into(), true), ("hand-empty".into(), false), ("path-free(goal)".into(), false)]
    );
    // Making a fact false that never holds changes nothing.
    assert!(parse_changes(&g, "not holding(goal)").unwrap().is_empty());
}

#[test]
fn a_bad_change_is_refused_with_its_column() {
    let g = domains::cube_sphere().unwrap();
    let err = |text: &str| parse_changes(&g, text).unwrap_err().to_string();
    assert_eq!(
        err("holding(cube), holdin(cube)"),
        "column 16: unknown predicate `holdin` (declared: at, holding, hand-empty, near, path-free, obstacle)"
    );
    assert_eq!(err("not at(cube)"), "column 5: `at` takes 2 arguments, not 1");
    assert_eq!(err("near(cub)"), "column 1: unknown object `cub`");
    assert_eq!(
        err("holding(cube), "),
        "column 16: an empty fact (write `predicate(object, ...)`, or `not predicate(...)`)"
    );
    assert_eq!(err("at(cube, goal"), "column 1: `at(cube, goal`: no `)` at the end");
    assert!(err("obstacle(cube)").starts_with("column 1: `obstacle(cube)` is static"), "{}", err("obstacle(cube)"));
    assert_eq!(
        err("holding(goal)"),
        "column 1: `holding(goal)` never holds in this problem: it is not in :init and no action makes it true"
    );
    assert_eq!(err("near(cube), not near(cube)"), "column 17: `near(cube)` is changed twice (also at column 1)");
}

#[test]
fn nothing_to_expand_when_the_tree_already_copes() {
    // Fig. 3(e) picks the cube up again when it is not in the hand: no expansion.
    let g = Arc::new(domains::cube_sphere().unwrap());
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let mut p = plan(g.clone(), c.clone(), Options::default()).unwrap();
    let at = expand_at(&mut p.planner, c.as_ref(), &parse_changes(&g, "near(goal)").unwrap(), 1000).unwrap();
    assert!(at.expansions.is_empty());
    assert_eq!(p.planner.nodes(), &p.nodes[..]);
}

fn blocks(problem: &str) -> (Arc<planner::ground::Grounding>, Arc<PddlCatalog>) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("domains/blocks");
    let d = parse_domain("domain.pddl", &std::fs::read_to_string(dir.join("domain.pddl")).unwrap()).unwrap();
    let p = parse_problem("problem.pddl", problem, &d).unwrap();
    (Arc::new(planner::ground::Grounding::new(&p).unwrap()), Arc::new(PddlCatalog::new(&p)))
}

/// The Sussman anomaly: C on A, the goal A on B on C.
const SUSSMAN: &str = "(define (problem sussman) (:domain blocks) (:objects a b c - block) \
    (:init (hand-empty) (on c a) (on-table a) (on-table b) (clear c) (clear b)) \
    (:goal (and (on a b) (on b c))))";

#[test]
fn an_oscillation_carries_the_tree_and_the_repeating_actions() {
    let (g, c) = blocks(SUSSMAN);
    let e = plan(g, c, Options { method: Method::Algorithm1, ..Options::default() }).unwrap_err();
    let PlanError::Oscillates { actions, .. } = &e else { panic!("{e}") };
    assert_eq!(actions, &["put-down(b)", "pick-up(b)"]);
    let (nodes, _) = e.tree().unwrap();
    assert!(nodes.len() > 100, "{}", nodes.len());
}

#[test]
fn algorithm_1_stuck_on_a_failing_tree_carries_it() {
    // The IPC blocks instance: Algorithm 1 alone ends with a tree that fails and that
    // it cannot expand further.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ipc/blocks");
    let d = parse_domain("domain.pddl", &std::fs::read_to_string(dir.join("domain.pddl")).unwrap()).unwrap();
    let ptext = std::fs::read_to_string(dir.join("probBLOCKS-4-0.pddl")).unwrap();
    let p = parse_problem("probBLOCKS-4-0.pddl", &ptext, &d).unwrap();
    let g = Arc::new(planner::ground::Grounding::new(&p).unwrap());
    let c = Arc::new(PddlCatalog::new(&p));
    let e = plan(g.clone(), c.clone(), Options { method: Method::Algorithm1, ..Options::default() }).unwrap_err();
    let PlanError::GoalNotReached { from, why, nodes, .. } = &e else { panic!("{e}") };
    assert_eq!(*from, "the initial state");
    assert!(why.starts_with("the tree fails, but every failed condition was expanded before"), "{why}");
    assert!(!nodes.is_empty());
    // With the default method, Algorithm 1 gives up and search guides it.
    let p = plan(g, c, Options::default()).unwrap();
    assert_eq!(p.method, planner::Made::SearchGuided);
    assert!(matches!(p.gave_up[0].error, PlanError::GoalNotReached { .. }));
}

#[test]
fn a_planner_goes_on_from_a_tree_read_back_as_from_its_own() {
    // Fig. 4 planned offline, read back from its bt-core nodes: the run-time expansion
    // for the cube in the hand grows it exactly as the planner that made it would.
    let g = Arc::new(domains::cube_sphere_blocked().unwrap());
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let made = plan(g.clone(), c.clone(), Options::default()).unwrap();
    let mut read = planner::Planner::from_nodes(g.clone(), &made.nodes, &[], Options::default()).unwrap();
    assert_eq!(read.nodes(), &made.nodes[..]);
    let mut own = made.planner;
    let changes = parse_changes(&g, "holding(cube), not hand-empty").unwrap();
    let ours = expand_at(&mut own, c.as_ref(), &changes, 1000).unwrap();
    let theirs = expand_at(&mut read, c.as_ref(), &changes, 1000).unwrap();
    assert_eq!(theirs.expansions, ours.expansions);
    assert_eq!(read.nodes(), own.nodes());
    assert_eq!(read.nodes().len(), 37);
}

#[test]
fn a_tree_of_other_kinds_is_refused_at_its_node() {
    let g = Arc::new(domains::cube_sphere().unwrap());
    let leaf = |name: &str| {
        let atom = g.atom_by_name(name, &["cube"]).unwrap();
        bt_core::Node::new(bt_core::NodeKind::Condition(g.condition_leaf(atom).unwrap()), 1)
    };
    let nodes = [bt_core::Node::new(bt_core::NodeKind::SequenceWithMemory, 3), leaf("holding"), leaf("near")];
    let e = planner::Planner::from_nodes(g.clone(), &nodes, &[], Options::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "the tree does not fit the behavior set: node 0: a SequenceWithMemory: the planner grows only Sequence, \
         Fallback and leaves"
    );
}
