//! Blended planning and acting, narrated: ticks a tree in a live world and, when the
//! root fails, lets the planner expand the tree in place (seed 000, Algorithm 1 at run
//! time), then goes on from the world as it is.
//!
//! The narration is for a robotics engineer following the run: world events, each
//! action that starts, finishes, fails or is halted, each expansion with its conflicts,
//! and the tree whenever it changes. Quiet stretches (an action running for many ticks)
//! take one line. Everything said is also kept for pictures ([`Record`]).

use std::fmt::Write as _;

use bt_core::{Catalog, Executor, Node, NodeId, NodeState, NodeStatus, Observer, Status, Tree};

use crate::episode::TICK_MS;
use planner::Planner;
use planner::ground::Grounding;
use planner::state::State;

/// Deepest tree the driver runs.
pub const DEPTH: usize = planner::DEPTH;

/// Named positions in the plane, metres: what the top view draws.
pub type Points = Vec<(&'static str, [f32; 2])>;

/// A world a scenario runs in: its behavior set over its state, advanced one tick at a
/// time after the tree was ticked.
pub trait Live: bt_core::BehaviorSet {
    /// Advances one tick: external agents act, motions move, physics runs. `running`
    /// names the action the tree left running (scripted agents may react to it).
    fn advance(&mut self, tick: u32, running: Option<&str>);

    /// World events since the last call, in plain words.
    fn drain_events(&mut self) -> Vec<String>;

    /// What the planner believes about the world: each ground atom of `g`, read through
    /// the world's own conditions.
    fn belief(&mut self, g: &Grounding) -> State {
        let mut state = State::new(g.atom_count());
        for atom in 0..g.atom_count() {
            let Ok(atom) = u32::try_from(atom) else { break };
            if let Some(leaf) = g.condition_leaf(atom) {
                let ctx = bt_core::Context { node: 0, now: 0, starting: true, values: &[] };
                state.set(atom, self.condition(&leaf, ctx) == Status::Success);
            }
        }
        state
    }

    /// Positions for the top view, by name, in metres (empty for worlds without
    /// geometry).
    fn points(&self) -> Points {
        Vec::new()
    }
}

/// The tree at one moment, for pictures.
#[derive(Clone, Debug)]
pub struct Snapshot {
    /// Tick of the snapshot.
    pub tick: u32,
    /// Why it was taken ("after expansion 3", "end").
    pub label: String,
    /// The tree's nodes.
    pub nodes: Vec<Node>,
    /// Each node's status then.
    pub states: Vec<NodeState>,
}

/// Everything a run produced, for summaries, tests and pictures.
#[derive(Clone, Debug, Default)]
pub struct Record {
    /// Positions at every tick (tick, name, x, y).
    pub frames: Vec<(u32, Points)>,
    /// World events with their tick and where the first named point was then.
    pub events: Vec<(u32, String)>,
    /// Expansions: tick and the planner's account.
    pub expansions: Vec<(u32, planner::Expansion)>,
    /// Tree snapshots: the start, after each expansion, the end.
    pub snapshots: Vec<Snapshot>,
    /// Actions halted by the tree (preemptions): tick and action.
    pub halts: Vec<(u32, String)>,
    /// The leaves each tick called, in order, with what they returned (for replay logs).
    pub leaf_calls: Vec<(u32, Vec<(NodeId, Status)>)>,
    /// How the run ended.
    pub status: Option<Status>,
    /// Ticks made.
    pub ticks: u32,
}

impl Record {
    /// The root returned `status` at `tick`: the run ends, with a last snapshot.
    fn end(&mut self, tick: u32, status: Status, nodes: &[Node], states: &[NodeState]) {
        self.status = Some(status);
        self.snapshots.push(Snapshot { tick, label: "end".into(), nodes: nodes.to_vec(), states: states.to_vec() });
    }
}

/// Where the tree comes from.
#[derive(Debug)]
pub enum Source<'a> {
    /// Grown by the planner as the run goes (blended planning and acting).
    Planner(&'a mut Planner),
    /// A fixed tree (planned offline, learned, or loaded).
    Fixed(&'a [Node]),
}

/// The world as the executor sees it: every leaf call is also written down.
struct Calls<'a, W> {
    world: &'a mut W,
    calls: Vec<(NodeId, Status)>,
}

impl<W: bt_core::BehaviorSet> bt_core::BehaviorSet for Calls<'_, W> {
    fn condition(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> Status {
        let s = self.world.condition(leaf, ctx);
        self.calls.push((ctx.node, s));
        s
    }

    fn action(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> Status {
        let s = self.world.action(leaf, ctx);
        self.calls.push((ctx.node, s));
        s
    }

    fn halt(&mut self, leaf: &bt_core::Leaf, node: NodeId) {
        self.world.halt(leaf, node);
    }
}

/// Records action status changes during a tick.
#[derive(Default)]
struct Changes(Vec<(NodeId, NodeStatus, NodeStatus)>);

impl Observer for Changes {
    fn on_change(&mut self, node: NodeId, old: NodeStatus, new: NodeStatus) {
        self.0.push((node, old, new));
    }
}

/// Runs `source` in `world` for at most `max_ticks`, writing the narration to `out`.
/// Stops at the first root Success.
///
/// # Errors
/// An invalid tree, a behavior that broke the tick rules, or the planner giving up.
pub fn run<W: Live, C: Catalog + ?Sized>(
    world: &mut W,
    mut source: Source<'_>,
    catalog: &C,
    max_ticks: u32,
    out: &mut String,
) -> anyhow::Result<Record> {
    let mut record = Record::default();
    let mut tick = 0u32;
    let mut quiet: Option<(u32, String)> = None;
    let mut states: Vec<NodeState> = Vec::new();
    let nodes_now = |s: &Source<'_>| -> Vec<Node> {
        match s {
            Source::Planner(p) => p.nodes().to_vec(),
            Source::Fixed(n) => n.to_vec(),
        }
    };
    let mut nodes = nodes_now(&source);
    show_tree(out, "the tree at the start", &nodes, catalog, None);
    record.snapshots.push(Snapshot { tick: 0, label: "start".into(), nodes: nodes.clone(), states: Vec::new() });
    record.frames.push((0, world.points()));
    'run: while tick < max_ticks {
        let tree: Tree<'_, DEPTH> =
            Tree::validate(&nodes, catalog).map_err(|e| anyhow::anyhow!("tick {tick}: the tree is not valid: {e}"))?;
        states.clear();
        states.resize(nodes.len(), NodeState::IDLE);
        let mut exec = Executor::new(tree, &mut states).map_err(|e| anyhow::anyhow!("tick {tick}: {e}"))?;
        loop {
            tick += 1;
            let mut changes = Changes::default();
            let mut calls = Calls { world: &mut *world, calls: Vec::new() };
            let status = exec
                .tick_observed(&mut calls, tick.saturating_mul(TICK_MS), &mut changes)
                .map_err(|e| anyhow::anyhow!("tick {tick}: {e}"))?;
            record.leaf_calls.push((tick, calls.calls));
            narrate_actions(out, &mut record, &mut quiet, tick, &nodes, catalog, &changes.0);
            let running = running_action(&nodes, exec.states(), catalog);
            match status {
                Status::Success => {
                    flush_quiet(out, &mut quiet, tick);
                    let _ = writeln!(out, "tick {tick:>3}  the root succeeds: the goal holds");
                    record.end(tick, Status::Success, &nodes, exec.states());
                    break 'run;
                }
                Status::Failure => {
                    flush_quiet(out, &mut quiet, tick);
                    let failed = failed_conditions(&nodes, exec.states(), catalog);
                    let _ = writeln!(out, "tick {tick:>3}  the root fails: {}", failed.join(", "));
                    let Source::Planner(planner) = &mut source else {
                        record.end(tick, Status::Failure, &nodes, exec.states());
                        break 'run;
                    };
                    let belief = world.belief(planner.grounding());
                    let expansion = planner
                        .on_failure(exec.states(), &belief)
                        .map_err(|e| anyhow::anyhow!("tick {tick}: the planner cannot expand the tree: {e}"))?;
                    narrate_expansion(out, record.expansions.len() + 1, &expansion);
                    record.expansions.push((tick, expansion));
                    nodes = nodes_now(&source);
                    show_tree(out, "the tree now", &nodes, catalog, None);
                    record.snapshots.push(Snapshot {
                        tick,
                        label: format!("expansion {}", record.expansions.len()),
                        nodes: nodes.clone(),
                        states: Vec::new(),
                    });
                    world.advance(tick, None);
                    world_events(out, &mut record, &mut quiet, world, tick);
                    record.frames.push((tick, world.points()));
                    continue 'run;
                }
                Status::Running | Status::Skipped => {}
            }
            world.advance(tick, running.as_deref());
            world_events(out, &mut record, &mut quiet, world, tick);
            record.frames.push((tick, world.points()));
            if tick >= max_ticks {
                break 'run;
            }
        }
    }
    flush_quiet(out, &mut quiet, tick + 1);
    record.ticks = tick;
    if record.status.is_none() {
        let _ = writeln!(out, "tick {tick:>3}  stopped: the tick budget ran out with the tree still running");
        record.status = Some(Status::Running);
    }
    Ok(record)
}

/// Prints the world's events since the last tick (closing a quiet stretch first).
fn world_events<W: Live>(
    out: &mut String,
    record: &mut Record,
    quiet: &mut Option<(u32, String)>,
    world: &mut W,
    tick: u32,
) {
    let events = world.drain_events();
    if !events.is_empty() {
        flush_quiet(out, quiet, tick + 1);
    }
    for e in &events {
        let _ = writeln!(out, "tick {tick:>3}  world: {e}");
        record.events.push((tick, e.clone()));
    }
}

/// One line per action start, success, failure and halt; an action running on quietly
/// is summed up when something else happens.
fn narrate_actions<C: Catalog + ?Sized>(
    out: &mut String,
    record: &mut Record,
    quiet: &mut Option<(u32, String)>,
    tick: u32,
    nodes: &[Node],
    catalog: &C,
    changes: &[(NodeId, NodeStatus, NodeStatus)],
) {
    for &(node, old, new) in changes {
        let Some(n) = nodes.get(usize::from(node)) else { continue };
        let bt_core::NodeKind::Action(leaf) = n.kind() else { continue };
        let name = leaf_name(catalog, leaf);
        match (old, new) {
            (NodeStatus::Running, NodeStatus::Idle) => {
                flush_quiet(out, quiet, tick);
                let _ = writeln!(out, "tick {tick:>3}  halts {name} (the tree moved to another branch)");
                record.halts.push((tick, name));
            }
            (NodeStatus::Running, NodeStatus::Success) => {
                flush_quiet(out, quiet, tick);
                let _ = writeln!(out, "tick {tick:>3}  {name} succeeds");
            }
            (NodeStatus::Running, NodeStatus::Failure) => {
                flush_quiet(out, quiet, tick);
                let _ = writeln!(out, "tick {tick:>3}  {name} fails");
            }
            (_, NodeStatus::Running) => {
                flush_quiet(out, quiet, tick);
                *quiet = Some((tick, name));
            }
            (_, NodeStatus::Success) => {
                flush_quiet(out, quiet, tick);
                let _ = writeln!(out, "tick {tick:>3}  {name} succeeds at once");
            }
            (_, NodeStatus::Failure) => {
                flush_quiet(out, quiet, tick);
                let _ = writeln!(out, "tick {tick:>3}  {name} fails at once");
            }
            _ => {}
        }
    }
}

/// Closes a quiet stretch: "ticks 5-14  move-to(cube) running".
fn flush_quiet(out: &mut String, quiet: &mut Option<(u32, String)>, now: u32) {
    if let Some((from, name)) = quiet.take() {
        let to = now.saturating_sub(1).max(from);
        if to > from {
            let _ = writeln!(out, "ticks {from:>3}-{to:<3} {name} running");
        } else {
            let _ = writeln!(out, "tick {from:>3}  {name} starts");
        }
    }
}

fn narrate_expansion(out: &mut String, n: usize, e: &planner::Expansion) {
    let _ = writeln!(
        out,
        "          expansion {n}: `{}` is replaced by its atomic BT (Fig. 2): a Fallback of the condition and {}",
        e.condition,
        e.actions.iter().map(|a| format!("Sequence[preconditions, {a}]")).collect::<Vec<_>>().join(", ")
    );
    for c in &e.conflicts {
        let how = match c.moved {
            planner::algorithm::Move::Left => "moves the new subtree one place left",
            planner::algorithm::Move::Up => "moves the new subtree up a level",
        };
        let _ = writeln!(
            out,
            "          conflict: `{}` runs before it and undoes its precondition `{}`: IncreasePriority {how}",
            c.by, c.precondition
        );
    }
}

fn show_tree<C: Catalog + ?Sized>(
    out: &mut String,
    title: &str,
    nodes: &[Node],
    catalog: &C,
    states: Option<&[NodeState]>,
) {
    let Ok(tree) = Tree::<'_, DEPTH>::validate(nodes, catalog) else { return };
    let _ = writeln!(out, "          {title} ({}):", crate::text::count(nodes.len(), "node"));
    let text = match states {
        Some(s) => tree.display(catalog).with_states(s).to_string(),
        None => tree.display(catalog).to_string(),
    };
    for line in text.lines() {
        let _ = writeln!(out, "            {line}");
    }
}

/// The name of a leaf as the catalog renders it.
pub fn leaf_name<C: Catalog + ?Sized>(catalog: &C, leaf: &bt_core::Leaf) -> String {
    bt_core::render::display_leaf(catalog, leaf, &[]).to_string()
}

/// The action left Running after a tick, by name.
fn running_action<C: Catalog + ?Sized>(nodes: &[Node], states: &[NodeState], catalog: &C) -> Option<String> {
    nodes.iter().zip(states).find_map(|(n, s)| match n.kind() {
        bt_core::NodeKind::Action(leaf) if s.status() == NodeStatus::Running => Some(leaf_name(catalog, leaf)),
        _ => None,
    })
}

/// The conditions whose Failure failed a Sequence (or the root) on the last tick: why
/// the tree failed. A condition failing as a Fallback's first child is the Fallback
/// doing its job, not a reason.
fn failed_conditions<C: Catalog + ?Sized>(nodes: &[Node], states: &[NodeState], catalog: &C) -> Vec<String> {
    let mut parents: Vec<usize> = Vec::new();
    let mut failed = Vec::new();
    for (i, (n, s)) in nodes.iter().zip(states).enumerate() {
        while parents.last().is_some_and(|&p| p + nodes.get(p).map_or(0, |q| usize::from(q.size())) <= i) {
            parents.pop();
        }
        let parent_is_sequence =
            parents.last().is_none_or(|&p| nodes.get(p).is_some_and(|q| *q.kind() == bt_core::NodeKind::Sequence));
        if let bt_core::NodeKind::Condition(leaf) = n.kind()
            && s.status() == NodeStatus::Failure
            && parent_is_sequence
        {
            failed.push(format!("{} is false", leaf_name(catalog, leaf)));
        }
        if n.kind().arity() != bt_core::Arity::Leaf {
            parents.push(i);
        }
    }
    if failed.is_empty() { vec!["an action failed".into()] } else { failed }
}
