//! Helpers shared by the physics tests: build a tree from seed-003 tokens and run it.
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)]

use bt_core::{Executor, Node, NodeState, Status, Tree};
use planner::duplo::Spec;
use sim_host::world::BrickWorld;

/// Parses `text` against the task's behaviors.
pub fn nodes(spec: &Spec, text: &str) -> Vec<Node> {
    bt_formats::tokens::parse(text, spec).unwrap_or_else(|e| panic!("{text}: {e}"))
}

/// How an episode ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// The last root status.
    pub status: Status,
    /// Ticks run.
    pub ticks: u32,
}

/// Ticks `text` on `world`, stepping between ticks, until `stop(world, status, last)`
/// says so after a tick (`last`: the status of the tick before) or `limit` ticks ran.
pub fn drive<W: BrickWorld>(
    world: &mut W,
    text: &str,
    limit: u32,
    mut stop: impl FnMut(&W, Status, Status) -> bool,
) -> Outcome {
    let spec = world.spec().clone();
    let nodes = nodes(&spec, text);
    let tree: Tree<'_, 32> = Tree::validate(&nodes, &spec).unwrap();
    let mut state = vec![NodeState::IDLE; nodes.len()];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    let mut status = Status::Running;
    let mut last = Status::Running;
    let mut t = 0;
    while t < limit {
        status = exec.tick(&mut *world, t).unwrap();
        t += 1;
        if stop(world, status, last) {
            break;
        }
        last = status;
        world.step();
    }
    Outcome { status, ticks: t }
}

/// Ticks `text` until the root returns something other than Running (or `limit`).
pub fn until_done<W: BrickWorld>(world: &mut W, text: &str, limit: u32) -> Outcome {
    drive(world, text, limit, |_, status, _| status != Status::Running)
}

/// One episode under Styrud et al.'s rules: ends at the first root Failure, after root
/// Success on two consecutive ticks, or after `limit` ticks.
pub fn episode<W: BrickWorld>(world: &mut W, text: &str, limit: u32) -> Outcome {
    drive(world, text, limit, |_, status, last| {
        status == Status::Failure || (status == Status::Success && last == Status::Success)
    })
}

/// Distance between two points.
pub fn dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}
