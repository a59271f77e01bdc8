//! Ticks the W100 benchmark tree a fixed number of times: for instruction counts under
//! `valgrind --tool=callgrind` (repeatable, unlike wall time on a shared machine).
//!
//! `cargo build --release -p bt-core --example tick_loop &&
//!  valgrind --tool=callgrind target/release/examples/tick_loop 100000`
#![allow(clippy::unwrap_used, clippy::indexing_slicing, missing_docs)]

use std::hint::black_box;

use bt_core::{BehaviorInfo, BehaviorSet, Builder, Context, Executor, Leaf, Node, NodeId, NodeState, Status, Tree};

struct World {
    values: [i32; 4],
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

const SET: [BehaviorInfo<'static>; 4] = [
    BehaviorInfo::condition("fails?", 0),
    BehaviorInfo::condition("holds?", 0),
    BehaviorInfo::action("succeeds!", 0),
    BehaviorInfo::action("runs!", 0),
];

fn main() {
    let ticks: u32 = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(100_000);
    let mut storage = vec![Node::EMPTY; 512];
    let mut b = Builder::<64>::new(&mut storage);
    b.fallback().unwrap();
    for _ in 0..100 {
        b.sequence().unwrap().condition(0, &[]).unwrap().action(2, &[]).unwrap().end().unwrap();
    }
    b.action(3, &[]).unwrap().end().unwrap();
    let nodes = b.finish().unwrap();
    let tree = Tree::<64>::validate(nodes, &SET).unwrap();
    let mut state = vec![NodeState::IDLE; nodes.len()];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    let mut w = World { values: [0, 1, 1, -1], counter: 0 };
    let start = std::time::Instant::now();
    for t in 0..ticks {
        black_box(exec.tick(&mut w, t).unwrap());
    }
    let ns = start.elapsed().as_nanos() as f64 / f64::from(ticks);
    println!("{ticks} ticks of W100: {ns:.0} ns/tick, {:.2} ns/visited node (counter {})", ns / 202.0, w.counter);
}
