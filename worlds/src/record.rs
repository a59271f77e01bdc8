//! Recorders: what sees an episode tick by tick — traces for pictures, narration, the
//! leaf calls of replay logs. `()` sees nothing and costs nothing.

use bt_core::{Node, NodeId, NodeState, NodeStatus, Status};

use crate::agent::TreeState;
use crate::runner::Outcome;

/// One tick, as a recorder sees it right after the tree was ticked.
#[derive(Clone, Copy, Debug)]
pub struct Ticked<'a> {
    /// The tick's number, from 1.
    pub tick: u32,
    /// What the root returned.
    pub root: Status,
    /// The tree and each node's state after the tick.
    pub tree: TreeState<'a>,
    /// The leaves the tick called, in order, with what each returned (empty unless the
    /// recorder asks for them, [`Recorder::LEAVES`]).
    pub calls: &'a [(NodeId, Status)],
    /// Every status change, in the order it happened: node, old, new (empty unless the
    /// recorder asks for them, [`Recorder::CHANGES`]).
    pub changes: &'a [(NodeId, NodeStatus, NodeStatus)],
}

/// Sees an episode of a world `W` whose tree may grow by `G` ([`crate::Trees`]).
/// Every method does nothing by default.
pub trait Recorder<W: ?Sized, G: ?Sized = ()> {
    /// False for recorders that ignore everything: the runner then skips every call at
    /// compile time.
    const ENABLED: bool = true;
    /// Whether [`Ticked::calls`] is filled.
    const LEAVES: bool = false;
    /// Whether [`Ticked::changes`] is filled.
    const CHANGES: bool = false;

    /// The episode starts: the world is as the first tick will find it.
    fn start(&mut self, world: &W, tree: &TreeState<'_>) {
        let _ = (world, tree);
    }

    /// A tick was made; the world has not moved on yet.
    fn ticked(&mut self, tick: &Ticked<'_>, world: &W) {
        let _ = (tick, world);
    }

    /// The root failed at `tick` and the tree grew by `growth` into `nodes`.
    fn grown(&mut self, tick: u32, growth: &G, nodes: &[Node]) {
        let _ = (tick, growth, nodes);
    }

    /// The world moved on after tick `tick` (whose root returned `root`): the agents
    /// acted and the world stepped. `states` are the nodes' states after the tick.
    fn stepped(&mut self, tick: u32, root: Status, states: &[NodeState], world: &W) {
        let _ = (tick, root, states, world);
    }

    /// The episode ended as `outcome` says; `tree` as the last tick left it.
    fn end(&mut self, outcome: &Outcome, tree: &TreeState<'_>, world: &W) {
        let _ = (outcome, tree, world);
    }
}

impl<W: ?Sized, G: ?Sized> Recorder<W, G> for () {
    const ENABLED: bool = false;
}

impl<W: ?Sized, G: ?Sized, R: Recorder<W, G> + ?Sized> Recorder<W, G> for &mut R {
    const ENABLED: bool = R::ENABLED;
    const LEAVES: bool = R::LEAVES;
    const CHANGES: bool = R::CHANGES;

    fn start(&mut self, world: &W, tree: &TreeState<'_>) {
        (**self).start(world, tree);
    }

    fn ticked(&mut self, tick: &Ticked<'_>, world: &W) {
        (**self).ticked(tick, world);
    }

    fn grown(&mut self, tick: u32, growth: &G, nodes: &[Node]) {
        (**self).grown(tick, growth, nodes);
    }

    fn stepped(&mut self, tick: u32, root: Status, states: &[NodeState], world: &W) {
        (**self).stepped(tick, root, states, world);
    }

    fn end(&mut self, outcome: &Outcome, tree: &TreeState<'_>, world: &W) {
        (**self).end(outcome, tree, world);
    }
}

/// Two recorders side by side, the first one told first.
impl<W: ?Sized, G: ?Sized, A: Recorder<W, G>, B: Recorder<W, G>> Recorder<W, G> for (A, B) {
    const ENABLED: bool = A::ENABLED || B::ENABLED;
    const LEAVES: bool = A::LEAVES || B::LEAVES;
    const CHANGES: bool = A::CHANGES || B::CHANGES;

    fn start(&mut self, world: &W, tree: &TreeState<'_>) {
        self.0.start(world, tree);
        self.1.start(world, tree);
    }

    fn ticked(&mut self, tick: &Ticked<'_>, world: &W) {
        self.0.ticked(tick, world);
        self.1.ticked(tick, world);
    }

    fn grown(&mut self, tick: u32, growth: &G, nodes: &[Node]) {
        self.0.grown(tick, growth, nodes);
        self.1.grown(tick, growth, nodes);
    }

    fn stepped(&mut self, tick: u32, root: Status, states: &[NodeState], world: &W) {
        self.0.stepped(tick, root, states, world);
        self.1.stepped(tick, root, states, world);
    }

    fn end(&mut self, outcome: &Outcome, tree: &TreeState<'_>, world: &W) {
        self.0.end(outcome, tree, world);
        self.1.end(outcome, tree, world);
    }
}

/// The leaves every tick called, in order, with what each returned: what a replay log
/// (Groot2's `.btlog`) is written from.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LeafCalls {
    /// Per tick: its number and its calls.
    pub ticks: Vec<(u32, Vec<(NodeId, Status)>)>,
}

impl<W: ?Sized, G: ?Sized> Recorder<W, G> for LeafCalls {
    const LEAVES: bool = true;

    fn start(&mut self, _: &W, _: &TreeState<'_>) {
        self.ticks.clear();
    }

    fn ticked(&mut self, tick: &Ticked<'_>, _: &W) {
        self.ticks.push((tick.tick, tick.calls.to_vec()));
    }
}
