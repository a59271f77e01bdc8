//! The mobile manipulator world of Colledanchise et al. 2019 Fig. 1: the cube-sphere contract, motions,
//! path-free by shape cast, and the external agents.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use bt_core::{Builder, Catalog, Context, Leaf, Node, Status, Tree};
use sim_host::physics::mobile::{Agent, CATALOG, CUBE, GOAL_OBJECT, MobileWorld, SPHERE};
use sim_host::scenario::agents::{ByTicks, Random};
use worlds::agent::TreeState;
use worlds::end::Finished;
use worlds::{Agent as _, Clock, Runner, Settings};

const AT: u16 = 0;
const HOLDING: u16 = 1;
const HAND_EMPTY: u16 = 2;
const NEAR: u16 = 3;
const PATH_FREE: u16 = 4;
const MOVE_TO: u16 = 6;
const PICK: u16 = 7;
const PLACE: u16 = 8;
const CLEAR_PATH: u16 = 10;

#[test]
fn the_catalog_follows_the_pddl_contract() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../planner/domains/cube-sphere/domain.pddl"))
            .unwrap();
    let body: String = text.lines().map(|l| l.split(';').next().unwrap_or("")).collect::<Vec<_>>().join("\n");
    let preds = body.split("(:predicates").nth(1).unwrap().split("(:action").next().unwrap();
    let mut want = Vec::new();
    for p in preds.split('(').skip(1) {
        let name = p.split_whitespace().next().unwrap().trim_end_matches(')');
        let arity = p.matches('?').count();
        want.push((name.to_string(), arity, bt_core::LeafKind::Condition));
    }
    for a in body.split("(:action").skip(1) {
        let name = a.split_whitespace().next().unwrap();
        let params = a.split(":parameters").nth(1).unwrap().split(')').next().unwrap();
        want.push((name.to_string(), params.matches('?').count(), bt_core::LeafKind::Action));
    }
    let have: Vec<_> = (0..CATALOG.len() as u16)
        .map(|i| {
            let info = CATALOG.info(i).unwrap();
            (info.name.to_string(), usize::from(info.arity), info.kind)
        })
        .collect();
    assert_eq!(have, want);
}

fn ctx(node: u16, starting: bool) -> Context<'static> {
    Context { node, now: 0, starting, values: &[] }
}

/// Runs one action leaf until it is done.
fn run(w: &mut MobileWorld, behavior: u16, args: &[u16], limit: u32) -> (Status, u32) {
    use bt_core::BehaviorSet;
    let leaf = Leaf::with_args(behavior, args).unwrap();
    let mut s = w.action(&leaf, ctx(7, true));
    let mut t = 1;
    while s == Status::Running && t < limit {
        w.step();
        s = w.action(&leaf, ctx(7, false));
        t += 1;
    }
    (s, t)
}

/// Agents act, then the world steps into its next tick.
fn step(w: &mut MobileWorld, agents: &mut ByTicks) {
    agents.act(w.tick() + 1, w, &TreeState { nodes: &[], states: &[] });
    w.step();
}

fn cond(w: &mut MobileWorld, behavior: u16, args: &[u16]) -> bool {
    use bt_core::BehaviorSet;
    w.condition(&Leaf::with_args(behavior, args).unwrap(), ctx(1, true)) == Status::Success
}

#[test]
fn move_to_reaches_pick_and_place_work() {
    let mut w = MobileWorld::new();
    assert!(!cond(&mut w, NEAR, &[CUBE]));
    assert!(cond(&mut w, PATH_FREE, &[CUBE]));
    assert_eq!(run(&mut w, MOVE_TO, &[CUBE], 60).0, Status::Success);
    assert!(cond(&mut w, NEAR, &[CUBE]));
    assert_eq!(run(&mut w, PICK, &[CUBE], 60).0, Status::Success);
    assert!(cond(&mut w, HOLDING, &[CUBE]) && !cond(&mut w, HAND_EMPTY, &[]));
    assert_eq!(run(&mut w, MOVE_TO, &[GOAL_OBJECT], 60).0, Status::Success);
    assert_eq!(run(&mut w, PLACE, &[CUBE, GOAL_OBJECT], 60).0, Status::Success);
    for _ in 0..5 {
        w.step();
    }
    assert!(cond(&mut w, AT, &[CUBE, GOAL_OBJECT]), "cube at {:?}", w.item(CUBE));
    assert!(cond(&mut w, HAND_EMPTY, &[]));
}

#[test]
fn a_sphere_in_the_path_makes_path_free_fail_and_clear_path_clears_it() {
    let mut w = MobileWorld::new();
    step(&mut w, &mut ByTicks::new(&[(1, Agent::BlockPath)]));
    assert!(w.events().iter().any(|e| e.to_string() == "tick 1: an agent rolls the sphere into the path to the goal"));
    assert!(!cond(&mut w, PATH_FREE, &[GOAL_OBJECT]), "sphere at {:?}", w.item(SPHERE));
    // Driving there anyway stops at the sphere.
    assert_eq!(run(&mut w, MOVE_TO, &[GOAL_OBJECT], 60).0, Status::Failure);
    assert_eq!(run(&mut w, MOVE_TO, &[SPHERE], 60).0, Status::Success);
    assert_eq!(run(&mut w, CLEAR_PATH, &[SPHERE, GOAL_OBJECT], 60).0, Status::Success);
    for _ in 0..5 {
        w.step();
    }
    assert!(cond(&mut w, PATH_FREE, &[GOAL_OBJECT]), "sphere at {:?}", w.item(SPHERE));
}

#[test]
fn each_scripted_agent_event_happens() {
    let mut w = MobileWorld::new();
    let mut agents = ByTicks::new(&[
        (1, Agent::HandCube),
        (3, Agent::TakeCube),
        (5, Agent::BlockPath),
        (7, Agent::UnblockPath),
        (9, Agent::CubeToGoal),
    ]);
    step(&mut w, &mut agents);
    assert_eq!(w.held(), Some(CUBE));
    step(&mut w, &mut agents);
    step(&mut w, &mut agents);
    assert_eq!(w.held(), None);
    for _ in 0..2 {
        step(&mut w, &mut agents);
    }
    assert!(!cond(&mut w, PATH_FREE, &[GOAL_OBJECT]));
    for _ in 0..2 {
        step(&mut w, &mut agents);
    }
    assert!(cond(&mut w, PATH_FREE, &[GOAL_OBJECT]));
    for _ in 0..4 {
        step(&mut w, &mut agents);
    }
    assert!(cond(&mut w, AT, &[CUBE, GOAL_OBJECT]));
    let lines: Vec<String> = w.events().iter().map(ToString::to_string).collect();
    assert_eq!(
        lines,
        [
            "tick 1: an agent puts the cube into the gripper",
            "tick 3: an agent takes the cube from the gripper",
            "tick 5: an agent rolls the sphere into the path to the goal",
            "tick 7: an agent rolls the sphere out of the way",
            "tick 9: an agent puts the cube on the goal",
        ]
    );
}

/// Fig. 3(e) of Colledanchise et al. 2019 with the conflict-resolved clear-path branch of Fig. 4, built
/// by hand: the tree copes with random agents and reaches the goal.
fn example_tree(storage: &mut [Node; 32]) -> &[Node] {
    let mut b = Builder::<8>::new(storage);
    b.fallback().unwrap();
    b.condition(AT, &[CUBE, GOAL_OBJECT]).unwrap();
    b.sequence().unwrap();
    // path to the goal free, else clear it (hand empty first)
    b.fallback().unwrap();
    b.condition(PATH_FREE, &[GOAL_OBJECT]).unwrap();
    b.sequence().unwrap();
    b.fallback().unwrap().condition(HAND_EMPTY, &[]).unwrap().action(9, &[CUBE]).unwrap().end().unwrap();
    b.fallback().unwrap().condition(NEAR, &[SPHERE]).unwrap().action(MOVE_TO, &[SPHERE]).unwrap().end().unwrap();
    b.action(CLEAR_PATH, &[SPHERE, GOAL_OBJECT]).unwrap();
    b.end().unwrap().end().unwrap();
    // holding the cube
    b.fallback().unwrap();
    b.condition(HOLDING, &[CUBE]).unwrap();
    b.sequence().unwrap();
    b.fallback().unwrap().condition(NEAR, &[CUBE]).unwrap().action(MOVE_TO, &[CUBE]).unwrap().end().unwrap();
    b.condition(HAND_EMPTY, &[]).unwrap();
    b.action(PICK, &[CUBE]).unwrap();
    b.end().unwrap().end().unwrap();
    // near the goal
    b.fallback()
        .unwrap()
        .condition(NEAR, &[GOAL_OBJECT])
        .unwrap()
        .action(MOVE_TO, &[GOAL_OBJECT])
        .unwrap()
        .end()
        .unwrap();
    b.action(PLACE, &[CUBE, GOAL_OBJECT]).unwrap();
    b.end().unwrap().end().unwrap();
    b.finish().unwrap()
}

/// The example tree in `w` with `agents`, until the root is done or 400 ticks (tick k
/// at `now` k - 1).
fn episode(mut w: MobileWorld, mut agents: impl worlds::Agent<MobileWorld>) -> (Status, MobileWorld, u32) {
    let mut storage = [Node::EMPTY; 32];
    let nodes = example_tree(&mut storage).to_vec();
    let tree: Tree<'_, 8> = Tree::validate(&nodes, &CATALOG).unwrap();
    let settings = Settings { moves_on_at_stop: false, ..Settings::new(400, Clock { ms_per_tick: 1, first: 0 }) };
    let out = Runner::new(settings).run(tree, &mut w, &mut Finished, &mut agents, &mut ()).unwrap();
    (out.root, w, out.ticks)
}

#[test]
fn the_example_tree_copes_with_agents_that_undo_and_block() {
    let agents = ByTicks::new(&[(12, Agent::BlockPath), (20, Agent::TakeCube), (60, Agent::UnblockPath)]);
    let (s, w, t) = episode(MobileWorld::new(), agents);
    assert_eq!(s, Status::Success, "after {t} ticks: {:?}", w.events());
    assert!(w.events().len() >= 3);
}

#[test]
fn random_agents_are_deterministic_per_seed() {
    let trace = |seed| {
        let (s, w, t) = episode(MobileWorld::new(), Random::new(seed, 0.05));
        (s, t, w.events().to_vec(), w.base().map(f32::to_bits), w.item(CUBE).map(|p| p.map(f32::to_bits)))
    };
    assert_eq!(trace(7), trace(7));
    assert_ne!(trace(7).2, trace(8).2);
}
