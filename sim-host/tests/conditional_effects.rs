//! Conditional effects in learning: GP's STRIPS episodes fire an action's `when`
//! effects as the planner's world does, and a problem whose planner tree checks a
//! condition that only a `when` mentions learns. The lamp (`tests/fixtures/lamp`):
//! `flip` lights it only when it is powered, `plug` powers it; the goal is `lit`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;
use std::sync::Arc;

use sim_host::learn::StripsProblem;
use sim_host::learn::strips::StripsRunner;

mod cli_common;
use cli_common::{ok, sim_host};

const FIXTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures");

fn problem(name: &str) -> StripsProblem {
    let dir = Path::new(FIXTURES).join(name);
    let text = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
    StripsProblem::new("domain.pddl", text("domain.pddl"), "problem.pddl", text("problem.pddl"), false, gp::Bound::NONE)
        .unwrap()
}

fn pddl(name: &str, file: &str) -> String {
    Path::new(FIXTURES).join(name).join(file).to_str().unwrap().to_string()
}

#[test]
fn conditional_effects_fire_in_learning_episodes() {
    // `powered` is a precondition of `unplug` too, so the problem is read as before; the
    // planner's tree plugs the lamp in, then flips it.
    let p = Arc::new(problem("lamp-unplug"));
    let tree = bt_formats::tokens::to_string(p.planner_tree(), p.catalog()).unwrap();
    assert_eq!(tree, "f( lit? s( f( powered? plug! ) flip! ) )");
    let mut runner = StripsRunner::new(p.clone(), p.default_tick_limit());
    let e = runner.episode(p.planner_tree(), None).unwrap();
    assert!(e.goal_reached(), "flip lights the powered lamp: {e:?}");
    // Flipped before it is powered, the lamp stays dark.
    let flip = bt_formats::tokens::parse("flip!", p.catalog()).unwrap();
    let dark = runner.episode(&flip, None).unwrap();
    assert!(!dark.goal_reached(), "{dark:?}");
}

#[test]
fn a_condition_only_a_conditional_effect_mentions_is_learned_on() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let (domain, problem) = (pddl("lamp", "domain.pddl"), pddl("lamp", "problem.pddl"));
    let args =
        ["learn", "--domain", &domain, "--problem", &problem, "--seeds", "1", "--generations", "5", "--out", out];
    ok(&sim_host(&args));
    let run = dir.path().join("light-baseline-strips-seed1");
    let text = std::fs::read_to_string(run.join("run.txt")).unwrap();
    assert!(text.contains("baseline = f( lit? s( f( powered? plug! ) flip! ) )"), "{text}");
    // The learned tree and the planner's both reach the goal in the learning world.
    let best = run.join("best.bt");
    let learned = ok(&sim_host(&["run", "--domain", &domain, "--problem", &problem, "--tree", best.to_str().unwrap()]));
    assert!(learned.contains("goal     reached in 1 of 1 episode"), "{learned}");
    let planned = ok(&sim_host(&["run", "--domain", &domain, "--problem", &problem]));
    assert!(planned.contains("goal     reached in 1 of 1 episode"), "{planned}");
}
