//! Episode ending rules and fitness terms on hand-computed cases, with a scripted world.
#![allow(clippy::unwrap_used, clippy::float_cmp)]

use super::*;
use bt_core::{BehaviorSet, Context, Leaf, NodeId, NodeKind};
use planner::duplo::Spec;
use worlds::World;

use Status::{Failure, Running, Success};

/// A world whose one action returns a script, tick by tick, and whose bricks sit where
/// the test puts them.
struct Scripted {
    spec: Spec,
    script: Vec<Status>,
    tick: usize,
    positions: Vec<[f32; 3]>,
    held: Option<u8>,
    resets: usize,
}

impl Scripted {
    fn new(task: Task, script: &[Status]) -> Self {
        let spec = task.spec();
        let positions = spec.goal.iter().map(|g| g.unwrap_or([0.0; 3])).collect();
        Self { spec, script: script.to_vec(), tick: 0, positions, held: None, resets: 0 }
    }
}

impl BehaviorSet for Scripted {
    fn condition(&mut self, _: &Leaf, _: Context<'_>) -> Status {
        Failure
    }
    fn action(&mut self, _: &Leaf, _: Context<'_>) -> Status {
        self.script.get(self.tick).copied().unwrap_or(Running)
    }
    fn halt(&mut self, _: &Leaf, _: NodeId) {}
}

impl World for Scripted {
    fn reset(&mut self) {
        self.tick = 0;
        self.resets += 1;
    }
    fn step(&mut self) {
        self.tick += 1;
    }
}

impl BrickWorld for Scripted {
    fn spec(&self) -> &Spec {
        &self.spec
    }
    fn position(&self, brick: usize) -> [f32; 3] {
        self.positions[brick]
    }
    fn held(&self) -> Option<u8> {
        self.held
    }
    fn tick_limit(&self) -> u32 {
        10
    }
}

/// A tree of one action (its status is the script's) under `wrappers` Sequences.
fn nodes(wrappers: u16) -> Vec<Node> {
    let action = Node::new(NodeKind::Action(Leaf::new(12)), 1);
    let mut v: Vec<Node> = (0..wrappers).map(|k| Node::new(NodeKind::Sequence, wrappers - k + 1)).collect();
    v.push(action);
    v
}

fn run(world: Scripted, wrappers: u16) -> Episode {
    Runner::new(world).unwrap().run_nodes(&nodes(wrappers)).unwrap()
}

#[test]
fn the_first_root_failure_ends_the_episode_and_costs_phi() {
    let e = run(Scripted::new(Task::Tower, &[Running, Success, Failure, Success]), 0);
    assert_eq!((e.end, e.ticks, e.timed_out), (End::Failure, 3, false));
    assert_eq!(e.fitness.failure, 50.0);
    assert_eq!(e.fitness.timeout, 0.0);
}

#[test]
fn success_on_two_consecutive_ticks_ends_the_episode() {
    let e = run(Scripted::new(Task::Tower, &[Success, Running, Success, Success, Failure]), 0);
    assert_eq!((e.end, e.ticks, e.timed_out), (End::Success, 4, false));
    assert_eq!(e.fitness.cost(), 0.1, "only the length: the bricks sit on their goals");
}

#[test]
fn running_to_the_limit_is_a_timeout_and_costs_tau() {
    let e = run(Scripted::new(Task::Tower, &[Success, Running].repeat(10)), 0);
    assert_eq!((e.end, e.ticks, e.timed_out), (End::Timeout, 10, true));
    assert_eq!(e.fitness.timeout, 10.0);
    assert_eq!(e.fitness.failure, 0.0);
}

#[test]
fn the_last_tick_counts_for_the_timeout_whatever_it_returned() {
    let mut script = [Running; 10];
    script[9] = Failure;
    let e = run(Scripted::new(Task::Tower, &script), 0);
    assert_eq!((e.end, e.ticks, e.timed_out), (End::Failure, 10, true));
    assert_eq!((e.fitness.failure, e.fitness.timeout), (50.0, 10.0));
    script[8] = Success;
    script[9] = Success;
    let e = run(Scripted::new(Task::Tower, &script), 0);
    assert_eq!((e.end, e.ticks, e.timed_out), (End::Success, 10, true));
    assert_eq!((e.fitness.failure, e.fitness.timeout), (0.0, 10.0));
}

#[test]
fn length_is_lambda_per_node_control_nodes_included() {
    let e = run(Scripted::new(Task::Tower, &[Success, Success]), 4);
    assert_eq!(e.nodes, 5);
    assert_eq!(e.fitness.length, 0.1 * 5.0);
    assert_eq!(e.fitness.value(), -0.5);
}

#[test]
fn distance_costs_1000_per_metre_beyond_delta() {
    let mut w = Scripted::new(Task::Tower, &[Success, Success]);
    // Brick 0: 0.3 mm off (within δ = 0.4 mm): free. Brick 1: 3 mm off in z: 2.6.
    // Brick 2: 3 mm and 4 mm off in x and y, 5 mm in all: 4.6.
    w.positions[0][1] += 0.0003;
    w.positions[1][2] += 0.003;
    w.positions[2][0] += 0.003;
    w.positions[2][1] -= 0.004;
    let e = run(w, 0);
    let d = e.fitness.distance;
    assert_eq!(d[0], 0.0);
    assert!((d[1] - 2.6).abs() < 1e-4, "{d:?}");
    assert!((d[2] - 4.6).abs() < 1e-4, "{d:?}");
    assert_eq!(d[3], 0.0, "no brick 3");
    assert!((e.fitness.value() - -(0.1 + 2.6 + 4.6)).abs() < 1e-4);
}

#[test]
fn only_bricks_with_a_goal_count() {
    // Balance: only brick 0 has a goal; bricks 1 and 2 may be anywhere.
    let mut w = Scripted::new(Task::Balance, &[Success, Success]);
    w.positions[1] = [5.0, 5.0, 5.0];
    w.positions[0][2] += 0.0104; // 10.4 mm above its goal: 10.0
    let e = run(w, 0);
    assert!((e.fitness.distance[0] - 10.0).abs() < 1e-3, "{:?}", e.fitness.distance);
    assert_eq!(&e.fitness.distance[1..], &[0.0; 3]);
}

#[test]
fn holding_a_brick_at_the_end_costs_eta_in_the_balance_task_only() {
    let mut w = Scripted::new(Task::Balance, &[Success, Success]);
    w.held = Some(1);
    let e = run(w, 0);
    assert_eq!((e.held, e.fitness.held), (Some(1), 100.0));
    let mut w = Scripted::new(Task::Tower, &[Success, Success]);
    w.held = Some(1);
    assert_eq!(run(w, 0).fitness.held, 0.0);
}

#[test]
fn terms_add_up_in_a_fixed_order() {
    let f = Fitness { length: 1.5, distance: [1.0, 2.0, 0.0, 0.25], failure: 50.0, timeout: 10.0, held: 100.0 };
    assert_eq!(f.distance_total(), 3.25);
    assert_eq!(f.cost(), 164.75);
    assert_eq!(f.value(), -164.75);
}

#[test]
fn every_episode_starts_from_a_reset_world_and_reuses_the_runner() {
    let mut runner = Runner::new(Scripted::new(Task::Tower, &[Running, Failure])).unwrap();
    let small = nodes(0);
    let big = nodes(6);
    let a = runner.run_nodes(&big).unwrap();
    let b = runner.run_nodes(&small).unwrap();
    let c = runner.run_nodes(&big).unwrap();
    assert_eq!(runner.world().resets, 3);
    assert_eq!(a, c);
    assert_eq!((b.end, b.ticks, b.nodes), (End::Failure, 2, 1));
}

#[test]
fn the_trace_sees_every_tick_and_changes_nothing() {
    let mut runner = Runner::new(Scripted::new(Task::Tower, &[Running, Success, Running, Success, Success])).unwrap();
    let n = nodes(1);
    let tree: Tree<'_, 4> = Tree::validate(&n, runner.world().spec()).unwrap();
    let mut trace = Trace::default();
    let recorded = runner.run_recorded(tree, &mut trace).unwrap();
    assert_eq!(recorded, runner.run(tree).unwrap());
    assert_eq!(trace.ticks.len(), 5);
    let roots: Vec<Status> = trace.ticks.iter().map(|t| t.root).collect();
    assert_eq!(roots, [Running, Success, Running, Success, Success]);
    assert_eq!(trace.ticks[0].nodes, [NodeStatus::Running, NodeStatus::Running]);
    assert_eq!(trace.start.len(), 3);
    assert_eq!(trace.path(2).count(), 6, "the start and one position per tick");
    // Recording again starts a new trace.
    runner.run_recorded(tree, &mut trace).unwrap();
    assert_eq!(trace.ticks.len(), 5);
}

#[test]
fn an_invalid_tree_is_an_error_not_an_episode() {
    let mut runner = Runner::new(Scripted::new(Task::Tower, &[])).unwrap();
    let bad = [Node::new(NodeKind::Action(Leaf::new(500)), 1)];
    assert!(matches!(runner.run_nodes(&bad), Err(EpisodeError::Invalid(LoadError::UnknownBehavior { .. }))));
    assert!(matches!(runner.run_nodes(&[]), Err(EpisodeError::Invalid(LoadError::EmptyTree))));
}

#[test]
fn a_condition_returning_running_is_a_tick_error() {
    struct Broken(Scripted);
    impl BehaviorSet for Broken {
        fn condition(&mut self, _: &Leaf, _: Context<'_>) -> Status {
            Running
        }
        fn action(&mut self, _: &Leaf, _: Context<'_>) -> Status {
            Running
        }
        fn halt(&mut self, _: &Leaf, _: NodeId) {}
    }
    impl World for Broken {
        fn reset(&mut self) {}
    }
    impl BrickWorld for Broken {
        fn spec(&self) -> &Spec {
            &self.0.spec
        }
        fn position(&self, b: usize) -> [f32; 3] {
            self.0.position(b)
        }
        fn held(&self) -> Option<u8> {
            None
        }
    }
    let mut runner = Runner::new(Broken(Scripted::new(Task::Tower, &[]))).unwrap();
    assert_eq!(runner.tick_limit(), crate::world::PHYSICS_TICK_LIMIT, "the trait's default");
    let cond = [Node::new(NodeKind::Condition(Leaf::new(0)), 1)];
    assert!(matches!(runner.run_nodes(&cond), Err(EpisodeError::Tick(TickError::ConditionRunning { .. }))));
}
