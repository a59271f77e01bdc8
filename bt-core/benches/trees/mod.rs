//! The three benchmark trees of the bt-core issue and the world their leaves read, shared
//! by `benches/tick.rs` (wall time) and `examples/tick_loop.rs` (instruction counts), so
//! both measure the same code: the executor is compiled for this world type.

use bt_core::{
    BehaviorInfo, BehaviorSet, Builder, Context, Executor, Leaf, Node, NodeId, NodeStatus, Observer, Status,
};

/// Behavior ids index `values`: the leaf returns Success when the value is positive,
/// Failure when zero, Running when negative (actions only).
pub struct World {
    values: [i32; 16],
    /// Bumped by every leaf call (and by 1000 per halt), so no call is optimized away.
    pub counter: u64,
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
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        if self.read(leaf) > 0 { Status::Success } else { Status::Failure }
    }
    #[inline(always)]
    fn action(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
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

/// The behavior set of the three trees.
pub const SET: [BehaviorInfo<'static>; 12] = [
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

/// Every leaf of the three trees as the issue sets it.
pub fn world() -> World {
    let mut values = [0; 16];
    values[usize::from(C_OK)] = 1;
    values[usize::from(A_OK)] = 1;
    values[usize::from(A_RUN)] = -1;
    values[usize::from(FREE)] = 1;
    values[usize::from(HAND_EMPTY)] = 1;
    values[usize::from(MOVE_TO)] = -1;
    World { values, counter: 0 }
}

/// W100: `Fallback[ 100 x Sequence[Condition->Failure, Action->Success], Action->Running ]`.
pub fn w100(storage: &mut [Node]) -> &[Node] {
    let mut b = Builder::<64>::new(storage);
    b.fallback().unwrap();
    for _ in 0..100 {
        b.sequence().unwrap().condition(C_FAIL, &[]).unwrap().action(A_OK, &[]).unwrap().end().unwrap();
    }
    b.action(A_RUN, &[]).unwrap().end().unwrap();
    b.finish().unwrap()
}

/// D50: 50 nested `Sequence[Condition->Success, next]`, the innermost
/// `[Condition->Success, Action->Running]`.
pub fn d50(storage: &mut [Node]) -> &[Node] {
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

/// Cube: Fig. 3(e) of Colledanchise et al. 2019, robot far from the cube, hand empty, path free.
pub fn cube(storage: &mut [Node]) -> &[Node] {
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
pub type MakeTree = fn(&mut [Node]) -> &[Node];

/// The three trees: name, builder, nodes visited per tick.
pub const TREES: [(&str, MakeTree, u64); 3] = [("W100", w100, 202), ("D50", d50, 101), ("Cube", cube, 11)];

/// Counts status changes. On the first tick every visited node goes from Idle to its
/// status once, so this counts the nodes a tick visits.
struct Visits(u64);

impl Observer for Visits {
    fn on_change(&mut self, _: NodeId, _: NodeStatus, _: NodeStatus) {
        self.0 += 1;
    }
}

/// Ticks a fresh executor once, observed, and checks that the tree runs and that the
/// tick visits `visited` nodes, as the benchmark's figures per visited node assume.
pub fn first_tick(exec: &mut Executor<'_, '_, 64>, world: &mut World, name: &str, visited: u64) {
    let mut first = Visits(0);
    assert_eq!(exec.tick_observed(world, 0, &mut first).unwrap(), Status::Running, "{name}: first tick");
    assert_eq!(first.0, visited, "{name}: nodes visited on the first tick");
}
