//! Our side of the version 3 differential test: the document imported as `sim-host
//! import` imports it, its image loaded as a controller loads it, ticked with leaves
//! that read `in` and write `out` as the harness's do, and compared with what
//! BehaviorTree.CPP 3.8 did.

use std::fmt::Write as _;
use std::path::Path;

use bt_core::script::{ScriptFault, Value};
use bt_core::{BehaviorSet, Context, Executor, Leaf, Node, NodeId, NodeStatus, Port, PortTable, Status};
use btcpp::xml::lower::stoi;
use btcpp::xml::{ImportOptions, Imported, import_text};

use super::super::case::Tick;
use super::super::compare::{Comparison, Ours, Walked, compare_tick};
use super::{Case, Recorded};

/// The leaves, the blackboard and what happened since the last tick.
struct Leaves<'a> {
    imported: &'a Imported,
    ports: PortTable<'a>,
    slots: Vec<Option<Value>>,
    calls: Vec<usize>,
    events: Vec<String>,
    case: &'a Case,
}

impl Leaves<'_> {
    /// BehaviorTree.CPP's pre-order index of bt-core node `node`.
    fn index(&self, node: NodeId) -> usize {
        self.imported.meta.get(usize::from(node)).map_or(usize::MAX, |m| usize::from(m.uid) - 1)
    }

    /// What port `in` gives as an `int`, as the harness prints it.
    fn read(&self, args: &[u16]) -> String {
        let int = match self.ports.port(args, 0) {
            Some(Port::Constant(c)) => match c {
                bt_core::port::Constant::Int(v) => Some(v),
                bt_core::port::Constant::Str(s) => stoi(s),
                _ => None,
            },
            Some(Port::Slot(s)) => match self.slots.get(usize::from(s)).copied().flatten() {
                Some(Value::Int(v)) => Some(v),
                Some(Value::Double(d)) if d.fract() == 0.0 => Some(d as i64),
                Some(Value::Bool(b)) => Some(i64::from(b)),
                Some(Value::Str(c)) => match self.ports.constant(c) {
                    Some(bt_core::port::Constant::Str(s)) => stoi(s),
                    _ => None,
                },
                _ => None,
            },
            _ => None,
        };
        int.map_or_else(|| "-".to_string(), |v| v.to_string())
    }

    fn call(&mut self, leaf: &Leaf, ctx: Context<'_>, action: bool) -> Status {
        let b = usize::from(leaf.behavior());
        let Some(ty) =
            self.imported.catalog.behaviors().get(b).and_then(|b| self.case.types.iter().find(|t| t.name == b.id))
        else {
            return Status::Failure;
        };
        let args = ctx.args(leaf);
        let read = self.read(args);
        if self.calls.len() <= b {
            self.calls.resize(b + 1, 0);
        }
        let letters = ty.script.as_bytes();
        let k = self.calls[b];
        self.calls[b] += 1;
        let s = match letters.get(k % letters.len().max(1)) {
            Some(b'S') => Status::Success,
            Some(b'F') => Status::Failure,
            _ => Status::Running,
        };
        if let Some(Port::Slot(out)) = self.ports.port(args, 1)
            && let Some(slot) = self.slots.get_mut(usize::from(out))
        {
            *slot = Some(Value::Int(ty.number() * 1000 + self.calls[b] as i64));
        }
        let c = letter(s);
        let c = if action && !ctx.starting { c.to_ascii_lowercase() } else { c };
        self.events.push(format!("{}{c}:{read}", self.index(ctx.node)));
        s
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

impl BehaviorSet for Leaves<'_> {
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        self.call(leaf, ctx, false)
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        self.call(leaf, ctx, true)
    }

    fn halt(&mut self, _: &Leaf, node: NodeId) {
        self.events.push(format!("H{}", self.index(node)));
    }

    fn script(&mut self, code: &[u16], _: Context<'_>) -> Result<Value, ScriptFault> {
        bt_core::script::run(code, &self.ports, self.slots.as_mut_slice())
    }
}

/// BehaviorTree.CPP's nodes (pre-order, SubTree nodes included) as bt-core nodes: a
/// SubTree node shows the status of its subtree's root.
fn shown(imported: &Imported) -> Vec<usize> {
    let count = imported.meta.len() + imported.subtrees.len();
    let mut out = vec![usize::MAX; count];
    for (i, m) in imported.meta.iter().enumerate() {
        if let Some(o) = out.get_mut(usize::from(m.uid) - 1) {
            *o = i;
        }
    }
    for s in &imported.subtrees {
        if let Some(o) = out.get_mut(usize::from(s.uid) - 1) {
            *o = usize::from(s.node);
        }
    }
    out
}

/// Imports the case's document, with the leaf types' models.
///
/// # Errors
/// The import error, as text.
pub fn import(case: &Case) -> Result<Imported, String> {
    let xml = case.xml.replacen("</root>", &format!("{}</root>", super::generate::models()), 1);
    import_text(Path::new("case.xml"), &xml, &ImportOptions::default()).map_err(|e| e.to_string())
}

/// Runs the case on our executor: one [`Tick`] per tick, in the harness's notation.
///
/// # Errors
/// A message when the document does not import or load, or a tick fails.
pub fn run(case: &Case) -> Result<Vec<Tick>, String> {
    let imported = import(case)?;
    let image = imported.image().map_err(|e| e.to_string())?;
    let mut nodes = vec![Node::EMPTY; imported.nodes.len()];
    let mut values = vec![0u16; imported.values.len().max(1)];
    let (tree, ports): (bt_core::Tree<'_, 64>, _) =
        bt_core::load_with_ports(&image, &imported.catalog, &mut nodes, &mut values).map_err(|e| e.to_string())?;
    // Slots a SubTree starts at a literal hold it from the start.
    let slots = (0..imported.slots.len())
        .map(|s| {
            let c = ports.slot(u16::try_from(s).ok()?)?.initial?;
            Some(match ports.constant(c)? {
                bt_core::port::Constant::Int(v) => Value::Int(v),
                bt_core::port::Constant::Double(v) => Value::Double(v),
                bt_core::port::Constant::Bool(v) => Value::Bool(v),
                bt_core::port::Constant::Str(_) => Value::Str(c),
            })
        })
        .collect();
    let mut leaves = Leaves { imported: &imported, ports, slots, calls: vec![], events: vec![], case };
    let mut state = vec![bt_core::NodeState::IDLE; imported.nodes.len()];
    let mut exec = Executor::new(tree, &mut state).map_err(|e| e.to_string())?;
    let shown = shown(&imported);
    let mut out = vec![];
    for k in 0..case.ticks {
        let now = if case.period_ms == 0 { k } else { k * case.period_ms };
        let root = exec.tick(&mut leaves, now).map_err(|e| format!("tick {k}: {e}"))?;
        let states = exec.states();
        let statuses = shown
            .iter()
            .map(|&i| match states.get(i).map(bt_core::NodeState::status) {
                Some(NodeStatus::Success) => 'S',
                Some(NodeStatus::Failure) => 'F',
                Some(NodeStatus::Running) => 'R',
                _ => 'I',
            })
            .collect();
        out.push(Tick { root: letter(root), events: std::mem::take(&mut leaves.events), statuses });
    }
    Ok(out)
}

/// The node types whose children BehaviorTree.CPP 3.8 shows Running or Idle only: the
/// reactive controls reset every child but the Running one, and every decorator resets
/// a child that finished (`DecoratorNode::executeTick`).
fn resets_finished_children(id: &str) -> bool {
    !matches!(id, "Sequence" | "Fallback" | "SequenceStar" | "Parallel" | "IfThenElse" | "WhileDoElse")
}

/// Our statuses as BehaviorTree.CPP 3.8 would show them (see
/// `resets_finished_children`); a finished root shows Idle (`tickRoot()` resets it).
#[must_use]
pub fn btcpp_view(nodes: &[(String, Option<usize>)], ours: &str) -> String {
    let ours: Vec<char> = ours.chars().collect();
    let mut view = vec!['I'; nodes.len()];
    for (i, (_, parent)) in nodes.iter().enumerate() {
        let s = ours.get(i).copied().unwrap_or('I');
        view[i] = match parent {
            None => {
                if s == 'R' {
                    'R'
                } else {
                    'I'
                }
            }
            Some(p) => {
                let pv = view[*p];
                if pv != 'R' {
                    'I'
                } else if resets_finished_children(&nodes[*p].0) {
                    if s == 'R' { 'R' } else { 'I' }
                } else {
                    s
                }
            }
        };
    }
    view.into_iter().collect()
}

/// Whether `call` starts an action (`7R:-`: an upper-case letter on an action type's
/// node).
fn starts_action(rec: &Recorded, call: &str) -> bool {
    let Some((head, _)) = call.split_once(':') else { return false };
    let Some(letter) = head.chars().last() else { return false };
    if !matches!(letter, 'S' | 'F' | 'R') {
        return false;
    }
    let node: usize = head[..head.len() - 1].parse().unwrap_or(usize::MAX);
    rec.nodes.get(node).is_some_and(|(id, _)| id.starts_with('A'))
}

/// Compares our run with BehaviorTree.CPP 3.8's recording, as the version 4 test does:
/// the same leaf calls (and what `in` gave them), halts (earlier only by halt before
/// start), root status, nodes Running, and statuses as BehaviorTree.CPP shows them but
/// for the finished ones it leaves behind under a node it reset.
///
/// # Errors
/// The first disagreement, with the tick and both sides.
pub fn compare(rec: &Recorded, ours: &[Tick]) -> Result<Comparison, String> {
    let mut cmp = Comparison::default();
    for (k, (want, got)) in rec.ticks.iter().zip(ours).enumerate() {
        let view = btcpp_view(&rec.nodes, &got.statuses);
        let fail = |what: &str| {
            let mut m = format!("{}: tick {k}: {what}\n", rec.case.name);
            let _ = writeln!(m, "  xml       {}", rec.case.xml);
            let _ = writeln!(m, "  BT.CPP    {} | {} | {}", want.root, want.events.join(" "), want.statuses);
            let _ = writeln!(m, "  bt-core   {} | {} | {}", got.root, got.events.join(" "), got.statuses);
            let _ = writeln!(m, "  as BT.CPP shows it            {view}");
            m
        };
        let ours = Ours { tick: got, running: &view, view: &view };
        let parent = |n: usize| rec.nodes.get(n).and_then(|(_, p)| *p);
        match compare_tick(want, &ours, &parent, &|c| starts_action(rec, c), &mut cmp) {
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
