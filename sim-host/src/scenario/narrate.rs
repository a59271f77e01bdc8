//! The narration of a scenario run, a [`worlds::Recorder`]: world events, each action
//! that starts, finishes, fails or is halted, each expansion with its conflicts, and the
//! tree whenever it changes. Quiet stretches (an action running for many ticks) take
//! one line. Everything said is also kept for pictures and replay logs ([`Record`]).

use std::fmt::Write as _;

use bt_core::{Catalog, Node, NodeId, NodeState, NodeStatus, Status, Tree};
use worlds::agent::TreeState;
use worlds::record::Ticked;
use worlds::{Outcome, Recorder, Stop};

use super::driver::{DEPTH, Points, Scene, leaf_name};

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
    /// World events with their tick.
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

/// How a tree's growth is told and kept.
pub trait Narrate {
    /// Tells growth number `n` (from 1) and keeps it in `record` (made at `tick`).
    fn narrate(&self, n: usize, tick: u32, out: &mut String, record: &mut Record);
}

/// A fixed tree does not grow.
impl Narrate for () {
    fn narrate(&self, _: usize, _: u32, _: &mut String, _: &mut Record) {}
}

impl Narrate for planner::Expansion {
    fn narrate(&self, n: usize, tick: u32, out: &mut String, record: &mut Record) {
        let _ = writeln!(
            out,
            "          expansion {n}: `{}` is replaced by its atomic BT (Fig. 2): a Fallback of the condition and {}",
            self.condition,
            self.actions.iter().map(|a| format!("Sequence[preconditions, {a}]")).collect::<Vec<_>>().join(", ")
        );
        for c in &self.conflicts {
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
        record.expansions.push((tick, self.clone()));
    }
}

/// Narrates a run into `out` and keeps its [`Record`].
pub(super) struct Narration<'a, C: ?Sized> {
    catalog: &'a C,
    out: &'a mut String,
    record: Record,
    /// An action running on quietly since a tick.
    quiet: Option<(u32, String)>,
    /// World events told so far.
    told: usize,
}

impl<'a, C: Catalog + ?Sized> Narration<'a, C> {
    pub(super) fn new(catalog: &'a C, out: &'a mut String) -> Self {
        Self { catalog, out, record: Record::default(), quiet: None, told: 0 }
    }

    pub(super) fn into_record(self) -> Record {
        self.record
    }

    /// Closes a quiet stretch: "ticks 5-14  move-to(cube) running".
    fn flush_quiet(&mut self, now: u32) {
        if let Some((from, name)) = self.quiet.take() {
            let to = now.saturating_sub(1).max(from);
            if to > from {
                let _ = writeln!(self.out, "ticks {from:>3}-{to:<3} {name} running");
            } else {
                let _ = writeln!(self.out, "tick {from:>3}  {name} starts");
            }
        }
    }

    /// One line per action start, success, failure and halt; an action running on
    /// quietly is summed up when something else happens.
    fn narrate_actions(&mut self, tick: u32, nodes: &[Node], changes: &[(NodeId, NodeStatus, NodeStatus)]) {
        for &(node, old, new) in changes {
            let Some(n) = nodes.get(usize::from(node)) else { continue };
            let bt_core::NodeKind::Action(leaf) = n.kind() else { continue };
            let name = leaf_name(self.catalog, leaf);
            match (old, new) {
                (NodeStatus::Running, NodeStatus::Idle) => {
                    self.flush_quiet(tick);
                    let _ = writeln!(self.out, "tick {tick:>3}  halts {name} (the tree moved to another branch)");
                    self.record.halts.push((tick, name));
                }
                (NodeStatus::Running, NodeStatus::Success) => {
                    self.flush_quiet(tick);
                    let _ = writeln!(self.out, "tick {tick:>3}  {name} succeeds");
                }
                (NodeStatus::Running, NodeStatus::Failure) => {
                    self.flush_quiet(tick);
                    let _ = writeln!(self.out, "tick {tick:>3}  {name} fails");
                }
                (_, NodeStatus::Running) => {
                    self.flush_quiet(tick);
                    self.quiet = Some((tick, name));
                }
                (_, NodeStatus::Success) => {
                    self.flush_quiet(tick);
                    let _ = writeln!(self.out, "tick {tick:>3}  {name} succeeds at once");
                }
                (_, NodeStatus::Failure) => {
                    self.flush_quiet(tick);
                    let _ = writeln!(self.out, "tick {tick:>3}  {name} fails at once");
                }
                _ => {}
            }
        }
    }

    fn show_tree(&mut self, title: &str, nodes: &[Node]) {
        let Ok(tree) = Tree::<'_, DEPTH>::validate(nodes, self.catalog) else { return };
        let _ = writeln!(self.out, "          {title} ({}):", crate::text::count(nodes.len(), "node"));
        for line in tree.display(self.catalog).to_string().lines() {
            let _ = writeln!(self.out, "            {line}");
        }
    }

    /// The conditions whose Failure failed a Sequence (or the root) on the last tick:
    /// why the tree failed. A condition failing as a Fallback's first child is the
    /// Fallback doing its job, not a reason.
    fn failed_conditions(&self, nodes: &[Node], states: &[NodeState]) -> Vec<String> {
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
                failed.push(format!("{} is false", leaf_name(self.catalog, leaf)));
            }
            if n.kind().arity() != bt_core::Arity::Leaf {
                parents.push(i);
            }
        }
        if failed.is_empty() { vec!["an action failed".into()] } else { failed }
    }

    fn snapshot(&mut self, tick: u32, label: String, tree: &TreeState<'_>) {
        let (nodes, states) = (tree.nodes.to_vec(), tree.states.to_vec());
        self.record.snapshots.push(Snapshot { tick, label, nodes, states });
    }
}

impl<W: Scene, G: Narrate, C: Catalog + ?Sized> Recorder<W, G> for Narration<'_, C> {
    const LEAVES: bool = true;
    const CHANGES: bool = true;

    fn start(&mut self, world: &W, tree: &TreeState<'_>) {
        self.show_tree("the tree at the start", tree.nodes);
        self.snapshot(0, "start".into(), tree);
        self.record.frames.push((0, world.points()));
    }

    fn ticked(&mut self, t: &Ticked<'_>, _: &W) {
        let tick = t.tick;
        self.record.leaf_calls.push((tick, t.calls.to_vec()));
        self.narrate_actions(tick, t.tree.nodes, t.changes);
        if t.root == Status::Failure {
            self.flush_quiet(tick);
            let failed = self.failed_conditions(t.tree.nodes, t.tree.states);
            let _ = writeln!(self.out, "tick {tick:>3}  the root fails: {}", failed.join(", "));
        }
    }

    fn grown(&mut self, tick: u32, growth: &G, nodes: &[Node]) {
        let n = self.record.expansions.len() + 1;
        growth.narrate(n, tick, self.out, &mut self.record);
        self.show_tree("the tree now", nodes);
        let label = format!("expansion {}", self.record.expansions.len());
        self.snapshot(tick, label, &TreeState { nodes, states: &[] });
    }

    fn stepped(&mut self, tick: u32, _: Status, _: &[NodeState], world: &W) {
        if world.event(self.told).is_some() {
            self.flush_quiet(tick + 1);
        }
        while let Some(e) = world.event(self.told) {
            let _ = writeln!(self.out, "tick {tick:>3}  world: {e}");
            self.record.events.push((tick, e.to_string()));
            self.told += 1;
        }
        self.record.frames.push((tick, world.points()));
    }

    fn end(&mut self, outcome: &Outcome, tree: &TreeState<'_>, _: &W) {
        let tick = outcome.ticks;
        match outcome.stop {
            Stop::Success => {
                self.flush_quiet(tick);
                let _ = writeln!(self.out, "tick {tick:>3}  the root succeeds: the goal holds");
                self.record.status = Some(Status::Success);
                self.snapshot(tick, "end".into(), tree);
            }
            Stop::Failure => {
                self.record.status = Some(Status::Failure);
                self.snapshot(tick, "end".into(), tree);
            }
            _ => {}
        }
        self.flush_quiet(tick + 1);
        self.record.ticks = tick;
        if self.record.status.is_none() {
            let _ = writeln!(self.out, "tick {tick:>3}  stopped: the tick budget ran out with the tree still running");
            self.record.status = Some(Status::Running);
        }
    }
}
