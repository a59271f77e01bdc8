//! Regression trees closed over disturbances (`planner::regress::close`): on IPC
//! fixtures where the plain regression tree fails after an external agent does one of
//! its actions, the closed tree handles every such state and still reaches the goal.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;
use std::sync::Arc;

use planner::coverage::{self, Settings};
use planner::ground::Grounding;
use planner::guide::Trace;
use planner::pddl::{parse_domain, parse_problem};
use planner::regress::{self, Budget, Policy};
use planner::search::{self, SearchOptions};
use planner::state::State;
use planner::{Options, PddlCatalog};

fn grounding(domain: &str, problem: &str) -> (Arc<Grounding>, Arc<PddlCatalog>) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ipc");
    let dtext = std::fs::read_to_string(dir.join(domain)).unwrap();
    let ptext = std::fs::read_to_string(dir.join(problem)).unwrap();
    let p = parse_domain(domain, &dtext).and_then(|d| parse_problem(problem, &ptext, &d)).unwrap();
    (Arc::new(Grounding::new(&p).unwrap()), Arc::new(PddlCatalog::new(&p)))
}

/// The states one of the tree's actions leads to from a state the tree passes through
/// from the initial state, and whether the tree has a rule (or the goal) there.
fn one_disturbance_away(g: &Grounding, policy: &Policy) -> Vec<(State, bool)> {
    let mut out = Vec::new();
    for s in policy.path(g, g.init()) {
        for a in policy.actions() {
            let x = g.action(a).unwrap();
            if x.applicable(&s) {
                let mut t = s.clone();
                x.apply(&mut t);
                let covered = g.goal_holds(&t) || policy.first(&t).is_some();
                out.push((t, covered));
            }
        }
    }
    out
}

fn plain_policy(g: &Grounding) -> Policy {
    let found = search::gbfs(g, &SearchOptions::default()).unwrap();
    Policy::of_trace(g, &Trace::new(g, &found.plan).unwrap())
}

#[test]
fn the_closed_tree_has_a_rule_wherever_one_disturbance_leads() {
    let (g, _) = grounding("assembly/domain.pddl", "assembly/prob01.pddl");
    let mut policy = plain_policy(&g);
    let before = one_disturbance_away(&g, &policy);
    assert!(before.iter().any(|(_, covered)| !covered), "the plain tree already covers every state");
    let closed = regress::close(&g, &mut policy, &Budget::default()).unwrap();
    assert!(closed.plans > 0, "{closed}");
    for (t, covered) in one_disturbance_away(&g, &policy) {
        if !covered {
            // Only where no plan exists.
            assert!(search::gbfs_from(&g, &t, &SearchOptions::default()).is_err(), "{closed}");
        }
    }
    // From every such state, the tree's path ends at the goal, never in a loop.
    for (t, covered) in one_disturbance_away(&g, &policy) {
        if covered {
            let path = policy.path(&g, &t);
            assert!(g.goal_holds(path.last().unwrap()), "a path stopped short of the goal");
        }
    }
}

#[test]
fn rules_are_ordered_by_distance_and_none_is_preempted_by_an_earlier_one() {
    let (g, _) = grounding("assembly/domain.pddl", "assembly/prob01.pddl");
    let mut policy = plain_policy(&g);
    regress::close(&g, &mut policy, &Budget::default()).unwrap();
    let rules = policy.rules();
    assert!(rules.windows(2).all(|w| w[0].distance <= w[1].distance));
    for (i, r) in rules.iter().enumerate() {
        for earlier in &rules[..i] {
            assert!(!earlier.when.iter().all(|l| r.when.contains(l)), "a rule can never be the first to hold");
        }
    }
}

#[test]
fn disturbed_episodes_of_the_planned_tree_reach_the_goal() {
    // The planner closes its regression trees; the bench's disturbed episodes (undo
    // the last action, or do one of the tree's actions) then all reach the goal here,
    // where the plain regression tree of the same plan failed most of them.
    let (g, c) = grounding("assembly/domain.pddl", "assembly/prob01.pddl");
    let plan = planner::plan(g.clone(), c.clone(), Options::default()).unwrap();
    assert_eq!(plan.method, planner::Made::Regression, "this fixture no longer needs the regression tree");
    let settings = Settings { episodes: 40, ..Settings::default() };
    let ticks = plan.goal_ticks.unwrap();
    let (reached, ran) = coverage::disturbed(&plan.nodes, &plan.values, c.as_ref(), &g, ticks, &settings).unwrap();
    assert_eq!((reached, ran), (40, 40));

    let plain = plain_policy(&g).tree(&g).flatten(&g).unwrap();
    let (plain_reached, _) =
        coverage::disturbed(&plain.nodes, &plain.values, c.as_ref(), &g, ticks, &settings).unwrap();
    assert!(plain_reached < 40, "the plain tree reaches the goal in every episode too: the test shows nothing");
}
