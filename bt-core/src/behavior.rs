//! The interface between the executor and the world: behavior sets and observers.

use crate::node::{Leaf, NodeId};
use crate::script::{ScriptFault, Value};
use crate::status::{NodeStatus, Status};

/// What a behavior is told when it is ticked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Context<'t> {
    /// The leaf's node id: lets a behavior set keep per-node state.
    pub node: NodeId,
    /// The caller's clock, as given to [`Executor::tick`](crate::Executor::tick).
    pub now: u32,
    /// For actions, true on the first tick of an activation (the action was not Running);
    /// false while it continues. Always true for conditions.
    pub starting: bool,
    /// The tree's value table, where extended leaves keep their values.
    pub values: &'t [u16],
}

impl<'t> Context<'t> {
    /// The values of `leaf` (grounded arguments or port references), inline or from the
    /// tree's value table: what a behavior reads instead of [`Leaf::args`], which only
    /// knows inline values.
    #[inline]
    #[must_use]
    pub fn args<'a>(self, leaf: &'a Leaf) -> &'a [u16]
    where
        't: 'a,
    {
        leaf.args_in(self.values)
    }
}

/// What a [`NodeKind::ManualSelector`](crate::NodeKind::ManualSelector) does on this
/// tick, as the behavior set chooses it ([`BehaviorSet::select`]): the operator's
/// choice of BehaviorTree.CPP's `ManualSelector`, given on the controller by a command
/// or a button instead of a terminal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Selection {
    /// Tick child `k` (0-based, in the tree's order) and return what it returns.
    Child(u8),
    /// Return Success without ticking a child.
    Success,
    /// Return Failure without ticking a child.
    Failure,
    /// Return Running without ticking a child (a child still Running stays so).
    Running,
}

/// The conditions and actions a tree's leaves run, implemented by the caller over its
/// world. Behavior ids and arities are declared by a [`Catalog`](crate::Catalog).
pub trait BehaviorSet {
    /// Evaluates a condition. Must return Success or Failure: Running is a usage error
    /// that the tick reports as [`TickError::ConditionRunning`].
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status;

    /// Starts or continues an action.
    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status;

    /// Stops a Running action that the tree no longer wants. Called exactly once per
    /// preemption, before any other action starts in its place.
    fn halt(&mut self, leaf: &Leaf, node: NodeId);

    /// Runs a `Script` or `ScriptCondition` node's program (its words, from the tree's
    /// value table) on the set's blackboard: usually
    /// [`script::run`](crate::script::run)`(code, &ports, &mut blackboard)`. The default
    /// refuses, for sets without a blackboard.
    ///
    /// # Errors
    /// The [`ScriptFault`] that stopped the script; the tick ends with it.
    fn script(&mut self, code: &[u16], ctx: Context<'_>) -> Result<Value, ScriptFault> {
        let _ = (code, ctx);
        Err(ScriptFault::Unsupported)
    }

    /// Takes the front element of the blackboard queue in slot `queue` into slot
    /// `value`, for a `Loop` whose queue is a `{key}`: `Ok(true)` when it took one,
    /// `Ok(false)` when the queue is empty. `ctx.node` is the `Loop`'s node, and
    /// `ctx.starting` is set on its first pop of an activation (BehaviorTree.CPP reads a
    /// string entry such as `"1;2;3"` afresh then, and pops a queue entry in place). The
    /// set owns its queues: a controller keeps them in fixed storage (a
    /// `heapless::Deque` per queue slot). The default refuses with
    /// [`ScriptFault::NoQueues`], for sets without queues.
    ///
    /// # Errors
    /// The [`ScriptFault`] that stopped it (an unset entry, one that holds no queue); the
    /// tick ends with it.
    fn pop(&mut self, queue: u16, value: u16, ctx: Context<'_>) -> Result<bool, ScriptFault> {
        let _ = (queue, value, ctx);
        Err(ScriptFault::NoQueues)
    }

    /// Chooses what the `ManualSelector` at `ctx.node`, which has `children` children,
    /// does on this tick: tick one of them, or return a status without ticking any (with
    /// no children, only a status will do). Asked on every tick, also while a child runs,
    /// as BehaviorTree.CPP asks its operator; with `repeat_last_selection` only once for
    /// the life of the executor. `ctx.starting` is set when the node starts afresh (it
    /// was not Running). The answer comes from the controller's inputs: a teleoperation
    /// command, a button, a mode switch. The default refuses with
    /// [`ScriptFault::NoSelections`], for sets that give none.
    ///
    /// # Errors
    /// The [`ScriptFault`] that stopped it; the tick ends with it. A child that does not
    /// exist ends the tick with [`TickError::NoSuchChild`].
    fn select(&mut self, children: u8, ctx: Context<'_>) -> Result<Selection, ScriptFault> {
        let _ = (children, ctx);
        Err(ScriptFault::NoSelections)
    }
}

impl<B: BehaviorSet + ?Sized> BehaviorSet for &mut B {
    #[inline(always)]
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        (**self).condition(leaf, ctx)
    }

    #[inline(always)]
    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        (**self).action(leaf, ctx)
    }

    #[inline(always)]
    fn halt(&mut self, leaf: &Leaf, node: NodeId) {
        (**self).halt(leaf, node);
    }

    #[inline(always)]
    fn script(&mut self, code: &[u16], ctx: Context<'_>) -> Result<Value, ScriptFault> {
        (**self).script(code, ctx)
    }

    #[inline(always)]
    fn pop(&mut self, queue: u16, value: u16, ctx: Context<'_>) -> Result<bool, ScriptFault> {
        (**self).pop(queue, value, ctx)
    }

    #[inline(always)]
    fn select(&mut self, children: u8, ctx: Context<'_>) -> Result<Selection, ScriptFault> {
        (**self).select(children, ctx)
    }
}

/// Receives every change of a node's status, in the order they happen: how traces, logs
/// and visualizations are made. `()` is the observer that does nothing and costs nothing.
pub trait Observer {
    /// False for observers that ignore everything; the executor then skips the
    /// comparison and the call at compile time.
    const ENABLED: bool = true;

    /// Node `node` went from `old` to `new`.
    fn on_change(&mut self, node: NodeId, old: NodeStatus, new: NodeStatus);
}

impl Observer for () {
    const ENABLED: bool = false;

    #[inline(always)]
    fn on_change(&mut self, _: NodeId, _: NodeStatus, _: NodeStatus) {}
}

impl<O: Observer + ?Sized> Observer for &mut O {
    const ENABLED: bool = O::ENABLED;

    #[inline(always)]
    fn on_change(&mut self, node: NodeId, old: NodeStatus, new: NodeStatus) {
        (**self).on_change(node, old, new);
    }
}

/// Why a tick stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TickError {
    /// A condition returned Running (rule 1): a bug in the behavior set.
    #[error("condition node {node} (behavior {behavior}) returned Running; conditions return Success or Failure")]
    ConditionRunning {
        /// The condition's node id.
        node: NodeId,
        /// Its behavior id.
        behavior: u16,
    },
    /// An index left the node array. Cannot happen with a tree made by
    /// [`Tree::validate`](crate::Tree::validate) or [`load`](crate::load); reported
    /// instead of panicking.
    #[error("internal error: node index {node} out of range")]
    OutOfRange {
        /// The index.
        node: usize,
    },
    /// A leaf returned [`Status::Skipped`](crate::Status::Skipped) in a build of bt-core
    /// without the `btcpp` feature, which leaves Skipped out of the tick loop (rule 8).
    #[error(
        "leaf node {node} (behavior {behavior}) returned Skipped; this build of bt-core has no btcpp feature, \
         which Skipped needs"
    )]
    LeafSkipped {
        /// The leaf's node id.
        node: NodeId,
        /// Its behavior id.
        behavior: u16,
    },
    /// A `Script`, `ScriptCondition`, `Precondition`, guard or `Loop` stopped with a fault
    /// (BehaviorTree.CPP throws), or the behavior set refused a `ManualSelector` its
    /// choice ([`BehaviorSet::select`]).
    #[error("script node {node}: {fault}")]
    Script {
        /// The script's node id.
        node: NodeId,
        /// Why it stopped.
        fault: ScriptFault,
    },
    /// The behavior set chose for a `ManualSelector` a child it does not have
    /// ([`BehaviorSet::select`]; BehaviorTree.CPP would index past its children).
    #[cfg(feature = "btcpp")]
    #[error(
        "manual selector node {node} has {}; the behavior set chose child {child} (counted from 0)",
        crate::error::Count(usize::from(*.children), "child", "children")
    )]
    NoSuchChild {
        /// The `ManualSelector`'s node id.
        node: NodeId,
        /// The child chosen (0-based).
        child: u8,
        /// How many children it has.
        children: u8,
    },
}

impl TickError {
    /// A short, stable identifier of the fault (`"condition-running"`, `"out-of-range"`).
    #[must_use]
    pub const fn code(&self) -> &'static str {
        match self {
            Self::ConditionRunning { .. } => "condition-running",
            Self::OutOfRange { .. } => "out-of-range",
            Self::LeafSkipped { .. } => "leaf-skipped",
            Self::Script { .. } => "script",
            #[cfg(feature = "btcpp")]
            Self::NoSuchChild { .. } => "no-such-child",
        }
    }
}
