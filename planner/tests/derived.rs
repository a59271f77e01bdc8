//! Derived predicates (`:derived`): read, grounded, closed in every state, planned end
//! to end into trees that reach the goal; and the errors for rules the model cannot
//! take.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::sync::Arc;

use planner::ground::Grounding;
use planner::model::ModelError;
use planner::pddl::{ErrorKind, parse_domain, parse_problem};
use planner::strips::{self, StripsWorld, Verdict};
use planner::{Options, PddlCatalog, plan};

/// A small power network: a node is `fed` when it is the source or a closed line
/// joins it to a fed node (a recursive rule); `dark` negates `fed`, a lower stratum.
const GRID: &str = "(define (domain grid)
  (:requirements :strips :typing :negative-preconditions :existential-preconditions
                 :disjunctive-preconditions :derived-predicates)
  (:types node)
  (:predicates (source ?n - node) (line ?a ?b - node) (closed ?a ?b - node)
               (fed ?n - node) (dark ?n - node))
  (:derived (fed ?n - node)
    (or (source ?n) (exists (?m - node) (and (fed ?m) (closed ?m ?n)))))
  (:derived (dark ?n - node) (not (fed ?n)))
  (:action close :parameters (?a ?b - node)
    :precondition (and (line ?a ?b) (not (closed ?a ?b)))
    :effect (closed ?a ?b))
  (:action open :parameters (?a ?b - node)
    :precondition (closed ?a ?b)
    :effect (not (closed ?a ?b))))";

/// n1 must be fed and n2 dark: the line n1-n2, closed at first, must be opened
/// before n0-n1 is closed, or afterwards.
const GRID_PROBLEM: &str = "(define (problem p) (:domain grid)
  (:objects n0 n1 n2 n3 - node)
  (:init (source n0) (line n0 n1) (line n1 n2) (line n1 n3) (line n2 n3) (closed n1 n2))
  (:goal (and (fed n3) (dark n2))))";

fn grounding(domain: &str, problem: &str) -> Grounding {
    let d = parse_domain("d.pddl", domain).unwrap();
    Grounding::new(&parse_problem("p.pddl", problem, &d).unwrap()).unwrap()
}

#[test]
fn rules_are_read_with_their_strata() {
    let d = parse_domain("d.pddl", GRID).unwrap();
    assert_eq!(d.axioms.len(), 2);
    let (fed, dark) = (d.predicate("fed").unwrap(), d.predicate("dark").unwrap());
    let strata = d.strata().unwrap();
    assert!(strata[usize::from(dark)] > strata[usize::from(fed)], "{strata:?}");
    assert_eq!(strata[usize::from(d.predicate("closed").unwrap())], 0);
    assert!(!d.static_predicates()[usize::from(fed)], "derived atoms change with the state");
}

#[test]
fn every_state_is_closed_under_the_rules() {
    let g = grounding(GRID, GRID_PROBLEM);
    let atom = |p: &str, o: &[&str]| g.atom_by_name(p, o).unwrap();
    let init = g.init();
    assert!(init.holds(atom("fed", &["n0"])));
    assert!(!init.holds(atom("fed", &["n1"])));
    assert!(init.holds(atom("dark", &["n2"])), "nothing feeds n1, so nothing feeds n2");
    // Closing n0-n1 feeds n1 and, through the closed n1-n2, n2: derived atoms follow.
    let close = g.actions().iter().position(|a| g.action_name(a_id(&g, a)) == "close(n0, n1)").unwrap();
    let mut s = init.clone();
    g.apply(&g.actions()[close], &mut s);
    assert!(s.holds(atom("fed", &["n1"])) && s.holds(atom("fed", &["n2"])));
    assert!(!s.holds(atom("dark", &["n2"])));
    // An external change of a basic atom: the world closes the state again.
    let mut w = StripsWorld::new(Arc::new(g.clone()));
    w.set_state(s);
    assert!(w.holds(atom("fed", &["n2"])));
    assert!(w.set_named("closed", &["n1", "n2"], false));
    assert!(!w.holds(atom("fed", &["n2"])) && w.holds(atom("dark", &["n2"])));
    // Setting a derived atom directly changes nothing: it follows the basic ones.
    w.set(atom("fed", &["n3"]), true);
    assert!(!w.holds(atom("fed", &["n3"])));
}

fn a_id(g: &Grounding, a: &planner::ground::GroundAction) -> u32 {
    g.actions().iter().position(|x| std::ptr::eq(x, a)).unwrap() as u32
}

#[test]
fn a_recursive_rule_and_a_negation_over_it_are_planned_into_a_tree_that_reaches_the_goal() {
    let g = Arc::new(grounding(GRID, GRID_PROBLEM));
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let p = plan(g.clone(), c.clone(), Options::default()).unwrap();
    assert!(p.goal_ticks.is_some());
    let names: Vec<String> = p.executed.iter().map(|&a| g.action_name(a)).collect();
    assert!(names.contains(&"open(n1, n2)".to_string()), "{names:?}");
    // The tree, run again in the symbolic world, reaches the goal by itself.
    let mut world = StripsWorld::new(g.clone());
    let out = run_to_goal(&p, &c, &mut world);
    assert_eq!(out, Verdict::Reached { ticks: p.goal_ticks.unwrap() });
    assert!(world.goal_reached());
    // The same problem plans to the same tree, with the search on threads or not.
    for parallel in [true, false] {
        let again = plan(g.clone(), c.clone(), Options { parallel, ..Options::default() }).unwrap();
        assert_eq!(again.nodes, p.nodes);
        assert_eq!(again.executed, p.executed);
    }
}

#[test]
fn the_tree_recovers_when_a_disturbance_changes_what_is_derived() {
    let g = Arc::new(grounding(GRID, GRID_PROBLEM));
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let p = plan(g.clone(), c.clone(), Options::default()).unwrap();
    // Start from the goal state with n1-n2 closed again: n2 is fed, so not dark.
    let mut world = StripsWorld::new(g.clone());
    let mut s = g.init().clone();
    for &a in &p.executed {
        g.apply(g.action(a).unwrap(), &mut s);
    }
    world.set_state(s);
    assert!(world.goal_reached());
    assert!(world.set_named("closed", &["n1", "n2"], true));
    assert!(!world.goal_reached());
    assert!(matches!(run_to_goal(&p, &c, &mut world), Verdict::Reached { .. }));
    assert!(world.goal_reached());
}

fn run_to_goal(p: &planner::Plan<PddlCatalog>, c: &PddlCatalog, world: &mut StripsWorld) -> Verdict {
    let ends = strips::Ends::DETERMINISTIC;
    strips::run_to_goal((&p.nodes, &p.values), c, world, 1000, ends, (), &mut Vec::new()).unwrap()
}

#[test]
fn a_derived_goal_that_no_rule_reaches_is_unsolvable() {
    let d = parse_domain("d.pddl", GRID).unwrap();
    let p = parse_problem(
        "p.pddl",
        "(define (problem p) (:domain grid) (:objects n0 n1 - node) (:init (line n0 n1)) (:goal (fed n1)))",
        &d,
    )
    .unwrap();
    assert!(matches!(Grounding::new(&p), Err(planner::PlanError::Unsolvable(_))));
}

#[test]
fn an_action_that_changes_a_derived_predicate_is_refused_where_it_is_written() {
    let text = GRID.replace(":effect (closed ?a ?b))", ":effect (and (closed ?a ?b) (fed ?b)))");
    let e = parse_domain("d.pddl", &text).unwrap_err();
    assert!(
        matches!(&*e.kind, ErrorKind::Model(ModelError::DerivedChanged { action, predicate })
            if action == "close" && predicate == "fed"),
        "{e}"
    );
    // The action's name.
    assert!(e.to_string().starts_with("d.pddl:10:12:"), "{e}");
}

#[test]
fn a_negation_cycle_through_derived_predicates_is_refused_where_it_is_written() {
    let text = GRID.replace(
        "(:derived (dark ?n - node) (not (fed ?n)))",
        "(:derived (dark ?n - node) (not (fed ?n)))
  (:derived (fed ?n - node) (and (line ?n ?n) (not (dark ?n))))",
    );
    let e = parse_domain("d.pddl", &text).unwrap_err();
    assert!(matches!(&*e.kind, ErrorKind::Model(ModelError::NotStratifiable { .. })), "{e}");
    assert!(e.to_string().contains("stratifiable"), "{e}");
    // The rule that closes the cycle: `fed` through `not dark`.
    assert!(e.to_string().starts_with("d.pddl:10:13:"), "{e}");
    // A positive cycle is fine: `fed` through `fed`.
    parse_domain("d.pddl", GRID).unwrap();
}

#[test]
fn a_rule_for_an_undeclared_predicate_or_with_the_wrong_arity_is_refused() {
    let e =
        parse_domain("d.pddl", &GRID.replace("(:derived (dark ?n - node)", "(:derived (lit ?n - node)")).unwrap_err();
    assert!(matches!(&*e.kind, ErrorKind::Model(ModelError::UnknownPredicate { .. })), "{e}");
    let e = parse_domain("d.pddl", &GRID.replace("(:derived (dark ?n - node)", "(:derived (dark ?n ?m - node)"))
        .unwrap_err();
    assert!(matches!(&*e.kind, ErrorKind::Model(ModelError::WrongArity { .. })), "{e}");
    let e = parse_domain(
        "d.pddl",
        &GRID.replace("(:derived (dark ?n - node) (not (fed ?n)))", "(:derived (dark ?n - node))"),
    )
    .unwrap_err();
    assert!(e.to_string().contains("(:derived"), "{e}");
}

#[test]
fn a_support_holds_where_its_literal_does_and_implies_it_everywhere() {
    let g = grounding(GRID, GRID_PROBLEM);
    let lines: Vec<u32> = ["n0 n1", "n1 n2", "n1 n3", "n2 n3"]
        .iter()
        .map(|l| g.atom_by_name("closed", &l.split(' ').collect::<Vec<_>>()).unwrap())
        .collect();
    // Every assignment of the lines, closed under the rules.
    let states: Vec<planner::state::State> = (0..1u32 << lines.len())
        .map(|bits| {
            let mut s = g.init().clone();
            for (i, &a) in lines.iter().enumerate() {
                s.set(a, bits & (1 << i) != 0);
            }
            g.close(&mut s);
            s
        })
        .collect();
    let derived: Vec<u32> = (0..g.atom_count() as u32).filter(|&a| g.is_derived(a)).collect();
    assert_eq!(derived.len(), 8, "fed and dark of four nodes");
    let mut checked = 0;
    for s in &states {
        for &a in &derived {
            let lit = planner::ground::Lit { atom: a, positive: s.holds(a) };
            let support = g.support(s, &[lit]);
            assert!(support.iter().all(|l| !g.is_derived(l.atom) && l.holds(s)), "{}", g.lit_name(lit));
            for t in &states {
                if support.iter().all(|l| l.holds(t)) {
                    assert!(lit.holds(t), "{} from {support:?}", g.lit_name(lit));
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 16 * 8, "{checked}");
}
