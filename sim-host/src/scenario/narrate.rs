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

/// Tells a run in plain words, whatever drives it: the scenario's runner
/// (`sim-host scenario`) or a controller's status stream ([`crate::blend`]). Keeps what it
/// told in a [`Record`].
#[derive(Debug)]
pub struct Teller<'a, C: ?Sized> {
    catalog: &'a C,
    out: String,
    /// What was told.
    pub record: Record,
    /// An action running on quietly since a tick.
    quiet: Option<(u32, String)>,
}

impl<'a, C: Catalog + ?Sized> Teller<'a, C> {
    /// Tells a run, naming leaves with `catalog`.
    pub fn new(catalog: &'a C) -> Self {
        Self { catalog, out: String::new(), record: Record::default(), quiet: None }
    }

    /// The text told since the last call.
    pub fn take_text(&mut self) -> String {
        std::mem::take(&mut self.out)
    }

    /// What was told.
    #[must_use]
    pub fn into_record(self) -> Record {
        self.record
    }

    /// Closes a quiet stretch before tick `now`: "ticks 5-14  move-to(cube) running".
    pub fn flush_quiet(&mut self, now: u32) {
        if let Some((from, name)) = self.quiet.take() {
            let to = now.saturating_sub(1).max(from);
            if to > from {
                let _ = writeln!(self.out, "ticks {from:>3}-{to:<3} {name} running");
            } else {
                let _ = writeln!(self.out, "tick {from:>3}  {name} starts");
            }
        }
    }

    /// One line of the tick's own: `tick  12  text` (after a quiet stretch is closed).
    pub fn say(&mut self, tick: u32, text: &str) {
        self.flush_quiet(tick);
        let _ = writeln!(self.out, "tick {tick:>3}  {text}");
    }

    /// A line under the tick's: `          text`.
    pub fn add(&mut self, text: &str) {
        let _ = writeln!(self.out, "          {text}");
    }

    /// A line as it is (it names its own ticks).
    pub fn add_raw(&mut self, line: &str) {
        let _ = writeln!(self.out, "{line}");
    }

    /// One line per action start, success, failure and halt; an action running on
    /// quietly is summed up when something else happens.
    pub fn actions(&mut self, tick: u32, nodes: &[Node], changes: &[(NodeId, NodeStatus, NodeStatus)]) {
        for &(node, old, new) in changes {
            let Some(n) = nodes.get(usize::from(node)) else { continue };
            let bt_core::NodeKind::Action(leaf) = n.kind() else { continue };
            let name = leaf_name(self.catalog, leaf);
            match (old, new) {
                (NodeStatus::Running, NodeStatus::Idle) => {
                    self.say(tick, &format!("halts {name} (the tree moved to another branch)"));
                    self.record.halts.push((tick, name));
                }
                (NodeStatus::Running, NodeStatus::Success) => self.say(tick, &format!("{name} succeeds")),
                (NodeStatus::Running, NodeStatus::Failure) => self.say(tick, &format!("{name} fails")),
                (_, NodeStatus::Running) => {
                    self.flush_quiet(tick);
                    self.quiet = Some((tick, name));
                }
                (_, NodeStatus::Success) => self.say(tick, &format!("{name} succeeds at once")),
                (_, NodeStatus::Failure) => self.say(tick, &format!("{name} fails at once")),
                _ => {}
            }
        }
    }

    /// The tree, indented, under a title: `the tree now (6 nodes):`.
    pub fn show_tree(&mut self, title: &str, nodes: &[Node], values: &[u16]) {
        let Ok(tree) = Tree::<'_, DEPTH>::validate_with(nodes, values, self.catalog) else { return };
        let _ = writeln!(self.out, "          {title} ({}):", crate::text::count(nodes.len(), "node"));
        for line in tree.display(self.catalog).to_string().lines() {
            let _ = writeln!(self.out, "            {line}");
        }
    }

    /// The root failed: says which conditions failed it.
    pub fn root_fails(&mut self, tick: u32, nodes: &[Node], statuses: &[NodeStatus]) {
        let failed = self.failed_conditions(nodes, statuses);
        self.say(tick, &format!("the root fails: {}", failed.join(", ")));
    }

    /// The conditions whose Failure failed a Sequence (or the root) on the last tick:
    /// why the tree failed. A condition failing as a Fallback's first child is the
    /// Fallback doing its job, not a reason.
    fn failed_conditions(&self, nodes: &[Node], statuses: &[NodeStatus]) -> Vec<String> {
        let mut parents: Vec<usize> = Vec::new();
        let mut failed = Vec::new();
        for (i, (n, s)) in nodes.iter().zip(statuses).enumerate() {
            while parents.last().is_some_and(|&p| p + nodes.get(p).map_or(0, |q| usize::from(q.size())) <= i) {
                parents.pop();
            }
            let parent_is_sequence =
                parents.last().is_none_or(|&p| nodes.get(p).is_some_and(|q| *q.kind() == bt_core::NodeKind::Sequence));
            if let bt_core::NodeKind::Condition(leaf) = n.kind()
                && *s == NodeStatus::Failure
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

    /// Growth number `n` (from 1) made at `tick`, and the tree it made.
    pub fn grown<G: Narrate + ?Sized>(&mut self, tick: u32, growth: &G, nodes: &[Node], values: &[u16]) {
        self.grown_with(tick, growth, "", nodes, values);
    }

    /// [`Teller::grown`] with a line of the caller's before the tree (none if empty).
    pub fn grown_with<G: Narrate + ?Sized>(
        &mut self,
        tick: u32,
        growth: &G,
        note: &str,
        nodes: &[Node],
        values: &[u16],
    ) {
        let n = self.record.expansions.len() + 1;
        growth.narrate(n, tick, &mut self.out, &mut self.record);
        if !note.is_empty() {
            self.add(note);
        }
        self.show_tree("the tree now", nodes, values);
    }

    /// The behavior set leaves are named with.
    #[must_use]
    pub fn catalog(&self) -> &'a C {
        self.catalog
    }
}

/// Narrates a scenario run into `out` and keeps its [`Record`].
pub(super) struct Narration<'a, C: ?Sized> {
    teller: Teller<'a, C>,
    /// World events told so far.
    told: usize,
}

impl<'a, C: Catalog + ?Sized> Narration<'a, C> {
    pub(super) fn new(catalog: &'a C) -> Self {
        Self { teller: Teller::new(catalog), told: 0 }
    }

    /// The text told since the last call.
    pub(super) fn take_text(&mut self) -> String {
        self.teller.take_text()
    }

    pub(super) fn into_record(self) -> Record {
        self.teller.into_record()
    }

    fn snapshot(&mut self, tick: u32, label: String, tree: &TreeState<'_>) {
        let (nodes, states) = (tree.nodes.to_vec(), tree.states.to_vec());
        self.teller.record.snapshots.push(Snapshot { tick, label, nodes, states });
    }
}

impl<W: Scene, G: Narrate, C: Catalog + ?Sized> Recorder<W, G> for Narration<'_, C> {
    const LEAVES: bool = true;
    const CHANGES: bool = true;

    fn start(&mut self, world: &W, tree: &TreeState<'_>) {
        self.teller.show_tree("the tree at the start", tree.nodes, &[]);
        self.snapshot(0, "start".into(), tree);
        self.teller.record.frames.push((0, world.points()));
    }

    fn ticked(&mut self, t: &Ticked<'_>, _: &W) {
        let tick = t.tick;
        self.teller.record.leaf_calls.push((tick, t.calls.to_vec()));
        self.teller.actions(tick, t.tree.nodes, t.changes);
        if t.root == Status::Failure {
            let statuses: Vec<NodeStatus> = t.tree.states.iter().map(NodeState::status).collect();
            self.teller.root_fails(tick, t.tree.nodes, &statuses);
        }
    }

    fn grown(&mut self, tick: u32, growth: &G, nodes: &[Node]) {
        self.teller.grown(tick, growth, nodes, &[]);
        let label = format!("expansion {}", self.teller.record.expansions.len());
        self.snapshot(tick, label, &TreeState { nodes, states: &[] });
    }

    fn stepped(&mut self, tick: u32, _: Status, _: &[NodeState], world: &W) {
        if world.event(self.told).is_some() {
            self.teller.flush_quiet(tick + 1);
        }
        while let Some(e) = world.event(self.told) {
            let _ = writeln!(self.teller.out, "tick {tick:>3}  world: {e}");
            self.teller.record.events.push((tick, e.to_string()));
            self.told += 1;
        }
        self.teller.record.frames.push((tick, world.points()));
    }

    fn end(&mut self, outcome: &Outcome, tree: &TreeState<'_>, _: &W) {
        let tick = outcome.ticks;
        match outcome.stop {
            Stop::Success => {
                self.teller.say(tick, "the root succeeds: the goal holds");
                self.teller.record.status = Some(Status::Success);
                self.snapshot(tick, "end".into(), tree);
            }
            Stop::Failure => {
                self.teller.record.status = Some(Status::Failure);
                self.snapshot(tick, "end".into(), tree);
            }
            _ => {}
        }
        self.teller.flush_quiet(tick + 1);
        self.teller.record.ticks = tick;
        if self.teller.record.status.is_none() {
            let _ = writeln!(
                self.teller.out,
                "tick {tick:>3}  stopped: the tick budget ran out with the tree still running"
            );
            self.teller.record.status = Some(Status::Running);
        }
    }
}
