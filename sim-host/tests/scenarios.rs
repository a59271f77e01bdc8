//! The papers' scenarios: the blended demo reaches the goal through the expansions of
//! Examples 1-2 and copes with agents without replanning; every scenario runs in each
//! world it offers, deterministically; the `scenario` command's errors.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::process::Output;

use bt_core::Status;
use planner::duplo::Task;
use sim_host::scenario::{self, Scenario, is_external};
use worlds::WorldKind;

mod cli_common;
use cli_common::sim_host;

fn expanded(run: &scenario::Run) -> Vec<String> {
    run.record.expansions.iter().map(|(_, e)| e.condition.clone()).collect()
}

#[test]
fn the_blended_demo_follows_examples_1_and_2_in_both_worlds() {
    for world in [WorldKind::Physics, WorldKind::Symbolic] {
        let run = scenario::run(Scenario::Cube, world, None).unwrap();
        assert_eq!(run.record.status, Some(Status::Success), "{world:?}\n{}", run.narration);
        // Fig. 3 (b)-(e), then Example 2: the blocked path, its conflict, and the
        // preconditions of clearing it.
        assert_eq!(
            expanded(&run),
            [
                "at(cube, goal)",
                "holding(cube)",
                "near(cube)",
                "near(goal)",
                "path-free(goal)",
                "near(sphere)",
                "hand-empty"
            ],
            "{world:?}"
        );
        let (_, blocked) = &run.record.expansions[4];
        assert!(!blocked.conflicts.is_empty(), "the clearing subtree conflicts with pick(cube)");
        assert!(run.narration.contains("IncreasePriority moves the new subtree up a level"));
        // Fig. 4: the clearing subtree now runs first in the sequence under the root.
        let end = run.record.snapshots.last().unwrap();
        let tokens = |i: usize| {
            scenario::driver::leaf_name(
                run.catalog.as_ref(),
                match end.nodes[i].kind() {
                    bt_core::NodeKind::Condition(l) | bt_core::NodeKind::Action(l) => l,
                    _ => panic!("not a leaf"),
                },
            )
        };
        assert_eq!(tokens(1), "at(cube, goal)");
        assert_eq!(tokens(4), "path-free(goal)", "the clearing subtree comes first");
        // The story after the last expansion: help, undo, block and unblock, all
        // handled by the tree as it was.
        let last = run.record.expansions.last().unwrap().0;
        let later: Vec<&String> =
            run.record.events.iter().filter(|(t, e)| *t > last && is_external(e)).map(|(_, e)| e).collect();
        assert_eq!(
            later,
            [
                "an agent puts the cube into the gripper",
                "an agent takes the cube from the gripper",
                "an agent rolls the sphere into the path to the goal",
                "an agent rolls the sphere out of the way"
            ],
            "{world:?}\n{}",
            run.narration
        );
    }
}

#[test]
fn the_cube_scenario_shows_fig_4_after_the_blocked_path_is_expanded() {
    // Fig. 4 of Colledanchise et al. 2019 is a run-time expansion: Fig. 3(e) with the cube in the hand
    // when the sphere blocks the path. The narration prints the tree after each
    // expansion; after the fifth it is Fig. 4 (pinned against the paper's notation in
    // planner/tests/shipped_trees.rs).
    let fig_4 = "f( at(cube, goal)? s( f( path-free(goal)? s( near(sphere)? hand-empty? clear-path(sphere, goal)! ) ) \
                 f( holding(cube)? s( f( near(cube)? s( path-free(cube)? move-to(cube)! ) ) hand-empty? pick(cube)! ) ) \
                 f( near(goal)? s( path-free(goal)? move-to(goal)! ) ) place(cube, goal)! ) )";
    for world in [WorldKind::Physics, WorldKind::Symbolic] {
        let run = scenario::run(Scenario::Cube, world, None).unwrap();
        let after_5 = &run.record.snapshots[5].nodes;
        assert_eq!(bt_formats::tokens::to_string(after_5, run.catalog.as_ref()).unwrap(), fig_4, "{world:?}");
        let at = run.narration.find("expansion 5: `path-free(goal)`").unwrap();
        assert!(run.narration[at..].contains("the tree now (25 nodes):"), "{world:?}");
    }
}

#[test]
fn scenarios_are_deterministic() {
    for (world, seed) in [(WorldKind::Physics, None), (WorldKind::Physics, Some(3)), (WorldKind::Symbolic, Some(3))] {
        let a = scenario::run(Scenario::Cube, world, seed).unwrap();
        let b = scenario::run(Scenario::Cube, world, seed).unwrap();
        assert_eq!(a.narration, b.narration);
        let bits = |r: &scenario::Run| -> Vec<u32> {
            r.record.frames.iter().flat_map(|(_, p)| p.iter().flat_map(|(_, q)| q.map(f32::to_bits))).collect()
        };
        assert_eq!(bits(&a), bits(&b));
    }
    let a = scenario::run(Scenario::Cube, WorldKind::Physics, Some(3)).unwrap();
    let b = scenario::run(Scenario::Cube, WorldKind::Physics, Some(4)).unwrap();
    assert_ne!(a.narration, b.narration, "another seed, other agents");
}

#[test]
fn the_cellphone_is_assembled_through_a_slip_and_a_help() {
    let run = scenario::run(Scenario::Cellphone, WorldKind::Symbolic, None).unwrap();
    assert_eq!(run.record.status, Some(Status::Success), "{}", run.narration);
    let events: Vec<&str> = run.record.events.iter().map(|(_, e)| e.as_str()).collect();
    assert_eq!(
        events,
        ["the board slips out of the right gripper back onto the table", "a co-worker mounts the camera on the board"]
    );
    // The slipped board is picked again by the tree as it was: no expansion between the
    // slip and the board's mount.
    let slip = run.record.events[0].0;
    assert!(run.record.expansions.iter().all(|(t, e)| *t <= slip || !e.condition.contains("board")));
    assert!(run.narration.contains("hand-over(left, right, chassis) succeeds"), "a regrasp by hand-over");
    assert!(scenario::run(Scenario::Cellphone, WorldKind::Physics, None).is_err());
}

#[test]
fn the_brick_scenarios_show_the_planners_tree_as_the_paper_reports() {
    for task in Task::ALL {
        for world in [WorldKind::Symbolic, WorldKind::Physics] {
            let run = scenario::run(Scenario::Bricks(task), world, None).unwrap();
            let solved = run.record.status == Some(Status::Success);
            assert_eq!(solved, task == Task::Tower, "{task:?} {world:?}\n{}", run.narration);
        }
    }
}

fn one_line_error(out: &Output, parts: &[&str]) {
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    for p in parts {
        assert!(err.contains(p), "{err} lacks {p}");
    }
}

#[test]
fn the_command_line() {
    let out = sim_host(&["scenario", "--list"]);
    assert!(out.status.success());
    let list = String::from_utf8(out.stdout).unwrap();
    for s in Scenario::ALL {
        assert!(list.contains(s.name()), "{list}");
    }
    one_line_error(&sim_host(&["scenario", "kitchen"]), &["unknown scenario `kitchen`", "cube, cellphone, tower"]);
    one_line_error(&sim_host(&["scenario", "cellphone", "--world", "physics"]), &["no physics world"]);
    one_line_error(&sim_host(&["scenario", "tower", "--seed", "1"]), &["--seed applies to the cube scenario"]);

    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("cube.svg");
    let out = sim_host(&["scenario", "cube", "--svg", svg.to_str().unwrap()]);
    assert!(out.status.success());
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.contains("goal region") && text.contains("expansion 5"));
    let nowhere = dir.path().join("missing").join("cube.svg");
    let out = sim_host(&["scenario", "cube", "--svg", nowhere.to_str().unwrap()]);
    one_line_error(&out, &["missing"]);
    assert!(out.stdout.is_empty(), "nothing is narrated as if all went well");

    // The demo: no arguments.
    let out = sim_host(&[]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("the root succeeds: the goal holds"), "{text}");
}

/// The cube scenario with random agents in the physics world, seed by seed.
fn random_cube(seed: u64) -> scenario::Run {
    scenario::run(Scenario::Cube, WorldKind::Physics, Some(seed)).unwrap_or_else(|e| panic!("seed {seed}: {e:#}"))
}

#[test]
fn random_agents_that_hand_over_the_cube_early_do_not_stop_the_robot() {
    // Seeds 27, 36 and 124 hand the cube over before the robot has driven anywhere; the
    // drive from the start to the goal (51 ticks) outlasted the flat 50-tick action
    // limit, move-to failed and no condition was left to expand (exit 2, no narration).
    // Seed 27 also reads in the singular where it counts one.
    let narration = random_cube(27).narration;
    assert!(narration.contains("the tree at the start (1 node):"), "{narration}");
    assert!(narration.contains("after 60 ticks, 2 expansions, 1 external event, 2 actions halted"), "{narration}");
    for seed in [27, 36, 124] {
        let run = random_cube(seed);
        assert_eq!(run.record.status, Some(Status::Success), "seed {seed}\n{}", run.narration);
        assert!(!run.narration.contains("move-to(goal) fails"), "seed {seed}\n{}", run.narration);
    }
    // Seed 167: an agent handed the cube over while the robot reached for it; the robot
    // grasped it a second time, one grasp outlived every release, and the robot placed
    // and picked up the floating cube until the tick budget ran out.
    let run = random_cube(167);
    assert_eq!(run.record.status, Some(Status::Success), "{}", run.narration);
}

#[test]
fn a_thousand_random_agent_seeds_reach_the_goal() {
    // Seeds 0-999: about 15 s in a debug build on one core (the physics crates are
    // optimised even there). Before the fixes above, seeds 27, 36 and 124 stopped with
    // an error; with the time limit fixed alone, 11 of these 1000 ran out of ticks. `sim-host scenario cube --world physics --seed N` runs one.
    let failed: Vec<String> = (0..1000u64)
        .filter_map(|seed| match scenario::run(Scenario::Cube, WorldKind::Physics, Some(seed)) {
            Ok(run) if run.record.status == Some(Status::Success) => None,
            Ok(run) => Some(format!("seed {seed}: {:?} after {} ticks", run.record.status, run.record.ticks)),
            Err(e) => Some(format!("seed {seed}: {e:#}")),
        })
        .collect();
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn an_unreachable_goal_is_refused_before_the_first_tick() {
    // `obstacle` is static: no action achieves it. Grounding refuses the goal before any
    // tick (it used to start, and the run stopped at tick 1 naming that tick).
    let domain = planner::pddl::parse_domain("d", planner::domains::CUBE_SPHERE_DOMAIN).unwrap();
    let text =
        planner::domains::CUBE_SPHERE_PROBLEM.replace("(:goal (and (at cube goal)))", "(:goal (and (obstacle cube)))");
    assert_ne!(text, planner::domains::CUBE_SPHERE_PROBLEM);
    let problem = planner::pddl::parse_problem("p", &text, &domain).unwrap();
    let Err(e) = planner::ground::Grounding::new(&problem) else { panic!("an unreachable goal was grounded") };
    assert!(e.to_string().contains("`obstacle(cube)`"), "{e}");
}

/// The labels of the top view: (x, baseline y, text) of the bold mark numbers and the goal
/// region's label.
fn top_view_labels(svg: &str) -> Vec<(f32, f32, String)> {
    let attr = |tag: &str, name: &str| -> f32 {
        let from = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        tag[from..from + tag[from..].find('"').unwrap()].parse().unwrap()
    };
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let (tag, rest) = t.split_once('>')?;
            let text = rest.split_once("</text>")?.0.to_string();
            let mark =
                tag.contains("font-weight=\"bold\"") && text.chars().all(|c| c.is_ascii_digit() || ", ".contains(c));
            (mark || text == "goal region").then(|| (attr(tag, "x"), attr(tag, "y"), text))
        })
        .collect()
}

#[test]
fn the_top_views_labels_do_not_overlap() {
    // Events and expansions where the robot stood still were drawn on one spot, their
    // numbers over each other and over the goal region's label.
    for seed in [None, Some(7), Some(27)] {
        let run = scenario::run(Scenario::Cube, WorldKind::Physics, seed).unwrap();
        let svg = sim_host::picture::scenario::svg(&run, "test");
        let labels = top_view_labels(&svg);
        assert!(labels.iter().any(|l| l.2 == "goal region"), "{seed:?}");
        let marks: usize = labels.iter().filter(|l| l.2 != "goal region").map(|l| l.2.split(", ").count()).sum();
        assert_eq!(marks, run.record.events.len() + run.record.expansions.len(), "{seed:?}: every mark numbered");
        // Boxes: each label from its start and baseline, each ring around its centre.
        let width = |t: &str| if t == "goal region" { 70.0 } else { 7.0 * t.len() as f32 };
        let mut boxes: Vec<([f32; 4], String)> =
            labels.iter().map(|(x, y, t)| ([*x, y - 10.0, x + width(t), y + 2.0], format!("label {t}"))).collect();
        for ring in svg.split("<circle").skip(1).filter(|c| c.contains(" r=\"7\"")) {
            let num = |name: &str| -> f32 {
                let from = ring.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
                ring[from..from + ring[from..].find('"').unwrap()].parse().unwrap()
            };
            let (x, y) = (num("cx"), num("cy"));
            boxes.push(([x - 7.0, y - 7.0, x + 7.0, y + 7.0], format!("ring at {x},{y}")));
        }
        for (i, (a, an)) in boxes.iter().enumerate() {
            for (b, bn) in boxes.iter().skip(i + 1) {
                let rings = an.starts_with("ring") && bn.starts_with("ring");
                let overlap = a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3];
                assert!(rings || !overlap, "{seed:?}: {an} and {bn} overlap");
            }
        }
    }
}
