//! Tick cost on the three reference trees of the bt-core issue, with leaves that read
//! an integer from a world struct and bump a counter:
//!
//! - W100: `Fallback[ 100 x Sequence[Condition->Failure, Action->Success], Action->Running ]`,
//!   202 nodes visited per tick;
//! - D50: 50 nested `Sequence`s, each `[Condition->Success, next]`, the innermost
//!   `[Condition->Success, Action->Running]`, 101 visited;
//! - Cube: the Fig. 3(e) tree of seed 000 with the robot far from the cube, hand empty,
//!   path free, so `MoveTo(cube)` runs, 11 visited.
//!
//! `cargo bench -p bt-core` prints ns per tick; divide by the visited count for ns per
//! visited node (the bench prints both in its header).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing, missing_docs)]

use std::hint::black_box;

use bt_core::{BehaviorInfo, BehaviorSet, Builder, Context, Executor, Leaf, Node, NodeId, NodeState, Status, Tree};
use criterion::{Criterion, criterion_group, criterion_main};

/// Behavior ids index `values`: the leaf returns Success when the value is positive,
/// Failure when zero, Running when negative (actions only).
struct World {
    values: [i32; 16],
    counter: u64,
}

impl World {
    #[inline(always)]
    fn read(&mut self, leaf: &Leaf) -> i32 {
        self.counter += 1;
        self.values[usize::from(leaf.behavior())]
    }
}

impl BehaviorSet for World {
    #[inline(always)]
    fn condition(&mut self, leaf: &Leaf, _: Context) -> Status {
        if self.read(leaf) > 0 { Status::Success } else { Status::Failure }
    }
    #[inline(always)]
    fn action(&mut self, leaf: &Leaf, _: Context) -> Status {
        match self.read(leaf) {
            v if v > 0 => Status::Success,
            0 => Status::Failure,
            _ => Status::Running,
        }
    }
    fn halt(&mut self, _: &Leaf, _: NodeId) {
        self.counter += 1000;
    }
}

const C_FAIL: u16 = 0;
const C_OK: u16 = 1;
const A_OK: u16 = 2;
const A_RUN: u16 = 3;
// Cube world (Fig. 3(e)): robot far from cube, hand empty, path free.
const ON_GOAL: u16 = 4;
const HOLDING: u16 = 5;
const NEAR: u16 = 6;
const FREE: u16 = 7;
const HAND_EMPTY: u16 = 8;
const MOVE_TO: u16 = 9;
const PICK: u16 = 10;
const PLACE: u16 = 11;

const SET: [BehaviorInfo<'static>; 12] = [
    BehaviorInfo::condition("fails?", 0),
    BehaviorInfo::condition("holds?", 0),
    BehaviorInfo::action("succeeds!", 0),
    BehaviorInfo::action("runs!", 0),
    BehaviorInfo::condition("cube on goal?", 0),
    BehaviorInfo::condition("holding cube?", 0),
    BehaviorInfo::condition("near", 1),
    BehaviorInfo::condition("free", 1),
    BehaviorInfo::condition("hand empty?", 0),
    BehaviorInfo::action("MoveTo", 2),
    BehaviorInfo::action("Pick", 0),
    BehaviorInfo::action("Place", 0),
];

fn world() -> World {
    let mut values = [0; 16];
    values[usize::from(C_OK)] = 1;
    values[usize::from(A_OK)] = 1;
    values[usize::from(A_RUN)] = -1;
    values[usize::from(FREE)] = 1;
    values[usize::from(HAND_EMPTY)] = 1;
    values[usize::from(MOVE_TO)] = -1;
    World { values, counter: 0 }
}

fn w100(storage: &mut [Node]) -> &[Node] {
    let mut b = Builder::<64>::new(storage);
    b.fallback().unwrap();
    for _ in 0..100 {
        b.sequence().unwrap().condition(C_FAIL, &[]).unwrap().action(A_OK, &[]).unwrap().end().unwrap();
    }
    b.action(A_RUN, &[]).unwrap().end().unwrap();
    b.finish().unwrap()
}

fn d50(storage: &mut [Node]) -> &[Node] {
    let mut b = Builder::<64>::new(storage);
    for _ in 0..50 {
        b.sequence().unwrap().condition(C_OK, &[]).unwrap();
    }
    b.action(A_RUN, &[]).unwrap();
    for _ in 0..50 {
        b.end().unwrap();
    }
    b.finish().unwrap()
}

fn cube(storage: &mut [Node]) -> &[Node] {
    let mut b = Builder::<64>::new(storage);
    b.fallback().unwrap().condition(ON_GOAL, &[]).unwrap();
    b.sequence().unwrap();
    b.fallback().unwrap().condition(HOLDING, &[]).unwrap();
    b.sequence().unwrap();
    b.fallback().unwrap().condition(NEAR, &[0]).unwrap();
    b.sequence().unwrap().condition(FREE, &[0]).unwrap().action(MOVE_TO, &[0, 0]).unwrap();
    b.end().unwrap().end().unwrap();
    b.condition(HAND_EMPTY, &[]).unwrap().action(PICK, &[]).unwrap();
    b.end().unwrap().end().unwrap();
    b.fallback().unwrap().condition(NEAR, &[1]).unwrap();
    b.sequence().unwrap().condition(FREE, &[1]).unwrap().action(MOVE_TO, &[1, 1]).unwrap().end().unwrap();
    b.end().unwrap();
    b.action(PLACE, &[]).unwrap();
    b.end().unwrap().end().unwrap();
    b.finish().unwrap()
}

/// Builds a benchmark tree into the storage it is given.
type MakeTree = fn(&mut [Node]) -> &[Node];

/// Counts the nodes a tick visits: every status write goes through the observer, but
/// unchanged statuses do not, so count leaf calls and the control nodes entered instead.
struct Visits(u64);
impl bt_core::Observer for Visits {
    fn on_change(&mut self, _: NodeId, _: bt_core::NodeStatus, _: bt_core::NodeStatus) {
        self.0 += 1;
    }
}

fn bench(c: &mut Criterion) {
    eprintln!(
        "bytes per node: {} (node) + {} (runtime state) = {}",
        size_of::<Node>(),
        size_of::<NodeState>(),
        size_of::<Node>() + size_of::<NodeState>()
    );
    let trees: [(&str, MakeTree, u64); 3] = [("W100", w100, 202), ("D50", d50, 101), ("Cube", cube, 11)];
    let mut group = c.benchmark_group("tick");
    for (name, make, visited) in trees {
        let mut storage = vec![Node::EMPTY; 512];
        let nodes = make(&mut storage);
        let tree = Tree::<64>::validate(nodes, &SET).unwrap();
        let mut state = vec![NodeState::IDLE; nodes.len()];
        let mut exec = Executor::new(tree, &mut state).unwrap();
        let mut w = world();
        // First tick: every visited node goes from Idle to its status, once.
        let mut first = Visits(0);
        assert_eq!(exec.tick_observed(&mut w, 0, &mut first).unwrap(), Status::Running);
        assert_eq!(first.0, visited, "{name}: nodes visited on the first tick");
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
