//! Our side of the differential test: the spec as a bt-core tree, run on the case's
//! scripts, and compared with what BehaviorTree.CPP did.

use bt_core::{
    BehaviorInfo, BehaviorSet, Builder, Context, Executor, Leaf, Node, NodeId, NodeKind, NodeStatus, Span, Status, Tree,
};

use super::case::{Case, Tick};
use super::spec::{HOOKS, Kind, SCRIPTS, Spec, loop_elements};
use bt_core::script::{ScriptFault, Value};
use btcpp::xml::script::{ScriptError, Symbols, parse};

/// Scripted leaves per kind in the fixtures' behavior set: condition `Ck` is behavior
/// `k`, action `Ak` is behavior `LEAVES + k`, `k` the leaf's node id.
pub const LEAVES: u16 = 64;

/// The behavior set of the fixtures: `C0`..`C63`, then `A0`..`A63`.
#[must_use]
pub fn catalog() -> Vec<BehaviorInfo<'static>> {
    let names: &'static [String] = Box::leak(
        (0..LEAVES).map(|k| format!("C{k}")).chain((0..LEAVES).map(|k| format!("A{k}"))).collect::<Vec<_>>().into(),
    );
    names
        .iter()
        .enumerate()
        .map(|(i, n)| if i < usize::from(LEAVES) { BehaviorInfo::condition(n, 0) } else { BehaviorInfo::action(n, 0) })
        .collect()
}

/// BehaviorTree.CPP's count for `Repeat`/`RetryUntilSuccessful` as ours: `-1` is for
/// ever, other negative counts are 0.
fn cycles(n: i32) -> u16 {
    match n {
        -1 => NodeKind::FOREVER,
        n if n < 0 => 0,
        n => n.min(i32::from(u16::MAX - 1)) as u16,
    }
}

/// A Parallel threshold as BehaviorTree.CPP resolves it against `children`.
fn resolve(t: i32, children: usize) -> u16 {
    let t = if t < 0 { (children as i32 + t + 1).max(0) } else { t };
    t as u16
}

/// The bt-core kind for a spec node with `children` children.
#[must_use]
pub fn kind(spec: &Spec, id: usize) -> NodeKind {
    let n = spec.children.len();
    let span = |ms: u32| Span::new(ms).unwrap_or(Span::new(Span::MAX).unwrap_or_else(|| unreachable!()));
    match spec.kind {
        Kind::Sequence => NodeKind::SequenceWithMemory,
        Kind::SequenceWithMemory => NodeKind::SequenceStar,
        Kind::Fallback => NodeKind::FallbackWithMemory,
        Kind::ReactiveSequence => NodeKind::Sequence,
        Kind::ReactiveFallback => NodeKind::Fallback,
        Kind::Parallel { success, failure } => NodeKind::Parallel {
            success_threshold: resolve(success, n),
            failure_threshold: resolve(failure, n),
            count_skipped: success < 0,
        },
        Kind::ParallelAll { max_failures } => NodeKind::ParallelAll { max_failures: resolve(max_failures, n) },
        Kind::IfThenElse => NodeKind::IfThenElse,
        Kind::WhileDoElse => NodeKind::WhileDoElse,
        Kind::Inverter => NodeKind::Inverter,
        Kind::ForceSuccess => NodeKind::ForceSuccess,
        Kind::ForceFailure => NodeKind::ForceFailure,
        Kind::Repeat(c) => NodeKind::RepeatCycles(cycles(c)),
        Kind::RetryUntilSuccessful(c) => NodeKind::RetryUntilSuccessful(cycles(c)),
        Kind::KeepRunningUntilFailure => NodeKind::KeepRunningUntilFailure,
        Kind::RunOnce { then_skip } => NodeKind::RunOnce { then_skip },
        Kind::Timeout(ms) => NodeKind::TimeLimit(span(ms)),
        Kind::Delay(ms) => NodeKind::Delay(span(ms)),
        Kind::Sleep(ms) => NodeKind::Sleep(span(ms)),
        Kind::AlwaysSuccess => NodeKind::AlwaysSuccess,
        Kind::AlwaysFailure => NodeKind::AlwaysFailure,
        // The program's place in the value table is set by `build_with_values`.
        Kind::Script(_) => NodeKind::Script(bt_core::Code { start: 0, len: 1 }),
        Kind::ScriptCondition(_) => NodeKind::ScriptCondition(bt_core::Code { start: 0, len: 1 }),
        Kind::Precondition(_, otherwise) => {
            NodeKind::Precondition { code: bt_core::Code { start: 0, len: 1 }, otherwise: status_of(otherwise) }
        }
        Kind::Loop { if_empty, .. } => {
            NodeKind::Loop { table: bt_core::Code { start: 0, len: 1 }, if_empty: status_of(if_empty) }
        }
        Kind::Condition => NodeKind::Condition(Leaf::new(id as u16)),
        Kind::Action => NodeKind::Action(Leaf::new(LEAVES + id as u16)),
    }
}

/// The status of a spec's status letter (`K`: Skipped).
fn status_of(letter: char) -> Status {
    match letter {
        'S' => Status::Success,
        'F' => Status::Failure,
        'R' => Status::Running,
        _ => Status::Skipped,
    }
}

/// A spec loop's table: a literal queue whose programs assign each element to `n`
/// (`LoopInt`) or `m` (`LoopDouble`), as the importer writes them.
fn loop_table(double: bool, count: u8) -> Result<Vec<u16>, String> {
    use bt_core::script::Element;
    use btcpp::xml::script::{Push, element_program, literal_queue};
    let (element, slot) = if double { (Element::Double, 1) } else { (Element::Int, 0) };
    let mut programs = Vec::new();
    for text in loop_elements(double, count) {
        let push = if double {
            Push::Double(text.parse().map_err(|e: std::num::ParseFloatError| e.to_string())?)
        } else {
            Push::Int(text.parse().map_err(|e: std::num::ParseIntError| e.to_string())?)
        };
        programs.push(element_program(push, Some(slot)));
    }
    literal_queue(element, u16::MAX, &programs).ok_or_else(|| "a queue too long".to_string())
}

/// The spec as a bt-core node array.
///
/// # Errors
/// A message when the builder refuses it.
pub fn build(spec: &Spec) -> Result<Vec<Node>, String> {
    Ok(build_nodes(spec)?.nodes)
}

/// The keys of [`SCRIPTS`], as slots.
const KEYS: [&str; 3] = ["n", "m", "flag"];

struct Keys;

impl Symbols for Keys {
    fn slot(&mut self, name: &str, offset: usize) -> Result<(u16, bool), ScriptError> {
        match KEYS.iter().position(|k| *k == name) {
            Some(i) => Ok((i as u16, false)),
            None => Err(ScriptError { offset, message: format!("no key `{name}`") }),
        }
    }

    fn string(&mut self, _: &str) -> Result<u16, ScriptError> {
        Err(ScriptError { offset: 0, message: "no strings".into() })
    }
}

/// A spec as bt-core nodes: a node with scripted attributes gets a `Guard` in front.
#[derive(Clone, Debug)]
pub struct Built {
    /// The nodes.
    pub nodes: Vec<Node>,
    /// Their value table (programs of scripts and guards).
    pub values: Vec<u16>,
    /// The spec node each bt-core node stands for (a guard and its node: the same).
    pub to_spec: Vec<usize>,
    /// The bt-core node whose status is each spec node's (a guarded node: its guard).
    pub shown: Vec<usize>,
}

/// The spec as a bt-core node array and its value table (the scripts' programs,
/// compiled by the importer's compiler).
///
/// # Errors
/// A message when the builder refuses it or a script does not compile.
pub fn build_with_values(spec: &Spec) -> Result<(Vec<Node>, Vec<u16>), String> {
    let b = build_full(spec)?;
    Ok((b.nodes, b.values))
}

fn compile(i: u8) -> Result<Vec<u16>, String> {
    let text = SCRIPTS.get(usize::from(i)).ok_or(format!("no script {i}"))?;
    parse(text).and_then(|p| p.compile(&mut Keys)).map_err(|e| format!("{text}: {}", e.message))
}

/// [`build_with_values`], with the maps between bt-core and spec nodes.
///
/// # Errors
/// As [`build_with_values`].
pub fn build_full(spec: &Spec) -> Result<Built, String> {
    let mut values = Vec::new();
    let Built { mut nodes, to_spec, shown, .. } = build_nodes(spec)?;
    let pre = spec.preorder();
    let place = |values: &mut Vec<u16>, words: &[u16]| -> Result<bt_core::Code, String> {
        let start = u16::try_from(values.len()).map_err(|_| "value table full".to_string())?;
        let len = u16::try_from(words.len()).map_err(|_| "script too long".to_string())?;
        values.extend_from_slice(words);
        Ok(bt_core::Code { start, len })
    };
    for (ours, node) in nodes.iter_mut().enumerate() {
        let s = pre[to_spec[ours]];
        let kind = match *node.kind() {
            NodeKind::Guard(_) => {
                let mut table = vec![0u16];
                for (bit, (letter, _)) in HOOKS.iter().enumerate() {
                    if let Some(&(_, i)) = s.hooks.iter().find(|(h, _)| h == letter) {
                        let words = compile(i)?;
                        table[0] |= 1 << bit;
                        table.push(words.len() as u16);
                        table.extend_from_slice(&words);
                    }
                }
                NodeKind::Guard(place(&mut values, &table)?)
            }
            NodeKind::Loop { if_empty, .. } => {
                let Kind::Loop { double, count, .. } = s.kind else {
                    return Err("a loop node without a queue".into());
                };
                NodeKind::Loop { table: place(&mut values, &loop_table(double, count)?)?, if_empty }
            }
            NodeKind::Script(_) | NodeKind::ScriptCondition(_) | NodeKind::Precondition { .. } => {
                let (Kind::Script(i) | Kind::ScriptCondition(i) | Kind::Precondition(i, _)) = s.kind else {
                    return Err("a script node without a script".into());
                };
                let code = place(&mut values, &compile(i)?)?;
                match *node.kind() {
                    NodeKind::Script(_) => NodeKind::Script(code),
                    NodeKind::Precondition { otherwise, .. } => NodeKind::Precondition { code, otherwise },
                    _ => NodeKind::ScriptCondition(code),
                }
            }
            _ => continue,
        };
        *node = Node::new(kind, node.size());
    }
    Ok(Built { nodes, values, to_spec, shown })
}

/// The nodes (scripts' and guards' programs not placed yet) and the maps of [`Built`].
fn build_nodes(spec: &Spec) -> Result<Built, String> {
    let guards = spec.preorder().iter().filter(|n| !n.hooks.is_empty()).count();
    let mut storage = vec![Node::EMPTY; spec.len() + guards];
    let mut b = Builder::<16>::new(&mut storage);
    // Iterative pre-order with explicit closes.
    enum Step<'a> {
        Open(&'a Spec),
        Close,
    }
    let mut stack = vec![Step::Open(spec)];
    let mut id = 0usize;
    let (mut to_spec, mut shown) = (Vec::new(), Vec::new());
    while let Some(step) = stack.pop() {
        match step {
            Step::Close => {
                b.end().map_err(|e| e.to_string())?;
            }
            Step::Open(s) => {
                let k = kind(s, id);
                shown.push(to_spec.len());
                if !s.hooks.is_empty() {
                    b.open(NodeKind::Guard(bt_core::Code { start: 0, len: 1 })).map_err(|e| e.to_string())?;
                    to_spec.push(id);
                    stack.push(Step::Close);
                }
                to_spec.push(id);
                id += 1;
                if s.kind.is_leaf() {
                    b.leaf(k).map_err(|e| e.to_string())?;
                } else {
                    b.open(k).map_err(|e| e.to_string())?;
                    stack.push(Step::Close);
                    stack.extend(s.children.iter().rev().map(Step::Open));
                }
            }
        }
    }
    Ok(Built { nodes: b.finish().map_err(|e| e.to_string())?.to_vec(), values: Vec::new(), to_spec, shown })
}

struct Scripted<'a> {
    case: &'a Case,
    calls: Vec<usize>,
    events: Vec<String>,
    /// The keys of [`SCRIPTS`].
    blackboard: [Option<Value>; 3],
    /// The spec node of each bt-core node ([`Built::to_spec`]).
    to_spec: Vec<usize>,
    /// Whether each bt-core node is a `Script` (whose run always counts as Success).
    is_script: Vec<bool>,
}

impl Scripted<'_> {
    /// The spec's (BehaviorTree.CPP's) id of bt-core node `node`.
    fn spec(&self, node: NodeId) -> usize {
        self.to_spec.get(usize::from(node)).copied().unwrap_or(usize::from(node))
    }

    fn next(&mut self, node: NodeId) -> Status {
        let node = self.spec(node);
        let Some(script) = self.case.scripts.iter().find(|s| s.node == node) else {
            return Status::Failure;
        };
        let letters = script.statuses.as_bytes();
        let k = self.calls[node];
        self.calls[node] += 1;
        match letters.get(k % letters.len().max(1)) {
            Some(b'S') => Status::Success,
            Some(b'F') => Status::Failure,
            _ => Status::Running,
        }
    }
}

fn letter(s: Status) -> char {
    match s {
        Status::Success => 'S',
        Status::Failure => 'F',
        Status::Running => 'R',
        Status::Skipped => 'K',
    }
}

fn status_letter(s: NodeStatus) -> char {
    match s {
        NodeStatus::Idle => 'I',
        NodeStatus::Success => 'S',
        NodeStatus::Failure => 'F',
        NodeStatus::Running => 'R',
    }
}

impl BehaviorSet for Scripted<'_> {
    fn condition(&mut self, _: &Leaf, ctx: Context<'_>) -> Status {
        let s = self.next(ctx.node);
        self.events.push(format!("{}{}", self.spec(ctx.node), letter(s)));
        s
    }

    fn action(&mut self, _: &Leaf, ctx: Context<'_>) -> Status {
        let s = self.next(ctx.node);
        let c = letter(s);
        let c = if ctx.starting { c } else { c.to_ascii_lowercase() };
        self.events.push(format!("{}{c}", self.spec(ctx.node)));
        s
    }

    fn halt(&mut self, _: &Leaf, node: NodeId) {
        self.events.push(format!("H{}", self.spec(node)));
    }

    fn script(&mut self, code: &[u16], ctx: Context<'_>) -> Result<Value, ScriptFault> {
        let v = bt_core::script::run(code, &bt_core::PortTable::EMPTY, &mut self.blackboard)?;
        // For the replay of logs, not for the harness's events: `$` marks it, and it
        // names the bt-core node (a guard's scripts are the guard's, not its node's).
        let held =
            self.is_script.get(usize::from(ctx.node)) == Some(&true) || bt_core::script::truth(v).unwrap_or(false);
        self.events.push(format!("${}{}", ctx.node, if held { 'S' } else { 'F' }));
        Ok(v)
    }
}

/// The `now` tick `k` of a case gives bt-core: milliseconds for clocked cases (the
/// harness ticks every `period_ms` of real time), else the tick number.
#[must_use]
pub fn now(case: &Case, k: u32) -> u32 {
    if case.period_ms == 0 { k } else { k * case.period_ms }
}

/// Runs the case on our executor: one [`Tick`] per tick, in the harness's notation.
///
/// # Errors
/// A message when the tree does not build or validate, or a tick fails.
pub fn run(case: &Case) -> Result<Vec<Tick>, String> {
    let Built { nodes, values, to_spec, shown } = build_full(&case.spec)?;
    let catalog = catalog();
    let tree = Tree::<16>::validate_with(&nodes, &values, catalog.as_slice()).map_err(|e| e.to_string())?;
    let mut state = vec![bt_core::NodeState::IDLE; nodes.len()];
    let mut exec = Executor::new(tree, &mut state).map_err(|e| e.to_string())?;
    let is_script = nodes.iter().map(|n| matches!(n.kind(), NodeKind::Script(_))).collect();
    let mut world =
        Scripted { case, calls: vec![0; nodes.len()], events: vec![], blackboard: [None; 3], to_spec, is_script };
    let mut out = vec![];
    for k in 0..case.ticks {
        let now = now(case, k);
        let mut root = exec.tick(&mut world, now).map_err(|e| format!("tick {k}: {e}"))?;
        if case.once {
            // BehaviorTree.CPP's tickOnce(): again while Running and woken.
            let mut again = 0;
            while root == Status::Running && exec.take_woken() {
                again += 1;
                if again > 10_000 {
                    return Err(format!("tick {k}: runaway"));
                }
                root = exec.tick(&mut world, now).map_err(|e| format!("tick {k}: {e}"))?;
            }
        }
        // BehaviorTree.CPP's nodes' statuses: a guarded node's is its guard's.
        let states = exec.states();
        let statuses = shown.iter().map(|&i| states.get(i).map_or('I', |s| status_letter(s.status()))).collect();
        out.push(Tick { root: letter(root), events: std::mem::take(&mut world.events), statuses });
    }
    Ok(out)
}
