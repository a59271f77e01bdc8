//! The episode runner (see the [crate docs](crate) for one tick).

use bt_core::script::{ScriptFault, Value};
use bt_core::{
    BehaviorSet, Context, Executor, Leaf, LoadError, Node, NodeId, NodeState, NodeStatus, Observer, Selection, Status,
    TickError, Tree,
};

use crate::World;
use crate::agent::{Agent, TreeState};
use crate::end::{Ends, Stop};
use crate::record::{Recorder, Ticked};

/// Simulated time: the `now` bt-core's tick `k` (from 1) gets is
/// `(k - 1 + first) * ms_per_tick`. Only timed node kinds (BehaviorTree.CPP's `Delay`,
/// `Timeout`, ...) read it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Clock {
    /// Milliseconds per tick.
    pub ms_per_tick: u32,
    /// Ticks already on the clock at tick 1 (0: tick 1 at `now` 0).
    pub first: u32,
}

impl Clock {
    /// Ten ticks a second, tick 1 at 0 ms: the rate of the worlds and of the example
    /// firmware.
    pub const TENTHS: Self = Self { ms_per_tick: 100, first: 0 };

    /// `now` for tick `tick` (from 1).
    #[inline]
    #[must_use]
    pub const fn now(self, tick: u32) -> u32 {
        tick.saturating_sub(1).saturating_add(self.first).saturating_mul(self.ms_per_tick)
    }
}

/// How the runner runs an episode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Settings {
    /// Most ticks an episode makes; reaching it ends it with [`Stop::Limit`] (0: the
    /// episode ends before its first tick).
    pub limit: u32,
    /// Simulated time.
    pub clock: Clock,
    /// After the last tick of an episode ended by the tick limit, the world moves on
    /// once more (the agents act, the world steps): the last tick's commands take effect.
    pub moves_on_at_limit: bool,
    /// The same after the tick on which an end rule stopped the episode.
    pub moves_on_at_stop: bool,
    /// Halt the actions still running when the episode ends at the tick limit or in a
    /// loop, so that none is left half done (the tree is then reset to Idle).
    pub halt_at_limit: bool,
}

impl Settings {
    /// At most `limit` ticks on `clock`; the world moves on after every tick, the last
    /// one too; nothing is halted at the end.
    #[must_use]
    pub const fn new(limit: u32, clock: Clock) -> Self {
        Self { limit, clock, moves_on_at_limit: true, moves_on_at_stop: true, halt_at_limit: false }
    }
}

/// How an episode ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// Why it ended.
    pub stop: Stop,
    /// Ticks made (the last one's number).
    pub ticks: u32,
    /// What the root returned on the last tick.
    pub root: Status,
}

/// Where an episode's tree comes from, and whether it may grow when the root fails:
/// the blended planning and acting of Colledanchise et al. 2019 (Algorithm 1 at run
/// time) expands the failed condition in place and goes on from the world as it is.
pub trait Trees<W: ?Sized> {
    /// What a growth was, for recorders.
    type Growth;
    /// Why the tree could not grow.
    type Error;

    /// The tree as it is now, validated.
    ///
    /// # Errors
    /// The tree is not valid for its behavior set.
    fn tree<const D: usize>(&self) -> Result<Tree<'_, D>, LoadError>;

    /// The root failed at `tick`, the nodes in `states`: grow the tree and return what
    /// was done (the episode goes on with the new tree), or `None` to end the episode.
    ///
    /// # Errors
    /// Whatever stopped the growth; the episode ends with it.
    fn grow(&mut self, tick: u32, states: &[NodeState], world: &mut W) -> Result<Option<Self::Growth>, Self::Error>;
}

/// A tree that does not grow: nodes, their value table and the behavior set they are
/// validated against.
#[derive(Debug)]
pub struct Fixed<'a, C: ?Sized> {
    /// The nodes, in pre-order.
    pub nodes: &'a [Node],
    /// Their value table.
    pub values: &'a [u16],
    /// The behavior set.
    pub catalog: &'a C,
}

impl<W: ?Sized, C: bt_core::Catalog + ?Sized> Trees<W> for Fixed<'_, C> {
    type Growth = ();
    type Error = std::convert::Infallible;

    fn tree<const D: usize>(&self) -> Result<Tree<'_, D>, LoadError> {
        Tree::validate_with(self.nodes, self.values, self.catalog)
    }

    fn grow(&mut self, _: u32, _: &[NodeState], _: &mut W) -> Result<Option<()>, Self::Error> {
        Ok(None)
    }
}

/// Why [`Runner::run_growing`] stopped early.
#[derive(Debug, thiserror::Error)]
#[error("tick {tick}: {kind}")]
pub struct RunError<E> {
    /// The tick it happened at (0: before the first).
    pub tick: u32,
    /// What happened.
    pub kind: RunErrorKind<E>,
}

/// What stopped a run early.
#[derive(Debug, thiserror::Error)]
pub enum RunErrorKind<E> {
    /// The tree is not valid.
    #[error("the tree is not valid: {0}")]
    Invalid(LoadError),
    /// A behavior broke the tick rules.
    #[error("{0}")]
    Tick(TickError),
    /// The tree could not grow.
    #[error("{0}")]
    Grow(E),
}

/// Runs episodes, keeping the node states and scratch buffers between them: an episode
/// of a recorder-less, agent-less run allocates nothing once warm.
///
/// A runner is `Send` and `Clone`; parallel evaluation gives each worker its own, and
/// results do not depend on which worker ran which tree.
#[derive(Clone, Debug)]
pub struct Runner {
    settings: Settings,
    states: Vec<NodeState>,
    calls: Vec<(NodeId, Status)>,
    changes: Vec<(NodeId, NodeStatus, NodeStatus)>,
}

/// How one stretch of ticks of one tree ended.
struct Part {
    outcome: Outcome,
    /// The root failed and the tree may grow.
    grow: bool,
    /// Nodes of the tree.
    nodes: usize,
}

impl Runner {
    /// A runner with these settings.
    #[must_use]
    pub fn new(settings: Settings) -> Self {
        Self { settings, states: Vec::new(), calls: Vec::new(), changes: Vec::new() }
    }

    /// The runner, keeping node states in `states` (storage it takes over).
    #[must_use]
    pub fn with_states(mut self, states: Vec<NodeState>) -> Self {
        self.states = states;
        self
    }

    /// The node states' storage, handed back.
    #[must_use]
    pub fn into_states(self) -> Vec<NodeState> {
        self.states
    }

    /// The settings.
    #[must_use]
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The settings, to change between episodes.
    pub fn settings_mut(&mut self) -> &mut Settings {
        &mut self.settings
    }

    /// Each node's state after the last tick of the last episode (parallel to its tree's
    /// nodes; entries past them are left over from larger trees).
    #[must_use]
    pub fn states(&self) -> &[NodeState] {
        &self.states
    }

    /// One episode of `tree` in `world` as the world is now (reset it first for an
    /// episode from the start).
    ///
    /// # Errors
    /// [`TickError`] when a behavior breaks the tick rules.
    #[inline]
    pub fn run<const D: usize, W, E, A, R>(
        &mut self,
        tree: Tree<'_, D>,
        world: &mut W,
        ends: &mut E,
        agents: &mut A,
        recorder: &mut R,
    ) -> Result<Outcome, TickError>
    where
        W: World,
        E: Ends<W>,
        A: Agent<W>,
        R: Recorder<W>,
    {
        if R::ENABLED {
            recorder.start(world, &TreeState { nodes: tree.nodes(), states: &[] });
        }
        if A::ENABLED {
            agents.start(world);
        }
        let part = self.part::<D, W, E, A, R, ()>(tree, 1, world, ends, agents, recorder, false).map_err(|e| e.1)?;
        if R::ENABLED {
            let states = self.states.get(..part.nodes).unwrap_or(&[]);
            recorder.end(&part.outcome, &TreeState { nodes: tree.nodes(), states }, world);
        }
        Ok(part.outcome)
    }

    /// One episode of a tree that may grow when its root fails ([`Trees::grow`]): the
    /// grown tree goes on from the world as it is, with fresh node states, the tick count
    /// and the clock going on; after a growth the world moves on before the next tick
    /// (the agents act, the world steps).
    ///
    /// # Errors
    /// A tree that is not valid, a behavior that breaks the tick rules, or the tree
    /// failing to grow, each with the tick.
    pub fn run_growing<const D: usize, W, T, E, A, R>(
        &mut self,
        trees: &mut T,
        world: &mut W,
        ends: &mut E,
        agents: &mut A,
        recorder: &mut R,
    ) -> Result<Outcome, RunError<T::Error>>
    where
        W: World,
        T: Trees<W>,
        E: Ends<W>,
        A: Agent<W>,
        R: Recorder<W, T::Growth>,
    {
        let invalid = |tick, e| RunError { tick, kind: RunErrorKind::Invalid(e) };
        let mut first = 1;
        loop {
            let part = {
                let tree: Tree<'_, D> = trees.tree().map_err(|e| invalid(first - 1, e))?;
                if first == 1 {
                    if R::ENABLED {
                        recorder.start(world, &TreeState { nodes: tree.nodes(), states: &[] });
                    }
                    if A::ENABLED {
                        agents.start(world);
                    }
                }
                if first > self.settings.limit {
                    // The tree grew on the last tick.
                    let outcome = Outcome { stop: Stop::Limit, ticks: self.settings.limit, root: Status::Failure };
                    Part { outcome, grow: false, nodes: 0 }
                } else {
                    self.part::<D, W, E, A, R, T::Growth>(tree, first, world, ends, agents, recorder, true)
                        .map_err(|(tick, e)| RunError { tick, kind: RunErrorKind::Tick(e) })?
                }
            };
            let tick = part.outcome.ticks;
            let states = self.states.get(..part.nodes).unwrap_or(&[]);
            let growth = if part.grow {
                trees.grow(tick, states, world).map_err(|e| RunError { tick, kind: RunErrorKind::Grow(e) })?
            } else {
                None
            };
            let tree: Tree<'_, D> = trees.tree().map_err(|e| invalid(tick, e))?;
            let Some(growth) = growth else {
                if R::ENABLED {
                    let states = if part.nodes == tree.len() { states } else { &[] };
                    recorder.end(&part.outcome, &TreeState { nodes: tree.nodes(), states }, world);
                }
                return Ok(part.outcome);
            };
            if R::ENABLED {
                recorder.grown(tick, &growth, tree.nodes());
            }
            // The world moves on between the failed tick and the new tree's first.
            if A::ENABLED {
                agents.act(tick, world, &TreeState { nodes: tree.nodes(), states: &[] });
            }
            world.step();
            if R::ENABLED {
                recorder.stepped(tick, part.outcome.root, states, world);
            }
            first = tick + 1;
        }
    }

    /// Ticks `tree` from tick `first` until an end rule or the limit stops it (or, with
    /// `grows`, until the root fails).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn part<const D: usize, W, E, A, R, G>(
        &mut self,
        tree: Tree<'_, D>,
        first: u32,
        world: &mut W,
        ends: &mut E,
        agents: &mut A,
        recorder: &mut R,
        grows: bool,
    ) -> Result<Part, (u32, TickError)>
    where
        W: World,
        E: Ends<W>,
        A: Agent<W>,
        R: Recorder<W, G>,
        G: ?Sized,
    {
        let n = tree.len();
        if self.states.len() < n {
            self.states.resize(n, NodeState::IDLE);
        }
        let Self { settings, states, calls, changes } = self;
        let settings = *settings;
        let mut exec = match Executor::new(tree, &mut states[..n]) {
            Ok(exec) => exec,
            // The slice holds exactly one state per node.
            Err(_) => return Err((first, TickError::OutOfRange { node: n })),
        };
        ends.start(world);
        if first > settings.limit {
            // No tick left (a limit of 0).
            let outcome = Outcome { stop: Stop::Limit, ticks: first - 1, root: Status::Running };
            return Ok(Part { outcome, grow: false, nodes: n });
        }
        let mut tick = first;
        loop {
            let now = settings.clock.now(tick);
            let root = if R::ENABLED && (R::LEAVES || R::CHANGES) {
                calls.clear();
                changes.clear();
                let mut spy = Spy { world: &mut *world, calls: &mut *calls, on: R::LEAVES };
                let mut seen = Changes { changes: &mut *changes };
                if R::CHANGES { exec.tick_observed(&mut spy, now, &mut seen) } else { exec.tick(&mut spy, now) }
            } else {
                exec.tick(&mut *world, now)
            }
            .map_err(|e| (tick, e))?;
            if R::ENABLED {
                let view = TreeState { nodes: tree.nodes(), states: exec.states() };
                recorder.ticked(&Ticked { tick, root, tree: view, calls, changes }, world);
            }
            let stop = ends.check(tick, root, world);
            let at_limit = tick >= settings.limit;
            let (end, moves_on) = match stop {
                Some(Stop::Failure) if grows => {
                    return Ok(Part {
                        outcome: Outcome { stop: Stop::Failure, ticks: tick, root },
                        grow: true,
                        nodes: n,
                    });
                }
                Some(stop) => (Some(stop), settings.moves_on_at_stop),
                None if at_limit => (Some(Stop::Limit), settings.moves_on_at_limit),
                None => (None, true),
            };
            if moves_on {
                if A::ENABLED {
                    agents.act(tick, world, &TreeState { nodes: tree.nodes(), states: exec.states() });
                }
                world.step();
                if R::ENABLED {
                    recorder.stepped(tick, root, exec.states(), world);
                }
            }
            if let Some(stop) = end {
                if settings.halt_at_limit && matches!(stop, Stop::Limit | Stop::Loop) {
                    exec.halt_all(&mut *world);
                }
                return Ok(Part { outcome: Outcome { stop, ticks: tick, root }, grow: false, nodes: n });
            }
            tick += 1;
        }
    }
}

/// The world as the executor sees it during a recorded tick: every leaf call is also
/// written down.
struct Spy<'a, W> {
    world: &'a mut W,
    calls: &'a mut Vec<(NodeId, Status)>,
    on: bool,
}

impl<W: BehaviorSet> BehaviorSet for Spy<'_, W> {
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let s = self.world.condition(leaf, ctx);
        if self.on {
            self.calls.push((ctx.node, s));
        }
        s
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let s = self.world.action(leaf, ctx);
        if self.on {
            self.calls.push((ctx.node, s));
        }
        s
    }

    fn halt(&mut self, leaf: &Leaf, node: NodeId) {
        self.world.halt(leaf, node);
    }

    fn script(&mut self, code: &[u16], ctx: Context<'_>) -> Result<Value, ScriptFault> {
        self.world.script(code, ctx)
    }

    fn pop(&mut self, queue: u16, value: u16, ctx: Context<'_>) -> Result<bool, ScriptFault> {
        self.world.pop(queue, value, ctx)
    }

    fn select(&mut self, children: u8, ctx: Context<'_>) -> Result<Selection, ScriptFault> {
        self.world.select(children, ctx)
    }
}

/// Every status change of a recorded tick.
struct Changes<'a> {
    changes: &'a mut Vec<(NodeId, NodeStatus, NodeStatus)>,
}

impl Observer for Changes<'_> {
    fn on_change(&mut self, node: NodeId, old: NodeStatus, new: NodeStatus) {
        self.changes.push((node, old, new));
    }
}

#[cfg(test)]
mod tests;
