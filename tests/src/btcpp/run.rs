//! Our side of the differential test: the spec as a bt-core tree, run on the case's
//! scripts, and compared with what BehaviorTree.CPP did.

use std::fmt::Write as _;

use bt_core::{
    BehaviorInfo, BehaviorSet, Builder, Context, Executor, Leaf, Node, NodeId, NodeKind, NodeStatus, Span, Status, Tree,
};

use super::case::{Case, Recorded, Tick};
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

/// What a comparison found.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Comparison {
    /// Ticks compared.
    pub ticks: usize,
    /// Halts that came earlier in our tick than in BehaviorTree.CPP's, before an action
    /// started in place of the halted one (halt before start).
    pub halts_moved_earlier: usize,
    /// Set when halt before start halted a branch that BehaviorTree.CPP went on running
    /// (the action that preempted it finished at once): the tick where it happened.
    /// From there on the two runs differ by design and are not compared.
    pub restarted_at: Option<usize>,
    /// Ticks where the statuses after the tick, seen as BehaviorTree.CPP shows them
    /// ([`btcpp_view`]), differ: only in finished statuses BehaviorTree.CPP leaves
    /// behind under a node it has reset.
    pub ticks_with_other_statuses: usize,
}

/// Comparisons of many cases added up, for the differential tests' summary lines.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Totals {
    /// Ticks compared.
    pub ticks: usize,
    /// Halts that came earlier by halt before start.
    pub halts_moved_earlier: usize,
    /// Cases compared only up to a branch that halt before start restarted.
    pub restarted: usize,
    /// Ticks whose statuses, as BehaviorTree.CPP shows them, differ in finished statuses
    /// it leaves behind.
    pub ticks_with_other_statuses: usize,
}

impl Totals {
    /// Adds one case's comparison.
    pub fn add(&mut self, c: &Comparison) {
        self.ticks += c.ticks;
        self.halts_moved_earlier += c.halts_moved_earlier;
        self.restarted += usize::from(c.restarted_at.is_some());
        self.ticks_with_other_statuses += c.ticks_with_other_statuses;
    }
}

impl std::fmt::Display for Totals {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} ticks compared; {} halts earlier (halt before start); {} cases compared up to a branch restarted \
             by halt before start; {} ticks with other statuses as BehaviorTree.CPP shows them",
            self.ticks, self.halts_moved_earlier, self.restarted, self.ticks_with_other_statuses
        )
    }
}

fn is_halt(e: &str) -> bool {
    e.starts_with('H') || e.starts_with('h')
}

/// Our node statuses as BehaviorTree.CPP would show them: it resets a finished node's
/// children to Idle, and a reactive node's or a decorator's children that are not
/// Running; bt-core keeps what they returned. The kinds that stand for
/// BehaviorTree.CPP-only nodes keep statuses exactly as it does.
#[must_use]
pub fn btcpp_view(spec: &Spec, ours: &str) -> String {
    let nodes = spec.preorder();
    let ours: Vec<char> = ours.chars().collect();
    let mut view = vec!['I'; nodes.len()];
    // (node, end) of the open ancestors.
    let mut open: Vec<(usize, usize)> = vec![];
    for (i, n) in nodes.iter().enumerate() {
        while open.last().is_some_and(|&(_, end)| end <= i) {
            open.pop();
        }
        let s = ours.get(i).copied().unwrap_or('I');
        view[i] = match open.last() {
            None => {
                if s == 'R' {
                    'R'
                } else {
                    'I'
                }
            }
            Some(&(p, _)) => {
                let pv = view[p];
                match nodes[p].kind {
                    Kind::ReactiveSequence
                    | Kind::ReactiveFallback
                    | Kind::Inverter
                    | Kind::ForceSuccess
                    | Kind::ForceFailure => {
                        if pv == 'R' && s == 'R' {
                            'R'
                        } else {
                            'I'
                        }
                    }
                    Kind::Sequence | Kind::Fallback | Kind::Parallel { .. } => {
                        if pv == 'R' {
                            s
                        } else {
                            'I'
                        }
                    }
                    _ => s,
                }
            }
        };
        open.push((i, i + n.len()));
    }
    view.into_iter().collect()
}

/// Compares our run with BehaviorTree.CPP's recording.
///
/// # Errors
/// The first disagreement, with the tick and both sides.
pub fn compare(rec: &Recorded, ours: &[Tick]) -> Result<Comparison, String> {
    let mut cmp = Comparison::default();
    for (k, (want, got)) in rec.ticks.iter().zip(ours).enumerate() {
        let fail = |what: &str| {
            let mut m = format!("{}: tick {k}: {what}\n", rec.case.name);
            let _ = writeln!(m, "  spec      {}", rec.case.spec);
            let _ = writeln!(m, "  BT.CPP    {} | {} | {}", want.root, want.events.join(" "), want.statuses);
            let _ = writeln!(m, "  bt-core   {} | {} | {}", got.root, got.events.join(" "), got.statuses);
            let _ = writeln!(m, "  as BT.CPP shows it            {}", btcpp_view(&rec.case.spec, &got.statuses));
            m
        };
        if want.events.iter().any(|e| e.starts_with('h')) {
            return Err(fail("BehaviorTree.CPP halted an action that was not Running"));
        }
        let view = btcpp_view(&rec.case.spec, &got.statuses);
        let parents = parents(&rec.case.spec);
        let ours = Ours { tick: got, running: &got.statuses, view: &view };
        match compare_tick(want, &ours, &|n| parents.get(n).copied().flatten(), &|call| is_action(rec, call), &mut cmp)
        {
            Ok(Walked::Same) => {}
            Ok(Walked::Restarted) => {
                cmp.restarted_at = Some(k);
                return Ok(cmp);
            }
            Err(what) => return Err(fail(&what)),
        }
    }
    if rec.ticks.len() != ours.len() {
        return Err(format!("{}: {} ticks recorded, {} run", rec.case.name, rec.ticks.len(), ours.len()));
    }
    Ok(cmp)
}

/// Our tick, for [`compare_tick`]: the tick, the statuses whose Running nodes must be
/// BehaviorTree.CPP's, and the statuses as BehaviorTree.CPP shows them.
#[derive(Debug)]
pub struct Ours<'a> {
    /// Our tick.
    pub tick: &'a Tick,
    /// Statuses per recorded node, for the Running ones.
    pub running: &'a str,
    /// Statuses as BehaviorTree.CPP shows them.
    pub view: &'a str,
}

/// Compares one tick of ours with BehaviorTree.CPP's `want`: the same leaf calls and
/// halts ([`walk_events`]), root status and nodes Running, and the same statuses as
/// BehaviorTree.CPP shows them but for a finished status it left behind under a node it
/// had reset (it resets a node, not its subtree), where bt-core's node is Idle (counted
/// in `cmp`). `parent` gives each recorded node's parent.
///
/// # Errors
/// What differs.
pub fn compare_tick(
    want: &Tick,
    ours: &Ours<'_>,
    parent: &dyn Fn(usize) -> Option<usize>,
    is_action: &dyn Fn(&str) -> bool,
    cmp: &mut Comparison,
) -> Result<Walked, String> {
    if walk_events(&want.events, &ours.tick.events, is_action, cmp)? == Walked::Restarted {
        return Ok(Walked::Restarted);
    }
    if want.root != ours.tick.root {
        return Err("root status differs".into());
    }
    let running = |s: &str| s.chars().map(|c| c == 'R').collect::<Vec<_>>();
    if running(&want.statuses) != running(ours.running) {
        return Err("different nodes Running after the tick".into());
    }
    if want.statuses != ours.view {
        let theirs: Vec<char> = want.statuses.chars().collect();
        for (n, (w, g)) in theirs.iter().zip(ours.view.chars()).enumerate() {
            let stale = g == 'I' && matches!(w, 'S' | 'F') && parent(n).is_some_and(|p| theirs[p] != 'R');
            if *w != g && !stale {
                return Err(format!("node {n} shows {w} in BehaviorTree.CPP, {g} here"));
            }
        }
        cmp.ticks_with_other_statuses += 1;
    }
    cmp.ticks += 1;
    Ok(Walked::Same)
}

/// How the events of one tick compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Walked {
    /// The same, but for halts moved earlier by halt before start.
    Same,
    /// Halt before start halted a branch that BehaviorTree.CPP went on running: the runs
    /// differ by design from here.
    Restarted,
}

/// Walks the events of one tick, BehaviorTree.CPP's (`want`) and ours (`got`, with our
/// script runs, `$...`, left out). Where we halt and BehaviorTree.CPP does not, the
/// halts must be followed by an action starting in both (halt before start,
/// `starts_action` tells a call that does); each such halt must come later in
/// BehaviorTree.CPP's tick, or the run has diverged by design. Consecutive halts at the
/// start of a tick (timers) may come in any order. Counts the halts moved earlier.
///
/// # Errors
/// What differs, in words.
pub fn walk_events(
    want: &[String],
    got: &[String],
    starts_action: &dyn Fn(&str) -> bool,
    cmp: &mut Comparison,
) -> Result<Walked, &'static str> {
    if want.iter().any(|e| e.starts_with('h')) {
        return Err("BehaviorTree.CPP halted an action that was not Running");
    }
    let mut theirs: Vec<&String> = want.iter().collect();
    let mine: Vec<&String> = got.iter().filter(|e| !e.starts_with('$')).collect();
    let (mut i, mut j) = (0usize, 0usize);
    if mine.first().is_some_and(|e| is_halt(e)) {
        let lead = |v: &[&String]| v.iter().take_while(|e| is_halt(e)).map(|e| e.to_string()).collect::<Vec<_>>();
        let (mut a, mut b) = (lead(&theirs), lead(&mine));
        a.sort();
        b.sort();
        if a == b {
            i = a.len();
            j = b.len();
        }
    }
    while j < mine.len() {
        if i < theirs.len() && theirs[i] == mine[j] {
            i += 1;
            j += 1;
            continue;
        }
        if !is_halt(mine[j]) {
            return Err("different events");
        }
        let run_end = (j..mine.len()).find(|&t| !is_halt(mine[t])).unwrap_or(mine.len());
        let start = mine.get(run_end);
        if !start.is_some_and(|c| starts_action(c)) || theirs.get(i) != start {
            return Err("a halt that is not before a start");
        }
        for h in &mine[j..run_end] {
            // BehaviorTree.CPP halts it later in the tick, without ticking it in
            // between: only the order differs. Otherwise it went on running it.
            let node = &h[1..];
            let continued =
                |e: &&String| e.strip_prefix(node).is_some_and(|s| s.starts_with(['S', 'F', 'R', 's', 'f', 'r']));
            match theirs[i..].iter().position(|e| e == h) {
                Some(p) if !theirs[i..i + p].iter().any(continued) => {
                    theirs.remove(i + p);
                    cmp.halts_moved_earlier += 1;
                }
                _ => return Ok(Walked::Restarted),
            }
        }
        j = run_end;
    }
    if i != theirs.len() {
        return Err("BehaviorTree.CPP did more");
    }
    Ok(Walked::Same)
}

/// Each node's parent, pre-order.
fn parents(spec: &Spec) -> Vec<Option<usize>> {
    let nodes = spec.preorder();
    let mut out = vec![None; nodes.len()];
    let mut open: Vec<(usize, usize)> = vec![];
    for (i, n) in nodes.iter().enumerate() {
        while open.last().is_some_and(|&(_, end)| end <= i) {
            open.pop();
        }
        out[i] = open.last().map(|&(p, _)| p);
        open.push((i, i + n.len()));
    }
    out
}

/// Whether `call` starts an action of the case (a call whose letter is upper case).
fn is_action(rec: &Recorded, call: &str) -> bool {
    if !call.ends_with(['S', 'F', 'R']) {
        return false;
    }
    let node: usize = call.trim_end_matches(|c: char| c.is_ascii_alphabetic()).parse().unwrap_or(usize::MAX);
    rec.case.scripts.iter().any(|s| s.node == node && s.action)
}
