//! Same inputs, same episode, bit for bit: twice in a row, and in parallel (rayon)
//! against sequentially.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod physics_common;

use bt_core::{Executor, NodeState, Status, Tree};
use planner::duplo::Task;
use rayon::prelude::*;
use sim_host::physics::PhysicsBrickWorld;
use sim_host::world::BrickWorld;
use worlds::World;

const TOWER: &str = "s( \
    f( 0 at pos (0.0, 0.05, 0.0)? s( f( picked 0? pick 0! ) place at (0.0, 0.05, 0.0)! ) ) \
    f( 1 at pos (0.0, 0.05, 0.0192)? s( f( 1 on 0? s( f( picked 1? pick 1! ) place on 0! ) ) apply force 1! ) ) \
    f( 2 at pos (0.0, 0.05, 0.0384)? s( f( 2 on 1? s( f( picked 2? pick 2! ) place on 1! ) ) apply force 2! ) ) )";

const BALANCE: &str = "s( f( 0 at pos (0.0, 0.0, 0.0192)? s( f( 1 at pos (0.0, 0.0, 0.0)? put 1 at (0.0, 0.0, 0.0)! ) f( 0 on 1? put 0 on 1! ) apply force 0! ) ) )";

/// Every brick's position bits after every tick, and the statuses.
fn trace(task: Task, text: &str, ticks: u32) -> (Vec<u32>, Vec<Status>) {
    let spec = task.spec();
    let nodes = physics_common::nodes(&spec, text);
    let tree: Tree<'_, 32> = Tree::validate(&nodes, &spec).unwrap();
    let mut state = vec![NodeState::IDLE; nodes.len()];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    let mut world = PhysicsBrickWorld::new(&spec).unwrap();
    let mut bits = Vec::new();
    let mut statuses = Vec::new();
    for t in 0..ticks {
        statuses.push(exec.tick(&mut world, t).unwrap());
        world.step();
        for b in 0..spec.bricks.len() {
            bits.extend(world.position(b).map(f32::to_bits));
        }
        bits.extend(world.gripper().map(f32::to_bits));
    }
    (bits, statuses)
}

#[test]
fn the_same_episode_twice_is_bit_identical() {
    let a = trace(Task::Tower, TOWER, 100);
    let b = trace(Task::Tower, TOWER, 100);
    assert_eq!(a, b);
    // The tipping brick is the chaotic case.
    assert_eq!(trace(Task::Balance, BALANCE, 80), trace(Task::Balance, BALANCE, 80));
}

#[test]
fn parallel_episodes_equal_sequential_ones() {
    let jobs = [(Task::Tower, TOWER), (Task::Balance, BALANCE), (Task::Tower, TOWER), (Task::Balance, BALANCE)];
    let sequential: Vec<_> = jobs.iter().map(|&(t, s)| trace(t, s, 60)).collect();
    let parallel: Vec<_> = jobs.par_iter().map(|&(t, s)| trace(t, s, 60)).collect();
    assert_eq!(sequential, parallel);
    assert_eq!(sequential[0], sequential[2]);
}
