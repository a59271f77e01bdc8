//! The planner's budgets and portfolio: Algorithm 1 gives up past its node budget and
//! the search-guided methods take over, the tree is the same with search on a second
//! thread or not, trees are cut to fit the size asked for, and the searches (eager,
//! deferred, with landmarks) find plans that reach the goal.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use planner::ground::Grounding;
use planner::pddl::{parse_domain, parse_problem};
use planner::search::{self, SearchOptions, landmarks::Landmarks};
use planner::{Fit, Made, Options, PddlCatalog, PlanError, domains, plan};

fn fixture(domain: &str, problem: &str) -> (Arc<Grounding>, Arc<PddlCatalog>) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ipc").join(domain);
    let d = parse_domain("domain.pddl", &std::fs::read_to_string(dir.join("domain.pddl")).unwrap()).unwrap();
    let p = parse_problem(problem, &std::fs::read_to_string(dir.join(problem)).unwrap(), &d).unwrap();
    (Arc::new(Grounding::new(&p).unwrap()), Arc::new(PddlCatalog::new(&p)))
}

fn blocks(n: usize) -> (Arc<Grounding>, Arc<PddlCatalog>) {
    let g = domains::blocks_world(n).unwrap();
    let c = PddlCatalog::new(g.problem());
    (Arc::new(g), Arc::new(c))
}

#[test]
fn algorithm_1_within_its_budget_keeps_its_tree_and_past_it_gives_way() {
    let (g, c) = blocks(10);
    let alone = plan(g.clone(), c.clone(), Options::default()).unwrap();
    assert_eq!(alone.method, Made::Algorithm1);
    assert!(alone.nodes.len() > 100, "{}", alone.nodes.len());
    // A budget the tree fits: the same tree.
    let roomy = Options { algorithm1_nodes: alone.nodes.len(), ..Options::default() };
    assert_eq!(plan(g.clone(), c.clone(), roomy).unwrap().nodes, alone.nodes);
    // A smaller one: Algorithm 1 gives up with the tree's size, and search takes over.
    let tight = Options { algorithm1_nodes: 40, ..Options::default() };
    let p = plan(g.clone(), c.clone(), tight).unwrap();
    assert_ne!(p.method, Made::Algorithm1);
    assert!(matches!(p.gave_up[0].error, PlanError::OverBudget { budget: 40, nodes } if nodes > 40), "{:?}", p.gave_up);
    // `--method algorithm-1` has no such budget.
    let only = Options { algorithm1_nodes: 40, method: planner::Method::Algorithm1, ..Options::default() };
    assert_eq!(plan(g, c, only).unwrap().nodes, alone.nodes);
}

#[test]
fn search_beside_algorithm_1_changes_the_time_not_the_tree() {
    // Algorithm 1 oscillates here and search's plan makes the tree.
    for (domain, problem) in [("blocks", "probBLOCKS-4-0.pddl"), ("transport-sat08-strips", "p01.pddl")] {
        let (g, c) = fixture(domain, problem);
        let one = plan(g.clone(), c.clone(), Options { parallel: false, ..Options::default() }).unwrap();
        let two = plan(g.clone(), c.clone(), Options { parallel: true, ..Options::default() }).unwrap();
        assert_eq!(one.nodes, two.nodes, "{domain}");
        assert_eq!(one.executed, two.executed, "{domain}");
    }
}

#[test]
fn the_closure_is_cut_to_fit_the_bytes_asked_for() {
    let (g, c) = fixture("blocks", "probBLOCKS-4-0.pddl");
    let whole = plan(g.clone(), c.clone(), Options { fit: Fit::NONE, ..Options::default() }).unwrap();
    assert_eq!(whole.fit.cut, None);
    let plain = plan(g.clone(), c.clone(), Options { close_nodes: 0, ..Options::default() }).unwrap();
    assert!(plain.fit.size.bytes + 100 < whole.fit.size.bytes, "{} {}", plain.fit, whole.fit);
    let limit = (whole.fit.size.bytes + plain.fit.size.bytes) / 2;
    let strict = Fit { bytes: limit, nodes: usize::MAX, strict: true };
    let cut = plan(g.clone(), c.clone(), Options { fit: strict, ..Options::default() }).unwrap();
    assert!(cut.fit.fits && cut.fit.size.bytes <= limit, "{}", cut.fit);
    assert!(cut.fit.cut.is_some(), "{}", cut.fit);
    // The image the controller holds is what was measured.
    let image = bt_formats::image::Image::new(&cut.nodes).values(&cut.values);
    assert_eq!(image.encode(bt_core::Catalog::fingerprint(c.as_ref())).unwrap().len(), cut.fit.size.bytes);
    // The plain tree does not fit 100 bytes: an error when strict, the tree when not.
    let tiny = Fit { bytes: 100, nodes: usize::MAX, strict: true };
    let e = plan(g.clone(), c.clone(), Options { fit: tiny, ..Options::default() }).unwrap_err();
    assert!(matches!(&e, PlanError::TooBig { what } if what.contains("100 bytes")), "{e}");
    let lenient = plan(g, c, Options { fit: Fit { strict: false, ..tiny }, ..Options::default() }).unwrap();
    assert!(!lenient.fit.fits);
}

#[test]
fn every_search_finds_a_plan_that_reaches_the_goal() {
    for (domain, problem) in [("blocks", "probBLOCKS-4-0.pddl"), ("transport-sat08-strips", "p01.pddl")] {
        let (g, _) = fixture(domain, problem);
        for (lazy, landmarks) in [(false, false), (true, false), (true, true)] {
            let o = SearchOptions { lazy, landmarks, ..SearchOptions::default() };
            let found = search::gbfs(&g, &o).unwrap();
            let end = search::execute(&g, &found.plan).unwrap();
            assert!(g.goal_holds(&end), "{domain} lazy {lazy} landmarks {landmarks}");
        }
    }
}

#[test]
fn a_search_told_to_stop_stops() {
    let (g, _) = blocks(12);
    let o = SearchOptions { stop: Some(Arc::new(AtomicBool::new(true))), ..SearchOptions::default() };
    assert!(matches!(search::gbfs(&g, &o), Err(PlanError::Timeout { .. })));
}

#[test]
fn the_goal_and_what_every_plan_passes_through_are_landmarks() {
    // Blocks: to put a on b, a is held at some point; so is every block the goal
    // stacks on another, from an initial state where they are all on the table.
    let (g, _) = blocks(4);
    let lm = Landmarks::new(&g, None).unwrap();
    assert!(lm.len() > g.goal().len(), "{}", lm.len());
    let mut accepted = Vec::new();
    lm.initial(g.init(), &mut accepted);
    let mut helpful = Vec::new();
    let h0 = lm.count(&g, &accepted, g.init(), &mut helpful);
    assert!(h0 as usize >= g.goal().len() && !helpful.is_empty(), "{h0}");
    // Along a plan the count ends at 0.
    let found = search::gbfs(&g, &SearchOptions::default()).unwrap();
    let mut s = g.init().clone();
    for &a in &found.plan {
        g.action(a).unwrap().apply(&mut s);
        let parent = accepted.clone();
        lm.accept(&parent, &s, &mut accepted);
    }
    assert_eq!(lm.count(&g, &accepted, &s, &mut helpful), 0);
}
