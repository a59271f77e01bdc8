//! The closure of a backchained tree cut short by the work it may do.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;
use std::sync::Arc;

use super::Made;
use super::closed::close_backchained_within;
use crate::ground::Grounding;
use crate::pddl::{parse_domain, parse_problem};
use crate::regress::{Budget, Stop};
use crate::{Options, PddlCatalog};

fn transport() -> (Arc<Grounding>, Arc<PddlCatalog>) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ipc/transport-sat08-strips");
    let d = std::fs::read_to_string(dir.join("domain.pddl")).unwrap();
    let p = std::fs::read_to_string(dir.join("p01.pddl")).unwrap();
    let problem = parse_domain("domain.pddl", &d).and_then(|d| parse_problem("p01.pddl", &p, &d)).unwrap();
    (Arc::new(Grounding::new(&problem).unwrap()), Arc::new(PddlCatalog::new(&problem)))
}

#[test]
fn a_closure_cut_short_by_its_states_keeps_the_rules_it_found() {
    let (g, c) = transport();
    let plain = crate::plan(g.clone(), c.clone(), Options { close_nodes: 0, ..Options::default() }).unwrap();
    assert_eq!(plain.method, Made::SearchGuided, "this fixture no longer makes a guided tree");
    let close = |states| {
        let budget = Budget { states, ..Budget::default() };
        close_backchained_within(plain.clone(), &g, Options::default(), &budget).unwrap()
    };
    let whole = close(Budget::default().states);
    let report = whole.closed.unwrap();
    assert!(report.complete && report.plans + report.undo > 1, "{report}");
    // Three states looked at of the eight the whole closure looks at: the rules found
    // by then are kept (they are each a way back from a disturbed state; here the third
    // state's, as return rules, already serve the states looked at after it).
    let short = close(3);
    let report = short.closed.unwrap();
    assert_eq!(report.stopped, Some(Stop::States), "{report}");
    assert!(!report.kept && report.plans > 0, "{report}");
    assert!(plain.nodes.len() < short.nodes.len() && short.nodes.len() <= whole.nodes.len());
    // And they serve: the benchmark's disturbed episodes (not the seed the planner
    // chose by) reach the goal at least as often as with the tree alone.
    let settings = crate::coverage::Settings { episodes: 40, ..crate::coverage::Settings::default() };
    let run = |p: &crate::Plan<PddlCatalog>| {
        crate::coverage::disturbed(&p.nodes, &p.values, c.as_ref(), &g, p.goal_ticks.unwrap(), &settings)
            .unwrap()
            .reached
    };
    let (alone, cut, all) = (run(&plain), run(&short), run(&whole));
    assert!(alone < cut && cut <= all, "{alone} {cut} {all}");
}

#[test]
fn the_rules_of_a_closure_cut_short_are_left_out_where_the_tree_alone_does_better() {
    let (g, c) = transport();
    let plain = crate::plan(g.clone(), c.clone(), Options { close_nodes: 0, ..Options::default() }).unwrap();
    // One state looked at: one undo rule, with which the planner's own episodes reach
    // the goal less often than with the tree alone.
    let budget = Budget { states: 1, ..Budget::default() };
    let p = close_backchained_within(plain.clone(), &g, Options::default(), &budget).unwrap();
    let report = p.closed.unwrap();
    assert!(report.undo == 1 && report.kept, "{report}");
    assert_eq!(p.nodes, plain.nodes);
}
