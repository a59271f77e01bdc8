//! Examples 1 and 2 of Colledanchise et al. 2019 (Fig. 3 and Fig. 4), structurally.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::sync::Arc;

use bt_core::Status;
use bt_formats::tokens;
use planner::algorithm::Move;
use planner::strips::StripsWorld;
use planner::{Options, PddlCatalog, domains, plan, run_blended};
use worlds::agent::BeforeTicks;

fn toks(nodes: &[bt_core::Node], c: &PddlCatalog) -> String {
    tokens::to_string(nodes, c).unwrap()
}

const MOVE_CUBE: &str = "f( near(cube)? s( path-free(cube)? move-to(cube)! ) )";
const PICK_CUBE: &str =
    "f( holding(cube)? s( f( near(cube)? s( path-free(cube)? move-to(cube)! ) ) hand-empty? pick(cube)! ) )";
const MOVE_GOAL: &str = "f( near(goal)? s( path-free(goal)? move-to(goal)! ) )";

#[test]
fn example_1_builds_the_trees_of_fig_3_in_order() {
    let g = Arc::new(domains::cube_sphere().unwrap());
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let p = plan(g, c.clone(), Options { record_steps: true, ..Options::default() }).unwrap();
    let steps: Vec<String> = p.steps.iter().map(|s| toks(s, &c)).collect();
    let fig3 = [
        "at(cube, goal)?".to_string(),
        "f( at(cube, goal)? s( holding(cube)? near(goal)? place(cube, goal)! ) )".to_string(),
        "f( at(cube, goal)? s( f( holding(cube)? s( near(cube)? hand-empty? pick(cube)! ) ) near(goal)? place(cube, goal)! ) )"
            .to_string(),
        format!("f( at(cube, goal)? s( f( holding(cube)? s( {MOVE_CUBE} hand-empty? pick(cube)! ) ) near(goal)? place(cube, goal)! ) )"),
        format!("f( at(cube, goal)? s( {PICK_CUBE} {MOVE_GOAL} place(cube, goal)! ) )"),
    ];
    assert_eq!(steps, fig3);
    let expanded: Vec<&str> = p.expansions.iter().map(|e| e.condition.as_str()).collect();
    assert_eq!(expanded, ["at(cube, goal)", "holding(cube)", "near(cube)", "near(goal)"]);
    assert!(p.expansions.iter().all(|e| e.conflicts.is_empty()));
    // MoveTo, Pick, MoveTo, Place: four actions, each Running for one tick.
    assert_eq!(p.goal_ticks, Some(5));
}

/// Fig. 4: the subtree that clears the path, moved to the front of the main Sequence;
/// the path condition stays as MoveTo's guard.
fn fig4(clear: &str) -> String {
    format!("f( at(cube, goal)? s( f( path-free(goal)? s( {clear} ) ) {PICK_CUBE} {MOVE_GOAL} place(cube, goal)! ) )")
}

#[test]
fn example_2_offline_resolves_the_conflict_into_fig_4() {
    let g = Arc::new(domains::cube_sphere_blocked().unwrap());
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let p = plan(g.clone(), c.clone(), Options { record_steps: true, ..Options::default() }).unwrap();
    let e = &p.expansions[4];
    assert_eq!(e.condition, "path-free(goal)");
    assert_eq!(e.actions, ["clear-path(sphere, goal)"]);
    let moves: Vec<Move> = e.conflicts.iter().map(|c| c.moved).collect();
    assert_eq!(moves, [Move::Up, Move::Left]);
    assert!(e.conflicts.iter().all(|c| c.precondition == "hand-empty" && c.by == "pick(cube)"), "{e}");
    assert_eq!(toks(&p.steps[5], &c), fig4("near(sphere)? hand-empty? clear-path(sphere, goal)!"));
    // Planned from the initial state again, the tree goes to the sphere first, with
    // the hand still empty: only `near(sphere)` is left to expand.
    let rest: Vec<&str> = p.expansions[5..].iter().map(|e| e.condition.as_str()).collect();
    assert_eq!(rest, ["near(sphere)"]);
    assert!(p.goal_ticks.is_some());
    let mut world = StripsWorld::new(g);
    let out = planner::strips::run((&p.nodes, &[]), c.as_ref(), &mut world, 100, (), &mut Vec::new()).unwrap();
    assert_eq!(out.status, Status::Success);
    assert!(world.holds_named("at", &["cube", "goal"]));
}

#[test]
fn example_2_at_run_time_expands_once_into_fig_4_then_reaches_the_goal() {
    let g = Arc::new(domains::cube_sphere().unwrap());
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let p = plan(g.clone(), c.clone(), Options::default()).unwrap();
    let mut planner = p.planner.clone();
    let mut world = StripsWorld::new(g.clone());
    let move_goal = action(&g, "move-to(goal)");
    let mut blocked_at = None;
    let script = BeforeTicks(|t, w: &mut StripsWorld| {
        // The sphere rolls into the path while the robot carries the cube to the goal.
        if blocked_at.is_none() && w.starts(move_goal) == 1 && w.holds_named("holding", &["cube"]) {
            w.set_named("path-free", &["goal"], false);
            blocked_at = Some(t);
        }
    });
    let out = run_blended(&mut planner, c.as_ref(), &mut world, 200, script).unwrap();
    assert_eq!(out.status, Status::Success);
    assert!(blocked_at.is_some());
    let first = &out.expansions[0].1;
    assert_eq!(first.condition, "path-free(goal)");
    assert_eq!(first.conflicts.iter().map(|c| c.moved).collect::<Vec<_>>(), [Move::Up, Move::Left]);
    let conds: Vec<&str> = out.expansions.iter().map(|e| e.1.condition.as_str()).collect();
    assert_eq!(conds, ["path-free(goal)", "near(sphere)", "hand-empty"]);
    assert!(world.holds_named("at", &["cube", "goal"]));
    assert!(world.holds_named("path-free", &["goal"]));
}

#[test]
fn example_2_first_expansion_is_exactly_fig_4() {
    let g = Arc::new(domains::cube_sphere().unwrap());
    let c = Arc::new(PddlCatalog::new(g.problem()));
    let mut planner = plan(g.clone(), c.clone(), Options::default()).unwrap().planner;
    let mut world = StripsWorld::new(g.clone());
    // Carry the cube: run until holding, then block the path and tick once.
    let out = planner::strips::run(
        (planner.nodes(), &[]),
        c.as_ref(),
        &mut world,
        100,
        BeforeTicks(|_, w: &mut StripsWorld| {
            if w.holds_named("holding", &["cube"]) {
                w.set_named("path-free", &["goal"], false);
            }
        }),
        &mut Vec::new(),
    );
    assert_eq!(out.unwrap().status, Status::Failure);
    let mut states = Vec::new();
    let again = planner::strips::run((planner.nodes(), &[]), c.as_ref(), &mut world, 1, (), &mut states).unwrap();
    assert_eq!(again.status, Status::Failure);
    let e = planner.on_failure(&states, world.state()).unwrap();
    assert_eq!(e.condition, "path-free(goal)");
    assert_eq!(toks(planner.nodes(), &c), fig4("near(sphere)? hand-empty? clear-path(sphere, goal)!"));
}

fn action(g: &planner::ground::Grounding, name: &str) -> u32 {
    (0..g.actions().len() as u32).find(|&a| g.action_name(a) == name).unwrap()
}
