//! The node model: one flat pre-order array of [`Node`]s.
//!
//! Node `i`'s first child is `i + 1`; the next sibling of a child `c` is
//! `c + size(c)`. No pointers and no boxes: the same array is the in-memory arena, the
//! unit of validation and the payload of the image.

/// Index of a node in its tree's pre-order array.
pub type NodeId = u16;

/// Identifier of a behavior (a condition or an action) in a behavior set.
pub type BehaviorId = u16;

mod leaf;

pub use leaf::{Leaf, LeafError, LeafKind, MAX_ARGS};

/// A span of the caller's clock: a number of units of the `now` given to
/// [`Executor::tick`](crate::Executor::tick), at most [`Span::MAX`] (2^24 - 1), or
/// [`Span::NEVER`].
///
/// Trees imported from BehaviorTree.CPP count `now` in milliseconds, so a span is then
/// at most 16,777,215 ms (4 h 39 min). Stored as two `u16` so that a [`Node`] stays 12
/// bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Span {
    lo: u16,
    hi: u16,
}

impl Span {
    /// The longest span: the executor keeps a start time in 24 bits of a node's state.
    pub const MAX: u32 = (1 << 24) - 1;

    /// A span longer than any time the clock counts (`now` is a `u32`): a timer with it
    /// never expires, a `RateController` with it ticks its child only when it starts
    /// and while the child runs (Nav2's "plan once" idiom, a rate near 0 Hz).
    pub const NEVER: Span = Span { lo: u16::MAX, hi: u16::MAX };

    /// A span of `units`, or `None` above [`Span::MAX`].
    #[must_use]
    pub const fn new(units: u32) -> Option<Span> {
        if units > Self::MAX {
            return None;
        }
        Some(Span { lo: units as u16, hi: (units >> 16) as u16 })
    }

    /// The span in units of `now` (`u32::MAX` for [`Span::NEVER`], more than any
    /// elapsed time the executor measures).
    #[inline]
    #[must_use]
    pub const fn get(self) -> u32 {
        (self.hi as u32) << 16 | self.lo as u32
    }
}

/// A script's program: `len` words of the tree's value table from `start` (see
/// [`script`](crate::script)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Code {
    /// The first word.
    pub start: u16,
    /// The number of words (at least 1).
    pub len: u16,
}

impl Code {
    /// The program's words in `values` (its tree's value table); empty when the range
    /// lies outside, which a validated tree rules out.
    #[must_use]
    pub fn words<'v>(&self, values: &'v [u16]) -> &'v [u16] {
        let start = usize::from(self.start);
        values.get(start..start + usize::from(self.len)).unwrap_or(&[])
    }
}

/// What a node is and does.
///
/// Control nodes have one or more children (`IfThenElse` and `WhileDoElse` two or
/// three, `Recovery` two, `ManualSelector` any number, none included), decorators
/// exactly one, leaves none. The tick rules of every
/// kind are in [`exec`](crate::exec); which BehaviorTree.CPP and Nav2 node each kind
/// stands for is in `docs/behaviortree-cpp.md`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NodeKind {
    /// Reactive sequence: ticks children from the first on every tick; returns the first
    /// Failure or Running, Success when all succeed.
    Sequence,
    /// Reactive fallback (selector): ticks children from the first on every tick; returns
    /// the first Success or Running, Failure when all fail.
    Fallback,
    /// Sequence with memory: resumes at the child that was Running; children that
    /// succeeded in the current activation are not ticked again.
    SequenceWithMemory,
    /// Fallback with memory: resumes at the child that was Running; children that
    /// failed in the current activation are not ticked again.
    FallbackWithMemory,
    /// Ticks all children that have not finished in the current activation; Success
    /// once `success_threshold` succeeded, Failure once `failure_threshold` failed or
    /// success can no longer be reached. The rest are halted.
    Parallel {
        /// Children that must succeed.
        success_threshold: u16,
        /// Children whose failure makes the whole node fail.
        failure_threshold: u16,
        /// Children that return Skipped in a tick count towards `success_threshold` in
        /// that tick (BehaviorTree.CPP does so when its `success_count` is negative, i.e.
        /// counted from the number of children).
        count_skipped: bool,
    },
    /// Swaps Success and Failure.
    Inverter,
    /// Turns Failure into Success.
    ForceSuccess,
    /// Turns Success into Failure.
    ForceFailure,
    /// Runs its child until it has succeeded `n` times (one iteration per tick);
    /// fails as soon as the child fails.
    Repeat(u16),
    /// Runs its child until it succeeds, at most `n` attempts (one per tick);
    /// fails when the `n`-th attempt fails.
    Retry(u16),
    /// Gives its child at most `n` ticks per activation: if the child is still Running
    /// after its `n`-th tick, it is halted and the node fails.
    Timeout(u16),
    /// A condition leaf.
    Condition(Leaf),
    /// An action leaf.
    Action(Leaf),
    /// BehaviorTree.CPP's `SequenceWithMemory` (`SequenceStar` in its version 3): a
    /// sequence that keeps its place. After a Failure it resumes at the child that
    /// failed; a halt does not move it either. Only finishing with Success sends it back
    /// to the first child. When a child that had not been Running succeeds and more
    /// follow, it returns Running and asks to be ticked again at once.
    SequenceStar,
    /// `IfThenElse`: ticks the first child (the condition) when it starts; on Success
    /// ticks the second child, on Failure the third (or fails with two children), and
    /// stays with that branch while it runs.
    IfThenElse,
    /// `WhileDoElse`: ticks the first child (the condition) on every tick; on Success
    /// halts the third child and ticks the second, on Failure halts the second and ticks
    /// the third (or fails with two children).
    WhileDoElse,
    /// `ParallelAll`: ticks every child that has not finished until all have; then
    /// Failure if at least `max_failures` of them failed, else Success.
    ParallelAll {
        /// Failures that make it fail (0: it always fails).
        max_failures: u16,
    },
    /// Nav2's `PipelineSequence`: ticks its children in order on every tick; a child that
    /// returns Running before the furthest child reached so far does not stop it.
    PipelineSequence,
    /// Nav2's `RecoveryNode`: two children. Ticks the first; when it fails, ticks the
    /// second (the recovery) and, if that succeeds, the first again, at most `retries`
    /// times.
    Recovery {
        /// Recoveries before giving up.
        retries: u16,
    },
    /// Nav2's `RoundRobin`: ticks one child at a time, going on to the next after each
    /// one finishes, wrapping around; Success at the first child that succeeds (the next
    /// activation starts after it), Failure when all have failed in turn.
    RoundRobin,
    /// BehaviorTree.CPP's `Repeat(num_cycles)`: ticks its child until it has succeeded
    /// `n` times ([`NodeKind::FOREVER`]: no limit); fails as soon as the child fails.
    /// After a Success of a child that had not been Running, it returns Running and asks
    /// to be ticked again at once ([`Executor::woken`](crate::Executor::woken)); after a
    /// Success of a child that had been Running, it ticks the child again in the same
    /// tick.
    RepeatCycles(u16),
    /// BehaviorTree.CPP's `RetryUntilSuccessful(num_attempts)`: ticks its child until it
    /// succeeds, at most `n` times ([`NodeKind::FOREVER`]: no limit); after a Failure it
    /// goes on as [`NodeKind::RepeatCycles`] does after a Success.
    RetryUntilSuccessful(u16),
    /// `KeepRunningUntilFailure`: Running while the child succeeds or runs; Failure when
    /// it fails.
    KeepRunningUntilFailure,
    /// `RunOnce`: ticks its child until it finishes once, ever; from then on returns
    /// Skipped (`then_skip`) or what the child returned that once.
    RunOnce {
        /// Skipped after the one run, instead of the child's result.
        then_skip: bool,
    },
    /// BehaviorTree.CPP's `Timeout(msec)`: if the child is still Running once the span
    /// has passed since the node started, the child is halted and the node fails. A span
    /// of 0 never expires.
    TimeLimit(Span),
    /// `Delay(delay_msec)`: Running until the span has passed since the node started,
    /// then ticks its child.
    Delay(Span),
    /// Nav2's `RateController(hz)`: ticks its child when it starts, while the child runs,
    /// and once the span has passed since the child last succeeded; Running otherwise.
    RateController(Span),
    /// A decorator gated by a behavior of the set (Nav2's `DistanceController`,
    /// `SpeedController`, `GoalUpdater`, `SingleTrigger`, ...): the gate is asked on every
    /// tick through [`BehaviorSet::action`](crate::BehaviorSet::action), with `starting`
    /// set when the node starts. While the child runs, it is ticked whatever the gate
    /// says; otherwise Success ticks it, Failure and Running are returned as they are.
    /// The gate's behavior is declared as an action and is never halted.
    Gate(Leaf),
    /// `AlwaysSuccess`: a leaf that succeeds.
    AlwaysSuccess,
    /// `AlwaysFailure`: a leaf that fails.
    AlwaysFailure,
    /// BehaviorTree.CPP's `Script`: runs its program through
    /// [`BehaviorSet::script`](crate::BehaviorSet::script) and succeeds; a script that
    /// stops with a fault ends the tick with [`TickError::Script`](crate::TickError::Script).
    Script(Code),
    /// `ScriptCondition`: runs its program; Success when the result holds
    /// ([`script::truth`](crate::script::truth)), else Failure.
    ScriptCondition(Code),
    /// BehaviorTree.CPP's scripted attributes (`_skipIf`, `_successIf`, `_failureIf`,
    /// `_while`, `_onSuccess`, `_onFailure`, `_onHalted`, `_post`) of the node that is
    /// its one child: a table of scripts ([`script::hook`](crate::script::hook)) run
    /// before and after the child as BehaviorTree.CPP runs them around the node (tick
    /// rule 12). Its status is the one BehaviorTree.CPP gives that node.
    Guard(Code),
    /// BehaviorTree.CPP's `Sleep(msec)`: a leaf that is Running until the span has passed
    /// since it started, then succeeds (at once for a span of 0).
    Sleep(Span),
    /// BehaviorTree.CPP's `Precondition(if, else)`: runs its program when its child is
    /// not under way; if the result holds, ticks the child and keeps ticking it (without
    /// asking again) until it succeeds or fails, else returns `otherwise`. Whether the
    /// child is under way survives halts, as in BehaviorTree.CPP.
    Precondition {
        /// The `if` script.
        code: Code,
        /// The `else` status.
        otherwise: crate::Status,
    },
    /// BehaviorTree.CPP's `LoopInt`, `LoopBool`, `LoopDouble`, `LoopString` (and the
    /// `LoopNode<T>` a program registers): while its child is not Running, takes the
    /// next element of its queue into the `value` slot and ticks the child; Running after
    /// each Success of the child, Failure when the child fails, `if_empty` once the queue
    /// has no element left. Its table ([`script::queue`](crate::script::queue)) holds
    /// either one assignment program per element of a literal queue, or the slots of a
    /// blackboard queue that [`BehaviorSet::pop`](crate::BehaviorSet::pop) takes from.
    Loop {
        /// The queue's table.
        table: Code,
        /// The status when the queue is empty.
        if_empty: crate::Status,
    },
    /// BehaviorTree.CPP's `ManualSelector`, with the choice made on the controller: on
    /// every tick it asks the behavior set ([`BehaviorSet::select`](crate::BehaviorSet::select):
    /// an operator's command, a button) which child to tick, or which status to return
    /// without ticking one, and returns what that child returns. Without children it
    /// asks for a status only. A child still Running that is not the one chosen is
    /// halted before the chosen one is ticked (or the node returns Success or Failure).
    /// At most 255 children.
    ManualSelector {
        /// After the first choice, make the same one again on every tick, without
        /// asking (BehaviorTree.CPP's `repeat_last_selection`). The choice is kept for
        /// the life of the executor, through halts and activations.
        repeat_last: bool,
    },
    /// BehaviorTree.CPP 3's `SequenceStar`: as [`NodeKind::SequenceStar`] it keeps its
    /// place after a Failure, but a child that succeeds is followed by the next in the
    /// same tick, and a halt while it runs sends it back to its first child.
    SequenceStarV3,
    /// BehaviorTree.CPP 3's `Parallel(success_threshold, failure_threshold)`: on every
    /// tick it goes through its children in order, ticking those that have not finished
    /// in the activation and counting those that have where they stand; Success as soon
    /// as `success_threshold` children have succeeded, Failure as soon as
    /// `failure_threshold` have failed or success can no longer be reached. Every child
    /// is then reset, those Running halted.
    ParallelV3 {
        /// Children that must succeed.
        success_threshold: u16,
        /// Children whose failure makes the whole node fail.
        failure_threshold: u16,
    },
    /// BehaviorTree.CPP's `Repeat` (`retry` false) or `RetryUntilSuccessful` (`retry`
    /// true) in the forms [`NodeKind::RepeatCycles`] and
    /// [`NodeKind::RetryUntilSuccessful`] do not take: its count read on every tick
    /// from blackboard slot `count` (`from_slot`, as BehaviorTree.CPP reads a `{key}`),
    /// and with `v3` as BehaviorTree.CPP 3 runs it: after each cycle the child is
    /// ticked again in the same tick, whether it had been Running or not.
    Cycles {
        /// The count ([`NodeKind::FOREVER`]: no limit), or the slot holding it.
        count: u16,
        /// `count` is a slot.
        from_slot: bool,
        /// `RetryUntilSuccessful`: a Failure counts a cycle and a Success ends it.
        retry: bool,
        /// BehaviorTree.CPP 3's loop within the tick.
        v3: bool,
    },
    /// BehaviorTree.CPP 3's `BlackboardCheckInt`, `BlackboardCheckDouble`,
    /// `BlackboardCheckString` and `BlackboardCheckBool`: on every tick runs its program
    /// (the comparison); when it holds, ticks its child and returns what the child
    /// returns, else halts the child if it runs and returns `otherwise`. A program
    /// that stops with a fault (a key read before it is set) does not hold, as
    /// BehaviorTree.CPP's `getInput` fails then.
    Check {
        /// The comparison.
        code: Code,
        /// The status when it does not hold (`return_on_mismatch`).
        otherwise: crate::Status,
    },
}

/// How many children a kind of node takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arity {
    /// A leaf: no children.
    Leaf,
    /// A decorator: exactly one child.
    One,
    /// A control node: one or more children.
    AtLeastOne,
    /// Exactly two children.
    Two,
    /// Two or three children.
    TwoOrThree,
    /// Any number of children, none included (`ManualSelector`).
    Any,
}

impl NodeKind {
    /// The count of [`NodeKind::RepeatCycles`] and [`NodeKind::RetryUntilSuccessful`]
    /// that sets no limit (BehaviorTree.CPP's `-1`).
    pub const FOREVER: u16 = u16::MAX;

    /// The kind's name, as in the papers and the renderer.
    #[must_use]
    pub const fn name(&self) -> &'static str {
        match self {
            Self::Sequence => "Sequence",
            Self::Fallback => "Fallback",
            Self::SequenceWithMemory => "SequenceWithMemory",
            Self::FallbackWithMemory => "FallbackWithMemory",
            Self::Parallel { .. } => "Parallel",
            Self::Inverter => "Inverter",
            Self::ForceSuccess => "ForceSuccess",
            Self::ForceFailure => "ForceFailure",
            Self::Repeat(_) => "Repeat",
            Self::Retry(_) => "Retry",
            Self::Timeout(_) => "Timeout",
            Self::Condition(_) => "Condition",
            Self::Action(_) => "Action",
            Self::SequenceStar => "SequenceStar",
            Self::IfThenElse => "IfThenElse",
            Self::WhileDoElse => "WhileDoElse",
            Self::ParallelAll { .. } => "ParallelAll",
            Self::PipelineSequence => "PipelineSequence",
            Self::Recovery { .. } => "Recovery",
            Self::RoundRobin => "RoundRobin",
            Self::RepeatCycles(_) => "RepeatCycles",
            Self::RetryUntilSuccessful(_) => "RetryUntilSuccessful",
            Self::KeepRunningUntilFailure => "KeepRunningUntilFailure",
            Self::RunOnce { .. } => "RunOnce",
            Self::TimeLimit(_) => "TimeLimit",
            Self::Delay(_) => "Delay",
            Self::RateController(_) => "RateController",
            Self::Gate(_) => "Gate",
            Self::AlwaysSuccess => "AlwaysSuccess",
            Self::AlwaysFailure => "AlwaysFailure",
            Self::Script(_) => "Script",
            Self::ScriptCondition(_) => "ScriptCondition",
            Self::Precondition { .. } => "Precondition",
            Self::Sleep(_) => "Sleep",
            Self::Guard(_) => "Guard",
            Self::Loop { .. } => "Loop",
            Self::ManualSelector { .. } => "ManualSelector",
            Self::SequenceStarV3 => "SequenceStarV3",
            Self::ParallelV3 { .. } => "ParallelV3",
            Self::Cycles { .. } => "Cycles",
            Self::Check { .. } => "Check",
        }
    }

    /// How many children this kind takes.
    #[must_use]
    pub const fn arity(&self) -> Arity {
        match self {
            Self::Sequence
            | Self::Fallback
            | Self::SequenceWithMemory
            | Self::FallbackWithMemory
            | Self::Parallel { .. }
            | Self::SequenceStar
            | Self::ParallelAll { .. }
            | Self::PipelineSequence
            | Self::RoundRobin
            | Self::SequenceStarV3
            | Self::ParallelV3 { .. } => Arity::AtLeastOne,
            Self::IfThenElse | Self::WhileDoElse => Arity::TwoOrThree,
            Self::Recovery { .. } => Arity::Two,
            Self::ManualSelector { .. } => Arity::Any,
            Self::Inverter
            | Self::ForceSuccess
            | Self::ForceFailure
            | Self::Repeat(_)
            | Self::Retry(_)
            | Self::Timeout(_)
            | Self::RepeatCycles(_)
            | Self::RetryUntilSuccessful(_)
            | Self::KeepRunningUntilFailure
            | Self::RunOnce { .. }
            | Self::TimeLimit(_)
            | Self::Delay(_)
            | Self::RateController(_)
            | Self::Gate(_)
            | Self::Precondition { .. }
            | Self::Loop { .. }
            | Self::Guard(_)
            | Self::Cycles { .. }
            | Self::Check { .. } => Arity::One,
            Self::Condition(_)
            | Self::Action(_)
            | Self::AlwaysSuccess
            | Self::AlwaysFailure
            | Self::Script(_)
            | Self::ScriptCondition(_)
            | Self::Sleep(_) => Arity::Leaf,
        }
    }

    /// The family of the executor that runs this kind.
    #[must_use]
    pub(crate) const fn family(&self) -> Family {
        match self {
            Self::Sequence | Self::Fallback | Self::SequenceWithMemory | Self::FallbackWithMemory => Family::Ordered,
            Self::Parallel { .. } => Family::Parallel,
            Self::Inverter
            | Self::ForceSuccess
            | Self::ForceFailure
            | Self::Repeat(_)
            | Self::Retry(_)
            | Self::Timeout(_) => Family::Decorators,
            Self::Condition(_) | Self::Action(_) => Family::Leaves,
            Self::SequenceStar | Self::SequenceStarV3 | Self::PipelineSequence | Self::RoundRobin => Family::Sequences,
            Self::IfThenElse | Self::WhileDoElse | Self::Recovery { .. } => Family::Branches,
            Self::ParallelAll { .. } | Self::ParallelV3 { .. } => Family::ParallelAll,
            Self::RepeatCycles(_)
            | Self::RetryUntilSuccessful(_)
            | Self::KeepRunningUntilFailure
            | Self::RunOnce { .. }
            | Self::Cycles { .. } => Family::Counting,
            Self::TimeLimit(_) | Self::Delay(_) | Self::RateController(_) | Self::Sleep(_) => Family::Timers,
            Self::Guard(_) | Self::Precondition { .. } | Self::Gate(_) | Self::Check { .. } => Family::Guards,
            Self::Loop { .. } => Family::Loops,
            Self::ManualSelector { .. } => Family::ManualSelector,
            Self::Script(_) | Self::ScriptCondition(_) | Self::AlwaysSuccess | Self::AlwaysFailure => Family::Scripts,
        }
    }

    /// The leaf and its kind, for leaves.
    #[must_use]
    pub const fn leaf(&self) -> Option<(LeafKind, Leaf)> {
        match *self {
            Self::Condition(l) => Some((LeafKind::Condition, l)),
            Self::Action(l) => Some((LeafKind::Action, l)),
            _ => None,
        }
    }
}

/// Which part of the executor runs a kind: each family enters and ascends its kinds in
/// one file of `exec/`. The papers' families are the ones the plain tick loop runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Family {
    /// Sequence and Fallback, with and without memory (`exec/ordered.rs`).
    Ordered,
    /// Parallel (`exec/parallel.rs`).
    Parallel,
    /// Inverter, ForceSuccess, ForceFailure, Repeat, Retry, Timeout
    /// (`exec/decorators.rs`).
    Decorators,
    /// Condition and Action: the tick loop's own (`exec/tick.rs`).
    Leaves,
    /// SequenceStar, SequenceStarV3, PipelineSequence, RoundRobin (`exec/sequences.rs`).
    Sequences,
    /// IfThenElse, WhileDoElse, Recovery (`exec/branches.rs`).
    Branches,
    /// ParallelAll and ParallelV3 (`exec/parallel_all.rs`).
    ParallelAll,
    /// RepeatCycles, RetryUntilSuccessful, Cycles, KeepRunningUntilFailure, RunOnce
    /// (`exec/counting.rs`).
    Counting,
    /// TimeLimit, Delay, RateController, Sleep (`exec/timers.rs`).
    Timers,
    /// Guard, Precondition, Gate, Check (`exec/guards.rs`).
    Guards,
    /// Loop (`exec/loops.rs`).
    Loops,
    /// ManualSelector (`exec/manual_selector.rs`).
    ManualSelector,
    /// Script, ScriptCondition, AlwaysSuccess, AlwaysFailure (`exec/scripts.rs`).
    Scripts,
}

impl Family {
    /// One of the papers' families: what the plain tick loop runs, and all a build
    /// without the `btcpp` feature has.
    #[inline]
    pub(crate) const fn is_papers(self) -> bool {
        matches!(self, Self::Ordered | Self::Parallel | Self::Decorators | Self::Leaves)
    }
}

/// One node of the flat pre-order array: its kind and the size of its subtree
/// (itself included). 12 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Node {
    kind: NodeKind,
    size: u16,
}

const _: () = assert!(size_of::<Node>() == 12);

impl Node {
    /// A placeholder to fill caller storage with (`[Node::EMPTY; N]`); a failing
    /// condition leaf of behavior 0.
    pub const EMPTY: Node = Node { kind: NodeKind::Condition(Leaf::new(0)), size: 1 };

    /// A node with the given subtree size (itself included).
    #[must_use]
    pub const fn new(kind: NodeKind, size: u16) -> Self {
        Self { kind, size }
    }

    /// What the node is.
    #[inline(always)]
    #[must_use]
    pub const fn kind(&self) -> &NodeKind {
        &self.kind
    }

    /// Size of the subtree rooted here, itself included.
    #[inline(always)]
    #[must_use]
    pub const fn size(&self) -> u16 {
        self.size
    }

    pub(crate) fn set_size(&mut self, size: u16) {
        self.size = size;
    }
}
