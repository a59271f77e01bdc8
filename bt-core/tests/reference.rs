//! The executor against a small recursive reference interpreter that follows the tick
//! rules of the design literally, on random trees of every node kind (depth up to 8,
//! up to 64 nodes) and random leaf outcomes over several ticks. On every tick the root
//! status, the leaves ticked (in order, with whether an action was starting), the halt
//! calls (in order) and every node's status must agree.
//!
//! A second executor ticks the same tree with an [`Observer`]: it must behave the same,
//! and the changes it reports, replayed from all-Idle, must give exactly its node
//! statuses, each change starting from the status the node had.
//!
//! `PROPTEST_CASES` overrides the number of cases (10,000 by default).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;

use bt_core::{
    BehaviorSet, Builder, Context, Executor, Leaf, Node, NodeId, NodeKind, NodeState, NodeStatus, Status, Tree,
};
use proptest::prelude::*;

// ---------------------------------------------------------------- random trees

#[derive(Clone, Debug)]
enum T {
    Condition,
    Action,
    Node(NodeKind, Vec<T>),
}

fn control() -> impl Strategy<Value = NodeKind> {
    prop_oneof![
        Just(NodeKind::Sequence),
        Just(NodeKind::Fallback),
        Just(NodeKind::SequenceWithMemory),
        Just(NodeKind::FallbackWithMemory),
        (1u16..=4, 1u16..=4).prop_map(|(s, f)| NodeKind::Parallel { success_threshold: s, failure_threshold: f }),
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
    ]
}

fn tree() -> impl Strategy<Value = T> {
    let leaf = prop_oneof![Just(T::Condition), Just(T::Action)];
    // 7 levels of recursion over a leaf: at most 8 levels.
    leaf.prop_recursive(7, 64, 4, |inner| {
        prop_oneof![
            3 => (control(), prop::collection::vec(inner.clone(), 1..5)).prop_map(|(k, c)| T::Node(k, c)),
            1 => (decorator(), inner).prop_map(|(k, c)| T::Node(k, vec![c])),
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
        T::Node(kind, children) => {
            let kind = match *kind {
                NodeKind::Parallel { success_threshold, failure_threshold } => {
                    let n = children.len() as u16;
                    NodeKind::Parallel {
                        success_threshold: success_threshold.min(n),
                        failure_threshold: failure_threshold.min(n),
                    }
                }
                k => k,
            };
            b.open(kind).unwrap();
            for c in children {
                emit(c, b);
            }
            b.end().unwrap();
        }
    }
}

// ---------------------------------------------------------------- scripted leaves

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ev {
    Tick { node: usize, starting: bool },
    Halt { node: usize },
}

fn outcome(nodes: &[Node], script: &[u8], node: usize) -> Status {
    let v = script[node];
    match nodes[node].kind() {
        NodeKind::Condition(_) => [Status::Success, Status::Failure][usize::from(v % 2)],
        _ => [Status::Success, Status::Failure, Status::Running][usize::from(v % 3)],
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
}

// ---------------------------------------------------------------- the reference

#[derive(Clone, Copy, Default)]
struct RState {
    status: NodeStatus,
    /// Sequence/Fallback: the child it returned at.
    last: Option<usize>,
    /// Repeat/Retry/Timeout count.
    count: u16,
}

/// Recursive, straight from the rules; no shortcuts.
struct Reference<'a> {
    nodes: &'a [Node],
    st: Vec<RState>,
    log: Vec<Ev>,
    script: Vec<u8>,
    /// For each reactive Sequence/Fallback being ticked: the later child that was
    /// Running on the previous tick, which an action starting below must halt first.
    preempted: Vec<Option<usize>>,
    finished: bool,
}

impl<'a> Reference<'a> {
    fn new(nodes: &'a [Node]) -> Self {
        Self {
            nodes,
            st: vec![RState::default(); nodes.len()],
            log: vec![],
            script: vec![],
            preempted: vec![],
            finished: false,
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

    fn tick_root(&mut self, script: &[u8]) -> Status {
        self.script = script.to_vec();
        if self.finished {
            // Rule 5: a finished root starts a new activation; nothing can be Running.
            assert!(self.st.iter().all(|s| s.status != NodeStatus::Running));
            self.st.fill(RState::default());
        }
        let r = self.tick(0);
        self.finished = r != Status::Running;
        r
    }

    /// Rule 3: halt every Running action below `i`, children first, and reset to Idle.
    fn halt(&mut self, i: usize) {
        for c in self.kids(i) {
            self.halt(c);
        }
        if matches!(self.nodes[i].kind(), NodeKind::Action(_)) && self.st[i].status == NodeStatus::Running {
            self.log.push(Ev::Halt { node: i });
        }
        self.st[i] = RState::default();
    }

    fn tick(&mut self, i: usize) -> Status {
        let was = self.st[i];
        let running = was.status == NodeStatus::Running;
        let r = match *self.nodes[i].kind() {
            NodeKind::Condition(_) => {
                self.log.push(Ev::Tick { node: i, starting: true });
                outcome(self.nodes, &self.script, i)
            }
            NodeKind::Action(_) => {
                if !running {
                    // Rule 4: halt before start, innermost first.
                    for p in self.preempted.clone().into_iter().rev().flatten() {
                        self.halt(p);
                    }
                }
                self.log.push(Ev::Tick { node: i, starting: !running });
                outcome(self.nodes, &self.script, i)
            }
            kind @ (NodeKind::Sequence
            | NodeKind::Fallback
            | NodeKind::SequenceWithMemory
            | NodeKind::FallbackWithMemory) => {
                let is_seq = matches!(kind, NodeKind::Sequence | NodeKind::SequenceWithMemory);
                let memory = matches!(kind, NodeKind::SequenceWithMemory | NodeKind::FallbackWithMemory);
                let kids = self.kids(i);
                let start = if memory && running { kids.iter().position(|&c| Some(c) == was.last).unwrap() } else { 0 };
                let mut result = if is_seq { Status::Success } else { Status::Failure };
                let mut at = *kids.last().unwrap();
                for &c in &kids[start..] {
                    let old = if !memory && running && was.last.is_some_and(|l| l > c) { was.last } else { None };
                    if !memory {
                        self.preempted.push(old);
                    }
                    let s = self.tick(c);
                    if !memory {
                        self.preempted.pop();
                    }
                    if (is_seq && s != Status::Success) || (!is_seq && s != Status::Failure) {
                        result = s;
                        at = c;
                        break;
                    }
                }
                for c in kids.into_iter().filter(|&c| c > at) {
                    self.halt(c);
                }
                self.st[i].last = Some(at);
                result
            }
            NodeKind::Parallel { success_threshold, failure_threshold } => {
                let kids = self.kids(i);
                let n = kids.len() as u16;
                let (mut ok, mut failed) = (0u16, 0u16);
                let mut verdict = None;
                let mut reached = kids.len();
                for (k, &c) in kids.iter().enumerate() {
                    let prior = self.st[c].status;
                    let s = match prior {
                        NodeStatus::Success if running => Status::Success,
                        NodeStatus::Failure if running => Status::Failure,
                        _ => self.tick(c),
                    };
                    match s {
                        Status::Success => ok += 1,
                        Status::Failure => failed += 1,
                        Status::Running => {}
                    }
                    if ok >= success_threshold {
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
                    None => Status::Running,
                }
            }
            NodeKind::Inverter => match self.tick(i + 1) {
                Status::Success => Status::Failure,
                Status::Failure => Status::Success,
                Status::Running => Status::Running,
            },
            NodeKind::ForceSuccess => match self.tick(i + 1) {
                Status::Running => Status::Running,
                _ => Status::Success,
            },
            NodeKind::ForceFailure => match self.tick(i + 1) {
                Status::Running => Status::Running,
                _ => Status::Failure,
            },
            NodeKind::Repeat(n) | NodeKind::Retry(n) => {
                let repeat = matches!(kind_of(self.nodes, i), NodeKind::Repeat(_));
                let count = if running { was.count } else { 0 };
                let s = self.tick(i + 1);
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
                let s = self.tick(i + 1);
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
        };
        self.st[i].status = r.into();
        r
    }
}

fn kind_of(nodes: &[Node], i: usize) -> NodeKind {
    *nodes[i].kind()
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
        let mut storage = vec![Node::EMPTY; 64];
        let mut b = Builder::<16>::new(&mut storage);
        emit(&t, &mut b);
        let nodes = b.finish().unwrap();
        let catalog = common::catalog();
        let tree = Tree::<8>::validate(nodes, catalog.as_slice()).unwrap();
        let mut state = vec![NodeState::IDLE; nodes.len()];
        let mut exec = Executor::new(tree, &mut state).unwrap();
        let mut observed_state = vec![NodeState::IDLE; nodes.len()];
        let mut observed = Executor::new(tree, &mut observed_state).unwrap();
        // The observed executor's statuses as its reported changes give them.
        let mut replayed = vec![NodeStatus::Idle; nodes.len()];
        let mut reference = Reference::new(nodes);

        for (k, script) in ticks.iter().enumerate() {
            let mut world = Script { nodes, tick: script, log: vec![] };
            let got = exec.tick(&mut world, k as u32).unwrap();
            reference.log.clear();
            let want = reference.tick_root(script);
            prop_assert_eq!(got, want, "root status on tick {}", k);
            prop_assert_eq!(&world.log, &reference.log, "leaves and halts on tick {}", k);
            let got_states: Vec<_> = exec.states().iter().map(|s| s.status()).collect();
            let want_states: Vec<_> = reference.st.iter().map(|s| s.status).collect();
            prop_assert_eq!(&got_states, &want_states, "node statuses after tick {}", k);

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
                    "observed: node {} went {:?} -> {:?} on tick {} but had {:?}", node, old, new, k, had
                );
                *had = new;
            }
            prop_assert_eq!(&replayed, &observed_states, "observed: replayed changes after tick {}", k);
        }
    }
}
