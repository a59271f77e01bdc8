//! Ticks one of the benchmark trees (W100, D50, Cube; see `benches/tick.rs`) a fixed
//! number of times: for instruction counts under `valgrind --tool=callgrind`, which are
//! repeatable, unlike wall time on a shared machine.
//!
//! `cargo build --release -p bt-core --example tick_loop &&
//!  valgrind --tool=callgrind target/release/examples/tick_loop 10000 W100`
#![allow(clippy::unwrap_used, clippy::indexing_slicing, missing_docs)]

use std::hint::black_box;

use bt_core::{BehaviorInfo, BehaviorSet, Builder, Context, Executor, Leaf, Node, NodeId, NodeState, Status, Tree};

struct World {
    values: [i32; 8],
    counter: u64,
}

impl BehaviorSet for World {
    #[inline(always)]
    fn condition(&mut self, leaf: &Leaf, _: Context) -> Status {
        self.counter += 1;
        if self.values[usize::from(leaf.behavior())] > 0 { Status::Success } else { Status::Failure }
    }
    #[inline(always)]
    fn action(&mut self, leaf: &Leaf, _: Context) -> Status {
        self.counter += 1;
        match self.values[usize::from(leaf.behavior())] {
            v if v > 0 => Status::Success,
            0 => Status::Failure,
            _ => Status::Running,
        }
    }
    fn halt(&mut self, _: &Leaf, _: NodeId) {}
}

const SET: [BehaviorInfo<'static>; 8] = [
    BehaviorInfo::condition("fails?", 0),
    BehaviorInfo::condition("holds?", 0),
    BehaviorInfo::action("succeeds!", 0),
    BehaviorInfo::action("runs!", 0),
    BehaviorInfo::condition("near", 1),
    BehaviorInfo::condition("free", 1),
    BehaviorInfo::action("MoveTo", 2),
    BehaviorInfo::action("Place", 0),
];

fn build(name: &str, storage: &mut [Node]) -> (usize, usize) {
    let mut b = Builder::<64>::new(storage);
    let visited = match name {
        "W100" => {
            b.fallback().unwrap();
            for _ in 0..100 {
                b.sequence().unwrap().condition(0, &[]).unwrap().action(2, &[]).unwrap().end().unwrap();
            }
            b.action(3, &[]).unwrap().end().unwrap();
            202
        }
        "D50" => {
            for _ in 0..50 {
                b.sequence().unwrap().condition(1, &[]).unwrap();
            }
            b.action(3, &[]).unwrap();
            for _ in 0..50 {
                b.end().unwrap();
            }
            101
        }
        _ => {
            // Fig. 3(e) with MoveTo(cube) running: conditions 0 (fails) and 1 (holds)
            // stand for the paper's, as in the benchmark.
            b.fallback().unwrap().condition(0, &[]).unwrap();
            b.sequence().unwrap();
            b.fallback().unwrap().condition(0, &[]).unwrap();
            b.sequence().unwrap();
            b.fallback().unwrap().condition(4, &[0]).unwrap();
            b.sequence().unwrap().condition(5, &[0]).unwrap().action(6, &[0, 0]).unwrap();
            b.end().unwrap().end().unwrap();
            b.condition(1, &[]).unwrap().action(2, &[]).unwrap();
            b.end().unwrap().end().unwrap();
            b.fallback().unwrap().condition(4, &[1]).unwrap();
            b.sequence().unwrap().condition(5, &[1]).unwrap().action(6, &[1, 1]).unwrap().end().unwrap();
            b.end().unwrap();
            b.action(7, &[]).unwrap();
            b.end().unwrap().end().unwrap();
            11
        }
    };
    (b.finish().unwrap().len(), visited)
}

fn main() {
    let ticks: u32 = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(100_000);
    let name = std::env::args().nth(2).unwrap_or_else(|| "W100".into());
    let mut storage = vec![Node::EMPTY; 512];
    let (len, visited) = build(&name, &mut storage);
    let nodes = &storage[..len];
    let tree = Tree::<64>::validate(nodes, &SET).unwrap();
    let mut state = vec![NodeState::IDLE; nodes.len()];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    // near? fails, free? holds, MoveTo runs.
    let mut w = World { values: [0, 1, 1, -1, 0, 1, -1, 1], counter: 0 };
    let start = std::time::Instant::now();
    for t in 0..ticks {
        black_box(exec.tick(&mut w, t).unwrap());
    }
    let ns = start.elapsed().as_nanos() as f64 / f64::from(ticks);
    println!(
        "{ticks} ticks of {name}: {ns:.0} ns/tick, {:.2} ns/visited node (counter {})",
        ns / visited as f64,
        w.counter
    );
}
