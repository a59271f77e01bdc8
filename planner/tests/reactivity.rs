//! The four reactivity properties of Problem 1 (Colledanchise et al. 2019, Section IV) in a scripted
//! symbolic world.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::sync::Arc;

use bt_core::Status;
use planner::ground::Grounding;
use planner::model::{DomainBuilder, ProblemBuilder};
use planner::strips::StripsWorld;
use planner::{Options, PddlCatalog, Planner, domains, plan, run_blended};
use worlds::agent::BeforeTicks;

fn action(g: &Grounding, name: &str) -> u32 {
    (0..g.actions().len() as u32).find(|&a| g.action_name(a) == name).unwrap()
}

fn cube() -> (Arc<Grounding>, Arc<PddlCatalog>, Planner) {
    let g = Arc::new(domains::cube_sphere().unwrap());
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let p = plan(g.clone(), c.clone(), Options::default()).unwrap();
    (g, c, p.planner)
}

#[test]
fn an_undone_action_is_redone_without_expanding() {
    let (g, c, mut planner) = cube();
    let pick = action(&g, "pick(cube)");
    let mut world = StripsWorld::new(g);
    let mut undone = false;
    let script = BeforeTicks(|_, w: &mut StripsWorld| {
        // An external agent takes the cube out of the hand once it has been picked.
        if !undone && w.completions(pick) == 1 {
            w.set_named("holding", &["cube"], false);
            w.set_named("hand-empty", &[], true);
            undone = true;
        }
    });
    let out = run_blended(&mut planner, c.as_ref(), &mut world, 100, script).unwrap();
    assert!(undone);
    assert_eq!(out.status, Status::Success);
    assert!(out.expansions.is_empty());
    assert_eq!(world.completions(pick), 2);
}

#[test]
fn a_helped_action_is_skipped_without_expanding() {
    let (g, c, mut planner) = cube();
    let pick = action(&g, "pick(cube)");
    let reach = action(&g, "move-to(cube)");
    let mut world = StripsWorld::new(g);
    let script = BeforeTicks(|t, w: &mut StripsWorld| {
        // An external agent hands the cube to the robot before it moves.
        if t == 1 {
            w.set_named("holding", &["cube"], true);
            w.set_named("hand-empty", &[], false);
        }
    });
    let out = run_blended(&mut planner, c.as_ref(), &mut world, 100, script).unwrap();
    assert_eq!(out.status, Status::Success);
    assert!(out.expansions.is_empty());
    assert_eq!((world.starts(reach), world.starts(pick)), (0, 0));
    assert!(world.holds_named("at", &["cube", "goal"]));
}

/// A door that opens by pushing or with the key: two actions achieve `open`.
fn door() -> Arc<Grounding> {
    let mut d = DomainBuilder::new("door");
    d.types(&["door", "room"], "object").unwrap();
    d.predicate("open", &[("d", "door")]).unwrap();
    d.predicate("at-door", &[]).unwrap();
    d.predicate("has-key", &[]).unwrap();
    d.predicate("unlatched", &[("d", "door")]).unwrap();
    d.predicate("inside", &[("r", "room")]).unwrap();
    d.predicate("leads-to", &[("d", "door"), ("r", "room")]).unwrap();
    d.action("push", &[("d", "door")])
        .unwrap()
        .pre("at-door", &[])
        .unwrap()
        .pre("unlatched", &["d"])
        .unwrap()
        .effect("open", &["d"])
        .unwrap();
    d.action("unlock", &[("d", "door")])
        .unwrap()
        .pre("at-door", &[])
        .unwrap()
        .pre("has-key", &[])
        .unwrap()
        .effect("open", &["d"])
        .unwrap()
        .effect("unlatched", &["d"])
        .unwrap();
    d.action("enter", &[("d", "door"), ("r", "room")])
        .unwrap()
        .pre("leads-to", &["d", "r"])
        .unwrap()
        .pre("open", &["d"])
        .unwrap()
        .effect("inside", &["r"])
        .unwrap();
    let d = d.build().unwrap();
    let mut p = ProblemBuilder::new("enter-lab", &d);
    p.objects(&["front"], "door").unwrap().objects(&["lab"], "room").unwrap();
    p.init("at-door", &[]).unwrap().init("has-key", &[]).unwrap().init("leads-to", &["front", "lab"]).unwrap();
    p.init("unlatched", &["front"]).unwrap();
    p.goal("inside", &["lab"]).unwrap();
    Arc::new(Grounding::new(&p.build().unwrap()).unwrap())
}

#[test]
fn with_two_achieving_actions_the_second_is_used_when_the_first_fails() {
    let g = door();
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let p = plan(g.clone(), c.clone(), Options::default()).unwrap();
    let opened = p.expansions.iter().find(|e| e.condition == "open(front)").unwrap();
    assert_eq!(opened.actions, ["push(front)", "unlock(front)"]);
    let (push, unlock) = (action(&g, "push(front)"), action(&g, "unlock(front)"));
    let mut planner = p.planner;
    let mut world = StripsWorld::new(g);
    // Someone latches the door before the robot pushes it: pushing cannot work any
    // more, unlocking it with the key still does.
    let script = BeforeTicks(|t, w: &mut StripsWorld| {
        if t == 1 {
            w.set_named("unlatched", &["front"], false);
        }
    });
    let out = run_blended(&mut planner, c.as_ref(), &mut world, 50, script).unwrap();
    assert_eq!(out.status, Status::Success);
    assert!(out.expansions.is_empty());
    assert_eq!((world.starts(push), world.completions(unlock)), (0, 1));
    assert!(world.holds_named("inside", &["lab"]));
}

#[test]
fn a_condition_assumed_true_that_turns_false_is_expanded_on_the_fly() {
    let (g, c, mut planner) = cube();
    let before = planner.nodes().len();
    let mut world = StripsWorld::new(g);
    let script = BeforeTicks(|t, w: &mut StripsWorld| {
        // The path to the cube, free when the tree was planned, is blocked at run time.
        if t == 1 {
            w.set_named("path-free", &["cube"], false);
        }
    });
    let out = run_blended(&mut planner, c.as_ref(), &mut world, 200, script).unwrap();
    assert_eq!(out.status, Status::Success);
    assert_eq!(out.expansions[0].1.condition, "path-free(cube)");
    assert_eq!(out.expansions[0].1.actions, ["clear-path(sphere, cube)"]);
    assert!(planner.nodes().len() > before);
    assert!(world.holds_named("at", &["cube", "goal"]));
}

/// A disturbed run goes on after one failed tick, as a robot ticks on, when
/// `Ends::failures` is 2; with 1 the first Failure ends it.
#[test]
fn a_run_can_tick_on_after_a_failed_tick() {
    use planner::strips::{self, Ends, Verdict};
    let (g, c, planner) = cube();
    let go = action(&g, "move-to(goal)");
    let (tree, values) = (planner.nodes().to_vec(), planner.values().to_vec());
    let run = |failures| {
        let mut world = StripsWorld::new(g.clone());
        world.set_checked_completion(true);
        let mut blocked = None;
        let ends = Ends { on_loop: false, failures };
        let verdict = strips::run_to_goal(
            (&tree, &values),
            c.as_ref(),
            &mut world,
            100,
            ends,
            BeforeTicks(|t, w: &mut StripsWorld| match blocked {
                // The sphere rolls into the path while the robot moves to the goal, and
                // out of it again at the next tick.
                None if w.starts(go) == 1 && w.completions(go) == 0 => {
                    w.set_named("path-free", &["goal"], false);
                    blocked = Some(t);
                }
                Some(b) if t == b + 1 => {
                    w.set_named("path-free", &["goal"], true);
                }
                _ => {}
            }),
            &mut Vec::new(),
        )
        .unwrap();
        (verdict, blocked)
    };
    let (first, blocked) = run(1);
    assert!(matches!(first, Verdict::Failed { ticks } if Some(ticks) == blocked), "{first:?}, blocked at {blocked:?}");
    let (on, _) = run(2);
    assert!(on.reached(), "{on:?}");
}
