//! Each brick behavior does what it says on a fresh physics world, and the physics the
//! planner does not know happens.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod physics_common;

use bt_core::Status;
use physics_common::{dist, episode, until_done};
use planner::duplo::Task;
use sim_host::physics::PhysicsBrickWorld;
use sim_host::world::BrickWorld;
use worlds::World;

fn world(task: Task) -> PhysicsBrickWorld {
    PhysicsBrickWorld::new(&task.spec()).unwrap()
}

#[test]
fn pick_lifts_the_brick() {
    let mut w = world(Task::Tower);
    let out = until_done(&mut w, "pick 0!", 60);
    assert_eq!(out.status, Status::Success, "{:?}", w.events());
    assert_eq!(w.held(), Some(0));
    let p = w.position(0);
    assert!(p[2] > 0.07, "lifted to travel height: {p:?}");
    assert!((p[0] + 0.05).abs() < 1e-3 && (p[1] + 0.1).abs() < 1e-3, "straight up: {p:?}");
    println!("pick took {} ticks", out.ticks);
}

#[test]
fn place_puts_it_within_the_margin() {
    let mut w = world(Task::Tower);
    let out = until_done(
        &mut w,
        "f( 0 at pos (0.0, 0.05, 0.0)? s( f( picked 0? pick 0! ) place at (0.0, 0.05, 0.0)! ) )",
        120,
    );
    assert_eq!(out.status, Status::Success, "{:?}", w.events());
    assert_eq!(w.held(), None);
    for _ in 0..10 {
        w.step();
    }
    let p = w.position(0);
    println!("placed at {p:?} after {} ticks", out.ticks);
    assert!(dist(p, [0.0, 0.05, 0.0]) < 0.001, "{p:?}");
    assert_eq!(until_done(&mut w, "0 at pos (0.0, 0.05, 0.0)?", 1).status, Status::Success);
}

const TOWER_G0: &str = "f( 0 at pos (0.0, 0.05, 0.0)? s( f( picked 0? pick 0! ) place at (0.0, 0.05, 0.0)! ) )";

#[test]
fn place_on_stacks_it_and_apply_force_presses_and_fixes() {
    let mut w = world(Task::Tower);
    let on = format!("s( {TOWER_G0} f( 1 on 0? s( f( picked 1? pick 1! ) place on 0! ) ) )");
    let out = until_done(&mut w, &on, 150);
    assert_eq!(out.status, Status::Success, "{:?}", w.events());
    for _ in 0..5 {
        w.step();
    }
    let (p0, p1) = (w.position(0), w.position(1));
    // On the studs, not pressed: 2 mm higher than a pressed brick.
    assert!((p1[0] - p0[0]).abs() < 1e-3 && (p1[1] - p0[1]).abs() < 1e-3, "{p0:?} {p1:?}");
    assert!((p1[2] - p0[2] - 0.0212).abs() < 5e-4, "{p0:?} {p1:?}");
    assert_eq!(until_done(&mut w, "1 on 0?", 1).status, Status::Success);
    assert_eq!(until_done(&mut w, "1 at pos (0.0, 0.05, 0.0192)?", 1).status, Status::Failure);
    assert_eq!(w.fixed_below(1), None);

    let out = until_done(&mut w, "apply force 1!", 60);
    assert_eq!(out.status, Status::Success, "{:?}", w.events());
    for _ in 0..5 {
        w.step();
    }
    assert_eq!(w.fixed_below(1), Some(0));
    let p1 = w.position(1);
    assert!(dist(p1, [0.0, 0.05, 0.0192]) < 1e-3, "pressed to {p1:?}");
    assert_eq!(until_done(&mut w, "1 at pos (0.0, 0.05, 0.0192)?", 1).status, Status::Success);
    assert_eq!(until_done(&mut w, "1 on 0?", 1).status, Status::Success);
}

#[test]
fn actions_fail_at_once_where_the_reference_says() {
    let mut w = world(Task::Tower);
    // Nothing held: place fails on its first tick.
    assert_eq!(until_done(&mut w, "place on 0!", 5), physics_common::Outcome { status: Status::Failure, ticks: 1 });
    assert_eq!(until_done(&mut w, "pick 2!", 60).status, Status::Success);
    // Holding: apply force and picking another brick fail at once, picking the held one succeeds.
    assert_eq!(until_done(&mut w, "apply force 0!", 5).ticks, 1);
    assert_eq!(until_done(&mut w, "pick 0!", 5), physics_common::Outcome { status: Status::Failure, ticks: 1 });
    assert_eq!(until_done(&mut w, "pick 2!", 5), physics_common::Outcome { status: Status::Success, ticks: 1 });
    assert_eq!(w.held(), Some(2));
}

#[test]
fn put_is_pick_then_place() {
    let mut w = world(Task::Balance);
    let out = until_done(&mut w, "put 1 at (0.0, 0.0, 0.0)!", 60);
    assert_eq!(out.status, Status::Success, "{:?}", w.events());
    assert_eq!(w.held(), None);
    assert!(dist(w.position(1), [0.0, 0.0, 0.0]) < 1e-3, "{:?}", w.position(1));
    // Already there: succeeds on its first tick.
    assert_eq!(until_done(&mut w, "put 1 at (0.0, 0.0, 0.0)!", 5).ticks, 1);
}

#[test]
fn placing_into_an_occupied_spot_is_blocked_and_keeps_the_brick() {
    let mut w = world(Task::Tower);
    let text = format!("s( {TOWER_G0} f( picked 1? pick 1! ) place at (0.0, 0.05, 0.0)! )");
    let out = until_done(&mut w, &text, 150);
    assert_eq!(out.status, Status::Failure);
    assert_eq!(w.held(), Some(1));
    assert!(w.events().iter().any(|e| matches!(e, sim_host::physics::BrickEvent::Blocked { by: Some(0), .. })));
    assert!(dist(w.position(0), [0.0, 0.05, 0.0]) < 1e-3, "the occupant did not move");
    assert!(w.position(1)[2] > 0.0192, "stopped above it: {:?}", w.position(1));
}

#[test]
fn the_unbalanced_brick_falls_off_a_2x2() {
    let mut w = world(Task::Balance);
    assert_eq!(until_done(&mut w, "put 1 at (0.0, 0.0, 0.0)!", 60).status, Status::Success, "{:?}", w.events());
    assert_eq!(until_done(&mut w, "put 0 on 1!", 60).status, Status::Success, "{:?}", w.events());
    for _ in 0..15 {
        w.step();
    }
    assert_eq!(until_done(&mut w, "0 on 1?", 1).status, Status::Failure, "fell: {:?}", w.position(0));
    let (_, q) = w.pose(0).unwrap();
    // Tilted about x (the long side lies along y): the heavy end went down.
    let tilt = 2.0 * q[0].abs().asin();
    assert!(tilt > 0.2, "tipped over by {tilt} rad: {:?}", w.pose(0));

    // Known weakness: on a 4x2 base (the paper's solution) the long brick still rocks
    // over sideways after release in this world; see the report.
}

#[test]
fn nothing_stays_on_the_cone_brick() {
    // The blocking task's brick 2 lies on spot A at the start: putting brick 0 there
    // meets the cone's tip, well above the brick itself.
    let mut w = world(Task::Blocking);
    let out = until_done(&mut w, "put 0 at (-0.1, 0.0, 0.0)!", 60);
    assert_eq!(out.status, Status::Failure);
    assert_eq!(w.held(), Some(0));
    assert!(w.events().iter().any(|e| matches!(e, sim_host::physics::BrickEvent::Blocked { by: Some(2), .. })));
    assert!(w.position(0)[2] > 0.0192 + 0.02, "stopped by the cone's tip: {:?}", w.position(0));

    // A task variant with `place on 2!`: the place fails the same way.
    let mut spec = Task::Blocking.spec();
    spec.behaviors = vec![
        planner::duplo::Behavior::Picked(0),
        planner::duplo::Behavior::Pick(0),
        planner::duplo::Behavior::PlaceOn(2),
    ];
    spec.names = spec.behaviors.iter().map(|&b| Task::Blocking.behavior_name(b)).collect();
    let mut w = PhysicsBrickWorld::new(&spec).unwrap();
    let out = until_done(&mut w, "s( f( picked 0? pick 0! ) place on 2! )", 100);
    assert_eq!(out.status, Status::Failure);
    assert!(dist(w.position(0), w.position(2)) > 0.04, "not on the cone brick: {:?}", w.position(0));
}

#[test]
fn in_blocking_spot_c_is_blocked_by_bricks_on_b_and_d() {
    let mut w = world(Task::Blocking);
    let out = until_done(&mut w, "put 2 at (0.0, 0.0, 0.0)!", 60);
    assert_eq!(out.status, Status::Failure, "{:?}", w.events());
    assert_eq!(w.held(), Some(2));
}

const CROISSANT_G0: &str = "f( 0 at pos (0.0, 0.0, 0.0)? s( f( picked 0? pick 0! ) place at (0.0, 0.0, 0.0)! ) )";
const CROISSANT_G1: &str =
    "f( 1 at pos (0.0, 0.0, 0.0192)? s( f( 1 on 0? s( f( picked 1? pick 1! ) place on 0! ) ) apply force 1! ) )";
const CROISSANT_G2: &str =
    "f( 2 at pos (0.016, -0.032, 0.0)? s( f( picked 2? pick 2! ) place at (0.016, -0.032, 0.0)! ) )";
const CROISSANT_G3: &str =
    "f( 3 at pos (0.016, 0.032, 0.0)? s( f( picked 3? pick 3! ) place at (0.016, 0.032, 0.0)! ) )";

#[test]
fn croissant_side_bricks_collide_with_the_long_brick_in_place() {
    let mut w = world(Task::Croissant);
    let planner = format!("s( {CROISSANT_G0} {CROISSANT_G1} {CROISSANT_G2} {CROISSANT_G3} )");
    let out = episode(&mut w, &planner, 200);
    assert_eq!(out.status, Status::Failure, "{:?}", w.events());
    assert!(w.events().iter().any(|e| matches!(e, sim_host::physics::BrickEvent::Blocked { by: Some(1), .. })));
    assert!(dist(w.position(1), [0.0, 0.0, 0.0192]) < 1e-3);

    // Side bricks first, then the long brick: everything lands at its goal.
    let mut w = world(Task::Croissant);
    let reordered = format!("s( {CROISSANT_G0} {CROISSANT_G2} {CROISSANT_G3} {CROISSANT_G1} )");
    let out = episode(&mut w, &reordered, 200);
    assert_eq!(out.status, Status::Success, "{:?}", w.events());
    let spec = Task::Croissant.spec();
    for (i, goal) in spec.goal.iter().enumerate() {
        let goal = goal.unwrap();
        assert!(dist(w.position(i), goal) < 1e-3, "brick {i} at {:?}, goal {goal:?}", w.position(i));
    }
}

/// The planner's tree for the tower, written by hand from the templates of
/// `docs/brick-tasks.md`: the goal conditions in brick order, each expanded to its atomic BT.
pub const TOWER_PLANNER_TREE: &str = "s( \
    f( 0 at pos (0.0, 0.05, 0.0)? s( f( picked 0? pick 0! ) place at (0.0, 0.05, 0.0)! ) ) \
    f( 1 at pos (0.0, 0.05, 0.0192)? s( f( 1 on 0? s( f( picked 1? pick 1! ) place on 0! ) ) apply force 1! ) ) \
    f( 2 at pos (0.0, 0.05, 0.0384)? s( f( 2 on 1? s( f( picked 2? pick 2! ) place on 1! ) ) apply force 2! ) ) )";

#[test]
fn the_planners_tree_builds_the_tower() {
    let mut w = world(Task::Tower);
    let out = episode(&mut w, TOWER_PLANNER_TREE, 200);
    println!("tower: {out:?}");
    assert_eq!(out.status, Status::Success, "{:?}", w.events());
    assert!(out.ticks < 200, "ended by two successes, not the tick limit");
    let spec = Task::Tower.spec();
    for (i, goal) in spec.goal.iter().enumerate() {
        let goal = goal.unwrap();
        assert!(dist(w.position(i), goal) < 4e-4, "brick {i} at {:?}, goal {goal:?}", w.position(i));
    }
    assert_eq!((w.fixed_below(1), w.fixed_below(2)), (Some(0), Some(1)));
    assert_eq!(w.held(), None);
}

/// The GP idiom `s( pick 1! place on 0! )`: every tick `pick 1!` starts again (and
/// succeeds at once while the brick is held), which halts `place on 0!` before the tick
/// comes back to it. Under the default rule the place carries on and sets the brick
/// down on 0; taken literally (`Cancel`) it restarts every tick and never gets there.
#[test]
fn an_action_halted_and_restarted_within_a_tick_carries_on() {
    use sim_host::physics::BrickEvent;
    use sim_host::symbolic::HaltRule;

    /// Ticks the idiom for up to 60 ticks; true when brick 1 was let go.
    fn set_down(w: &mut PhysicsBrickWorld) -> bool {
        let released =
            |w: &PhysicsBrickWorld| w.events().iter().any(|e| matches!(e, BrickEvent::Released { brick: 1, .. }));
        physics_common::drive(w, "s( pick 1! place on 0! )", 60, |w, _, _| released(w));
        released(w)
    }

    let mut w = world(Task::Tower);
    assert_eq!(w.halt_rule(), HaltRule::ResumeWithinTick);
    assert!(set_down(&mut w), "placed within 60 ticks: {:?}", w.events());
    assert_eq!(until_done(&mut w, "1 on 0?", 1).status, Status::Success, "{:?}", (w.position(0), w.position(1)));

    let mut w = world(Task::Tower).with_halt_rule(HaltRule::Cancel);
    assert!(!set_down(&mut w), "never set down under Cancel: {:?}", w.events());
    assert_eq!(w.held(), Some(1));
    w.reset();
    assert_eq!(w.halt_rule(), HaltRule::Cancel, "reset keeps the rule");
}

/// While the gripper holds a brick, conditions see every brick where it was when the
/// fingers closed (as the published AGX behaviors do for `at pos`): the brick in the
/// fingers has not left its place for the tree until it is let go.
#[test]
fn while_a_brick_is_held_conditions_see_it_where_it_was_grasped() {
    let mut w = world(Task::Tower);
    let goal = "0 at pos (0.0, 0.05, 0.0)?";
    assert_eq!(until_done(&mut w, TOWER_G0, 120).status, Status::Success, "{:?}", w.events());
    assert_eq!(until_done(&mut w, "pick 0!", 60).status, Status::Success, "{:?}", w.events());
    assert!(w.position(0)[2] > 0.07, "lifted: {:?}", w.position(0));
    assert_eq!(until_done(&mut w, goal, 1).status, Status::Success, "still seen at its goal");
    let out = until_done(&mut w, "place on 1!", 60);
    assert_eq!((out.status, w.held()), (Status::Success, None), "{:?}", w.events());
    assert_eq!(until_done(&mut w, goal, 1).status, Status::Failure, "seen where it is once let go");
    assert_eq!(until_done(&mut w, "0 on 1?", 1).status, Status::Success);
}

/// The blocking task's shuffle, guarded as GP writes it: brick 0 goes on 1, brick 2 to
/// D, then 0 to A. While `put 0 at A!` carries brick 0 off brick 1, the first `put 0 on
/// 1!` is ticked again; seeing 0 still on 1 it succeeds at once instead of carrying it
/// back (measured before the rule: the two puts undid each other until the tick limit,
/// fitness -286.9).
#[test]
fn the_blocking_shuffle_is_not_undone_in_transit() {
    let mut w = world(Task::Blocking);
    let tree = "s( f( 0 at pos (-0.1, 0.0, 0.0)? s( put 0 on 1! put 2 at (0.0, -0.05, 0.0)! put 0 at (-0.1, 0.0, 0.0)! ) ) \
                f( 1 at pos (-0.1, 0.0, 0.0192)? s( put 1 on 0! apply force 1! ) ) put 2 at (0.0, 0.0, 0.0)! )";
    let out = episode(&mut w, tree, 200);
    assert_eq!(out.status, Status::Success, "{out:?} {:?}", w.events());
    assert!(out.ticks < 200, "ended by two successes: {out:?}");
    for (i, goal) in Task::Blocking.spec().goal.iter().enumerate() {
        let goal = goal.unwrap();
        assert!(dist(w.position(i), goal) < 4e-4, "brick {i} at {:?}, goal {goal:?}", w.position(i));
    }
}

/// A brick sitting loose on the studs of the one being lifted rides along and is set
/// down with it, still on top (it used to stop the lift: the guard met it).
#[test]
fn a_loose_brick_on_top_rides_along() {
    let mut w = world(Task::Blocking);
    let a = [-0.1, 0.0, 0.0];
    let tree = "s( put 1 on 0! put 2 at (0.0, 0.05, 0.0)! put 0 at (-0.1, 0.0, 0.0)! )";
    let out = until_done(&mut w, tree, 200);
    assert_eq!(out.status, Status::Success, "{out:?} {:?}", w.events());
    for _ in 0..10 {
        w.step();
    }
    assert!(dist(w.position(0), a) < 1e-3, "brick 0 at A: {:?}", w.position(0));
    assert_eq!(until_done(&mut w, "1 on 0?", 1).status, Status::Success, "{:?}", (w.position(0), w.position(1)));
    assert_eq!(w.fixed_below(1), None, "not pressed on the way");
}
