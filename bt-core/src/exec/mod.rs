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
//!    `SequenceStar`'s place and a `RunOnce`'s result always, a `RoundRobin`'s turn, a
//!    `Recovery`'s count and a `SequenceStarV3`'s place unless halted while Running. A `RateController` or `Gate` starts
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
//! 14. **BehaviorTree.CPP 3.** Its kinds follow 3.8's nodes. A `SequenceStarV3` goes on
//!     to the next child in the same tick when a child succeeds (no wake-up), keeps its
//!     place after a Failure and through resets, and goes back to its first child when
//!     it is halted while Running. A `ParallelV3` counts anew on every tick, in child
//!     order: a child that finished earlier in the activation counts where it stands, one
//!     that has not is ticked; it returns Success as soon as `success_threshold` have
//!     succeeded, Failure as soon as `failure_threshold` have failed or fewer than
//!     `success_threshold` can still succeed, and then resets every child (halting the
//!     Running ones); otherwise Running. A `Cycles` is a `RepeatCycles` (or, with
//!     `retry`, a `RetryUntilSuccessful`) whose count may be read on every tick from a
//!     slot (through [`BehaviorSet::script`], a one-word program that loads it: -1 is no
//!     limit, other negative counts are 0, anything else that is no count from 0 to
//!     65,534 ends the tick with [`TickError::Script`]); with `v3` the child is ticked
//!     again in the same tick after every cycle, without a wake-up, up to 65,535
//!     cycles in a tick (then Running, with a wake-up: 3.8 never returns from a loop for
//!     ever over a child that finishes at once). Reaching its count
//!     without ticking the child (a count that fell) halts a child still Running. A
//!     `Check` runs its program on every tick: when it holds, it ticks its child and
//!     returns what the child returns; otherwise (a fault included, as 3.8's failed
//!     `getInput`) it halts a Running child and returns `otherwise`.
//!
//! After a tick, a node's status is what it returned when last ticked in the current
//! activation of its parent, and `Idle` for nodes that were halted or left behind:
//! children of a Sequence/Fallback after the one it returned at are reset, so what a
//! renderer shows is what happened.

//!
//! # Two loops
//!
//! Every executor ticks with one of two copies of the same loop. The *plain* one runs the
//! papers' kinds (rules 1 to 7) and knows nothing of BehaviorTree.CPP's: the compiler
//! leaves their families, Skipped and the wake-up signal out of it. A tree that uses one
//! of BehaviorTree.CPP's kinds ticks with the *full* one; so does a tree of the papers'
//! kinds from the moment a leaf returns Skipped, from that leaf on. Both give the same
//! results: the plain loop is the full one with what cannot happen taken out.

// Without the `btcpp` feature, the frames and memory of its kinds are never used.
#![cfg_attr(not(feature = "btcpp"), allow(dead_code))]

// The tick loop and what it stands on.
mod frame;
mod halting;
mod run;
mod tick;
// The papers' kinds, one file per family (and Skipped in Sequence and Fallback).
mod decorators;
mod ordered;
mod parallel;
mod skipped;
// BehaviorTree.CPP's and Nav2's kinds, one file per family, in the full loop only.
#[cfg(feature = "btcpp")]
mod branches;
#[cfg(feature = "btcpp")]
mod btcpp;
#[cfg(feature = "btcpp")]
mod counting;
#[cfg(feature = "btcpp")]
mod guards;
#[cfg(feature = "btcpp")]
mod loops;
#[cfg(feature = "btcpp")]
mod manual_selector;
#[cfg(feature = "btcpp")]
mod parallel_all;
#[cfg(feature = "btcpp")]
mod scripts;
#[cfg(feature = "btcpp")]
mod sequences;
#[cfg(feature = "btcpp")]
mod timers;

use self::frame::{Extra, Frame};
use self::halting::Scan;
use self::run::{Run, Side};
use crate::behavior::{BehaviorSet, Observer, TickError};
use crate::node::{NodeId, NodeKind};
use crate::status::{NodeStatus, Status};
use crate::tree::Tree;

/// The runtime state of one node, kept by the caller in an array parallel to the nodes.
/// 4 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[repr(C, align(4))]
pub struct NodeState {
    /// Sequence/Fallback (with or without memory): the child it returned at when last
    /// ticked (children after it are Idle). Repeat/Retry/Timeout: the count. The kinds
    /// of BehaviorTree.CPP: as their family's file says.
    aux: u16,
    status: NodeStatus,
    /// 0 except for the kinds of BehaviorTree.CPP that need a third byte (a 24-bit start
    /// time, a count): with no padding byte the whole state is written in one store.
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

/// What an [`Executor`] carries between ticks besides the node states: the wake-up
/// signal, and (with BehaviorTree.CPP's kinds) whether a leaf has returned Skipped, after
/// which the tree ticks with the full loop. [`Executor::carry`] takes it,
/// [`Executor::resume`] gives it back.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Carry {
    woken: bool,
    #[cfg(feature = "btcpp")]
    full: bool,
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
    /// No node in the tree that ticks another child after one still Running (`Parallel`,
    /// `Timeout`, ...): see `Run::still_running`.
    still_running: bool,
    /// The tree has a `TimeLimit`, `Delay` or `Sleep`: see `Run::timers`.
    #[cfg(feature = "btcpp")]
    timers: bool,
    /// The tree has a `Guard`, whose `_onHalted` may fail while a tick halts.
    #[cfg(feature = "btcpp")]
    guards: bool,
}

#[derive(Debug)]
struct Stack<const DEPTH: usize> {
    frames: [Frame; DEPTH],
    extra: [Extra; DEPTH],
    side: Side<DEPTH>,
}

/// Binds a tick's pieces: `$run`, the [`Run`] over the executor's tree, its state (one
/// entry per node, which lets the compiler drop the state bounds checks) and the caller's
/// behaviors, and the stack's `$frames` and `$extra`. A macro, not a function: returned
/// from a function, even one always inlined, the pieces cost the plain loop 3 to 5 % more
/// instructions per tick on the benchmark trees.
macro_rules! tick_pieces {
    ($exec:ident, $behaviors:ident, $observer:ident, $full:literal => $run:ident, $frames:ident, $extra:ident) => {
        let Stack { frames: $frames, extra: $extra, side } = &mut $exec.stack;
        let nodes = $exec.tree.nodes();
        let state = match $exec.state.get_mut(..nodes.len()) {
            Some(s) => s,
            None => return Err(oob(nodes.len())),
        };
        let mut $run = Run::<B, O, DEPTH, $full> {
            nodes,
            values: $exec.tree.values(),
            state,
            side,
            behaviors: $behaviors,
            observer: $observer,
            still_running: $exec.still_running,
        };
    };
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
        Self::resume(tree, state, Carry::default())
    }

    /// An executor that goes on from where another over the same `tree` and `state`
    /// stopped: the node states are kept as they are, and `carry` is what that executor's
    /// [`Executor::carry`] returned. For a caller that cannot keep an executor between
    /// ticks (it borrows the tree and the state): a sans-IO controller that owns the
    /// storage and makes an executor for each tick.
    ///
    /// # Errors
    /// [`StateTooSmall`] when `state` has fewer entries than the tree has nodes.
    pub fn resume(tree: Tree<'t, DEPTH>, state: &'s mut [NodeState], carry: Carry) -> Result<Self, StateTooSmall> {
        if state.len() < tree.len() {
            return Err(StateTooSmall { needed: tree.len(), given: state.len() });
        }
        let nodes = tree.nodes();
        let still_running = !nodes.iter().any(|n| match n.kind() {
            NodeKind::Parallel { .. } | NodeKind::Timeout(_) => true,
            NodeKind::ParallelAll { .. } | NodeKind::ParallelV3 { .. } | NodeKind::PipelineSequence => BTCPP,
            _ => false,
        });
        // Decided once: a tree of the papers' kinds ticks with the plain loop.
        let full = BTCPP && nodes.iter().any(|n| !n.kind().family().is_papers());
        #[cfg(feature = "btcpp")]
        let full = full || carry.full;
        let mut stack =
            Stack { frames: [Frame::default(); DEPTH], extra: [Extra::default(); DEPTH], side: Side::new(full) };
        stack.side.woken = carry.woken;
        Ok(Self {
            tree,
            state,
            stack,
            still_running,
            #[cfg(feature = "btcpp")]
            timers: nodes
                .iter()
                .any(|n| matches!(n.kind(), NodeKind::TimeLimit(_) | NodeKind::Delay(_) | NodeKind::Sleep(_))),
            #[cfg(feature = "btcpp")]
            guards: nodes.iter().any(|n| matches!(n.kind(), NodeKind::Guard(_))),
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
        self.stack.side.woken
    }

    /// What this executor carries from one tick to the next besides the node states,
    /// for [`Executor::resume`].
    #[must_use]
    pub fn carry(&self) -> Carry {
        Carry {
            woken: self.stack.side.woken,
            #[cfg(feature = "btcpp")]
            full: self.stack.side.full,
        }
    }

    /// Returns [`Executor::woken`] and clears it.
    pub fn take_woken(&mut self) -> bool {
        core::mem::take(&mut self.stack.side.woken)
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
        #[cfg(feature = "btcpp")]
        if self.stack.side.full {
            return self.tick_full(behaviors, now, observer);
        }
        tick_pieces!(self, behaviors, observer, false => run, frames, extra);
        let result = run.run_loop(frames, extra, now, 0, 0, None);
        if result.is_err() {
            // Mid-tick, nodes on the path have not taken their new status yet: scan all.
            run.cold().reset(0, Scan::All);
        }
        result
    }

    /// [`Executor::tick_observed`] with the full loop, out of line: the plain loop does
    /// not even keep what calling it needs.
    #[cfg(feature = "btcpp")]
    #[inline(never)]
    fn tick_full<B: BehaviorSet, O: Observer>(
        &mut self,
        behaviors: &mut B,
        now: u32,
        observer: &mut O,
    ) -> Result<Status, TickError> {
        let (timers, guards) = (self.timers, self.guards);
        tick_pieces!(self, behaviors, observer, true => run, frames, extra);
        run.tick_full(frames, extra, now, timers, guards)
    }

    /// Halts every Running action (post-order) and resets the whole tree to Idle.
    pub fn halt_all<B: BehaviorSet>(&mut self, behaviors: &mut B) {
        self.halt_all_observed(behaviors, &mut ());
    }

    /// As [`Executor::halt_all`], reporting status changes to `observer`.
    pub fn halt_all_observed<B: BehaviorSet, O: Observer>(&mut self, behaviors: &mut B, observer: &mut O) {
        let mut run = Run::<B, O, DEPTH, BTCPP> {
            nodes: self.tree.nodes(),
            values: self.tree.values(),
            state: self.state,
            side: &mut self.stack.side,
            behaviors,
            observer,
            still_running: self.still_running,
        };
        run.reset(0, Scan::All);
        // An `_onHalted` script that failed here is not reported: there is no tick.
        #[cfg(feature = "btcpp")]
        {
            self.stack.side.fault = None;
        }
    }
}

const fn oob(node: usize) -> TickError {
    TickError::OutOfRange { node }
}

/// Whether this build has BehaviorTree.CPP's kinds and Skipped (rule 8): the `btcpp`
/// feature. Without it no kind returns Skipped, a leaf that does is a
/// [`TickError::LeafSkipped`], and there is no full loop: those kinds would cost a
/// controller's flash.
pub(crate) const BTCPP: bool = cfg!(feature = "btcpp");
