//! The executor against a small recursive reference interpreter that follows the tick
//! rules of `bt_core::exec` literally (for the kinds that stand for BehaviorTree.CPP's
//! and Nav2's nodes, a line-by-line reading of their C++ `tick()`), on random trees of
//! every node kind (depth up to 8, up to 64 nodes) and random leaf outcomes over several
//! ticks. On every tick the root status, the leaves and gates ticked (in order, with
//! whether an action was starting), the halt calls (in order), every node's status and
//! the wake-up request must agree.
//!
//! A second executor ticks the same tree with an [`Observer`]: it must behave the same,
//! and the changes it reports, replayed from all-Idle, must give exactly its node
//! statuses, each change starting from the status the node had.
//!
//! `PROPTEST_CASES` overrides the number of cases (10,000 by default).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;

use bt_core::script::{self, ScriptFault, Value};
use bt_core::{
    BehaviorSet, Builder, Code, Context, Executor, Leaf, Node, NodeId, NodeKind, NodeState, NodeStatus, Selection,
    Span, Status, Tree,
};
use proptest::prelude::*;

// ---------------------------------------------------------------- random trees

#[derive(Clone, Debug)]
enum T {
    Condition,
    Action,
    /// A condition (false) or action (true) whose behavior may also return Skipped:
    /// [`SKIPS`].
    Skipping(bool),
    Always(bool),
    /// A `Script` (false) or `ScriptCondition` (true) whose program the scripted set
    /// does not read: it answers from the tick script, as for conditions.
    Script(bool),
    /// A `Sleep`.
    Sleep(Span),
    Node(NodeKind, Vec<T>),
}

fn span() -> impl Strategy<Value = Span> {
    (0u32..=4).prop_map(|d| Span::new(d).unwrap())
}

fn cycles() -> impl Strategy<Value = u16> {
    prop_oneof![4 => 0u16..=3, 1 => Just(NodeKind::FOREVER)]
}

fn control() -> impl Strategy<Value = NodeKind> {
    prop_oneof![
        Just(NodeKind::Sequence),
        Just(NodeKind::Fallback),
        Just(NodeKind::SequenceWithMemory),
        Just(NodeKind::FallbackWithMemory),
        (1u16..=4, 1u16..=4, any::<bool>()).prop_map(|(s, f, c)| NodeKind::Parallel {
            success_threshold: s,
            failure_threshold: f,
            count_skipped: c
        }),
        Just(NodeKind::SequenceStar),
        Just(NodeKind::IfThenElse),
        Just(NodeKind::WhileDoElse),
        (0u16..=4).prop_map(|m| NodeKind::ParallelAll { max_failures: m }),
        Just(NodeKind::PipelineSequence),
        (0u16..=2).prop_map(|r| NodeKind::Recovery { retries: r }),
        Just(NodeKind::RoundRobin),
        Just(NodeKind::SequenceStarV3),
        (1u16..=4, 1u16..=4).prop_map(|(s, f)| NodeKind::ParallelV3 { success_threshold: s, failure_threshold: f }),
    ]
}

fn decorator() -> impl Strategy<Value = NodeKind> {
    prop_oneof![
        Just(NodeKind::Inverter),
        Just(NodeKind::ForceSuccess),
        Just(NodeKind::ForceFailure),
        (1u16..=3).prop_map(NodeKind::Repeat),
        (1u16..=3).prop_map(NodeKind::Retry),
        (1u16..=3).prop_map(NodeKind::Timeout),
        cycles().prop_map(NodeKind::RepeatCycles),
        cycles().prop_map(NodeKind::RetryUntilSuccessful),
        Just(NodeKind::KeepRunningUntilFailure),
        any::<bool>().prop_map(|then_skip| NodeKind::RunOnce { then_skip }),
        span().prop_map(NodeKind::TimeLimit),
        span().prop_map(NodeKind::Delay),
        span().prop_map(NodeKind::RateController),
        Just(NodeKind::Gate(Leaf::new(common::act(1)))),
        status().prop_map(|otherwise| NodeKind::Precondition { code: Code { start: 0, len: 1 }, otherwise }),
        Just(NodeKind::Guard(GUARD_CODE)),
        (prop_oneof![Just(KEY_QUEUE), Just(LITERAL_QUEUE)], status())
            .prop_map(|(table, if_empty)| NodeKind::Loop { table, if_empty }),
        // Version 3's for ever over a child that finishes at once runs 65,535 cycles a
        // tick (`counting.rs` tests it): finite counts here.
        (cycles(), any::<bool>(), any::<bool>(), any::<bool>()).prop_map(|(count, from_slot, retry, v3)| {
            let count = if v3 && count == NodeKind::FOREVER { 3 } else { count };
            NodeKind::Cycles { count, from_slot, retry, v3 }
        }),
        status().prop_map(|otherwise| NodeKind::Check { code: Code { start: 0, len: 1 }, otherwise }),
    ]
}

fn status() -> impl Strategy<Value = Status> {
    prop_oneof![Just(Status::Success), Just(Status::Failure), Just(Status::Running), Just(Status::Skipped)]
}

fn tree() -> impl Strategy<Value = T> {
    let leaf = prop_oneof![
        4 => Just(T::Condition),
        4 => Just(T::Action),
        1 => any::<bool>().prop_map(T::Always),
        1 => any::<bool>().prop_map(T::Script),
        1 => span().prop_map(T::Sleep),
    ];
    // 7 levels of recursion over a leaf: at most 8 levels.
    leaf.prop_recursive(7, 64, 4, |inner| {
        prop_oneof![
            3 => (control(), prop::collection::vec(inner.clone(), 1..5)).prop_map(|(k, c)| T::Node(k, c)),
            2 => (decorator(), inner.clone()).prop_map(|(k, c)| T::Node(k, vec![c])),
            1 => (any::<bool>(), prop::collection::vec(inner, 0..4))
                .prop_map(|(repeat_last, c)| T::Node(NodeKind::ManualSelector { repeat_last }, c)),
        ]
    })
    .prop_filter("at most 64 nodes", |t| count(t) <= 64)
}

/// Trees of the papers' kinds only, which the executor ticks with its plain loop, with
/// leaves that may return Skipped: the full loop takes over from the plain one there.
fn papers_tree() -> impl Strategy<Value = T> {
    let leaf = prop_oneof![
        2 => Just(T::Condition),
        2 => Just(T::Action),
        1 => any::<bool>().prop_map(T::Skipping),
    ];
    let control = prop_oneof![
        Just(NodeKind::Sequence),
        Just(NodeKind::Fallback),
        Just(NodeKind::SequenceWithMemory),
        Just(NodeKind::FallbackWithMemory),
        (1u16..=4, 1u16..=4, any::<bool>()).prop_map(|(s, f, c)| NodeKind::Parallel {
            success_threshold: s,
            failure_threshold: f,
            count_skipped: c
        }),
    ];
    let decorator = prop_oneof![
        Just(NodeKind::Inverter),
        Just(NodeKind::ForceSuccess),
        Just(NodeKind::ForceFailure),
        (1u16..=3).prop_map(NodeKind::Repeat),
        (1u16..=3).prop_map(NodeKind::Retry),
        (1u16..=3).prop_map(NodeKind::Timeout),
    ];
    leaf.prop_recursive(7, 64, 4, move |inner| {
        prop_oneof![
            3 => (control.clone(), prop::collection::vec(inner.clone(), 1..5)).prop_map(|(k, c)| T::Node(k, c)),
            2 => (decorator.clone(), inner).prop_map(|(k, c)| T::Node(k, vec![c])),
        ]
    })
    .prop_filter("at most 64 nodes", |t| count(t) <= 64)
}

fn count(t: &T) -> usize {
    match t {
        T::Node(_, c) => 1 + c.iter().map(count).sum::<usize>(),
        _ => 1,
    }
}

fn emit(t: &T, b: &mut Builder<'_, 16>) {
    match t {
        T::Condition => {
            b.condition(common::cond(0), &[]).unwrap();
        }
        T::Action => {
            b.action(common::act(0), &[]).unwrap();
        }
        T::Skipping(false) => {
            b.condition(common::cond(SKIPS), &[]).unwrap();
        }
        T::Skipping(true) => {
            b.action(common::act(SKIPS), &[]).unwrap();
        }
        T::Always(ok) => {
            b.leaf(if *ok { NodeKind::AlwaysSuccess } else { NodeKind::AlwaysFailure }).unwrap();
        }
        T::Sleep(d) => {
            b.leaf(NodeKind::Sleep(*d)).unwrap();
        }
        T::Script(condition) => {
            let code = Code { start: 0, len: 1 };
            b.leaf(if *condition { NodeKind::ScriptCondition(code) } else { NodeKind::Script(code) }).unwrap();
        }
        T::Node(kind, children) => {
            let n = children.len() as u16;
            let kind = match *kind {
                NodeKind::Parallel { success_threshold, failure_threshold, count_skipped } => NodeKind::Parallel {
                    success_threshold: success_threshold.min(n),
                    failure_threshold: failure_threshold.min(n),
                    count_skipped,
                },
                NodeKind::ParallelAll { max_failures } => NodeKind::ParallelAll { max_failures: max_failures.min(n) },
                NodeKind::ParallelV3 { success_threshold, failure_threshold } => NodeKind::ParallelV3 {
                    success_threshold: success_threshold.min(n),
                    failure_threshold: failure_threshold.min(n),
                },
                k => k,
            };
            b.open(kind).unwrap();
            for c in children {
                emit(c, b);
            }
            // Two or three children for IfThenElse and WhileDoElse, two for Recovery.
            let want = match kind {
                NodeKind::IfThenElse | NodeKind::WhileDoElse => 2.max(children.len()).min(3),
                NodeKind::Recovery { .. } => 2,
                _ => children.len(),
            };
            for _ in children.len()..want {
                b.action(common::act(0), &[]).unwrap();
            }
            b.end().unwrap();
        }
    }
}

/// `emit`, but IfThenElse, WhileDoElse and Recovery with too many children lose the rest.
fn fit(t: &T) -> T {
    match t {
        T::Node(k, c) => {
            let max = match k {
                NodeKind::IfThenElse | NodeKind::WhileDoElse => 3,
                NodeKind::Recovery { .. } => 2,
                _ => usize::MAX,
            };
            T::Node(*k, c.iter().take(max).map(fit).collect())
        }
        other => other.clone(),
    }
}

// ---------------------------------------------------------------- scripted leaves

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ev {
    Tick {
        node: usize,
        starting: bool,
    },
    Halt {
        node: usize,
    },
    /// A guard's hook ran.
    Hook {
        node: usize,
        hook: u16,
    },
}

/// The guards' table in the value table: every hook, hook `h`'s program the one word
/// `HOOK + h` (which the scripted set reads to tell them apart).
const HOOK: u16 = 100;
const GUARD: [u16; 17] =
    [0xFF, 1, HOOK, 1, HOOK + 1, 1, HOOK + 2, 1, HOOK + 3, 1, HOOK + 4, 1, HOOK + 5, 1, HOOK + 6, 1, HOOK + 7];
const GUARD_CODE: Code = Code { start: 1, len: GUARD.len() as u16 };

/// The loops' tables after the guards': a blackboard queue (the scripted set's `pop`
/// takes an element when the loop's outcome is Success) and a literal queue of
/// [`LITERAL_ELEMENTS`] (each program one word, which the scripted set runs as a script).
const QUEUES: [u16; 11] = [script::QUEUE_KEY | 1, u16::MAX, 0, 0, 1, u16::MAX, LITERAL_ELEMENTS, 1, 0, 1, 0];
const LITERAL_ELEMENTS: u16 = 2;
const KEY_QUEUE: Code = Code { start: GUARD_CODE.start + GUARD_CODE.len, len: 4 };
const LITERAL_QUEUE: Code = Code { start: KEY_QUEUE.start + 4, len: 7 };

/// Whether hook `h` of the guard at `node` holds on this tick: bit `h` of its byte.
fn hook_holds(script: &[u8], node: usize, h: u16) -> bool {
    (script[node] >> h) & 1 == 1
}

/// The leaves of behavior `SKIPS` (`common::cond(SKIPS)`, `common::act(SKIPS)`) may also
/// return Skipped.
const SKIPS: u16 = 2;

fn outcome(nodes: &[Node], script: &[u8], node: usize) -> Status {
    let v = script[node];
    match nodes[node].kind() {
        NodeKind::Condition(l) if l.behavior() == common::cond(SKIPS) => {
            [Status::Success, Status::Failure, Status::Skipped][usize::from(v % 3)]
        }
        NodeKind::Action(l) if l.behavior() == common::act(SKIPS) => {
            [Status::Success, Status::Failure, Status::Running, Status::Skipped][usize::from(v % 4)]
        }
        NodeKind::Condition(_)
        | NodeKind::ScriptCondition(_)
        | NodeKind::Precondition { .. }
        | NodeKind::Check { .. }
        | NodeKind::Loop { .. } => [Status::Success, Status::Failure][usize::from(v % 2)],
        NodeKind::Script(_) => Status::Success,
        _ => [Status::Success, Status::Failure, Status::Running][usize::from(v % 3)],
    }
}

/// What a `ManualSelector` at `node` with `children` children is told on this tick: a
/// child or a status, from its byte.
fn selection(script: &[u8], node: usize, children: usize) -> Selection {
    let pick = usize::from(script[node]) % (children + 3);
    match pick.checked_sub(children) {
        None => Selection::Child(pick as u8),
        Some(0) => Selection::Success,
        Some(1) => Selection::Failure,
        Some(_) => Selection::Running,
    }
}

struct Script<'a> {
    nodes: &'a [Node],
    tick: &'a [u8],
    log: Vec<Ev>,
}

impl BehaviorSet for Script<'_> {
    fn condition(&mut self, _: &Leaf, ctx: Context<'_>) -> Status {
        self.log.push(Ev::Tick { node: usize::from(ctx.node), starting: true });
        outcome(self.nodes, self.tick, usize::from(ctx.node))
    }
    fn action(&mut self, _: &Leaf, ctx: Context<'_>) -> Status {
        self.log.push(Ev::Tick { node: usize::from(ctx.node), starting: ctx.starting });
        outcome(self.nodes, self.tick, usize::from(ctx.node))
    }
    fn halt(&mut self, _: &Leaf, node: NodeId) {
        self.log.push(Ev::Halt { node: usize::from(node) });
    }
    fn script(&mut self, code: &[u16], ctx: Context<'_>) -> Result<Value, ScriptFault> {
        let node = usize::from(ctx.node);
        if let Some(&w) = code.first().filter(|&&w| w >= HOOK) {
            self.log.push(Ev::Hook { node, hook: w - HOOK });
            return Ok(Value::Bool(hook_holds(self.tick, node, w - HOOK)));
        }
        self.log.push(Ev::Tick { node: usize::from(ctx.node), starting: true });
        let held = outcome(self.nodes, self.tick, usize::from(ctx.node)) == Status::Success;
        Ok(Value::Bool(held))
    }
    fn pop(&mut self, _: u16, _: u16, ctx: Context<'_>) -> Result<bool, ScriptFault> {
        self.log.push(Ev::Tick { node: usize::from(ctx.node), starting: ctx.starting });
        Ok(outcome(self.nodes, self.tick, usize::from(ctx.node)) == Status::Success)
    }
    fn select(&mut self, children: u8, ctx: Context<'_>) -> Result<Selection, ScriptFault> {
        self.log.push(Ev::Tick { node: usize::from(ctx.node), starting: ctx.starting });
        Ok(selection(self.tick, usize::from(ctx.node), usize::from(children)))
    }
}

// ---------------------------------------------------------------- the reference

#[derive(Clone, Copy, Default, Debug)]
struct RState {
    status: NodeStatus,
    /// Sequence/Fallback: the child it returned at.
    last: Option<usize>,
    /// Repeat/Retry/Timeout count; RepeatCycles/RetryUntilSuccessful count; Recovery
    /// recoveries; RoundRobin failures.
    count: u16,
    /// SequenceStar: child to resume at; IfThenElse: the branch; PipelineSequence: the
    /// furthest child Running; RoundRobin: the next child (0-based); Recovery: the child.
    mem: usize,
    /// TimeLimit, Delay, RateController: when it started.
    start: u32,
    /// RunOnce: its result, once it has one.
    done: Option<Status>,
    /// ManualSelector: the last selection it was told (with children).
    choice: Option<Selection>,
}

/// Recursive, straight from the rules; no shortcuts.
struct Reference<'a> {
    nodes: &'a [Node],
    st: Vec<RState>,
    log: Vec<Ev>,
    script: Vec<u8>,
    now: u32,
    woken: bool,
    /// For each reactive Sequence/Fallback being ticked: the later child that was
    /// Running on the previous tick, which an action starting below must halt first.
    preempted: Vec<Option<usize>>,
}

fn is_reactive_or_reused(kind: &NodeKind) -> bool {
    matches!(
        kind,
        NodeKind::Sequence
            | NodeKind::Fallback
            | NodeKind::SequenceWithMemory
            | NodeKind::FallbackWithMemory
            | NodeKind::Parallel { .. }
            | NodeKind::Inverter
            | NodeKind::ForceSuccess
            | NodeKind::ForceFailure
            | NodeKind::Repeat(_)
            | NodeKind::Retry(_)
            | NodeKind::Timeout(_)
    )
}

impl<'a> Reference<'a> {
    fn new(nodes: &'a [Node]) -> Self {
        Self {
            nodes,
            st: vec![RState::default(); nodes.len()],
            log: vec![],
            script: vec![],
            now: 0,
            woken: false,
            preempted: vec![],
        }
    }

    fn kids(&self, i: usize) -> Vec<usize> {
        let end = i + usize::from(self.nodes[i].size());
        let mut v = vec![];
        let mut c = i + 1;
        while c < end {
            v.push(c);
            c += usize::from(self.nodes[c].size());
        }
        v
    }

    fn status(&self, i: usize) -> NodeStatus {
        self.st[i].status
    }

    fn runs_an_action(&self, i: usize) -> bool {
        (matches!(self.nodes[i].kind(), NodeKind::Action(_)) && self.status(i) == NodeStatus::Running)
            || self.kids(i).into_iter().any(|c| self.runs_an_action(c))
    }

    fn tick_root(&mut self, script: &[u8], now: u32) -> Status {
        self.script = script.to_vec();
        self.now = now;
        self.timers();
        self.tick(0, false)
    }

    /// What BehaviorTree.CPP's timers did since the last tick, in pre-order.
    fn timers(&mut self) {
        for i in 0..self.nodes.len() {
            if self.status(i) != NodeStatus::Running {
                continue;
            }
            let elapsed = self.now.wrapping_sub(self.st[i].start) & Span::MAX;
            match *self.nodes[i].kind() {
                NodeKind::TimeLimit(d)
                    if d.get() > 0 && elapsed >= d.get() && self.status(i + 1) == NodeStatus::Running =>
                {
                    self.halt(i + 1);
                    self.woken = true;
                }
                NodeKind::Delay(d) if elapsed >= d.get() && self.status(i + 1) == NodeStatus::Idle => self.woken = true,
                NodeKind::Sleep(d) if elapsed >= d.get() => self.woken = true,
                _ => {}
            }
        }
    }

    /// Rule 3: halt every Running action below `i`, children first, and reset to Idle,
    /// keeping the memory that survives a halt. An Idle node's subtree is left as it is.
    fn halt(&mut self, i: usize) {
        if self.status(i) == NodeStatus::Idle {
            return;
        }
        for c in self.kids(i) {
            self.halt(c);
        }
        if matches!(self.nodes[i].kind(), NodeKind::Guard(_)) && self.status(i) == NodeStatus::Running {
            self.log.push(Ev::Hook { node: i, hook: 4 });
        }
        if matches!(self.nodes[i].kind(), NodeKind::Action(_)) && self.status(i) == NodeStatus::Running {
            self.log.push(Ev::Halt { node: i });
        }
        let was = self.st[i];
        let mut fresh = RState::default();
        match self.nodes[i].kind() {
            NodeKind::SequenceStar => fresh.mem = was.mem,
            // BehaviorTree.CPP 3's forgets its place when halted Running.
            NodeKind::SequenceStarV3 if was.status != NodeStatus::Running => fresh.mem = was.mem,
            NodeKind::RunOnce { .. } => fresh.done = was.done,
            NodeKind::Precondition { .. } => fresh.mem = was.mem,
            NodeKind::ManualSelector { .. } => fresh.choice = was.choice,
            NodeKind::RoundRobin | NodeKind::Recovery { .. } if was.status != NodeStatus::Running => {
                fresh.mem = was.mem;
                fresh.count = was.count;
            }
            _ => {}
        }
        self.st[i] = fresh;
    }

    /// BehaviorTree.CPP's haltChild: halt a Running child, else only make it Idle.
    fn halt_child(&mut self, c: usize) {
        if self.status(c) == NodeStatus::Running {
            self.halt(c);
        } else {
            self.st[c].status = NodeStatus::Idle;
        }
    }

    fn halt_children(&mut self, i: usize) {
        for c in self.kids(i) {
            self.halt_child(c);
        }
    }

    /// Whether a RateController or Gate at `i` starts afresh.
    fn fresh(&self, i: usize, parent_mirrors: bool) -> bool {
        match self.status(i) {
            NodeStatus::Idle => true,
            NodeStatus::Running => false,
            _ => !parent_mirrors,
        }
    }

    /// A Loop or Precondition starting afresh after it finished is Idle (BT.CPP's parent
    /// reset it), which a Skipped result keeps.
    fn forget_result(&mut self, i: usize, fresh: bool) {
        if fresh && matches!(self.status(i), NodeStatus::Success | NodeStatus::Failure) {
            self.st[i].status = NodeStatus::Idle;
        }
    }

    fn elapsed(&self, i: usize) -> u32 {
        self.now.wrapping_sub(self.st[i].start) & Span::MAX
    }

    fn tick(&mut self, i: usize, parent_mirrors: bool) -> Status {
        let was = self.st[i];
        let running = was.status == NodeStatus::Running;
        let mirrors = !is_reactive_or_reused(self.nodes[i].kind());
        let r = match *self.nodes[i].kind() {
            NodeKind::Condition(_) => {
                self.log.push(Ev::Tick { node: i, starting: true });
                outcome(self.nodes, &self.script, i)
            }
            NodeKind::Action(_) => {
                if !running {
                    // Rule 4: halt before start, innermost first, the branches where an
                    // action runs.
                    for p in self.preempted.clone().into_iter().rev().flatten() {
                        if self.runs_an_action(p) {
                            self.halt(p);
                        }
                    }
                }
                self.log.push(Ev::Tick { node: i, starting: !running });
                outcome(self.nodes, &self.script, i)
            }
            NodeKind::AlwaysSuccess => Status::Success,
            NodeKind::AlwaysFailure => Status::Failure,
            // Rule 10: Running from its start until the span has passed.
            NodeKind::Sleep(d) => {
                if !running {
                    if d.get() == 0 {
                        return self.set(i, Status::Success);
                    }
                    self.st[i].start = self.now;
                    Status::Running
                } else if self.elapsed(i) >= d.get() {
                    Status::Success
                } else {
                    Status::Running
                }
            }
            // Rule 12: a script runs once per tick, as a condition.
            NodeKind::Script(_) | NodeKind::ScriptCondition(_) => {
                self.log.push(Ev::Tick { node: i, starting: true });
                outcome(self.nodes, &self.script, i)
            }
            kind @ (NodeKind::Sequence
            | NodeKind::Fallback
            | NodeKind::SequenceWithMemory
            | NodeKind::FallbackWithMemory) => {
                let is_seq = matches!(kind, NodeKind::Sequence | NodeKind::SequenceWithMemory);
                let memory = matches!(kind, NodeKind::SequenceWithMemory | NodeKind::FallbackWithMemory);
                let go_on = if is_seq { Status::Success } else { Status::Failure };
                let kids = self.kids(i);
                let start = if memory && running { kids.iter().position(|&c| Some(c) == was.last).unwrap() } else { 0 };
                let mut result = None;
                let mut at = *kids.last().unwrap();
                for &c in &kids[start..] {
                    let old = if !memory && running && was.last.is_some_and(|l| l > c) { was.last } else { None };
                    if !memory {
                        self.preempted.push(old);
                    }
                    let s = self.tick(c, false);
                    if !memory {
                        self.preempted.pop();
                    }
                    if s == Status::Skipped {
                        // Reactive nodes halt a child that skipped.
                        if !memory {
                            self.halt(c);
                        }
                        continue;
                    }
                    if s != go_on {
                        result = Some(s);
                        at = c;
                        break;
                    }
                }
                for c in kids.iter().copied().filter(|&c| c > at) {
                    self.halt(c);
                }
                let result = result.unwrap_or_else(|| {
                    // No child stopped it: all skipped (none returned `go_on` in this
                    // activation), or `go_on`.
                    if kids.iter().any(|&c| self.status(c) == go_on.into()) { go_on } else { Status::Skipped }
                });
                if memory && result != Status::Running {
                    // Finished: children that skipped and stayed Running are reset.
                    for c in kids.iter().copied().filter(|&c| c < at || result == Status::Skipped || c == at) {
                        if self.status(c) == NodeStatus::Running {
                            self.halt(c);
                        }
                    }
                }
                self.st[i].last = Some(if result == Status::Skipped && memory { kids[0] } else { at });
                result
            }
            NodeKind::Parallel { success_threshold, failure_threshold, count_skipped } => {
                // Counts are totals of the activation; the verdict is checked after each
                // child, ticked or passed over.
                let kids = self.kids(i);
                let n = kids.len() as u16;
                let finished = |me: &Self, c: usize, s: NodeStatus| running && me.st[c].status == s;
                let mut ok = kids.iter().filter(|&&c| finished(self, c, NodeStatus::Success)).count() as u16;
                let mut failed = kids.iter().filter(|&&c| finished(self, c, NodeStatus::Failure)).count() as u16;
                let mut skipped = 0u16;
                let mut verdict = None;
                let mut reached = kids.len();
                for (k, &c) in kids.iter().enumerate() {
                    let done = finished(self, c, NodeStatus::Success) || finished(self, c, NodeStatus::Failure);
                    if !done {
                        match self.tick(c, false) {
                            Status::Success => ok += 1,
                            Status::Failure => failed += 1,
                            Status::Skipped => skipped += 1,
                            Status::Running => {}
                        }
                    }
                    if ok >= success_threshold || (count_skipped && ok + skipped >= success_threshold) {
                        verdict = Some(Status::Success);
                    } else if failed >= failure_threshold || n - failed < success_threshold {
                        verdict = Some(Status::Failure);
                    }
                    if verdict.is_some() {
                        reached = k + 1;
                        break;
                    }
                }
                match verdict {
                    Some(v) => {
                        for (k, &c) in kids.iter().enumerate() {
                            if k >= reached || self.st[c].status == NodeStatus::Running {
                                self.halt(c);
                            }
                        }
                        v
                    }
                    None if skipped == n => Status::Skipped,
                    None => Status::Running,
                }
            }
            NodeKind::Inverter => match self.tick(i + 1, false) {
                Status::Success => Status::Failure,
                Status::Failure => Status::Success,
                s => s,
            },
            NodeKind::ForceSuccess => match self.tick(i + 1, false) {
                Status::Success | Status::Failure => Status::Success,
                s => s,
            },
            NodeKind::ForceFailure => match self.tick(i + 1, false) {
                Status::Success | Status::Failure => Status::Failure,
                s => s,
            },
            NodeKind::Repeat(n) | NodeKind::Retry(n) => {
                let repeat = matches!(self.nodes[i].kind(), NodeKind::Repeat(_));
                let count = if running { was.count } else { 0 };
                let s = self.tick(i + 1, false);
                let again = if repeat { Status::Success } else { Status::Failure };
                if s == again {
                    if count + 1 >= n {
                        s
                    } else {
                        self.st[i].count = count + 1;
                        Status::Running
                    }
                } else {
                    if s == Status::Running {
                        self.st[i].count = count;
                    }
                    s
                }
            }
            NodeKind::Timeout(n) => {
                let count = if running { was.count } else { 0 };
                let s = self.tick(i + 1, false);
                if s == Status::Running {
                    if count + 1 >= n {
                        self.halt(i + 1);
                        Status::Failure
                    } else {
                        self.st[i].count = count + 1;
                        Status::Running
                    }
                } else {
                    s
                }
            }
            // ------------------------------------------- BehaviorTree.CPP's and Nav2's
            kind @ (NodeKind::SequenceStar | NodeKind::SequenceStarV3) => {
                // Version 3 goes on to the next child where version 4 wakes up.
                let v3 = kind == NodeKind::SequenceStarV3;
                let kids = self.kids(i);
                let mut idx = kids.iter().position(|&c| c == was.mem).unwrap_or(0);
                loop {
                    if idx == kids.len() {
                        let all_skipped = !kids.iter().any(|&c| self.status(c) == NodeStatus::Success);
                        self.halt_children(i);
                        self.st[i].mem = 0;
                        break if all_skipped { Status::Skipped } else { Status::Success };
                    }
                    let c = kids[idx];
                    let was_idle = self.status(c) == NodeStatus::Idle;
                    match self.tick(c, true) {
                        Status::Running => {
                            self.st[i].mem = c;
                            break Status::Running;
                        }
                        Status::Failure => {
                            for &k in &kids[idx..] {
                                self.halt_child(k);
                            }
                            self.st[i].mem = c;
                            break Status::Failure;
                        }
                        Status::Success => {
                            idx += 1;
                            if was_idle && idx < kids.len() && !v3 {
                                self.st[i].mem = kids[idx];
                                self.woken = true;
                                break Status::Running;
                            }
                        }
                        Status::Skipped => idx += 1,
                    }
                }
            }
            NodeKind::IfThenElse => {
                let kids = self.kids(i);
                let mut branch = if running { was.mem } else { 0 };
                let mut early = None;
                if branch == 0 {
                    match self.tick(kids[0], true) {
                        Status::Success => branch = kids[1],
                        Status::Failure if kids.len() == 3 => branch = kids[2],
                        s => {
                            if s != Status::Failure {
                                self.st[i].mem = 0;
                            }
                            early = Some(s);
                        }
                    }
                }
                match early {
                    Some(s) => s,
                    None => {
                        let s = self.tick(branch, true);
                        if s == Status::Running {
                            self.st[i].mem = branch;
                        } else {
                            self.halt_children(i);
                            self.st[i].mem = 0;
                        }
                        s
                    }
                }
            }
            NodeKind::WhileDoElse => {
                let kids = self.kids(i);
                let s = match self.tick(kids[0], true) {
                    Status::Running => return self.set(i, Status::Running),
                    Status::Success => {
                        if kids.len() == 3 {
                            self.halt_child(kids[2]);
                        }
                        self.tick(kids[1], true)
                    }
                    Status::Failure if kids.len() == 3 => {
                        self.halt_child(kids[1]);
                        self.tick(kids[2], true)
                    }
                    other => other,
                };
                if s != Status::Running {
                    self.halt_children(i);
                }
                s
            }
            NodeKind::ParallelAll { max_failures } => {
                let kids = self.kids(i);
                let (mut done, mut failed, mut skipped) = (0u16, 0u16, 0u16);
                for &c in &kids {
                    let prior = self.status(c);
                    let s = match prior {
                        NodeStatus::Success if running => Status::Success,
                        NodeStatus::Failure if running => Status::Failure,
                        _ => self.tick(c, true),
                    };
                    match s {
                        Status::Success => done += 1,
                        Status::Failure => {
                            done += 1;
                            failed += 1;
                        }
                        Status::Skipped => skipped += 1,
                        Status::Running => {}
                    }
                }
                let n = kids.len() as u16;
                if skipped == n {
                    Status::Skipped
                } else if skipped + done >= n {
                    self.halt_children(i);
                    if failed >= max_failures { Status::Failure } else { Status::Success }
                } else {
                    Status::Running
                }
            }
            // Counts anew each tick, in child order, finished children where they stand.
            NodeKind::ParallelV3 { success_threshold, failure_threshold } => {
                let kids = self.kids(i);
                let n = kids.len() as u16;
                let (mut ok, mut failed) = (0u16, 0u16);
                let mut verdict = None;
                for &c in &kids {
                    let r = match self.status(c) {
                        NodeStatus::Success if running => Status::Success,
                        NodeStatus::Failure if running => Status::Failure,
                        _ => self.tick(c, true),
                    };
                    match r {
                        Status::Success => ok += 1,
                        Status::Failure => failed += 1,
                        Status::Running | Status::Skipped => continue,
                    }
                    if ok >= success_threshold {
                        verdict = Some(Status::Success);
                    } else if failed >= failure_threshold || failed > n - success_threshold {
                        verdict = Some(Status::Failure);
                    }
                    if verdict.is_some() {
                        break;
                    }
                }
                match verdict {
                    Some(v) => {
                        self.halt_children(i);
                        v
                    }
                    None => Status::Running,
                }
            }
            NodeKind::PipelineSequence => {
                let kids = self.kids(i);
                let last = if running && was.mem != 0 { was.mem } else { kids[0] };
                let mut skipped = 0;
                let mut result = None;
                for &c in &kids {
                    match self.tick(c, true) {
                        Status::Failure => {
                            self.halt_children(i);
                            self.st[i].mem = 0;
                            result = Some(Status::Failure);
                            break;
                        }
                        Status::Skipped => skipped += 1,
                        Status::Running if c >= last => {
                            self.st[i].mem = c;
                            result = Some(Status::Running);
                            break;
                        }
                        _ => {}
                    }
                }
                result.unwrap_or_else(|| {
                    self.halt_children(i);
                    self.st[i].mem = 0;
                    if skipped == kids.len() { Status::Skipped } else { Status::Success }
                })
            }
            NodeKind::Recovery { retries } => {
                let kids = self.kids(i);
                let mut idx = was.mem;
                let mut retry = was.count;
                let give_up = |me: &mut Self, s| {
                    me.halt_children(i);
                    me.st[i].mem = 0;
                    me.st[i].count = 0;
                    s
                };
                loop {
                    if idx >= 2 || retry > retries {
                        break give_up(self, Status::Failure);
                    }
                    let s = self.tick(kids[idx], true);
                    if idx == 0 {
                        match s {
                            Status::Skipped | Status::Success => break give_up(self, s),
                            Status::Running => {
                                self.st[i].mem = 0;
                                self.st[i].count = retry;
                                break Status::Running;
                            }
                            Status::Failure if retry < retries => {
                                self.halt_child(kids[0]);
                                idx = 1;
                            }
                            Status::Failure => break give_up(self, Status::Failure),
                        }
                    } else {
                        match s {
                            Status::Skipped => {
                                self.halt_child(kids[1]);
                                self.st[i].mem = 0;
                                self.st[i].count = retry;
                                break Status::Failure;
                            }
                            Status::Running => {
                                self.st[i].mem = 1;
                                self.st[i].count = retry;
                                break Status::Running;
                            }
                            Status::Success => {
                                self.halt_child(kids[1]);
                                retry += 1;
                                idx = 0;
                            }
                            Status::Failure => break give_up(self, Status::Failure),
                        }
                    }
                }
            }
            NodeKind::RoundRobin => {
                let kids = self.kids(i);
                let n = kids.len() as u16;
                let mut idx = was.mem;
                let mut failed = was.count;
                let mut skipped = 0u16;
                loop {
                    if failed + skipped >= n {
                        self.halt_children(i);
                        self.st[i].mem = 0;
                        self.st[i].count = 0;
                        break if skipped == n { Status::Skipped } else { Status::Failure };
                    }
                    let s = self.tick(kids[idx], true);
                    if s != Status::Running {
                        idx = (idx + 1) % kids.len();
                    }
                    match s {
                        Status::Success => {
                            self.halt_children(i);
                            self.st[i].mem = idx;
                            self.st[i].count = 0;
                            break Status::Success;
                        }
                        Status::Failure => failed += 1,
                        Status::Skipped => skipped += 1,
                        Status::Running => {
                            self.st[i].mem = idx;
                            self.st[i].count = failed;
                            break Status::Running;
                        }
                    }
                }
            }
            kind @ (NodeKind::RepeatCycles(_) | NodeKind::RetryUntilSuccessful(_) | NodeKind::Cycles { .. }) => {
                let again = if matches!(kind, NodeKind::RepeatCycles(_) | NodeKind::Cycles { retry: false, .. }) {
                    Status::Success
                } else {
                    Status::Failure
                };
                let v3 = matches!(kind, NodeKind::Cycles { v3: true, .. });
                let n = match kind {
                    NodeKind::RepeatCycles(n) | NodeKind::RetryUntilSuccessful(n) => n,
                    // A count from a slot: the scripted set's truth, 0 or 1.
                    NodeKind::Cycles { from_slot: true, .. } => {
                        self.log.push(Ev::Tick { node: i, starting: true });
                        u16::from(outcome(self.nodes, &self.script, i) == Status::Success)
                    }
                    NodeKind::Cycles { count, .. } => count,
                    _ => unreachable!(),
                };
                let mut count = if running { was.count } else { 0 };
                let mut in_tick = 0u16;
                loop {
                    if !(count < n || n == NodeKind::FOREVER) {
                        if self.status(i + 1) == NodeStatus::Running {
                            self.halt(i + 1);
                        }
                        self.st[i].count = 0;
                        break again;
                    }
                    let was_idle = self.status(i + 1) == NodeStatus::Idle;
                    let s = self.tick(i + 1, true);
                    if s == Status::Running {
                        self.st[i].count = count;
                        break s;
                    }
                    self.halt_child(i + 1);
                    if s == Status::Skipped {
                        self.st[i].count = count;
                        break s;
                    }
                    if s != again {
                        self.st[i].count = 0;
                        break s;
                    }
                    count += 1;
                    in_tick += 1;
                    let yields = if v3 { in_tick == u16::MAX } else { was_idle };
                    if yields && (count < n || n == NodeKind::FOREVER) {
                        self.st[i].count = count;
                        self.woken = true;
                        break Status::Running;
                    }
                }
            }
            NodeKind::KeepRunningUntilFailure => match self.tick(i + 1, true) {
                Status::Failure => {
                    self.halt_child(i + 1);
                    Status::Failure
                }
                Status::Success => {
                    self.halt_child(i + 1);
                    Status::Running
                }
                _ => Status::Running,
            },
            // Rule 12: BT.CPP's scripted attributes around the node that is its child.
            NodeKind::Guard(_) => {
                let hold = |r: &mut Self, h: u16| {
                    r.log.push(Ev::Hook { node: i, hook: h });
                    hook_holds(&r.script, i, h)
                };
                let decided = if self.fresh(i, parent_mirrors) {
                    if hold(self, 0) {
                        Some(Status::Failure)
                    } else if hold(self, 1) {
                        Some(Status::Success)
                    } else if hold(self, 2) || !hold(self, 3) {
                        Some(Status::Skipped)
                    } else {
                        None
                    }
                } else if running && !hold(self, 3) {
                    self.halt(i + 1);
                    self.log.push(Ev::Hook { node: i, hook: 4 });
                    Some(Status::Skipped)
                } else {
                    None
                };
                let (r, from_child) = match decided {
                    Some(d) => (d, false),
                    None => (self.tick(i + 1, true), true),
                };
                match r {
                    Status::Success => self.log.push(Ev::Hook { node: i, hook: 6 }),
                    Status::Failure => self.log.push(Ev::Hook { node: i, hook: 5 }),
                    _ => {}
                }
                if matches!(r, Status::Success | Status::Failure) {
                    self.log.push(Ev::Hook { node: i, hook: 7 });
                    if from_child {
                        self.halt_child(i + 1);
                    }
                }
                if r == Status::Skipped {
                    // Its status is what the child kept, or Idle when it decided.
                    self.st[i].status = if from_child { self.status(i + 1) } else { NodeStatus::Idle };
                    return r;
                }
                r
            }
            // Rule 12: asks its script only while its child is not under way.
            NodeKind::Precondition { otherwise, .. } => {
                let fresh = self.fresh(i, parent_mirrors);
                self.forget_result(i, fresh);
                let go = was.mem == 1 || {
                    self.log.push(Ev::Tick { node: i, starting: true });
                    outcome(self.nodes, &self.script, i) == Status::Success
                };
                if !go {
                    // Decided without the child: the status it returns (Skipped: Idle).
                    return self.set(i, otherwise);
                }
                self.st[i].mem = 1;
                let s = self.tick(i + 1, true);
                if matches!(s, Status::Success | Status::Failure) {
                    self.st[i].mem = 0;
                    self.halt_child(i + 1);
                }
                s
            }
            // Asks on every tick; a mismatch halts a Running child.
            NodeKind::Check { otherwise, .. } => {
                self.log.push(Ev::Tick { node: i, starting: true });
                if outcome(self.nodes, &self.script, i) == Status::Success {
                    let s = self.tick(i + 1, true);
                    if matches!(s, Status::Success | Status::Failure) {
                        self.halt_child(i + 1);
                    }
                    s
                } else {
                    if self.status(i + 1) == NodeStatus::Running {
                        self.halt(i + 1);
                    }
                    if otherwise == Status::Skipped {
                        return self.set(i, otherwise);
                    }
                    otherwise
                }
            }
            NodeKind::RunOnce { then_skip } => match was.done {
                // A RunOnce that skips keeps no status: Idle.
                Some(_) if then_skip => return self.set(i, Status::Skipped),
                Some(done) => done,
                None => {
                    let s = self.tick(i + 1, true);
                    if matches!(s, Status::Success | Status::Failure) {
                        self.st[i].done = Some(s);
                        self.halt_child(i + 1);
                    }
                    s
                }
            },
            NodeKind::TimeLimit(d) => {
                if !running {
                    self.st[i].start = self.now;
                }
                if running && d.get() > 0 && self.elapsed(i) >= d.get() {
                    self.halt_child(i + 1);
                    Status::Failure
                } else {
                    let s = self.tick(i + 1, true);
                    if matches!(s, Status::Success | Status::Failure) {
                        self.halt_child(i + 1);
                    }
                    s
                }
            }
            NodeKind::Delay(d) => {
                if !running {
                    self.st[i].start = self.now;
                }
                if self.elapsed(i) >= d.get() || self.status(i + 1) == NodeStatus::Running {
                    let s = self.tick(i + 1, true);
                    if matches!(s, Status::Success | Status::Failure) {
                        self.halt_child(i + 1);
                    }
                    s
                } else {
                    Status::Running
                }
            }
            // Rule 12: takes an element while its child is not Running, then ticks it.
            NodeKind::Loop { table, if_empty } => {
                let fresh = self.fresh(i, parent_mirrors);
                self.forget_result(i, fresh);
                if fresh || !running || was.mem != 1 {
                    let taken = if fresh { 0 } else { was.count };
                    let popped = if table == KEY_QUEUE {
                        self.log.push(Ev::Tick { node: i, starting: fresh });
                        outcome(self.nodes, &self.script, i) == Status::Success
                    } else if taken < LITERAL_ELEMENTS {
                        self.log.push(Ev::Tick { node: i, starting: true });
                        true
                    } else {
                        false
                    };
                    if !popped {
                        self.st[i].count = taken;
                        // Skipping keeps its status, whatever it was.
                        return if if_empty == Status::Skipped { if_empty } else { self.set(i, if_empty) };
                    }
                    self.st[i].count = taken + 1;
                }
                let s = self.tick(i + 1, true);
                self.st[i].mem = usize::from(s == Status::Running);
                if matches!(s, Status::Success | Status::Failure) {
                    self.halt_child(i + 1);
                }
                if s == Status::Failure { s } else { Status::Running }
            }
            // Rule 13: asks on every tick (with repeat_last_selection once, ever) which
            // child to tick or which status to return; a child Running that is not
            // chosen is halted first, unless it returns Running without a child.
            NodeKind::ManualSelector { repeat_last } => {
                let kids = self.kids(i);
                let fresh = self.fresh(i, parent_mirrors);
                self.forget_result(i, fresh);
                let (choice, asked) = match was.choice {
                    Some(c) if repeat_last && !kids.is_empty() => (c, false),
                    _ => {
                        self.log.push(Ev::Tick { node: i, starting: fresh });
                        let c = selection(&self.script, i, kids.len());
                        if !kids.is_empty() {
                            self.st[i].choice = Some(c);
                        }
                        (c, true)
                    }
                };
                let chosen = match choice {
                    Selection::Child(k) => Some(kids[usize::from(k)]),
                    _ => None,
                };
                if choice != Selection::Running {
                    for &c in &kids {
                        if Some(c) != chosen && self.status(c) == NodeStatus::Running {
                            self.halt(c);
                        }
                    }
                }
                match (chosen, choice) {
                    (Some(c), _) => {
                        // BehaviorTree.CPP marks it Running when it asks.
                        if asked {
                            self.st[i].status = NodeStatus::Running;
                        }
                        self.tick(c, true)
                    }
                    (None, Selection::Success) => Status::Success,
                    (None, Selection::Failure) => Status::Failure,
                    (None, _) => Status::Running,
                }
            }
            NodeKind::RateController(d) => {
                let fresh = self.fresh(i, parent_mirrors);
                if fresh {
                    self.st[i].start = self.now;
                }
                if fresh || self.status(i + 1) == NodeStatus::Running || self.elapsed(i) >= d.get() {
                    let s = self.tick(i + 1, true);
                    if s == Status::Success {
                        self.st[i].start = self.now;
                    }
                    if matches!(s, Status::Success | Status::Failure) {
                        self.halt_child(i + 1);
                    }
                    s
                } else {
                    Status::Running
                }
            }
            NodeKind::Gate(_) => {
                let starting = self.fresh(i, parent_mirrors);
                self.log.push(Ev::Tick { node: i, starting });
                let open = outcome(self.nodes, &self.script, i);
                if self.status(i + 1) == NodeStatus::Running || open == Status::Success {
                    let s = self.tick(i + 1, true);
                    if matches!(s, Status::Success | Status::Failure) {
                        self.halt_child(i + 1);
                    }
                    s
                } else {
                    // The gate decides without the child: no status kept for Skipped.
                    if open == Status::Skipped {
                        return self.set(i, Status::Skipped);
                    }
                    open
                }
            }
        };
        let _ = mirrors;
        let new = match r {
            // A Precondition that skips keeps its status (BehaviorTree.CPP's does not
            // mark itself Running).
            Status::Skipped
                if matches!(self.nodes[i].kind(), NodeKind::Precondition { .. } | NodeKind::ManualSelector { .. }) =>
            {
                self.st[i].status
            }
            // A control node or decorator that skips stays Running; a leaf is Idle.
            Status::Skipped if self.nodes[i].kind().arity() != bt_core::Arity::Leaf => NodeStatus::Running,
            r => r.into(),
        };
        self.st[i].status = new;
        r
    }

    /// Sets the status `r` gives and returns `r` (Skipped: Idle).
    fn set(&mut self, i: usize, r: Status) -> Status {
        self.st[i].status = r.into();
        r
    }
}

// ---------------------------------------------------------------- the property

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(10_000)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), max_shrink_iters: 10_000, ..ProptestConfig::default() })]

    #[test]
    fn executor_agrees_with_the_reference_interpreter(
        t in tree(),
        ticks in prop::collection::vec(prop::collection::vec(any::<u8>(), 64), 1..=10),
    ) {
        agrees(&t, &ticks)?;
    }

    #[test]
    fn the_plain_loop_agrees_with_the_reference_interpreter_and_hands_skipped_to_the_full_one(
        t in papers_tree(),
        ticks in prop::collection::vec(prop::collection::vec(any::<u8>(), 64), 1..=10),
    ) {
        agrees(&t, &ticks)?;
    }
}

/// Ticks tree `t` with the executor, with an observed executor and with the reference,
/// one tick per script of `ticks`, and compares them after every tick.
fn agrees(t: &T, ticks: &[Vec<u8>]) -> Result<(), TestCaseError> {
    let t = fit(t);
    let mut storage = vec![Node::EMPTY; 128];
    let mut b = Builder::<16>::new(&mut storage);
    emit(&t, &mut b);
    let nodes = b.finish().unwrap();
    let catalog = common::catalog();
    let mut values = vec![script::op::POP];
    values.extend_from_slice(&GUARD);
    values.extend_from_slice(&QUEUES);
    let tree = Tree::<8>::validate_with(nodes, &values, catalog.as_slice()).unwrap();
    let mut state = vec![NodeState::IDLE; nodes.len()];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    let mut observed_state = vec![NodeState::IDLE; nodes.len()];
    let mut observed = Executor::new(tree, &mut observed_state).unwrap();
    // The observed executor's statuses as its reported changes give them.
    let mut replayed = vec![NodeStatus::Idle; nodes.len()];
    let mut reference = Reference::new(nodes);

    for (k, script) in ticks.iter().enumerate() {
        let script = &script[..];
        let mut script64 = script.to_vec();
        script64.resize(nodes.len().max(64), 0);
        let script = &script64[..];
        let mut world = Script { nodes, tick: script, log: vec![] };
        let got = exec.tick(&mut world, k as u32).unwrap();
        reference.log.clear();
        let want = reference.tick_root(script, k as u32);
        prop_assert_eq!(got, want, "root status on tick {}", k);
        prop_assert_eq!(&world.log, &reference.log, "leaves and halts on tick {}", k);
        let got_states: Vec<_> = exec.states().iter().map(|s| s.status()).collect();
        let want_states: Vec<_> = reference.st.iter().map(|s| s.status).collect();
        prop_assert_eq!(&got_states, &want_states, "node statuses after tick {}", k);
        prop_assert_eq!(exec.take_woken(), std::mem::take(&mut reference.woken), "wake-up on tick {}", k);

        let mut world_o = Script { nodes, tick: script, log: vec![] };
        let mut changes = common::Changes::default();
        let got_o = observed.tick_observed(&mut world_o, k as u32, &mut changes).unwrap();
        prop_assert_eq!(got_o, got, "observed: root status on tick {}", k);
        prop_assert_eq!(&world_o.log, &world.log, "observed: leaves and halts on tick {}", k);
        let observed_states: Vec<_> = observed.states().iter().map(|s| s.status()).collect();
        prop_assert_eq!(&observed_states, &got_states, "observed: node statuses after tick {}", k);
        for &(node, old, new) in &changes.0 {
            let had = &mut replayed[usize::from(node)];
            prop_assert!(
                *had == old && old != new,
                "observed: node {} went {:?} -> {:?} on tick {} but had {:?}",
                node,
                old,
                new,
                k,
                had
            );
            *had = new;
        }
        prop_assert_eq!(&replayed, &observed_states, "observed: replayed changes after tick {}", k);
    }
    Ok(())
}
