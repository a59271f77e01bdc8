//! The executor: iterative, with an explicit stack of `DEPTH` frames, over caller-owned
//! per-node state. No recursion, no allocation, each node visited at most once per tick.
//!
//! # Tick semantics
//!
//! 1. Statuses are Success, Failure, Running. A condition returning Running is reported
//!    as [`TickError::ConditionRunning`].
//! 2. Reactive `Sequence` ticks children from the first and returns the first Failure or
//!    Running, Success when all succeed; `Fallback` mirrors it.
//! 3. A node that was Running and is not reached, or is reached and abandoned, is halted:
//!    each Running action below it gets one `halt` call, children before parents and left
//!    to right (post-order), and the subtree's state goes back to Idle (subtrees already
//!    Idle at their root are left as they are).
//! 4. Halt before start: before an action *starts* (it was not Running), every Running
//!    branch that it preempts — a later child of a reactive ancestor that was Running on
//!    the previous tick, with an action Running in it — is halted. If the tick returns to
//!    the old branch without starting an action, the old branch keeps running and is
//!    never halted.
//! 5. When the root returns Success or Failure, the next tick starts a new activation:
//!    memory, counters and parallel results are only kept for nodes that are Running.
//! 6. With-memory nodes resume at the child that was Running. `Parallel` does not re-tick
//!    children that finished in the current activation, and returns as soon as a
//!    threshold is reached, halting the children still Running.
//! 7. `Repeat`, `Retry` and `Timeout` count ticks and activations, never `now`.
//! 8. **Skipped** means the node did nothing this tick and has no result. A Sequence or
//!    Fallback goes on past a child that skipped (a reactive one resets it) and skips
//!    itself when no child returned the status it goes on after; `Parallel` ticks a child
//!    that skipped again next tick, counts it towards success in that tick only with
//!    `count_skipped`, and skips when all children skipped; `ParallelAll` likewise, without
//!    counting it; decorators pass it on, except `KeepRunningUntilFailure` (Running) and
//!    `Recovery` (a skipped recovery fails it). A control node or decorator that skips
//!    stays Running (a `Precondition`, and a `ManualSelector` that did not ask, keeps its
//!    status) and keeps its memory; a leaf
//!    that skips, and a `RunOnce` or `Gate` that skips without ticking its child, is
//!    Idle.
//! 9. The kinds that stand for BehaviorTree.CPP's and Nav2's nodes follow their
//!    originals step by step (the rules of each are on [`NodeKind`] and in
//!    `docs/behaviortree-cpp.md`), and reset their children when the originals do: a
//!    Running child is halted (rule 3), any other child only becomes Idle, its subtree
//!    left as it is. Their memory survives resets where the originals' does: a
//!    `SequenceStar`'s place and a `RunOnce`'s result always, a `RoundRobin`'s turn and a
//!    `Recovery`'s count unless halted while Running. A `RateController` or `Gate` starts
//!    afresh when it is Idle, or when it finished under a parent that BehaviorTree.CPP
//!    would have reset it under (any parent but these kinds).
//! 10. **Time.** `TimeLimit`, `Delay`, `RateController` and `Sleep` measure spans of `now` (for
//!     trees imported from BehaviorTree.CPP: milliseconds), from start times kept in 24
//!     bits. Before a tick of a tree that has a `TimeLimit` or `Delay`, the timers that
//!     expired since the last tick act, in pre-order: a `TimeLimit` whose child still runs
//!     halts it (the tick then fails the `TimeLimit`), and a `Delay` whose span has passed
//!     asks for a wake-up, as does a Running `Sleep` whose span has passed. A `Sleep` is
//!     Running from its first tick until the span has passed, then succeeds; with a span
//!     of 0 it succeeds at once.
//! 11. **Wake-up.** A `SequenceStar` whose child succeeds after being Idle, with more to
//!     go, returns Running; a `RepeatCycles` (`RetryUntilSuccessful`) whose child succeeds
//!     (fails) after being Idle, with cycles left, returns Running; both ask to be ticked
//!     again at once ([`Executor::woken`]), as do the timers of rule 10. A child that was
//!     Running and finishes is ticked again at once instead. A tick is thus
//!     BehaviorTree.CPP's `tickExactlyOnce()`; its `tickOnce()` is a loop on `woken`.
//! 12. **Scripts.** A `Script` or `ScriptCondition` is a leaf that finishes in the tick
//!     it is reached, like a condition: its program runs once, through
//!     [`BehaviorSet::script`]; a `Script` then succeeds, a
//!     `ScriptCondition` succeeds when the result holds ([`script::truth`](crate::script::truth))
//!     and fails otherwise. A `Precondition` runs its program when it starts and while
//!     its child has not yet been let go: if the result holds it ticks its child, and
//!     goes on ticking it without asking again until the child succeeds or fails;
//!     otherwise it returns its `else` status (Idle for Skipped). That it let its child
//!     go survives halts, as in BehaviorTree.CPP. A `Loop`, when it starts afresh (as
//!     a `RateController` does, rule 9) or its child is not Running, takes the next
//!     element of its queue into its `value` slot (a literal queue's element program
//!     through [`BehaviorSet::script`], a blackboard queue
//!     through [`BehaviorSet::pop`]) and ticks its child;
//!     with no element left it returns `if_empty` (and skipping keeps its status). It
//!     returns Running after its child succeeds or skips, Failure when the child fails.
//!     A `Guard` runs BehaviorTree.CPP's
//!     scripted attributes around its one child: when it starts afresh (as a
//!     `RateController` does, rule 9), `_failureIf`, `_successIf` and `_skipIf`, the
//!     first that holds deciding Failure, Success or Skipped without ticking the child,
//!     then `_while`, which skips when false; while Running, only `_while`, which halts
//!     the child, runs `_onHalted` and skips when false; when the result is Success or
//!     Failure, `_onSuccess` or `_onFailure`, then `_post`, and the child is reset (its
//!     status only); when the guard is halted while Running, `_onHalted` after its
//!     subtree. A guard that skips keeps its child's status (Idle when it decided). A
//!     script that stops with a fault ends the tick with
//!     [`TickError::Script`], where BehaviorTree.CPP throws.
//! 13. **Manual selection.** A `ManualSelector` asks the behavior set on every tick
//!     ([`BehaviorSet::select`], with `starting` set when it starts afresh) which child
//!     to tick, or which status to return without ticking one, and returns what the
//!     chosen child returns; with `repeat_last_selection` it asks once and from then on
//!     makes the same choice without asking, for the life of the executor (halts and
//!     activations keep it). Before it ticks the chosen child, or returns Success or
//!     Failure, a child still Running that was not chosen is halted (halt before start;
//!     BehaviorTree.CPP leaves it Running); returning Running leaves it Running,
//!     unticked. Its children keep their statuses when they finish, as
//!     BehaviorTree.CPP's do. Without children it asks for a status only. A child it
//!     does not have ends the tick with [`TickError::NoSuchChild`], a set that refuses
//!     with [`TickError::Script`].
//!
//! After a tick, a node's status is what it returned when last ticked in the current
//! activation of its parent, and `Idle` for nodes that were halted or left behind:
//! children of a Sequence/Fallback after the one it returned at are reset, so what a
//! renderer shows is what happened.

// Without the `btcpp` feature, the frames and memory of its kinds are never used.
#![cfg_attr(not(feature = "btcpp"), allow(dead_code))]

#[cfg(feature = "btcpp")]
mod kinds;

use crate::behavior::{BehaviorSet, Context, Observer, TickError};
use crate::node::{Node, NodeId, NodeKind};
use crate::status::{NodeStatus, Status};
use crate::tree::Tree;

/// The runtime state of one node, kept by the caller in an array parallel to the nodes.
/// 4 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[repr(C, align(4))]
pub struct NodeState {
    /// Sequence/Fallback (with or without memory): the child it returned at when last
    /// ticked (children after it are Idle). Repeat/Retry/Timeout: the count. The other
    /// kinds: see `kinds.rs`.
    aux: u16,
    status: NodeStatus,
    /// 0 except for the kinds of `kinds.rs` that need a third byte (a 24-bit start time,
    /// a count): with no padding byte the whole state is written in one store.
    ext: u8,
}

const _: () = assert!(size_of::<NodeState>() == 4);

impl NodeState {
    /// The state of a node that has not been ticked; fill storage with it.
    pub const IDLE: NodeState = NodeState { status: NodeStatus::Idle, aux: 0, ext: 0 };

    /// What the node returned when last ticked, or Idle.
    #[inline(always)]
    #[must_use]
    pub const fn status(&self) -> NodeStatus {
        self.status
    }
}

/// The state array is shorter than the tree.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "state array holds {}, the tree has {}",
    crate::error::Count(*.given, "entry", "entries"),
    crate::error::Count(*.needed, "node", "nodes")
)]
pub struct StateTooSmall {
    /// Entries needed (the tree's node count).
    pub needed: usize,
    /// Entries given.
    pub given: usize,
}

/// What a frame's node is: all the ascent needs to know without reading the node.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(u8)]
enum FrameKind {
    // The ordered kinds come first: see `is_ordered` and `goes_on_after`.
    #[default]
    Sequence = 0,
    Fallback = 1,
    SequenceWithMemory = 2,
    FallbackWithMemory = 3,
    /// A reactive Sequence or Fallback ticking its last child: see [`Frame`].
    Last,
    Parallel,
    Inverter,
    ForceSuccess,
    ForceFailure,
    Repeat,
    Retry,
    Timeout,
    // The kinds of `kinds.rs` (BehaviorTree.CPP's and Nav2's): they reset their children
    // as BehaviorTree.CPP does, see `Run::fresh`.
    SequenceStar,
    IfThenElse,
    WhileDoElse,
    ParallelAll,
    PipelineSequence,
    Recovery,
    RoundRobin,
    RepeatCycles,
    RetryUntilSuccessful,
    KeepRunningUntilFailure,
    RunOnce,
    Precondition,
    Loop,
    ManualSelector,
    TimeLimit,
    Delay,
    RateController,
    Gate,
    Guard,
}

impl FrameKind {
    /// Sequence or Fallback, with or without memory.
    #[inline(always)]
    fn is_ordered(self) -> bool {
        (self as u8) < 4
    }

    /// SequenceWithMemory or FallbackWithMemory.
    #[inline(always)]
    fn is_memory(self) -> bool {
        matches!(self, Self::SequenceWithMemory | Self::FallbackWithMemory)
    }

    /// One of the kinds of `kinds.rs`, which keep a finished child's status exactly when
    /// BehaviorTree.CPP does.
    #[inline]
    fn mirrors_btcpp(self) -> bool {
        (self as u8) >= (Self::SequenceStar as u8)
    }

    /// For an ordered kind: the status after which it ticks the next child.
    #[inline(always)]
    fn goes_on_after(self) -> Status {
        if (self as u8) & 1 == 0 { Status::Success } else { Status::Failure }
    }
}

/// One level of the path from the root to the node being ticked. 8 bytes, so the
/// innermost frame lives in a register.
///
/// A Sequence or Fallback (either flavour) keeps the rest of what it needs in its own
/// state, which does not change before it returns: the child it returned at last time,
/// and whether it was Running. The loop writes only `node`, `end` and `kind` for it.
///
/// A reactive Sequence or Fallback ticking its *last* child gets a
/// [`FrameKind::Last`] frame, of which only `node` is read: when the child returns,
/// there is no next child, no later child to reset, and the status goes up unchanged;
/// the node only records it and the child it returned at. Rule 4 has nothing to halt in
/// it either: its previous child cannot come after its last. Trees built by
/// backchaining are mostly such tails (`Fallback[condition, Sequence[...]]`).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(8))]
struct Frame {
    /// The control node or decorator.
    node: u16,
    /// One past its last descendant.
    end: u16,
    /// Repeat/Retry/Timeout: the count so far. Otherwise unused.
    a: u16,
    kind: FrameKind,
    /// The node was Running when the tick reached it (not a new activation). Set for
    /// the nodes [`Run::enter_other`] opens.
    running: bool,
}

/// What a Parallel or a counting decorator needs beyond its [`Frame`], kept at the
/// same depth in a side stack so that frames stay small. The kinds of `kinds.rs` use
/// the fields as they say there.
#[derive(Clone, Copy, Debug, Default)]
struct Extra {
    /// Parallel: children that succeeded. Repeat/Retry/Timeout: `n`.
    ok: u16,
    /// Parallel: children that failed.
    failed: u16,
    /// Parallel: number of children.
    children: u16,
    /// Parallel: success threshold.
    success: u16,
    /// Parallel: failure threshold.
    failure: u16,
    /// Parallel: children that returned Skipped in this tick.
    skipped: u16,
    /// Parallel: skipped children count towards `success`.
    count_skipped: bool,
    /// `RepeatCycles`, `RetryUntilSuccessful`: the child was Idle when ticked.
    child_was_idle: bool,
}

/// Ticks one validated tree against a behavior set.
///
/// Holds the stack (`DEPTH` frames) between ticks so a tick initializes nothing; the
/// per-node state lives in the caller's array.
#[derive(Debug)]
pub struct Executor<'t, 's, const DEPTH: usize> {
    tree: Tree<'t, DEPTH>,
    state: &'s mut [NodeState],
    stack: Stack<DEPTH>,
    /// No `Parallel` or `Timeout` in the tree: see [`Run::still_running`].
    still_running: bool,
    /// The tree has a `TimeLimit` or `Delay`: see [`Run::timers`].
    timers: bool,
    /// What a tick leaves beside the statuses: see [`Side`].
    side: Side,
    /// The tree has a `Guard`, whose `_onHalted` may fail while a tick halts.
    #[cfg(feature = "btcpp")]
    guards: bool,
}

#[derive(Debug)]
struct Stack<const DEPTH: usize> {
    frames: [Frame; DEPTH],
    extra: [Extra; DEPTH],
    halt: [u16; DEPTH],
}

impl<'t, 's, const DEPTH: usize> Executor<'t, 's, DEPTH> {
    /// An executor over `tree` using `state` (at least one entry per node), which it
    /// resets to Idle.
    ///
    /// # Errors
    /// [`StateTooSmall`] when `state` has fewer entries than the tree has nodes.
    pub fn new(tree: Tree<'t, DEPTH>, state: &'s mut [NodeState]) -> Result<Self, StateTooSmall> {
        if state.len() < tree.len() {
            return Err(StateTooSmall { needed: tree.len(), given: state.len() });
        }
        state.fill(NodeState::IDLE);
        let stack = Stack { frames: [Frame::default(); DEPTH], extra: [Extra::default(); DEPTH], halt: [0; DEPTH] };
        let still_running = !tree.nodes().iter().any(|n| match n.kind() {
            NodeKind::Parallel { .. } | NodeKind::Timeout(_) => true,
            NodeKind::ParallelAll { .. } | NodeKind::PipelineSequence => BTCPP,
            _ => false,
        });
        let timers = BTCPP
            && tree
                .nodes()
                .iter()
                .any(|n| matches!(n.kind(), NodeKind::TimeLimit(_) | NodeKind::Delay(_) | NodeKind::Sleep(_)));
        Ok(Self {
            tree,
            state,
            stack,
            still_running,
            timers,
            side: Side::default(),
            #[cfg(feature = "btcpp")]
            guards: tree.nodes().iter().any(|n| matches!(n.kind(), NodeKind::Guard(_))),
        })
    }

    /// True when a node asked to be ticked again at once since [`Executor::take_woken`]
    /// last cleared it: BehaviorTree.CPP's wake-up signal. A `SequenceStar`,
    /// `RepeatCycles` or `RetryUntilSuccessful` asks when it returns Running after a
    /// child that finished at once; a `TimeLimit` that expires and a `Delay` that ends
    /// ask too. BehaviorTree.CPP's `tickOnce()` ticks again while the root is Running
    /// and the signal is set; [`Executor::tick`] is its `tickExactlyOnce()`:
    ///
    /// ```ignore
    /// let mut status = exec.tick(&mut world, now)?;
    /// while status == Status::Running && exec.take_woken() {
    ///     status = exec.tick(&mut world, now)?;
    /// }
    /// ```
    #[must_use]
    pub fn woken(&self) -> bool {
        self.side.woken
    }

    /// Returns [`Executor::woken`] and clears it.
    pub fn take_woken(&mut self) -> bool {
        core::mem::take(&mut self.side.woken)
    }

    /// The tree being ticked.
    #[must_use]
    pub fn tree(&self) -> Tree<'t, DEPTH> {
        self.tree
    }

    /// The per-node states, parallel to the tree's nodes.
    #[must_use]
    pub fn states(&self) -> &[NodeState] {
        self.state.get(..self.tree.len()).unwrap_or(&[])
    }

    /// The status of node `id`.
    #[must_use]
    pub fn status(&self, id: NodeId) -> Option<NodeStatus> {
        self.states().get(usize::from(id)).map(NodeState::status)
    }

    /// Ticks the tree once.
    ///
    /// # Errors
    /// [`TickError`] when a behavior breaks the rules; the tree is then halted
    /// ([`Executor::halt_all`]) before returning.
    #[inline]
    pub fn tick<B: BehaviorSet>(&mut self, behaviors: &mut B, now: u32) -> Result<Status, TickError> {
        self.tick_observed(behaviors, now, &mut ())
    }

    /// Ticks the tree once, reporting every status change to `observer`.
    ///
    /// # Errors
    /// As [`Executor::tick`].
    pub fn tick_observed<B: BehaviorSet, O: Observer>(
        &mut self,
        behaviors: &mut B,
        now: u32,
        observer: &mut O,
    ) -> Result<Status, TickError> {
        let Stack { frames, extra, halt } = &mut self.stack;
        let nodes = self.tree.nodes();
        // Exactly one state per node: lets the compiler drop the state bounds checks.
        let state = match self.state.get_mut(..nodes.len()) {
            Some(s) => s,
            None => return Err(oob(nodes.len())),
        };
        let values = self.tree.values();
        let mut run = Run {
            nodes,
            values,
            state,
            halt_stack: halt,
            behaviors,
            observer,
            still_running: self.still_running,
            #[cfg(feature = "btcpp")]
            side: &mut self.side,
        };
        #[cfg(feature = "btcpp")]
        if self.timers {
            run.cold().timers(now);
        }
        let result = run.tick(frames, extra, now);
        // A guard's `_onHalted` that failed while the tick halted its node.
        #[cfg(feature = "btcpp")]
        let result = if self.guards { run.cold().guard_fault(result) } else { result };
        if result.is_err() {
            // Mid-tick, nodes on the path have not taken their new status yet: scan all.
            run.cold().reset(0, Scan::All);
        }
        result
    }

    /// Halts every Running action (post-order) and resets the whole tree to Idle.
    pub fn halt_all<B: BehaviorSet>(&mut self, behaviors: &mut B) {
        self.halt_all_observed(behaviors, &mut ());
    }

    /// As [`Executor::halt_all`], reporting status changes to `observer`.
    pub fn halt_all_observed<B: BehaviorSet, O: Observer>(&mut self, behaviors: &mut B, observer: &mut O) {
        let mut run = Run {
            nodes: self.tree.nodes(),
            values: self.tree.values(),
            state: self.state,
            halt_stack: &mut self.stack.halt,
            behaviors,
            observer,
            still_running: self.still_running,
            #[cfg(feature = "btcpp")]
            side: &mut self.side,
        };
        run.reset(0, Scan::All);
        // An `_onHalted` script that failed here is not reported: there is no tick.
        #[cfg(feature = "btcpp")]
        {
            self.side.fault = None;
        }
    }
}

/// Which nodes [`Run::reset`] visits.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Scan {
    /// Skip subtrees whose root is Idle (their nodes are all Idle): between ticks, and
    /// mid-tick for subtrees off the current path.
    SkipIdle,
    /// Every node: when the state may not be consistent (a tick stopped half-way).
    All,
}

/// The borrowed pieces of one tick, split so that the hot loop sees plain slices.
struct Run<'r, B, O, const DEPTH: usize> {
    nodes: &'r [Node],
    /// The tree's value table, handed to behaviors in their [`Context`].
    values: &'r [u16],
    state: &'r mut [NodeState],
    halt_stack: &'r mut [u16; DEPTH],
    behaviors: &'r mut B,
    observer: &'r mut O,
    /// An action that was Running and runs on ends the tick: every ancestor was Running
    /// at the child on the path to it and stays so, with nothing to reset (an ancestor's
    /// later children were reset when it last returned there). True when the tree has
    /// no `Parallel`, `ParallelAll` or `PipelineSequence`, which go on to tick other
    /// children, and no `Timeout`, which counts the tick; the other decorators return
    /// Running unchanged, and the clocked ones decide on the way down.
    still_running: bool,
    /// What the tick leaves beside the statuses.
    #[cfg(feature = "btcpp")]
    side: &'r mut Side,
}

/// What a tick leaves beside the statuses (one pointer in [`Run`], which the tick loop
/// keeps in registers).
#[derive(Debug, Default)]
struct Side {
    /// A node asked to be ticked again at once: see [`Executor::woken`].
    woken: bool,
    /// A fault of a script run while halting (a `Guard`'s `_onHalted`), which the tick
    /// returns.
    #[cfg(feature = "btcpp")]
    fault: Option<TickError>,
}

const fn oob(node: usize) -> TickError {
    TickError::OutOfRange { node }
}

/// Whether this build has the kinds of `kinds.rs` and Skipped (rule 8): the `btcpp`
/// feature. Without it no kind returns Skipped, a leaf that does is a
/// [`TickError::LeafSkipped`], and the compiler drops every Skipped path and every check
/// for those kinds from the tick loop: they cost a controller's flash.
pub(crate) const BTCPP: bool = cfg!(feature = "btcpp");

/// A leaf returned Skipped in a build without the `btcpp` feature.
#[cold]
#[inline(never)]
const fn leaf_skipped(node: usize, behavior: u16) -> TickError {
    TickError::LeafSkipped { node: node as NodeId, behavior }
}

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH> {
    /// The same pieces, reborrowed for a call out of the tick loop. Built where the call
    /// is made, so that the loop keeps its pieces in registers instead of laying out a
    /// `Run` in memory on every tick for calls that are rarely made.
    #[inline(always)]
    fn cold(&mut self) -> Run<'_, B, O, DEPTH> {
        Run {
            nodes: self.nodes,
            values: self.values,
            state: &mut *self.state,
            halt_stack: &mut *self.halt_stack,
            behaviors: &mut *self.behaviors,
            observer: &mut *self.observer,
            still_running: self.still_running,
            #[cfg(feature = "btcpp")]
            side: &mut *self.side,
        }
    }

    #[inline(always)]
    fn node(&self, i: usize) -> Result<&Node, TickError> {
        self.nodes.get(i).ok_or(oob(i))
    }

    #[inline(always)]
    fn status(&self, i: usize) -> NodeStatus {
        self.state.get(i).map_or(NodeStatus::Idle, NodeState::status)
    }

    #[inline(always)]
    fn set_status(&mut self, i: usize, new: NodeStatus) {
        if let Some(s) = self.state.get_mut(i) {
            let old = s.status;
            s.status = new;
            if O::ENABLED && old != new {
                self.observer.on_change(i as NodeId, old, new);
            }
        }
    }

    /// Sets status and `aux` at once.
    #[inline(always)]
    fn set_state(&mut self, i: usize, new: NodeStatus, aux: u16) {
        if let Some(s) = self.state.get_mut(i) {
            let old = s.status;
            *s = NodeState { status: new, aux, ext: 0 };
            if O::ENABLED && old != new {
                self.observer.on_change(i as NodeId, old, new);
            }
        }
    }

    /// Records `node` as the reactive Sequence or Fallback whose children the child loop
    /// ticks at `depth`: it goes in the frame it pushes if a child needs one.
    #[inline(always)]
    fn ticking(frames: &mut [Frame; DEPTH], depth: usize, node: usize) -> Result<(), TickError> {
        match frames.get_mut(depth) {
            Some(slot) => {
                slot.node = node as u16;
                Ok(())
            }
            None => Err(oob(node)),
        }
    }

    /// Sets a node Idle and its `aux` to 0: the tick relies on an Idle node's `aux`
    /// being 0 (no child returned at, no count).
    #[inline(always)]
    fn set_idle(&mut self, i: usize) {
        self.set_state(i, NodeStatus::Idle, 0);
    }

    /// Control node or decorator `i` is reset: Idle, and its memory cleared, except
    /// what BehaviorTree.CPP keeps through a reset: a `SequenceStar`'s place, a
    /// `RunOnce`'s result and a `ManualSelector`'s last selection always, a `RoundRobin`'s and a `Recovery`'s counters unless it
    /// is halted while Running.
    fn set_idle_halted(&mut self, i: usize) {
        if !BTCPP {
            return self.set_idle(i);
        }
        #[cfg(feature = "btcpp")]
        if let Some(&NodeKind::Guard(table)) = self.nodes.get(i).map(Node::kind) {
            self.cold().guard_halted(i, table);
        }
        let keep = match self.nodes.get(i).map(Node::kind) {
            Some(
                NodeKind::SequenceStar
                | NodeKind::RunOnce { .. }
                | NodeKind::Precondition { .. }
                | NodeKind::ManualSelector { .. },
            ) => true,
            Some(NodeKind::RoundRobin | NodeKind::Recovery { .. }) => self.status(i) != NodeStatus::Running,
            _ => false,
        };
        if keep { self.set_status(i, NodeStatus::Idle) } else { self.set_idle(i) }
    }

    #[inline(always)]
    fn set_aux(&mut self, i: usize, aux: u16) {
        if let Some(s) = self.state.get_mut(i) {
            s.aux = aux;
        }
    }

    /// Sets `aux` and `ext`, leaving the status as it is.
    #[inline]
    fn set_memory(&mut self, i: usize, aux: u16, ext: u8) {
        if let Some(s) = self.state.get_mut(i) {
            s.aux = aux;
            s.ext = ext;
        }
    }

    /// Control node or decorator `i` returns `r`. One that returns Skipped stays
    /// Running, as BehaviorTree.CPP leaves it: it marked itself Running before it ticked
    /// its children.
    #[inline]
    fn set_returned(&mut self, i: usize, r: Status) {
        let new = if BTCPP && r == Status::Skipped { self.skipped_status(i) } else { r.into() };
        self.set_status(i, new);
    }

    /// The status of a control node or decorator `i` that returned Skipped: Running, as
    /// BehaviorTree.CPP leaves it (it marked itself Running before it ticked its
    /// children), but a Guard takes the status its child kept (BehaviorTree.CPP's node
    /// keeps its own when it skips), and a Precondition keeps its own (BehaviorTree.CPP's
    /// does not mark itself Running), as does a ManualSelector that repeated its last
    /// selection (one that asked has marked itself Running on the way up).
    #[cold]
    #[inline(never)]
    fn skipped_status(&self, i: usize) -> NodeStatus {
        match self.nodes.get(i).map(Node::kind) {
            Some(NodeKind::Guard(_)) => self.status(i + 1),
            Some(NodeKind::Precondition { .. } | NodeKind::ManualSelector { .. }) => self.status(i),
            _ => NodeStatus::Running,
        }
    }

    /// Node `i` decided Skipped without ticking a child: Idle, but a `Loop` keeps its
    /// status, as BehaviorTree.CPP's does.
    #[cold]
    #[inline(never)]
    fn decided_skipped(&mut self, i: usize) {
        if !matches!(self.nodes.get(i).map(Node::kind), Some(NodeKind::Loop { .. })) {
            self.set_status(i, NodeStatus::Idle);
        }
    }

    #[inline(always)]
    fn end_of(&self, i: usize) -> Result<usize, TickError> {
        Ok(i + usize::from(self.node(i)?.size()))
    }

    /// One tick from the root.
    ///
    /// `frames[..depth]` is the path from the root to the parent of node `c`, the node
    /// about to be ticked; `extra[d]` belongs to the frame at depth `d` when it is a
    /// Parallel or a counting decorator. While a reactive Sequence or Fallback ticks its
    /// children in place, its index is in `frames[depth].node`, the frame it pushes if
    /// a child needs one.
    #[inline(always)]
    fn tick(&mut self, frames: &mut [Frame; DEPTH], extra: &mut [Extra; DEPTH], now: u32) -> Result<Status, TickError> {
        let nodes = self.nodes;
        let values = self.values;
        let mut depth = 0usize;
        let mut c = 0usize;
        'descend: loop {
            let Some(node) = nodes.get(c) else {
                return Err(oob(c));
            };
            // Tick node `c`: a leaf returns at once; a control node or decorator pushes a
            // frame and descends into its first child.
            let (mut r, mut child_end) = match node.kind() {
                NodeKind::Condition(leaf) => {
                    let r = self.behaviors.condition(leaf, Context { node: c as NodeId, now, starting: true, values });
                    if r == Status::Running {
                        return Err(TickError::ConditionRunning { node: c as NodeId, behavior: leaf.behavior() });
                    }
                    if !BTCPP && r == Status::Skipped {
                        return Err(leaf_skipped(c, leaf.behavior()));
                    }
                    self.set_status(c, r.into());
                    (r, c + 1)
                }
                NodeKind::Action(leaf) => {
                    let starting = self.status(c) != NodeStatus::Running;
                    if starting {
                        self.cold().preempt(frames, depth, c);
                    }
                    let r = self.behaviors.action(leaf, Context { node: c as NodeId, now, starting, values });
                    if r == Status::Running && !starting && self.still_running {
                        return Ok(r);
                    }
                    if !BTCPP && r == Status::Skipped {
                        return Err(leaf_skipped(c, leaf.behavior()));
                    }
                    self.set_status(c, r.into());
                    (r, c + 1)
                }
                kind @ (NodeKind::Sequence | NodeKind::Fallback) => 'ordered: {
                    // Ticks the leading leaf children in place: a frame is pushed only
                    // when a child is itself a control node or decorator. The node's
                    // state stays as the tick found it until it returns, so what the
                    // frame and the return need of it is read then, not kept in
                    // registers through the loop.
                    let mut end = c + usize::from(node.size());
                    let mut go_on = if matches!(kind, NodeKind::Fallback) { Status::Failure } else { Status::Success };
                    let mut k = c + 1;
                    // The node being ticked is kept in the frame it would push, not in a
                    // register through the loop.
                    Self::ticking(frames, depth, c)?;
                    loop {
                        let Some(child) = nodes.get(k) else {
                            return Err(oob(k));
                        };
                        let r = match child.kind() {
                            NodeKind::Condition(leaf) => {
                                let r = self
                                    .behaviors
                                    .condition(leaf, Context { node: k as NodeId, now, starting: true, values });
                                if r == Status::Running {
                                    return Err(TickError::ConditionRunning {
                                        node: k as NodeId,
                                        behavior: leaf.behavior(),
                                    });
                                }
                                r
                            }
                            NodeKind::Action(leaf) if self.status(k) == NodeStatus::Running => {
                                let r = self
                                    .behaviors
                                    .action(leaf, Context { node: k as NodeId, now, starting: false, values });
                                if r == Status::Running && self.still_running {
                                    return Ok(r);
                                }
                                r
                            }
                            // A control child, or an action about to start (rule 4 may
                            // halt others first): ticked on the general path, under a
                            // frame for this node.
                            child_kind => {
                                let child_end = k + usize::from(child.size());
                                let Some(slot) = frames.get_mut(depth) else {
                                    return Err(oob(k));
                                };
                                if child_end >= end {
                                    // The last child: a one-field frame (see `Frame`).
                                    slot.kind = FrameKind::Last;
                                } else {
                                    // What it returned at last time, and whether it was
                                    // Running, are read from its state when needed: that
                                    // stays as it was until the node returns.
                                    slot.end = end as u16;
                                    slot.kind = if go_on == Status::Failure {
                                        FrameKind::Fallback
                                    } else {
                                        FrameKind::Sequence
                                    };
                                }
                                depth += 1;
                                // A reactive Sequence or Fallback child is ticked by this
                                // same loop, without going back to the dispatch above.
                                match child_kind {
                                    NodeKind::Sequence => go_on = Status::Success,
                                    NodeKind::Fallback => go_on = Status::Failure,
                                    _ => {
                                        c = k;
                                        continue 'descend;
                                    }
                                }
                                Self::ticking(frames, depth, k)?;
                                end = child_end;
                                k += 1;
                                continue;
                            }
                        };
                        self.set_status(k, r.into());
                        if r == go_on && k + 1 < end {
                            k += 1;
                            continue;
                        }
                        c = frames.get(depth).map_or(0, |f| usize::from(f.node));
                        if r == Status::Skipped {
                            if !BTCPP {
                                let behavior = match child.kind() {
                                    NodeKind::Condition(leaf) | NodeKind::Action(leaf) => leaf.behavior(),
                                    _ => 0,
                                };
                                return Err(leaf_skipped(k, behavior));
                            }
                            // A leaf that skipped: the node goes on as after `go_on`.
                            if k + 1 < end {
                                k += 1;
                                continue;
                            }
                            let r = self.cold().finish_skipped(c, end, k, go_on, false)?;
                            break 'ordered (r, end);
                        }
                        // Returns at child `k`: reset the children it reached last
                        // time beyond `k`.
                        self.finish_ordered(c, end, k, k + 1, r)?;
                        // Its parent goes on to the next child, a reactive Sequence or
                        // Fallback: ticked by this loop at once (the way back would
                        // come to the same).
                        if let Some(f) = depth.checked_sub(1).and_then(|top| frames.get(top))
                            && f.kind.is_ordered()
                            && r == f.kind.goes_on_after()
                            && end < usize::from(f.end)
                            && let Some(next) = nodes.get(end)
                        {
                            go_on = match next.kind() {
                                NodeKind::Sequence => Status::Success,
                                NodeKind::Fallback => Status::Failure,
                                _ => break 'ordered (r, end),
                            };
                            Self::ticking(frames, depth, end)?;
                            k = end + 1;
                            end += usize::from(next.size());
                            continue;
                        }
                        break 'ordered (r, end);
                    }
                }
                kind => 'enter: {
                    // Whether the parent keeps a finished child's status as
                    // BehaviorTree.CPP does (see `fresh`).
                    let parent_mirrors = BTCPP
                        && depth.checked_sub(1).and_then(|d| frames.get(d)).is_some_and(|f| f.kind.mirrors_btcpp());
                    let Some(slot) = frames.get_mut(depth) else {
                        return Err(oob(c));
                    };
                    let st = self.state.get(c).copied().unwrap_or_default();
                    let end = c + usize::from(node.size());
                    *slot = Frame {
                        node: c as u16,
                        end: end as u16,
                        // Set by `enter_other` for the kinds that count.
                        a: 0,
                        kind: FrameKind::Sequence,
                        running: st.status == NodeStatus::Running,
                    };
                    let Some(x) = extra.get_mut(depth) else {
                        return Err(oob(c));
                    };
                    let first = match self.cold().enter_other(kind, st, slot, x, parent_mirrors, now)? {
                        Entered::Child(first) => first,
                        Entered::Decided(v) => {
                            // A Loop that skips keeps its status, as BehaviorTree.CPP's
                            // node does (the only kind that may skip while Running).
                            if BTCPP && v == Status::Skipped {
                                self.cold().decided_skipped(c);
                            } else {
                                self.set_status(c, v.into());
                            }
                            break 'enter (v, end);
                        }
                    };
                    depth += 1;
                    c = first;
                    continue 'descend;
                }
            };

            // Ascend: node `c` (ending at `child_end`) returned `r` to the frame at
            // `depth - 1`.
            while let Some(top) = depth.checked_sub(1) {
                let Some(f) = frames.get(top) else {
                    return Err(oob(c));
                };
                if f.kind == FrameKind::Last {
                    // Its subtree ends where its last child's does.
                    let node = usize::from(f.node);
                    if BTCPP && r == Status::Skipped {
                        r = self.cold().last_skipped(node, c)?;
                    } else {
                        self.set_state(node, r.into(), c as u16);
                    }
                    c = node;
                    depth = top;
                    continue;
                }
                let f = *f;
                let more = child_end < usize::from(f.end);
                if f.kind.is_ordered() {
                    // Sequence goes on after Success, Fallback after Failure.
                    if r == f.kind.goes_on_after() && more {
                        c = child_end;
                        continue 'descend;
                    }
                    if BTCPP && r == Status::Skipped {
                        match self.cold().ordered_skipped(&f, c, child_end)? {
                            Ascent::Tick(next) => {
                                c = next;
                                continue 'descend;
                            }
                            Ascent::Return(v) => r = v,
                        }
                    } else {
                        if BTCPP && f.kind.is_memory() && r != Status::Running {
                            self.cold().reset_running(usize::from(f.node) + 1, c);
                        }
                        self.finish_ordered(usize::from(f.node), usize::from(f.end), c, child_end, r)?;
                    }
                } else {
                    match self.cold().ascend_other(frames, extra, top, c, child_end, r, now)? {
                        Ascent::Tick(next) => {
                            c = next;
                            continue 'descend;
                        }
                        Ascent::Return(v) => r = v,
                    }
                    self.set_returned(usize::from(f.node), r);
                }
                // The frame's node returns `r` to the frame below.
                c = usize::from(f.node);
                child_end = usize::from(f.end);
                depth = top;
            }
            return Ok(r);
        }
    }

    /// Enters a node other than a reactive Sequence or Fallback: fills in its frame and
    /// side entry, and says which child to tick first.
    #[cold]
    #[inline(never)]
    fn enter_other(
        &mut self,
        kind: &NodeKind,
        st: NodeState,
        frame: &mut Frame,
        x: &mut Extra,
        parent_mirrors: bool,
        now: u32,
    ) -> Result<Entered, TickError> {
        let idx = usize::from(frame.node);
        let end = usize::from(frame.end);
        let running = frame.running;
        match *kind {
            NodeKind::SequenceWithMemory | NodeKind::FallbackWithMemory => {
                frame.kind = if matches!(kind, NodeKind::SequenceWithMemory) {
                    FrameKind::SequenceWithMemory
                } else {
                    FrameKind::FallbackWithMemory
                };
                // Resume at the child that was Running.
                return Ok(Entered::Child(if running { usize::from(st.aux) } else { idx + 1 }));
            }
            NodeKind::Parallel { success_threshold, failure_threshold, count_skipped } => {
                frame.kind = FrameKind::Parallel;
                *x = Extra {
                    ok: 0,
                    failed: 0,
                    children: 0,
                    success: success_threshold,
                    failure: failure_threshold,
                    skipped: 0,
                    // Also guarded here: without the feature the store is then a constant
                    // (12 B of the firmware's flash).
                    count_skipped: BTCPP && count_skipped,
                    child_was_idle: false,
                };
                // As BehaviorTree.CPP, the counts are totals of the activation: the
                // children that finished on earlier ticks count from the start.
                let mut c = idx + 1;
                while c < end {
                    x.children = x.children.saturating_add(1);
                    if running {
                        match self.status(c) {
                            NodeStatus::Success => x.ok = x.ok.saturating_add(1),
                            NodeStatus::Failure => x.failed = x.failed.saturating_add(1),
                            _ => {}
                        }
                    }
                    c = self.end_of(c)?;
                }
                return match self.parallel_step(idx + 1, end, running)? {
                    Some(c) => Ok(Entered::Child(c)),
                    // Impossible: a Running parallel has a child that has not finished.
                    None => {
                        self.finish_parallel(idx, end, end)?;
                        Ok(Entered::Decided(Status::Failure))
                    }
                };
            }
            NodeKind::Repeat(n) | NodeKind::Retry(n) | NodeKind::Timeout(n) => {
                frame.kind = match kind {
                    NodeKind::Repeat(_) => FrameKind::Repeat,
                    NodeKind::Retry(_) => FrameKind::Retry,
                    _ => FrameKind::Timeout,
                };
                x.ok = n;
                frame.a = if running { st.aux } else { 0 };
            }
            NodeKind::Inverter => frame.kind = FrameKind::Inverter,
            NodeKind::ForceSuccess => frame.kind = FrameKind::ForceSuccess,
            NodeKind::ForceFailure => frame.kind = FrameKind::ForceFailure,
            NodeKind::Sequence | NodeKind::Fallback | NodeKind::Condition(_) | NodeKind::Action(_) => {
                return Err(oob(idx));
            }
            #[cfg(feature = "btcpp")]
            _ => return self.enter_btcpp(kind, st, frame, x, parent_mirrors, now),
            // Refused by validation without the feature.
            #[cfg(not(feature = "btcpp"))]
            _ => {
                let _ = (parent_mirrors, now);
                return Err(oob(idx));
            }
        }
        Ok(Entered::Child(idx + 1))
    }

    /// Child `c` (ending at `child_end`) returned `r` to a frame other than a Sequence
    /// or Fallback: tick another child, or return.
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn ascend_other(
        &mut self,
        frames: &mut [Frame; DEPTH],
        extra: &mut [Extra; DEPTH],
        depth: usize,
        c: usize,
        child_end: usize,
        r: Status,
        now: u32,
    ) -> Result<Ascent, TickError> {
        let (Some(top), Some(x)) = (frames.get_mut(depth), extra.get_mut(depth)) else {
            return Err(oob(c));
        };
        if top.kind.mirrors_btcpp() {
            #[cfg(feature = "btcpp")]
            return self.ascend_btcpp(top, x, c, child_end, r, now);
            #[cfg(not(feature = "btcpp"))]
            {
                let _ = now;
                return Err(oob(c));
            }
        }
        let top = *top;
        let node = usize::from(top.node);
        Ok(Ascent::Return(match top.kind {
            FrameKind::Parallel => {
                match r {
                    Status::Success => x.ok = x.ok.saturating_add(1),
                    Status::Failure => x.failed = x.failed.saturating_add(1),
                    Status::Skipped if BTCPP => x.skipped = x.skipped.saturating_add(1),
                    Status::Running | Status::Skipped => {}
                }
                if let Some(v) = parallel_verdict(x) {
                    self.finish_parallel(node, usize::from(top.end), child_end)?;
                    v
                } else {
                    match self.parallel_step(child_end, usize::from(top.end), top.running)? {
                        Some(next) => return Ok(Ascent::Tick(next)),
                        None if BTCPP && x.skipped == x.children => Status::Skipped,
                        None => Status::Running,
                    }
                }
            }
            FrameKind::Inverter => match r {
                Status::Success => Status::Failure,
                Status::Failure => Status::Success,
                Status::Running | Status::Skipped => r,
            },
            FrameKind::ForceSuccess if r == Status::Failure => Status::Success,
            FrameKind::ForceFailure if r == Status::Success => Status::Failure,
            FrameKind::Repeat | FrameKind::Retry => {
                let again = if top.kind == FrameKind::Repeat { Status::Success } else { Status::Failure };
                if r == again {
                    let count = top.a.saturating_add(1);
                    if count < x.ok {
                        self.set_aux(node, count);
                        Status::Running
                    } else {
                        r
                    }
                } else {
                    if r == Status::Running {
                        self.set_aux(node, top.a);
                    }
                    r
                }
            }
            FrameKind::Timeout if r == Status::Running => {
                let count = top.a.saturating_add(1);
                if count >= x.ok {
                    self.reset_subtree(c);
                    Status::Failure
                } else {
                    self.set_aux(node, count);
                    Status::Running
                }
            }
            _ => r,
        }))
    }

    /// Sequence or Fallback `node` (either flavour, subtree ending at `end`) returns `r`
    /// at child `child`, whose subtree ends at `next`: reset the children it reached last
    /// time beyond `child`, remember `child`.
    #[inline(always)]
    fn finish_ordered(
        &mut self,
        node: usize,
        end: usize,
        child: usize,
        next: usize,
        r: Status,
    ) -> Result<(), TickError> {
        // The child it returned at last time (0 for an Idle node: see `set_idle`), from
        // its state, which does not change before it returns.
        let last = self.state.get(node).map_or(0, |s| usize::from(s.aux));
        if last > child {
            // `end - 1` cannot wrap: `child` lies inside the subtree, below `end`.
            self.cold().reset_range(next, last.min(end - 1))?;
        }
        self.set_state(node, r.into(), child as u16);
        Ok(())
    }

    /// Resets the siblings from `from` up to and including the one starting at `last`.
    #[cold]
    #[inline(never)]
    fn reset_range(&mut self, from: usize, last: usize) -> Result<(), TickError> {
        let mut c = from;
        while c <= last {
            let after = self.end_of(c)?;
            self.reset_subtree(c);
            c = after;
        }
        Ok(())
    }

    /// True when a child of `node` (subtree ending at `end`) has status `s`.
    fn any_child(&self, node: usize, end: usize, s: NodeStatus) -> Result<bool, TickError> {
        let mut c = node + 1;
        while c < end {
            if self.status(c) == s {
                return Ok(true);
            }
            c = self.end_of(c)?;
        }
        Ok(false)
    }

    /// Reactive or memory Sequence/Fallback `node` (subtree ending at `end`) got
    /// Skipped from its last child `child`: it returns `go_on`, or Skipped when no child
    /// returned `go_on` in this activation (children that skipped are Idle or Running).
    /// A node that returns Skipped stays Running, resuming at its first child.
    #[cold]
    #[inline(never)]
    fn finish_skipped(
        &mut self,
        node: usize,
        end: usize,
        child: usize,
        go_on: Status,
        memory: bool,
    ) -> Result<Status, TickError> {
        let any = self.any_child(node, end, go_on.into())?;
        if memory {
            // Finished: BehaviorTree.CPP resets all children, here those still Running.
            self.reset_running(node + 1, end);
        }
        if any {
            self.set_state(node, go_on.into(), child as u16);
            Ok(go_on)
        } else {
            self.set_state(node, NodeStatus::Running, if memory { node as u16 + 1 } else { child as u16 });
            Ok(Status::Skipped)
        }
    }

    /// A reactive Sequence or Fallback ticking its last child `child` (a
    /// [`FrameKind::Last`] frame) got Skipped from it.
    #[cold]
    #[inline(never)]
    fn last_skipped(&mut self, node: usize, child: usize) -> Result<Status, TickError> {
        // BehaviorTree.CPP halts a reactive node's child that skipped.
        self.reset_subtree(child);
        let go_on = match self.node(node)?.kind() {
            NodeKind::Fallback => Status::Failure,
            _ => Status::Success,
        };
        let end = self.end_of(node)?;
        self.finish_skipped(node, end, child, go_on, false)
    }

    /// An ordered frame `f` got Skipped from child `c` (ending at `child_end`): go on
    /// to the next child, or finish.
    #[cold]
    #[inline(never)]
    fn ordered_skipped(&mut self, f: &Frame, c: usize, child_end: usize) -> Result<Ascent, TickError> {
        let memory = f.kind.is_memory();
        if !memory {
            self.reset_subtree(c);
        }
        if child_end < usize::from(f.end) {
            return Ok(Ascent::Tick(child_end));
        }
        let r = self.finish_skipped(usize::from(f.node), usize::from(f.end), c, f.kind.goes_on_after(), memory)?;
        Ok(Ascent::Return(r))
    }

    /// Resets the siblings from `from` up to (not including) `to` that are Running: the
    /// children that skipped before a SequenceWithMemory or FallbackWithMemory finishes.
    #[cold]
    #[inline(never)]
    fn reset_running(&mut self, from: usize, to: usize) {
        let mut c = from;
        while c < to {
            let Ok(after) = self.end_of(c) else { return };
            if self.status(c) == NodeStatus::Running {
                self.reset_subtree(c);
            }
            c = after;
        }
    }

    /// The next child of a parallel to tick, from `from` on: children that finished in
    /// the current activation (the parallel was Running) are passed over, their results
    /// already in the counts. `None` past the last child.
    fn parallel_step(&self, from: usize, end: usize, running: bool) -> Result<Option<usize>, TickError> {
        let mut c = from;
        while c < end {
            if !running || !matches!(self.status(c), NodeStatus::Success | NodeStatus::Failure) {
                return Ok(Some(c));
            }
            c = self.end_of(c)?;
        }
        Ok(None)
    }

    /// Parallel `node` decided: halt its Running children and reset those from
    /// `reached` on.
    fn finish_parallel(&mut self, node: usize, end: usize, reached: usize) -> Result<(), TickError> {
        let mut c = node + 1;
        while c < end {
            let after = self.end_of(c)?;
            if c >= reached || self.status(c) == NodeStatus::Running {
                self.reset_subtree(c);
            }
            c = after;
        }
        Ok(())
    }

    /// Rule 4: action `idx` is about to start. Halt every branch it preempts: for each
    /// reactive ancestor on the path (`frames[..depth]`) that was Running at a later
    /// child than the one being ticked, that child's subtree. Innermost first. Frames
    /// of nodes ticking their last child are passed over: nothing comes after it.
    #[cold]
    #[inline(never)]
    fn preempt(&mut self, frames: &[Frame; DEPTH], depth: usize, idx: usize) {
        if depth == 0 {
            return;
        }
        let mut current = idx;
        for f in frames.iter().take(depth).rev() {
            if matches!(f.kind, FrameKind::Sequence | FrameKind::Fallback)
                && let Some(&st) = self.state.get(usize::from(f.node))
                && st.status == NodeStatus::Running
            {
                let old = usize::from(st.aux);
                if old > current && self.runs_an_action(old) {
                    self.reset_subtree(old);
                }
            }
            current = usize::from(f.node);
        }
    }

    /// Whether an action is Running in the subtree of `root`: a branch without one (a
    /// `Delay` waiting, a `RepeatCycles` between cycles) preempts nothing.
    fn runs_an_action(&self, root: usize) -> bool {
        let Ok(end) = self.end_of(root) else { return false };
        (root..end).any(|i| {
            self.status(i) == NodeStatus::Running
                && matches!(self.nodes.get(i).map(Node::kind), Some(NodeKind::Action(_)))
        })
    }

    /// Halts the Running actions under `root` (post-order) and resets the subtree to
    /// Idle. Skips subtrees that are already Idle.
    #[inline]
    fn reset_subtree(&mut self, root: usize) {
        if self.status(root) != NodeStatus::Idle {
            self.reset(root, Scan::SkipIdle);
        }
    }

    /// Halts the Running actions under `root` in post-order (children before parents,
    /// left to right) and sets every node of the subtree to Idle.
    fn reset(&mut self, root: usize, scan: Scan) {
        let Ok(end) = self.end_of(root) else { return };
        let mut top = 0usize;
        let mut i = root;
        loop {
            // Close the open ancestors whose subtree ends here.
            while let Some(a) = top.checked_sub(1).and_then(|t| self.halt_stack.get(t)).map(|&a| usize::from(a)) {
                match self.end_of(a) {
                    Ok(a_end) if a_end <= i => {
                        top -= 1;
                        self.set_idle_halted(a);
                    }
                    _ => break,
                }
            }
            if i >= end {
                break;
            }
            let Some(node) = self.nodes.get(i).copied() else { break };
            if scan == Scan::SkipIdle && self.status(i) == NodeStatus::Idle {
                i += usize::from(node.size()).max(1);
                continue;
            }
            match node.kind() {
                NodeKind::Action(leaf) => {
                    if self.status(i) == NodeStatus::Running {
                        self.behaviors.halt(leaf, i as NodeId);
                    }
                    self.set_idle(i);
                }
                NodeKind::Condition(_) => self.set_idle(i),
                _ => match self.halt_stack.get_mut(top) {
                    Some(slot) => {
                        *slot = i as u16;
                        top += 1;
                    }
                    // Deeper than DEPTH: impossible for a validated tree.
                    None => self.set_idle_halted(i),
                },
            }
            i += 1;
        }
    }
}

enum Entered {
    /// Tick this child.
    Child(usize),
    /// The node returns this without a child being ticked.
    Decided(Status),
}

enum Ascent {
    /// Tick this child of the frame's node.
    Tick(usize),
    /// The frame's node returns this.
    Return(Status),
}

/// Success or Failure once a parallel's thresholds decide, else `None`.
#[inline]
fn parallel_verdict(x: &Extra) -> Option<Status> {
    if x.ok >= x.success || (BTCPP && x.count_skipped && x.ok.saturating_add(x.skipped) >= x.success) {
        Some(Status::Success)
    } else if x.failed >= x.failure || x.children.saturating_sub(x.failed) < x.success {
        Some(Status::Failure)
    } else {
        None
    }
}
