//! Physics episodes per second on one core: `cargo bench -p sim-host --bench physics`.
//!
//! An episode is 200 ticks (20 s at 10 Hz) under Styrud et al.'s rules: it ends early at the
//! first root Failure or after two successive root Successes.
#![allow(missing_docs, clippy::unwrap_used)]

use bt_core::{Executor, NodeState, Status, Tree};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use planner::duplo::Task;
use sim_host::physics::PhysicsBrickWorld;
use worlds::World;

const TOWER: &str = "s( \
    f( 0 at pos (0.0, 0.05, 0.0)? s( f( picked 0? pick 0! ) place at (0.0, 0.05, 0.0)! ) ) \
    f( 1 at pos (0.0, 0.05, 0.0192)? s( f( 1 on 0? s( f( picked 1? pick 1! ) place on 0! ) ) apply force 1! ) ) \
    f( 2 at pos (0.0, 0.05, 0.0384)? s( f( 2 on 1? s( f( picked 2? pick 2! ) place on 1! ) ) apply force 2! ) ) )";
const CROISSANT: &str = "s( \
    f( 0 at pos (0.0, 0.0, 0.0)? s( f( picked 0? pick 0! ) place at (0.0, 0.0, 0.0)! ) ) \
    f( 2 at pos (0.016, -0.032, 0.0)? s( f( picked 2? pick 2! ) place at (0.016, -0.032, 0.0)! ) ) \
    f( 3 at pos (0.016, 0.032, 0.0)? s( f( picked 3? pick 3! ) place at (0.016, 0.032, 0.0)! ) ) \
    f( 1 at pos (0.0, 0.0, 0.0192)? s( f( 1 on 0? s( f( picked 1? pick 1! ) place on 0! ) ) apply force 1! ) ) )";
const BALANCE: &str = "s( f( 0 at pos (0.0, 0.0, 0.0192)? s( f( 1 at pos (0.0, 0.0, 0.0)? put 1 at (0.0, 0.0, 0.0)! ) f( 0 on 1? put 0 on 1! ) apply force 0! ) ) )";
/// Runs `nodes` for one episode; with `full`, for all 200 ticks whatever the root
/// returns (the worst case a GP fitness evaluation can cost).
fn episode(task: Task, nodes: &[bt_core::Node], full: bool) -> u32 {
    let spec = task.spec();
    let tree: Tree<'_, 32> = Tree::validate(nodes, &spec).unwrap();
    let mut state = vec![NodeState::IDLE; nodes.len()];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    let mut world = PhysicsBrickWorld::new(&spec).unwrap();
    let mut last = Status::Running;
    for t in 0..200 {
        let s = exec.tick(&mut world, t).unwrap();
        if !full && (s == Status::Failure || (s == Status::Success && last == Status::Success)) {
            return t + 1;
        }
        last = s;
        world.step();
    }
    200
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("physics_episode");
    g.throughput(Throughput::Elements(1));
    g.sample_size(20);
    for (name, task, text, full) in [
        ("tower_planner_tree", Task::Tower, TOWER, false),
        ("croissant_side_bricks_first", Task::Croissant, CROISSANT, false),
        ("balance_planner_tree", Task::Balance, BALANCE, false),
        ("tower_planner_tree_all_200_ticks", Task::Tower, TOWER, true),
        ("balance_planner_tree_all_200_ticks", Task::Balance, BALANCE, true),
    ] {
        let nodes = bt_formats::tokens::parse(text, &task.spec()).unwrap();
        eprintln!("{name}: {} ticks", episode(task, &nodes, full));
        g.bench_function(name, |b| b.iter(|| episode(task, &nodes, full)));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
