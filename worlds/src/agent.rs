//! Agents: whoever besides the tree changes the world between ticks — the external
//! agents of Colledanchise et al. 2019 (Problem 1) that help and undo, a co-worker, a
//! scripted story, seeded random disturbances.
//!
//! An agent acts before the first tick ([`Agent::start`]) and then between ticks, after
//! the tree was ticked and before the world steps ([`Agent::act`]), seeing which action
//! the tree left running. It does not act after the tick that ends the episode unless
//! the runner's [`Settings`](crate::Settings) let the world move on there.

use bt_core::{Leaf, Node, NodeId, NodeKind, NodeState, NodeStatus};

/// The tree as the last tick left it: its nodes and their states.
#[derive(Clone, Copy, Debug)]
pub struct TreeState<'a> {
    /// The nodes, in pre-order.
    pub nodes: &'a [Node],
    /// Each node's state after the tick (empty before the first tick).
    pub states: &'a [NodeState],
}

impl<'a> TreeState<'a> {
    /// The first action, in pre-order, that the tick left Running.
    #[must_use]
    pub fn running_action(&self) -> Option<(NodeId, &'a Leaf)> {
        self.nodes.iter().zip(self.states).enumerate().find_map(|(i, (n, s))| match n.kind() {
            NodeKind::Action(leaf) if s.status() == NodeStatus::Running => Some((NodeId::try_from(i).ok()?, leaf)),
            _ => None,
        })
    }
}

/// Someone who acts on the world between ticks. `()` is nobody and costs nothing.
pub trait Agent<W: ?Sized> {
    /// False for agents that never act: the runner then skips the calls at compile time.
    const ENABLED: bool = true;

    /// Before the first tick of an episode.
    fn start(&mut self, world: &mut W) {
        let _ = world;
    }

    /// After tick `tick` and before the world steps; `tree` shows the statuses the tick
    /// left (the action left running).
    fn act(&mut self, tick: u32, world: &mut W, tree: &TreeState<'_>);
}

impl<W: ?Sized> Agent<W> for () {
    const ENABLED: bool = false;

    #[inline(always)]
    fn act(&mut self, _: u32, _: &mut W, _: &TreeState<'_>) {}
}

/// Maybe an agent: `None` is nobody.
impl<W: ?Sized, A: Agent<W>> Agent<W> for Option<A> {
    const ENABLED: bool = A::ENABLED;

    #[inline]
    fn start(&mut self, world: &mut W) {
        if let Some(a) = self {
            a.start(world);
        }
    }

    #[inline]
    fn act(&mut self, tick: u32, world: &mut W, tree: &TreeState<'_>) {
        if let Some(a) = self {
            a.act(tick, world, tree);
        }
    }
}

impl<W: ?Sized, A: Agent<W> + ?Sized> Agent<W> for &mut A {
    const ENABLED: bool = A::ENABLED;

    #[inline(always)]
    fn start(&mut self, world: &mut W) {
        (**self).start(world);
    }

    #[inline(always)]
    fn act(&mut self, tick: u32, world: &mut W, tree: &TreeState<'_>) {
        (**self).act(tick, world, tree);
    }
}

/// A script run before every tick: `BeforeTicks(|tick, world| ...)` is called with the
/// number of the tick about to come (from 1), so before tick 1 too.
#[derive(Clone, Copy, Debug, Default)]
pub struct BeforeTicks<F>(pub F);

impl<W: ?Sized, F: FnMut(u32, &mut W)> Agent<W> for BeforeTicks<F> {
    #[inline]
    fn start(&mut self, world: &mut W) {
        (self.0)(1, world);
    }

    #[inline]
    fn act(&mut self, tick: u32, world: &mut W, _: &TreeState<'_>) {
        (self.0)(tick.saturating_add(1), world);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bt_core::Status;

    /// Conditions fail, actions run.
    struct Busy;

    impl bt_core::BehaviorSet for Busy {
        fn condition(&mut self, _: &Leaf, _: bt_core::Context<'_>) -> Status {
            Status::Failure
        }
        fn action(&mut self, _: &Leaf, _: bt_core::Context<'_>) -> Status {
            Status::Running
        }
        fn halt(&mut self, _: &Leaf, _: NodeId) {}
    }

    #[test]
    fn the_running_action_is_the_first_in_pre_order() {
        let catalog = [bt_core::BehaviorInfo::condition("c", 0), bt_core::BehaviorInfo::action("a", 0)];
        let nodes = [
            Node::new(NodeKind::Fallback, 3),
            Node::new(NodeKind::Condition(Leaf::new(0)), 1),
            Node::new(NodeKind::Action(Leaf::new(1)), 1),
        ];
        let tree: bt_core::Tree<'_, 4> = bt_core::Tree::validate(&nodes, &catalog).unwrap();
        let mut states = [NodeState::IDLE; 3];
        assert_eq!(TreeState { nodes: &nodes, states: &states }.running_action(), None);
        let mut exec = bt_core::Executor::new(tree, &mut states).unwrap();
        assert_eq!(exec.tick(&mut Busy, 0), Ok(Status::Running));
        let after = TreeState { nodes: &nodes, states: exec.states() };
        assert_eq!(after.running_action().map(|(n, l)| (n, l.behavior())), Some((2, 1)));
        assert_eq!(TreeState { nodes: &nodes, states: &[] }.running_action(), None);
    }

    #[test]
    fn a_script_runs_before_every_tick() {
        let mut seen = Vec::new();
        let mut script = BeforeTicks(|t, w: &mut Vec<u32>| w.push(t));
        script.start(&mut seen);
        let tree = TreeState { nodes: &[], states: &[] };
        script.act(1, &mut seen, &tree);
        script.act(2, &mut seen, &tree);
        assert_eq!(seen, [1, 2, 3]);
    }
}
