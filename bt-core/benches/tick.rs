//! Tick cost on the three reference trees of the bt-core issue, with leaves that read
//! an integer from a world struct and bump a counter:
//!
//! - W100: `Fallback[ 100 x Sequence[Condition->Failure, Action->Success], Action->Running ]`,
//!   202 nodes visited per tick;
//! - D50: 50 nested `Sequence`s, each `[Condition->Success, next]`, the innermost
//!   `[Condition->Success, Action->Running]`, 101 visited;
//! - Cube: the Fig. 3(e) tree of Colledanchise et al. 2019 with the robot far from the cube, hand empty,
//!   path free, so `MoveTo(cube)` runs, 11 visited.
//!
//! `cargo bench -p bt-core` prints ns per tick; divide by the visited count for ns per
//! visited node (the bench prints both in its header).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing, missing_docs)]

use std::hint::black_box;

mod trees;

use bt_core::{Executor, Node, NodeState, Tree};
use criterion::{Criterion, criterion_group, criterion_main};
use trees::{SET, TREES, first_tick, world};

fn bench(c: &mut Criterion) {
    eprintln!(
        "bytes per node: {} (node) + {} (runtime state) = {}",
        size_of::<Node>(),
        size_of::<NodeState>(),
        size_of::<Node>() + size_of::<NodeState>()
    );
    let mut group = c.benchmark_group("tick");
    for (name, make, visited) in TREES {
        let mut storage = vec![Node::EMPTY; 512];
        let nodes = make(&mut storage);
        let tree = Tree::<64>::validate(nodes, &SET).unwrap();
        let mut state = vec![NodeState::IDLE; nodes.len()];
        let mut exec = Executor::new(tree, &mut state).unwrap();
        let mut w = world();
        first_tick(&mut exec, &mut w, name, visited);
        eprintln!("{name}: {} nodes, {visited} visited per tick", nodes.len());
        let mut now = 1u32;
        group.throughput(criterion::Throughput::Elements(visited));
        group.bench_function(name, |b| {
            b.iter(|| {
                now = now.wrapping_add(1);
                black_box(exec.tick(&mut w, black_box(now)).unwrap())
            });
        });
        black_box(w.counter);
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
