//! Conditional effects in learning: GP's STRIPS episodes fire an action's `when`
//! effects as the planner's world does. The lamp (`tests/fixtures/lamp-unplug`):
//! `flip` lights it only when it is powered, `plug` powers it; the goal is `lit`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;
use std::sync::Arc;

use sim_host::learn::StripsProblem;
use sim_host::learn::strips::StripsRunner;

const FIXTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures");

fn problem(name: &str) -> StripsProblem {
    let dir = Path::new(FIXTURES).join(name);
    let text = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
    StripsProblem::new("domain.pddl", text("domain.pddl"), "problem.pddl", text("problem.pddl"), false).unwrap()
}

#[test]
fn conditional_effects_fire_in_learning_episodes() {
    // `powered` is a precondition of `unplug` too, so the problem is read as before; the
    // planner's tree plugs the lamp in, then flips it.
    let p = Arc::new(problem("lamp-unplug"));
    let tree = planner::tokens::to_string(p.planner_tree(), p.catalog()).unwrap();
    assert_eq!(tree, "f( lit? s( f( powered? plug! ) flip! ) )");
    let mut runner = StripsRunner::new(p.clone(), p.default_tick_limit());
    let e = runner.episode(p.planner_tree(), None).unwrap();
    assert!(e.goal_reached(), "flip lights the powered lamp: {e:?}");
    // Flipped before it is powered, the lamp stays dark.
    let flip = planner::tokens::parse("flip!", p.catalog()).unwrap();
    let dark = runner.episode(&flip, None).unwrap();
    assert!(!dark.goal_reached(), "{dark:?}");
}
