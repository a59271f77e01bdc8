//! The scenario end to end on the host: the goal is reached, and every scripted event
//! happened and was handled by the tree's reactivity alone.

use std::string::String;
use std::vec::Vec;

use bt_core::{Leaf, NodeKind, Status};

use crate::catalog::{CLEAR_PATH, CUBE, DROP, GOAL, MOVE_TO, PICK, PLACE, SPHERE};
use crate::plant::Hand;
use crate::script::{Event, SCRIPT};
use crate::{CORRUPT_IMAGE, IMAGE, Outcome, Sink, run};

#[derive(Default)]
struct Lines(Vec<String>);

impl Sink for Lines {
    fn line(&mut self, line: &[u8]) {
        self.0.push(String::from_utf8(line.to_vec()).unwrap());
    }
}

/// One tick as the tests see it: the actions ticked with their results, the actions
/// halted, the event, and a copy of the plant.
struct Tick {
    n: u32,
    status: Status,
    actions: Vec<(Leaf, Status)>,
    halted: Vec<Leaf>,
    event: Option<Event>,
    hand: Hand,
    path_free_goal: bool,
}

fn leaf_of(kind: &NodeKind) -> Option<Leaf> {
    match kind {
        NodeKind::Action(l) | NodeKind::Condition(l) => Some(*l),
        _ => None,
    }
}

fn scenario() -> (Outcome, Vec<Tick>, Vec<String>) {
    let mut lines = Lines::default();
    let mut ticks = Vec::new();
    let outcome = run(IMAGE, &mut lines, |r| {
        let actions = r
            .ran
            .iter()
            .filter_map(|ran| {
                let node = r.nodes.get(usize::from(ran.node))?;
                matches!(node.kind(), NodeKind::Action(_)).then(|| (leaf_of(node.kind()).unwrap(), ran.status))
            })
            .collect();
        let halted = r.halted.iter().filter_map(|&id| r.nodes.get(usize::from(id)).and_then(|n| leaf_of(n.kind())));
        ticks.push(Tick {
            n: r.tick,
            status: r.status,
            actions,
            halted: halted.collect(),
            event: r.event.and_then(|(e, applied)| applied.is_ok().then_some(e)),
            hand: r.plant.hand,
            path_free_goal: r.plant.path_free(GOAL),
        });
    });
    (outcome, ticks, lines.0)
}

fn is(leaf: &Leaf, behavior: u16, arg0: u16) -> bool {
    leaf.behavior() == behavior && leaf.arg(0) == Some(arg0)
}

/// Ticks in `from..to` that ticked the action `behavior(arg0)` with result `status`.
fn ran(ticks: &[Tick], from: u32, to: u32, behavior: u16, arg0: u16, status: Option<Status>) -> Vec<u32> {
    ticks
        .iter()
        .filter(|t| t.n >= from && t.n < to)
        .filter(|t| t.actions.iter().any(|(l, s)| is(l, behavior, arg0) && status.is_none_or(|st| *s == st)))
        .map(|t| t.n)
        .collect()
}

fn event_tick(nth: usize) -> u32 {
    SCRIPT[nth].0
}

#[test]
fn the_run_reaches_the_goal_with_every_event_applied() {
    let (outcome, ticks, lines) = scenario();
    let last = ticks.last().unwrap();
    assert_eq!(outcome, Outcome::Goal { ticks: last.n + 1 });
    assert_eq!(last.status, Status::Success);
    let applied: Vec<Event> = ticks.iter().filter_map(|t| t.event).collect();
    let scripted: Vec<Event> = SCRIPT.iter().map(|&(_, e)| e).collect();
    assert_eq!(applied, scripted, "every scripted event happened, in order");
    assert!(lines.last().unwrap().starts_with("done GOAL "), "{:?}", lines.last());
    let place = ran(&ticks, 0, u32::MAX, PLACE, CUBE, Some(Status::Success));
    assert_eq!(place, [last.n], "placed once, on the last tick");
}

#[test]
fn the_helped_pick_is_skipped() {
    let (_, ticks, _) = scenario();
    let (help, slip) = (event_tick(0), event_tick(1));
    assert_eq!(SCRIPT[0].1, Event::Help);
    assert!(!ran(&ticks, 0, help, MOVE_TO, CUBE, None).is_empty(), "the robot was on its way to the cube");
    let after = &ticks[help as usize];
    assert!(after.halted.iter().any(|l| is(l, MOVE_TO, CUBE)), "move-to(cube) halted when the cube arrived");
    assert!(after.actions.iter().any(|(l, s)| is(l, MOVE_TO, GOAL) && *s == Status::Running));
    assert!(ran(&ticks, help, slip, PICK, CUBE, None).is_empty(), "no pick while the agent's cube is in the hand");
    assert!(ran(&ticks, help, slip, MOVE_TO, CUBE, None).is_empty());
}

#[test]
fn the_slipped_cube_is_fetched_and_picked_again() {
    let (_, ticks, _) = scenario();
    let (slip, block) = (event_tick(1), event_tick(2));
    assert_eq!(SCRIPT[1].1, Event::Slip);
    assert_eq!(ticks[slip as usize - 1].hand, Hand::Cube);
    let after = &ticks[slip as usize];
    assert!(after.halted.iter().any(|l| is(l, MOVE_TO, GOAL)), "the trip to the goal is interrupted");
    // move-to is halted by its own postcondition: near(cube) succeeds and the Fallback
    // moves on to pick.
    let drove = ran(&ticks, slip, block, MOVE_TO, CUBE, Some(Status::Running));
    assert!(!drove.is_empty(), "drove back to the cube");
    let picked = ran(&ticks, slip, block, PICK, CUBE, Some(Status::Success));
    assert_eq!(picked.len(), 1, "picked again once");
    assert_eq!(ticks[picked[0] as usize].hand, Hand::Cube);
    assert!(drove.last() < picked.first());
    assert!(!ran(&ticks, picked[0], block, MOVE_TO, GOAL, None).is_empty(), "and on to the goal");
}

#[test]
fn the_blocking_sphere_is_cleared_after_dropping_the_cube() {
    let (_, ticks, _) = scenario();
    let (block, again) = (event_tick(2), event_tick(3));
    assert_eq!(SCRIPT[2].1, Event::Block);
    assert!(!ticks[block as usize].path_free_goal);
    assert!(ticks[block as usize].halted.iter().any(|l| is(l, MOVE_TO, GOAL)));
    let reached = ran(&ticks, block, again, MOVE_TO, SPHERE, Some(Status::Running));
    let dropped = ran(&ticks, block, again, DROP, CUBE, Some(Status::Success));
    let cleared = ran(&ticks, block, again, CLEAR_PATH, SPHERE, Some(Status::Success));
    let repicked = ran(&ticks, block, again, PICK, CUBE, Some(Status::Success));
    assert!(!reached.is_empty(), "drove to the sphere");
    assert_eq!((dropped.len(), cleared.len(), repicked.len()), (1, 1, 1));
    assert!(
        reached[reached.len() - 1] < dropped[0] && dropped[0] < cleared[0] && cleared[0] < repicked[0],
        "Example 2's order"
    );
    assert!(ticks[cleared[0] as usize].path_free_goal);
    let clear_leaf = ticks[cleared[0] as usize].actions.iter().find(|(l, _)| l.behavior() == CLEAR_PATH).unwrap();
    assert_eq!(clear_leaf.0.args(), [SPHERE, GOAL]);
}

#[test]
fn the_sphere_moved_away_by_an_agent_is_ignored() {
    let (_, ticks, _) = scenario();
    let (block, away) = (event_tick(3), event_tick(4));
    assert_eq!((SCRIPT[3].1, SCRIPT[4].1), (Event::Block, Event::Unblock));
    assert!(!ran(&ticks, block, away, MOVE_TO, SPHERE, Some(Status::Running)).is_empty(), "heading for the sphere");
    assert!(ticks[away as usize].path_free_goal);
    assert!(ticks[away as usize].halted.iter().any(|l| is(l, MOVE_TO, SPHERE)), "the sphere's branch is abandoned");
    let end = ticks.len() as u32;
    for behavior in [DROP, CLEAR_PATH] {
        assert!(ran(&ticks, block, end, behavior, if behavior == DROP { CUBE } else { SPHERE }, None).is_empty());
    }
    assert!(ticks[block as usize..].iter().all(|t| t.hand == Hand::Cube || t.n == end - 1), "the cube stays in hand");
}

#[test]
fn the_trace_is_one_line_per_tick_and_reproducible() {
    let (_, ticks, lines) = scenario();
    let tick_lines = lines.iter().filter(|l| l.starts_with("tick ")).count();
    assert_eq!(tick_lines, ticks.len());
    assert!(lines.iter().all(|l| !l.ends_with('~')), "no line was cut");
    assert!(lines[0].starts_with("boot image="), "{}", lines[0]);
    assert_eq!(lines.iter().filter(|l| l.starts_with("event ")).count(), SCRIPT.len());
    let (_, _, again) = scenario();
    assert_eq!(lines, again);
}

#[test]
fn a_corrupted_image_is_refused_before_any_tick() {
    let mut lines = Lines::default();
    let mut ticked = false;
    let outcome = run(CORRUPT_IMAGE, &mut lines, |_| ticked = true);
    assert!(matches!(outcome, Outcome::Load(bt_core::LoadError::CrcMismatch { .. })), "{outcome:?}");
    assert!(!ticked);
    assert!(lines.0[0].starts_with("load error: crc-mismatch stored="), "{:?}", lines.0);
    assert!(lines.0.iter().all(|l| !l.starts_with("tick ")));
}

#[test]
fn the_image_matches_the_catalog_and_fits_the_controller() {
    let header = bt_core::image::read_header(IMAGE).unwrap();
    assert_eq!(header.fingerprint, crate::catalog::FINGERPRINT);
    assert!(usize::from(header.node_count) <= crate::MAX_NODES);
}

#[test]
fn a_line_too_long_is_cut_and_marked() {
    let mut line = crate::Line::new();
    let long = "x".repeat(crate::control::LINE_CAP + 10);
    let out = line.text("tick ").num(1).text(" ").text(&long).finish();
    assert_eq!(out.len(), crate::control::LINE_CAP);
    assert!(out.starts_with(b"tick 1 xx") && out.ends_with(b"x~"));
    let mut sent = Vec::new();
    line.send(&mut |l: &[u8]| sent.push(l.to_vec()));
    line.text("tick ").num(2).send(&mut |l: &[u8]| sent.push(l.to_vec()));
    assert_eq!(sent[1], b"tick 2", "the buffer starts over");
}

#[test]
fn numbers_are_written_as_core_fmt_would() {
    let mut line = crate::Line::new();
    for v in [0u32, 7, 10, 999, 1000, 65_535, u32::MAX] {
        assert_eq!(line.num(v).finish(), v.to_string().as_bytes());
        line.send(&mut |_: &[u8]| {});
    }
    for v in [0i32, -1, 42, -1000, i32::MIN, i32::MAX] {
        assert_eq!(line.int(v).finish(), v.to_string().as_bytes());
        line.send(&mut |_: &[u8]| {});
    }
    for (v, w) in [(0u64, 8), (0xdead_beef, 8), (0x1f, 8), (u64::MAX, 16), (0x2a, 16), (0x1_0000_0000, 1)] {
        assert_eq!(line.hex(v, w).finish(), format!("{v:0w$x}").as_bytes());
        line.send(&mut |_: &[u8]| {});
    }
}

#[test]
fn a_tree_with_a_kind_this_build_leaves_out_is_refused_at_load() {
    // bt-core is built without its `btcpp` feature here: an `IfThenElse` tree is a
    // valid image, but this controller does not carry that kind's code.
    use bt_core::{LoadError, Node};
    // Otherwise valid for this behavior set: hand-empty ? drop(cube).
    let cond = Leaf::with_args(crate::catalog::HAND_EMPTY, &[]).unwrap();
    let act = Leaf::with_args(DROP, &[CUBE]).unwrap();
    let nodes = [
        Node::new(NodeKind::IfThenElse, 3),
        Node::new(NodeKind::Condition(cond), 1),
        Node::new(NodeKind::Action(act), 1),
    ];
    let mut storage = [Node::EMPTY; 4];
    let mut image = [0u8; 128];
    // The same tree with a Sequence loads.
    let mut seq = nodes;
    seq[0] = Node::new(NodeKind::SequenceWithMemory, 3);
    let len = bt_core::encode(&seq, crate::catalog::FINGERPRINT, &mut image).unwrap();
    assert!(bt_core::load::<_, 4>(&image[..len], &crate::catalog::BEHAVIORS, &mut storage).is_ok());
    let len = bt_core::encode(&nodes, crate::catalog::FINGERPRINT, &mut image).unwrap();
    let err = bt_core::load::<_, 4>(&image[..len], &crate::catalog::BEHAVIORS, &mut storage).unwrap_err();
    // Refused as it decodes, without the kind's name (which would cost flash).
    assert!(matches!(err, LoadError::UnsupportedKind { node: 0, kind: "BehaviorTree.CPP or Nav2 kind" }), "{err:?}");
    assert_eq!(err.code(), "unsupported-kind");
    assert_eq!(
        err.to_string(),
        "node 0 is a BehaviorTree.CPP or Nav2 kind, which this build does not run (bt-core without the `btcpp` feature)"
    );
    // Validating the nodes in memory refuses it too, and names the node.
    let nested = [
        Node::new(NodeKind::Sequence, 4),
        Node::new(NodeKind::RunOnce { then_skip: false }, 2),
        Node::new(NodeKind::Action(act), 1),
        Node::new(NodeKind::Condition(cond), 1),
    ];
    let err = bt_core::Tree::<4>::validate(&nested, &crate::catalog::BEHAVIORS).unwrap_err();
    assert!(matches!(err, LoadError::UnsupportedKind { node: 1, .. }), "{err:?}");
    let mut lines = Lines::default();
    let outcome = run(&image[..len], &mut lines, |_| {});
    assert!(matches!(outcome, Outcome::Load(LoadError::UnsupportedKind { node: 0, .. })), "{outcome:?}");
    assert!(lines.0.iter().any(|l| l == "load error: unsupported-kind node=0"), "{:?}", lines.0);
}

#[test]
fn a_leaf_that_returns_skipped_is_a_tick_error_in_this_build() {
    // Without the `btcpp` feature the tick loop has no Skipped paths: a behavior that
    // returns Skipped stops the tick with an error naming the leaf.
    use bt_core::{BehaviorSet, Context, Executor, NodeState, TickError, Tree};
    struct Skips;
    impl BehaviorSet for Skips {
        fn condition(&mut self, _: &Leaf, _: Context<'_>) -> Status {
            Status::Success
        }
        fn action(&mut self, _: &Leaf, _: Context<'_>) -> Status {
            Status::Skipped
        }
        fn halt(&mut self, _: &Leaf, _: bt_core::NodeId) {}
    }
    let cond = Leaf::with_args(crate::catalog::HAND_EMPTY, &[]).unwrap();
    let act = Leaf::with_args(DROP, &[CUBE]).unwrap();
    // The action as the root, under a Sequence (ticked in place) and under a decorator.
    let trees: [&[bt_core::Node]; 3] = [
        &[bt_core::Node::new(NodeKind::Action(act), 1)],
        &[
            bt_core::Node::new(NodeKind::Sequence, 3),
            bt_core::Node::new(NodeKind::Condition(cond), 1),
            bt_core::Node::new(NodeKind::Action(act), 1),
        ],
        &[bt_core::Node::new(NodeKind::Inverter, 2), bt_core::Node::new(NodeKind::Action(act), 1)],
    ];
    for nodes in trees {
        let tree = Tree::<4>::validate(nodes, &crate::catalog::BEHAVIORS).unwrap();
        let mut state = [NodeState::IDLE; 4];
        let mut exec = Executor::new(tree, &mut state).unwrap();
        let leaf = nodes.len() as u16 - 1;
        let err = exec.tick(&mut Skips, 0).unwrap_err();
        assert_eq!(err, TickError::LeafSkipped { node: leaf, behavior: DROP }, "{nodes:?}");
        assert_eq!(err.code(), "leaf-skipped");
        // The tree is halted and Idle again after the error.
        assert!(exec.states().iter().all(|s| s.status() == bt_core::NodeStatus::Idle));
    }
}
