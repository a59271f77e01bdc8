//! Test fixtures shared by the per-family tests: a scripted behavior set that counts
//! ticks and halts per behavior and logs every call in order.
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use bt_core::script::{ScriptFault, Value};
use bt_core::{
    BehaviorInfo, BehaviorSet, Builder, Context, Leaf, Node, NodeId, NodeKind, NodeStatus, Observer, Selection, Status,
};

/// Success, Failure, Running and Skipped, as the tests write them.
pub const S: Status = Status::Success;
/// Failure.
pub const F: Status = Status::Failure;
/// Running.
pub const R: Status = Status::Running;
/// Skipped.
pub const K: Status = Status::Skipped;

/// Behaviors `0..16` are conditions `C0?`..`C15?`, `16..32` actions `A0!`..`A15!`.
pub const N: u16 = 16;

pub fn cond(i: u16) -> u16 {
    i
}

pub fn act(i: u16) -> u16 {
    N + i
}

pub fn catalog() -> Vec<BehaviorInfo<'static>> {
    let mut v = Vec::new();
    for i in 0..N {
        v.push(BehaviorInfo::condition(Box::leak(format!("C{i}?").into_boxed_str()), 0));
    }
    for i in 0..N {
        v.push(BehaviorInfo::action(Box::leak(format!("A{i}!").into_boxed_str()), 0));
    }
    v
}

/// One call the executor made, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    /// A condition or action was ticked (`starting` for actions not Running before).
    Tick { behavior: u16, starting: bool },
    /// An action was halted.
    Halt { behavior: u16 },
    /// A `ManualSelector` asked which child (it has `children`) or status.
    Select { node: NodeId, children: u8, starting: bool },
    /// A program whose first word is `word` ran for node `node`.
    Script { node: NodeId, word: u16 },
    /// A `Loop` at `node` took an element of the blackboard queue, or found it empty.
    Pop { node: NodeId, starting: bool },
}

/// Every behavior returns what `results[id]` says, and every `ManualSelector` what
/// `selection` says (none: the set refuses, as one without selections does); a program
/// gives what `programs` says for its first word (true when not there), and the
/// blackboard queue of every `Loop` holds `queue` elements; counts and logs every call.
#[derive(Debug)]
pub struct Scripted {
    pub results: Vec<Status>,
    pub selection: Option<Selection>,
    pub programs: Vec<(u16, Result<Value, ScriptFault>)>,
    pub queue: u32,
    pub ticks: Vec<u32>,
    pub halts: Vec<u32>,
    pub log: Vec<Call>,
}

impl Scripted {
    pub fn new() -> Self {
        let n = usize::from(2 * N);
        let mut results = vec![Status::Failure; n];
        for r in results.iter_mut().skip(usize::from(N)) {
            *r = Status::Running;
        }
        Self {
            results,
            selection: None,
            programs: Vec::new(),
            queue: 0,
            ticks: vec![0; n],
            halts: vec![0; n],
            log: Vec::new(),
        }
    }

    pub fn set(&mut self, behavior: u16, s: Status) -> &mut Self {
        self.results[usize::from(behavior)] = s;
        self
    }

    /// What every `ManualSelector` is told from now on.
    pub fn choose(&mut self, s: Selection) -> &mut Self {
        self.selection = Some(s);
        self
    }

    /// What the program whose first word is `word` gives from now on.
    pub fn program(&mut self, word: u16, result: Result<Value, ScriptFault>) -> &mut Self {
        self.programs.retain(|&(w, _)| w != word);
        self.programs.push((word, result));
        self
    }

    /// The first words of the programs run, in order.
    pub fn scripts(&self) -> Vec<u16> {
        self.log.iter().filter_map(|c| if let Call::Script { word, .. } = *c { Some(word) } else { None }).collect()
    }

    /// How many times a `ManualSelector` asked.
    pub fn selects(&self) -> usize {
        self.log.iter().filter(|c| matches!(c, Call::Select { .. })).count()
    }

    pub fn ticks(&self, behavior: u16) -> u32 {
        self.ticks[usize::from(behavior)]
    }

    pub fn halts(&self, behavior: u16) -> u32 {
        self.halts[usize::from(behavior)]
    }

    /// Forgets counts and log (results stay).
    pub fn clear(&mut self) {
        self.ticks.fill(0);
        self.halts.fill(0);
        self.log.clear();
    }

    fn run(&mut self, leaf: &Leaf, starting: bool) -> Status {
        let b = leaf.behavior();
        self.ticks[usize::from(b)] += 1;
        self.log.push(Call::Tick { behavior: b, starting });
        self.results[usize::from(b)]
    }
}

impl BehaviorSet for Scripted {
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        self.run(leaf, true)
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        self.run(leaf, ctx.starting)
    }

    fn halt(&mut self, leaf: &Leaf, _: NodeId) {
        let b = leaf.behavior();
        self.halts[usize::from(b)] += 1;
        self.log.push(Call::Halt { behavior: b });
    }

    fn select(&mut self, children: u8, ctx: Context<'_>) -> Result<Selection, ScriptFault> {
        self.log.push(Call::Select { node: ctx.node, children, starting: ctx.starting });
        self.selection.ok_or(ScriptFault::NoSelections)
    }

    fn script(&mut self, code: &[u16], ctx: Context<'_>) -> Result<Value, ScriptFault> {
        let word = code.first().copied().unwrap_or(u16::MAX);
        self.log.push(Call::Script { node: ctx.node, word });
        self.programs.iter().find(|&&(w, _)| w == word).map_or(Ok(Value::Bool(true)), |&(_, r)| r)
    }

    fn pop(&mut self, _: u16, _: u16, ctx: Context<'_>) -> Result<bool, ScriptFault> {
        self.log.push(Call::Pop { node: ctx.node, starting: ctx.starting });
        let took = self.queue > 0;
        self.queue = self.queue.saturating_sub(1);
        Ok(took)
    }
}

/// Records every status change.
#[derive(Debug, Default)]
pub struct Changes(pub Vec<(NodeId, NodeStatus, NodeStatus)>);

impl Observer for Changes {
    fn on_change(&mut self, node: NodeId, old: NodeStatus, new: NodeStatus) {
        self.0.push((node, old, new));
    }
}

/// Builds a tree with `f` into a leaked 256-node buffer and returns the nodes.
pub fn build(f: impl FnOnce(&mut Builder<'_, 32>) -> Result<(), bt_core::BuildError>) -> &'static [Node] {
    let storage: &'static mut [Node] = Box::leak(vec![Node::EMPTY; 256].into_boxed_slice());
    let mut b = Builder::<32>::new(storage);
    f(&mut b).expect("tree builds");
    b.finish().expect("tree finishes")
}

/// Whether every node but the root is Idle.
pub fn children_idle(states: &[bt_core::NodeState]) -> bool {
    states[1..].iter().all(|s| s.status() == NodeStatus::Idle)
}

/// A decorator `kind` over action `A0!`.
pub fn over_action(kind: NodeKind) -> &'static [Node] {
    build(|b| {
        b.open(kind)?.action(act(0), &[])?.end()?;
        Ok(())
    })
}

/// Declares `$exec`, an executor over `$nodes` with value table `$values`, checked
/// against the test catalog.
#[macro_export]
macro_rules! executor_with {
    ($exec:ident, $nodes:expr, $values:expr) => {
        let catalog = $crate::common::catalog();
        let tree = bt_core::Tree::<32>::validate_with($nodes, $values, catalog.as_slice()).expect("valid tree");
        let mut state = vec![bt_core::NodeState::IDLE; tree.len()];
        #[allow(unused_mut)]
        let mut $exec = bt_core::Executor::new(tree, &mut state).expect("state fits");
    };
}

/// Declares `$exec`, an executor over `$nodes` checked against the test catalog.
#[macro_export]
macro_rules! executor {
    ($exec:ident, $nodes:expr) => {
        let catalog = $crate::common::catalog();
        let tree = bt_core::Tree::<32>::validate($nodes, catalog.as_slice()).expect("valid tree");
        let mut state = vec![bt_core::NodeState::IDLE; tree.len()];
        #[allow(unused_mut)]
        let mut $exec = bt_core::Executor::new(tree, &mut state).expect("state fits");
    };
}
