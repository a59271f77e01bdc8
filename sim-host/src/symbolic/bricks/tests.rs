//! One test per rule of `docs/brick-tasks.md`, "The fast symbolic world".
#![allow(clippy::unwrap_used, clippy::float_cmp)]

use super::*;
use bt_core::{Context, Leaf, Status};
use planner::duplo::Task;
use worlds::World as _;

use Status::{Failure, Running, Success};

fn world(task: Task) -> SymbolicBrickWorld {
    SymbolicBrickWorld::new(&task.spec()).unwrap()
}

fn leaf(w: &SymbolicBrickWorld, name: &str) -> Leaf {
    Leaf::new(w.spec().id_by_name(name).unwrap_or_else(|| panic!("no behavior `{name}`")))
}

/// As if each behavior were ticked by its own node, numbered as the behavior.
fn ctx(l: &Leaf, starting: bool) -> Context<'static> {
    Context { node: l.behavior(), now: 0, starting, values: &[] }
}

/// The action's first tick.
fn start(w: &mut SymbolicBrickWorld, name: &str) -> Status {
    let l = leaf(w, name);
    w.action(&l, ctx(&l, true))
}

/// The action's second tick.
fn finish(w: &mut SymbolicBrickWorld, name: &str) -> Status {
    let l = leaf(w, name);
    w.action(&l, ctx(&l, false))
}

/// The executor halting the action's node.
fn halt(w: &mut SymbolicBrickWorld, name: &str) {
    let l = leaf(w, name);
    w.halt(&l, l.behavior());
}

/// Both ticks: asserts the first is Running, returns the second.
fn act(w: &mut SymbolicBrickWorld, name: &str) -> Status {
    assert_eq!(start(w, name), Running, "{name} should start");
    finish(w, name)
}

fn cond(w: &mut SymbolicBrickWorld, name: &str) -> Status {
    let l = leaf(w, name);
    w.condition(&l, ctx(&l, true))
}

fn pos(w: &SymbolicBrickWorld, b: usize) -> [f32; 3] {
    w.position(b)
}

fn close(a: [f32; 3], b: [f32; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6)
}

// ---- timing ----

#[test]
fn an_action_is_running_on_its_first_tick_and_acts_on_the_next() {
    let mut w = world(Task::Tower);
    assert_eq!(start(&mut w, "pick 0!"), Running);
    assert_eq!(w.held(), None, "no effect on the first tick");
    assert_eq!(pos(&w, 0), [-0.05, -0.1, 0.0]);
    assert_eq!(finish(&mut w, "pick 0!"), Success);
    assert_eq!(w.held(), Some(0));
}

#[test]
fn halt_cancels_an_action_before_its_effect() {
    let mut w = world(Task::Tower);
    assert_eq!(start(&mut w, "pick 0!"), Running);
    halt(&mut w, "pick 0!");
    assert_eq!(w.held(), None);
    assert_eq!(pos(&w, 0), [-0.05, -0.1, 0.0]);
    // On a later tick it starts afresh.
    w.step();
    assert_eq!(start(&mut w, "pick 0!"), Running);
    assert_eq!(w.held(), None);
}

#[test]
fn an_action_halted_and_restarted_within_one_tick_carries_on() {
    let mut w = world(Task::Tower);
    act(&mut w, "pick 1!");
    w.step();
    assert_eq!(start(&mut w, "place on 0!"), Running);
    w.step();
    // Next tick: the executor halts it (an earlier action starts), then reaches it again.
    halt(&mut w, "place on 0!");
    assert_eq!(start(&mut w, "pick 1!"), Success, "the shortcut");
    assert_eq!(start(&mut w, "place on 0!"), Success, "resumed: its second tick");
    assert_eq!(cond(&mut w, "1 on 0?"), Success);
    // Only the node that was halted resumes.
    let mut w = world(Task::Tower);
    act(&mut w, "pick 1!");
    halt(&mut w, "place on 1!");
    assert_eq!(start(&mut w, "place on 0!"), Running, "its node was not halted");
}

#[test]
fn under_the_cancel_rule_a_halted_action_always_starts_afresh() {
    let mut w = world(Task::Tower).with_halt_rule(HaltRule::Cancel);
    assert_eq!(w.halt_rule(), HaltRule::Cancel);
    act(&mut w, "pick 1!");
    assert_eq!(start(&mut w, "place on 0!"), Running);
    halt(&mut w, "place on 0!");
    assert_eq!(start(&mut w, "place on 0!"), Running);
    assert_eq!(w.held(), Some(1));
}

#[test]
fn steps_move_nothing() {
    let mut w = world(Task::Tower);
    for _ in 0..5 {
        w.step();
    }
    assert_eq!(w.ticks(), 5);
    assert!((0..3).all(|b| pos(&w, b) == w.spec().start[b]));
}

// ---- pick ----

#[test]
fn pick_holds_the_brick_and_lifts_it_by_the_pick_height() {
    let mut w = world(Task::Tower);
    assert_eq!(act(&mut w, "pick 1!"), Success);
    assert_eq!(w.held(), Some(1));
    assert_eq!(pos(&w, 1), [0.0, -0.1, PICK_HEIGHT]);
}

#[test]
fn pick_succeeds_at_once_when_it_already_holds_the_brick() {
    let mut w = world(Task::Tower);
    act(&mut w, "pick 1!");
    assert_eq!(start(&mut w, "pick 1!"), Success);
    assert_eq!(pos(&w, 1)[2], PICK_HEIGHT, "not lifted twice");
}

#[test]
fn pick_fails_at_once_when_it_holds_another_brick() {
    let mut w = world(Task::Tower);
    act(&mut w, "pick 1!");
    assert_eq!(start(&mut w, "pick 0!"), Failure);
    assert_eq!(w.held(), Some(1));
}

#[test]
fn pick_fails_on_its_second_tick_if_the_hand_filled_meanwhile() {
    let mut w = world(Task::Tower);
    assert_eq!(start(&mut w, "pick 0!"), Running);
    act(&mut w, "pick 2!");
    assert_eq!(finish(&mut w, "pick 0!"), Failure);
    assert_eq!(w.held(), Some(2));
}

// ---- place ----

#[test]
fn place_at_moves_the_held_brick_there_and_empties_the_hand() {
    let mut w = world(Task::Tower);
    act(&mut w, "pick 2!");
    assert_eq!(act(&mut w, "place at (0.0, 0.05, 0.0)!"), Success);
    assert_eq!(pos(&w, 2), [0.0, 0.05, 0.0]);
    assert_eq!(w.held(), None);
}

#[test]
fn place_on_sits_on_the_studs_not_pressed() {
    let mut w = world(Task::Tower);
    act(&mut w, "pick 1!");
    assert_eq!(act(&mut w, "place on 0!"), Success);
    assert_eq!(pos(&w, 1), [-0.05, -0.1, BRICK_HEIGHT + NOT_PRESSED_GAP]);
    assert_eq!(cond(&mut w, "1 on 0?"), Success);
}

#[test]
fn place_fails_at_once_on_an_empty_hand() {
    let mut w = world(Task::Tower);
    assert_eq!(start(&mut w, "place on 0!"), Failure);
    assert_eq!(start(&mut w, "place at (0.0, 0.05, 0.0)!"), Failure);
}

#[test]
fn place_fails_on_its_second_tick_if_the_hand_emptied_meanwhile() {
    let mut w = world(Task::Tower);
    act(&mut w, "pick 1!");
    assert_eq!(start(&mut w, "place on 0!"), Running);
    act(&mut w, "place at (0.0, 0.05, 0.0)!");
    assert_eq!(finish(&mut w, "place on 0!"), Failure);
}

#[test]
fn default_mode_places_into_an_occupied_spot() {
    // Decision: outside the blocking mode nothing is in the way; the bricks overlap.
    let mut w = world(Task::Tower);
    act(&mut w, "pick 0!");
    act(&mut w, "place at (0.0, 0.05, 0.0)!");
    act(&mut w, "pick 1!");
    assert_eq!(act(&mut w, "place at (0.0, 0.05, 0.0)!"), Success);
    assert_eq!(pos(&w, 0), pos(&w, 1));
}

// ---- apply force ----

#[test]
fn apply_force_presses_a_brick_onto_the_one_below() {
    let mut w = world(Task::Tower);
    act(&mut w, "pick 1!");
    act(&mut w, "place on 0!");
    assert_eq!(act(&mut w, "apply force 1!"), Success);
    assert_eq!(pos(&w, 1), [-0.05, -0.1, BRICK_HEIGHT]);
    assert_eq!(cond(&mut w, "1 on 0?"), Success, "still on top once pressed");
}

#[test]
fn apply_force_fails_at_once_while_holding() {
    let mut w = world(Task::Tower);
    act(&mut w, "pick 1!");
    assert_eq!(start(&mut w, "apply force 0!"), Failure);
}

#[test]
fn apply_force_on_a_brick_on_nothing_succeeds_and_changes_nothing() {
    let mut w = world(Task::Tower);
    assert_eq!(act(&mut w, "apply force 2!"), Success);
    assert_eq!(pos(&w, 2), [0.05, -0.1, 0.0]);
}

#[test]
fn apply_force_fails_on_its_second_tick_if_the_hand_filled_meanwhile() {
    let mut w = world(Task::Tower);
    assert_eq!(start(&mut w, "apply force 2!"), Running);
    act(&mut w, "pick 0!");
    assert_eq!(finish(&mut w, "apply force 2!"), Failure);
}

// ---- put ----

#[test]
fn put_on_picks_and_places_in_one_action() {
    let mut w = world(Task::Balance);
    assert_eq!(start(&mut w, "put 1 on 2!"), Running);
    assert_eq!(pos(&w, 1), [0.0, -0.1, 0.0]);
    assert_eq!(finish(&mut w, "put 1 on 2!"), Success);
    assert_eq!(pos(&w, 1), [0.05, -0.1, BRICK_HEIGHT + NOT_PRESSED_GAP]);
    assert_eq!(w.held(), None);
}

#[test]
fn put_on_succeeds_at_once_when_already_on() {
    let mut w = world(Task::Balance);
    act(&mut w, "put 1 on 2!");
    assert_eq!(start(&mut w, "put 1 on 2!"), Success);
}

#[test]
fn put_on_while_holding_starts_and_then_fails() {
    // The reference gives `put i on j` no start shortcut for a full hand: the pick in
    // its second tick fails.
    let mut w = world(Task::Balance);
    act(&mut w, "pick 0!");
    assert_eq!(start(&mut w, "put 1 on 2!"), Running);
    assert_eq!(finish(&mut w, "put 1 on 2!"), Failure);
    assert_eq!(w.held(), Some(0));
    assert_eq!(pos(&w, 1), [0.0, -0.1, 0.0]);
}

#[test]
fn put_at_moves_the_brick_and_succeeds_at_once_when_there() {
    let mut w = world(Task::Balance);
    assert_eq!(act(&mut w, "put 1 at (0.0, 0.0, 0.0)!"), Success);
    assert_eq!(pos(&w, 1), [0.0, 0.0, 0.0]);
    assert_eq!(start(&mut w, "put 1 at (0.0, 0.0, 0.0)!"), Success);
}

#[test]
fn put_at_fails_at_once_when_another_brick_is_held() {
    let mut w = world(Task::Balance);
    act(&mut w, "pick 0!");
    assert_eq!(start(&mut w, "put 1 at (0.0, 0.0, 0.0)!"), Failure);
}

#[test]
fn put_while_holding_the_same_brick_starts_and_then_fails() {
    // Decision (as the reference): the put's pick needs an empty hand.
    let mut w = world(Task::Balance);
    act(&mut w, "pick 1!");
    assert_eq!(start(&mut w, "put 1 at (0.0, 0.0, 0.0)!"), Running);
    assert_eq!(finish(&mut w, "put 1 at (0.0, 0.0, 0.0)!"), Failure);
    assert_eq!(w.held(), Some(1));
}

// ---- conditions ----

#[test]
fn at_pos_holds_below_the_position_margin() {
    let mut w = world(Task::Tower);
    let goal = [0.0, 0.05, 0.0];
    w.set_state(&[[0.0, 0.05 + 0.0009, 0.0]], None);
    assert_eq!(cond(&mut w, "0 at pos (0.0, 0.05, 0.0)?"), Success);
    w.set_state(&[[0.0, 0.05, 0.0011]], None);
    assert_eq!(cond(&mut w, "0 at pos (0.0, 0.05, 0.0)?"), Failure);
    w.set_state(&[goal], None);
    assert_eq!(cond(&mut w, "0 at pos (0.0, 0.05, 0.0)?"), Success);
    assert_eq!(cond(&mut w, "1 at pos (0.0, 0.05, 0.0192)?"), Failure);
}

#[test]
fn on_top_test_has_its_margins() {
    let mut w = world(Task::Tower);
    let on = |w: &mut SymbolicBrickWorld, upper: [f32; 3]| {
        w.set_state(&[[0.0, 0.0, 0.0], upper], None);
        cond(w, "1 on 0?")
    };
    assert_eq!(on(&mut w, [0.0029, -0.0029, 0.0192]), Success);
    assert_eq!(on(&mut w, [0.0031, 0.0, 0.0192]), Failure, "|dx| below 0.003");
    assert_eq!(on(&mut w, [0.0, 0.0031, 0.0192]), Failure, "|dy| below 0.003");
    assert_eq!(on(&mut w, [0.0, 0.0, 0.0]), Failure, "dz above 0");
    assert_eq!(on(&mut w, [0.0, 0.0, 0.0222]), Success, "dz up to 0.0222 included");
    assert_eq!(on(&mut w, [0.0, 0.0, 0.0223]), Failure);
    assert_eq!(cond(&mut w, "0 on 1?"), Failure, "not symmetric");
}

#[test]
fn picked_checks_the_held_brick() {
    let mut w = world(Task::Tower);
    assert_eq!(cond(&mut w, "picked 0?"), Failure);
    act(&mut w, "pick 0!");
    assert_eq!(cond(&mut w, "picked 0?"), Success);
    assert_eq!(cond(&mut w, "picked 1?"), Failure);
}

// ---- croissant ----

/// The croissant world holding `brick` (lifted) with brick 1 at y = `y1`.
fn croissant(brick: u8, y1: f32) -> SymbolicBrickWorld {
    let mut w = world(Task::Croissant);
    let mut p: Vec<[f32; 3]> = w.spec().start.clone();
    p[1] = [0.0, y1, BRICK_HEIGHT];
    p[usize::from(brick)][2] = PICK_HEIGHT;
    w.set_state(&p, Some(brick));
    w
}

#[test]
fn croissant_bricks_2_and_3_cannot_be_placed_while_the_long_brick_lies_near_y_0() {
    for (brick, place) in [(2, "place at (0.016, -0.032, 0.0)!"), (3, "place at (0.016, 0.032, 0.0)!")] {
        let mut w = croissant(brick, -0.0099);
        assert_eq!(act(&mut w, place), Failure, "brick {brick}");
        assert_eq!(w.held(), Some(brick), "a failed place leaves the brick held");
        assert_eq!(pos(&w, usize::from(brick))[2], PICK_HEIGHT);
        let mut w = croissant(brick, 0.01);
        assert_eq!(act(&mut w, place), Success, "|y1| = 0.01 is clear");
    }
    // Places on a brick too; bricks 0 and 1 are never blocked.
    let mut w = croissant(2, 0.0);
    assert_eq!(act(&mut w, "place on 0!"), Failure);
    let mut w = croissant(0, 0.0);
    assert_eq!(act(&mut w, "place at (0.0, 0.0, 0.0)!"), Success);
}

#[test]
fn croissant_rule_is_only_in_the_croissant_mode() {
    // The same situation in the default mode: brick 2 places fine over brick 1 at y 0.
    let mut w = world(Task::Tower);
    w.set_state(&[[-0.05, -0.1, 0.0], [0.0, 0.0, 0.0], [0.05, -0.1, PICK_HEIGHT]], Some(2));
    assert_eq!(act(&mut w, "place at (0.0, 0.05, 0.0)!"), Success);
}

// ---- balance ----

#[test]
fn balance_brick_0_placed_on_1_tips_off_in_y() {
    let mut w = world(Task::Balance);
    assert_eq!(act(&mut w, "put 0 on 1!"), Success);
    assert!(close(pos(&w, 0), [0.0, -0.1 + BALANCE_TIP, BRICK_HEIGHT + NOT_PRESSED_GAP]));
    assert_eq!(cond(&mut w, "0 on 1?"), Failure, "it is 10 mm off: not on top");
    // On brick 2, no tipping; brick 1 on 2 neither.
    let mut w = world(Task::Balance);
    act(&mut w, "put 0 on 2!");
    assert_eq!(pos(&w, 0), [0.05, -0.1, BRICK_HEIGHT + NOT_PRESSED_GAP]);
}

#[test]
fn balance_brick_2_placed_at_a_position_rises_while_brick_1_sits_at_y_0() {
    let mut w = world(Task::Balance);
    act(&mut w, "put 1 at (0.0, 0.0, 0.0)!");
    assert_eq!(act(&mut w, "put 2 at (0.0, 0.0, 0.0)!"), Success);
    assert_eq!(pos(&w, 2), [0.0, 0.0, BRICK_HEIGHT]);
    // Brick 1 elsewhere (y = -0.1): no rise. Brick 0 placed there: no rise.
    let mut w = world(Task::Balance);
    act(&mut w, "put 2 at (0.0, 0.0, 0.0)!");
    assert_eq!(pos(&w, 2), [0.0, 0.0, 0.0]);
    let mut w = world(Task::Balance);
    act(&mut w, "put 1 at (0.0, 0.0, 0.0)!");
    act(&mut w, "put 0 at (0.0, 0.0, 0.0)!");
    assert_eq!(pos(&w, 0), [0.0, 0.0, 0.0]);
}

#[test]
fn balance_rules_are_only_in_the_balance_mode() {
    let mut w = world(Task::Tower);
    act(&mut w, "pick 0!");
    act(&mut w, "place on 1!");
    assert_eq!(pos(&w, 0), [0.0, -0.1, BRICK_HEIGHT + NOT_PRESSED_GAP]);
}

// ---- blocking ----

#[test]
fn blocking_a_place_at_an_occupied_position_fails() {
    let mut w = world(Task::Blocking);
    // Brick 2 sits at (-0.1, 0, 0).
    assert_eq!(act(&mut w, "put 0 at (-0.1, 0.0, 0.0)!"), Failure);
    assert_eq!(w.held(), Some(0), "the put picked, then its place failed");
    assert_eq!(pos(&w, 0), [0.0, -0.05, PICK_HEIGHT]);
}

#[test]
fn blocking_brick_2_cannot_go_where_its_cone_hits_a_brick_at_the_same_x() {
    // Bricks 0 and 1 at x = 0, y = -+0.05: the cone collides at (0, 0, 0).
    let mut w = world(Task::Blocking);
    assert_eq!(act(&mut w, "put 2 at (0.0, 0.0, 0.0)!"), Failure);
    assert_eq!(w.held(), Some(2));
    // With both moved to x = -0.1 (stacked), (0, 0, 0) is free for brick 2.
    let mut w = world(Task::Blocking);
    w.set_state(&[[-0.1, 0.0, 0.0], [-0.1, 0.0, BRICK_HEIGHT], [0.0, 0.1, 0.0]], None);
    assert_eq!(act(&mut w, "put 2 at (0.0, 0.0, 0.0)!"), Success);
    // |dy| = 0.1 exactly is clear; a hair less is not.
    let mut w = world(Task::Blocking);
    w.set_state(&[[0.0, 0.1, 0.0], [-0.1, 0.0, 0.0], [0.0, -0.05, 0.0]], None);
    assert_eq!(act(&mut w, "put 2 at (0.0, 0.0, 0.0)!"), Success);
    let mut w = world(Task::Blocking);
    w.set_state(&[[0.0, 0.0999, 0.0], [-0.1, 0.0, 0.0], [0.0, -0.05, 0.0]], None);
    assert_eq!(act(&mut w, "put 2 at (0.0, 0.0, 0.0)!"), Failure);
    // The cone rule is brick 2's only: brick 0 may go between the bricks at x = 0.
    let mut w = world(Task::Blocking);
    assert_eq!(act(&mut w, "put 0 at (0.0, 0.0, 0.0)!"), Success);
}

#[test]
fn blocking_anything_placed_on_brick_2_ends_higher() {
    let mut w = world(Task::Blocking);
    w.set_state(&[[0.0, -0.05, 0.0], [0.0, 0.05, 0.0], [0.1, 0.1, 0.0]], None);
    // Only `put 0 on 1!` and `put 1 on 0!` exist in the task; place on 2 by hand.
    w.held = Some(0);
    assert!(w.place(Target::On(2)));
    assert!(close(pos(&w, 0), [0.1, 0.1, BRICK_HEIGHT + NOT_PRESSED_GAP + BLOCKING_CONE_LIFT]));
    assert!(!w.on_top(0, 2), "it does not stack on the cone");
    // On brick 1 it stacks normally.
    let mut w = world(Task::Blocking);
    assert_eq!(act(&mut w, "put 0 on 1!"), Success);
    assert_eq!(cond(&mut w, "0 on 1?"), Success);
}

// ---- the world ----

#[test]
fn reset_restores_the_start_state_in_place() {
    let mut w = world(Task::Croissant);
    act(&mut w, "pick 3!");
    w.step();
    w.reset();
    assert_eq!(w.held(), None);
    assert_eq!(w.ticks(), 0);
    assert!((0..4).all(|b| pos(&w, b) == w.spec().start[b]));
    assert!(pos(&w, 4)[0].is_nan(), "no brick 4");
}

#[test]
fn a_bad_spec_is_refused() {
    let mut spec = Task::Tower.spec();
    spec.start.pop();
    assert!(matches!(SymbolicBrickWorld::new(&spec), Err(SymbolicError::BadSpec { .. })));
    let mut spec = Task::Tower.spec();
    spec.behaviors.push(Behavior::Pick(7));
    let e = SymbolicBrickWorld::new(&spec).unwrap_err();
    assert_eq!(e.to_string(), "task tower: a behavior names brick 7, it has 3");
    let mut spec = Task::Croissant.spec();
    spec.bricks.push(planner::duplo::BrickKind::TwoByTwo);
    assert!(matches!(SymbolicBrickWorld::new(&spec), Err(SymbolicError::TooManyBricks { count: 5, .. })));
}

#[test]
fn behaviors_of_the_wrong_kind_or_unknown_fail() {
    let mut w = world(Task::Tower);
    let c = leaf(&w, "picked 0?");
    let a = leaf(&w, "pick 0!");
    let unknown = Leaf::new(999);
    assert_eq!(w.action(&c, ctx(&c, true)), Failure);
    assert_eq!(w.action(&c, ctx(&c, false)), Failure);
    assert_eq!(w.condition(&a, ctx(&a, true)), Failure);
    assert_eq!(w.action(&unknown, ctx(&unknown, true)), Failure);
    assert_eq!(w.condition(&unknown, ctx(&unknown, true)), Failure);
}
