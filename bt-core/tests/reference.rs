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
#[path = "reference/interp.rs"]
mod interp;

use interp::Reference;

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
