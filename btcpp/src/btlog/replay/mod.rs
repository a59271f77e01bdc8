//! BehaviorTree.CPP's status transitions for a run: a model of how its nodes set,
//! reset and halt, driven by what the leaves returned.
//!
//! Groot2 replays a log as the list of every status change BehaviorTree.CPP's nodes
//! made, transitions to Idle included, in the order they made them. Control nodes
//! become Running when ticked, reset their children when they finish, decorators reset
//! a finished child, and the root is reset when it finishes. This module ticks the same
//! tree the way BehaviorTree.CPP 4.10 does, asking a [`Leaves`] for each leaf's status,
//! and records the transitions. Fed the leaf results of one of our runs, it gives the
//! log BehaviorTree.CPP would have written for the same leaf results (and it checks
//! that it asks for the leaves our executor ticked, in the same order).
//!
//! Two things make one call of [`Replay::tick`] more than one pass over the tree:
//!
//! - **Wake-up.** `SequenceWithMemory`, `Repeat` and `RetryUntilSuccessful` end a pass
//!   with Running after a child that was Idle finished, and ask to be ticked again at
//!   once (BehaviorTree.CPP's `emitWakeUpSignal`, bt-core's `Executor::woken`). Ticked
//!   as `tickOnce()` ([`Ticking::Once`]), the replay ticks the root again while it is
//!   Running and a node asked; every transition of every pass goes into the log, as
//!   BehaviorTree.CPP's logger records them.
//! - **Time.** `Timeout`, `Delay` and Nav2's `RateController` measure spans of the
//!   tick's `now` (the same `now` the run gave bt-core; milliseconds for imported trees).
//!   What BehaviorTree.CPP's timer threads do between two ticks happens at the start of
//!   the next one, before the root is ticked, in the order the timers expired: an
//!   expired `Timeout` halts its Running child (its transitions to Idle come first in
//!   the tick) and asks for a wake-up, a `Delay` whose span has passed asks for one.
//!
//! Nav2's `PipelineSequence`, `RecoveryNode`, `RoundRobin` and `RateController` follow
//! Nav2's (jazzy) code on BehaviorTree.CPP; its plugin decorators are not modelled.
//!
//! A `ManualSelector` is told what to do by the run: the replay asks [`Leaves::select`]
//! for the selection the run made, where BehaviorTree.CPP asks its operator. It follows
//! BehaviorTree.CPP 4.10's node, not bt-core's halt before start: a child left Running
//! when another is chosen, or when the node returns Success or Failure, stays Running
//! in the log (it is halted when the node is). Where BehaviorTree.CPP cannot do what the
//! run did (a remembered status repeated, which it would take as a child index past its
//! children; child 253 or later, which it takes as a status) the replay refuses
//! ([`Replay::refusal`]).
//!
//! Where bt-core's decisions differ from BehaviorTree.CPP's in documented corner cases
//! (a `Timeout` found expired with a child that is not Running fails; timers are read
//! at ticks), the replay takes bt-core's, so that it asks for the leaves the run ticked;
//! the transitions are BehaviorTree.CPP's.

mod kinds;
mod v3;

use bt_core::Selection;
use bt_core::script::Hook;

use crate::btlog::tree::{Hooks, Kind, LogTree};

/// A node's status as BehaviorTree.CPP numbers it in logs.
pub mod status {
    /// Not ticked, or reset.
    pub const IDLE: u8 = 0;
    /// Running.
    pub const RUNNING: u8 = 1;
    /// Success.
    pub const SUCCESS: u8 = 2;
    /// Failure.
    pub const FAILURE: u8 = 3;
    /// Skipped (never stored as a node's status).
    pub const SKIPPED: u8 = 4;
}
use status::{FAILURE, IDLE, RUNNING, SKIPPED, SUCCESS};

/// What the leaves do.
pub trait Leaves {
    /// Leaf `core` (its bt-core node) is ticked: Running, Success or Failure (as
    /// [`status`] numbers them).
    fn tick(&mut self, core: usize) -> u8;
    /// Running action `core` is halted.
    fn halt(&mut self, core: usize);
    /// The `_onHalted` script of the node guarded by `core` runs (its result is not
    /// used). By default, asked as [`Leaves::tick`].
    fn halted_hook(&mut self, core: usize) {
        self.tick(core);
    }
    /// `ManualSelector` `core` asks what to do on this tick: the selection the run's
    /// behavior set made for it ([`bt_core::BehaviorSet::select`]). `None` when the run
    /// made none there (the default: the replay then refuses, [`Replay::refusal`]).
    fn select(&mut self, core: usize) -> Option<Selection> {
        let _ = core;
        None
    }
}

#[derive(Clone, Debug, Default)]
struct Rt {
    status: u8,
    /// Sequence/Fallback child index; reactive nodes' running child; IfThenElse child.
    idx: usize,
    /// Repeat/Retry count; Parallel successes; ParallelAll failures.
    count: i32,
    /// Parallel failures.
    count2: i32,
    /// Parallel / ParallelAll: children finished in this activation.
    done: Vec<bool>,
    /// RunOnce: already ticked, and what it returned.
    once: Option<u8>,
    /// Timeout, Delay, RateController: when its span started (`now`).
    start: u32,
    /// Sequence, SequenceWithMemory, Fallback: children that skipped in this
    /// activation.
    skipped: usize,
    /// ManualSelector: its last selection (`previously_executed_idx_`, kept through
    /// halts) and the last child that returned Running (`running_child_idx_`, cleared
    /// only by a halt).
    selected: Option<Selection>,
    running_child: Option<usize>,
}

/// How the root is ticked.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Ticking {
    /// `Tree::tickExactlyOnce()`: one pass per tick (bt-core's `Executor::tick`).
    #[default]
    ExactlyOnce,
    /// `Tree::tickOnce()`: another pass while the root is Running and a node asked for
    /// a wake-up (bt-core: `Executor::tick` in a loop on `Executor::take_woken`).
    Once,
}

/// Spans are measured in 24 bits of `now`, as bt-core keeps start times.
const SPAN_MASK: u32 = bt_core::Span::MAX;

/// A replay of one tree.
#[derive(Debug)]
pub struct Replay<'t> {
    tree: &'t LogTree,
    rt: Vec<Rt>,
    transitions: Vec<(u16, u8)>,
    /// A node asked to be ticked again at once (kept until a pass of
    /// [`Ticking::Once`] takes it, as BehaviorTree.CPP keeps its signal).
    woken: bool,
    /// The `now` of the tick being replayed.
    now: u32,
    /// Why the replay cannot give BehaviorTree.CPP's transitions for this run (the
    /// first reason since [`Replay::refusal`] last took it).
    refused: Option<String>,
    /// The last `ManualSelector` (node, child) left Running where bt-core halts it.
    left_running: Option<(usize, usize)>,
}

impl<'t> Replay<'t> {
    /// A replay with every node Idle.
    #[must_use]
    pub fn new(tree: &'t LogTree) -> Self {
        let rt = tree.nodes.iter().map(|n| Rt { done: vec![false; n.children.len()], ..Rt::default() }).collect();
        Self { tree, rt, transitions: Vec::new(), woken: false, now: 0, refused: None, left_running: None }
    }

    /// One tick of the root at `now`, ticked as `ticking` says: the root's status, and
    /// the transitions (uid, new status) made, in order (those of every pass).
    pub fn tick(&mut self, leaves: &mut dyn Leaves, now: u32, ticking: Ticking) -> (u8, Vec<(u16, u8)>) {
        self.transitions.clear();
        let mut root = self.pass(leaves, now);
        if ticking == Ticking::Once {
            while root == RUNNING && std::mem::take(&mut self.woken) {
                root = self.pass(leaves, now);
            }
        }
        if root == SUCCESS || root == FAILURE {
            self.reset_status(0);
        }
        (root, std::mem::take(&mut self.transitions))
    }

    /// Why the ticks replayed since the last call do not give BehaviorTree.CPP's
    /// transitions for the run (the first reason, naming the node), taken; `None` when
    /// they do.
    pub fn refusal(&mut self) -> Option<String> {
        self.refused.take()
    }

    /// The last `ManualSelector` that left a child Running, in BehaviorTree.CPP's way,
    /// where bt-core's halt before start halted it: (the `ManualSelector`, the child),
    /// both as indices into [`LogTree::nodes`], taken. Later ticks of the replay may then
    /// ask for other leaves than the run ticked.
    pub fn take_left_running(&mut self) -> Option<(usize, usize)> {
        self.left_running.take()
    }

    /// Refuses the run at node `i`, for `why`.
    fn refuse(&mut self, i: usize, why: &str) {
        if self.refused.is_none() {
            let n = &self.tree.nodes[i];
            self.refused = Some(format!("{} `{}` (uid {}) {why}", n.element, n.name, n.uid));
        }
    }

    /// Whether a node asked to be ticked again at once and no pass has taken it yet.
    #[must_use]
    pub fn woken(&self) -> bool {
        self.woken
    }

    /// One pass from the root at `now`, after what the timers did since the last one.
    fn pass(&mut self, leaves: &mut dyn Leaves, now: u32) -> u8 {
        self.now = now;
        if self.tree.nodes.is_empty() {
            return IDLE;
        }
        self.timers(leaves);
        self.execute(0, leaves)
    }

    /// Milliseconds (units of `now`) since node `i`'s span started.
    fn elapsed(&self, i: usize) -> u32 {
        self.now.wrapping_sub(self.rt[i].start) & SPAN_MASK
    }

    /// What BehaviorTree.CPP's timer threads did since the last pass, in the order its
    /// timers expired (those that expired together in tree order): an expired
    /// `Timeout` whose child runs halts it, a `Delay` whose span has passed while its
    /// child waits asks for a wake-up. The conditions are bt-core's (`Executor::tick`).
    fn timers(&mut self, leaves: &mut dyn Leaves) {
        // (how long ago it expired, node)
        let mut due: Vec<(u32, usize)> = Vec::new();
        for (i, n) in self.tree.nodes.iter().enumerate() {
            if self.rt[i].status != RUNNING {
                continue;
            }
            let span = match n.kind {
                Kind::Timeout(ms) if ms > 0 => ms,
                Kind::Delay(ms) | Kind::Sleep(ms) => ms,
                _ => continue,
            };
            let elapsed = self.elapsed(i);
            if elapsed >= span {
                due.push((elapsed - span, i));
            }
        }
        due.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
        for (_, i) in due {
            if self.rt[i].status != RUNNING {
                continue;
            }
            if let Kind::Sleep(_) = self.tree.nodes[i].kind {
                self.woken = true;
                continue;
            }
            let c = self.child(i, 0);
            match self.tree.nodes[i].kind {
                Kind::Timeout(_) if self.rt[c].status == RUNNING => {
                    self.halt_child(i, 0, leaves);
                    self.woken = true;
                }
                Kind::Delay(_) if self.rt[c].status == IDLE => self.woken = true,
                _ => {}
            }
        }
    }

    /// The status of every node (uid order).
    #[must_use]
    pub fn statuses(&self) -> Vec<u8> {
        self.rt.iter().map(|r| r.status).collect()
    }

    fn set_status(&mut self, i: usize, s: u8) {
        if self.rt[i].status != s {
            self.rt[i].status = s;
            self.transitions.push((self.tree.nodes[i].uid, s));
        }
    }

    fn reset_status(&mut self, i: usize) {
        if self.rt[i].status != IDLE {
            self.rt[i].status = IDLE;
            self.transitions.push((self.tree.nodes[i].uid, IDLE));
        }
    }

    fn child(&self, i: usize, k: usize) -> usize {
        self.tree.nodes[i].children[k]
    }

    /// `executeTick()` of node `i`.
    fn execute(&mut self, i: usize, leaves: &mut dyn Leaves) -> u8 {
        let s = match self.tree.nodes[i].hooks {
            Some(h) => self.guarded(i, h, leaves),
            None => self.tick_node(i, leaves),
        };
        if s != SKIPPED {
            self.set_status(i, s);
        }
        if self.tree.nodes[i].kind.is_decorator() {
            let c = self.child(i, 0);
            if matches!(self.rt[c].status, SUCCESS | FAILURE) {
                self.reset_status(c);
            }
        }
        s
    }

    /// `executeTick()`'s part for a node with scripted attributes, before its status is
    /// set: from Idle `_failureIf`, `_successIf`, `_skipIf` (the first that holds
    /// decides) and `_while` (false: skipped); while Running only `_while`, which halts
    /// the node when false; then, when the node succeeded or failed, `_onSuccess` or
    /// `_onFailure`, and `_post`. A script's truth is asked as a leaf's result
    /// (Success: it holds).
    fn guarded(&mut self, i: usize, h: Hooks, leaves: &mut dyn Leaves) -> u8 {
        let mut ask = |hook: Hook| h.has(hook).then(|| leaves.tick(h.core) == SUCCESS);
        let decided = match self.rt[i].status {
            IDLE => [(Hook::FailureIf, FAILURE), (Hook::SuccessIf, SUCCESS), (Hook::SkipIf, SKIPPED)]
                .into_iter()
                .find_map(|(hook, then)| (ask(hook) == Some(true)).then_some(then))
                .or_else(|| (ask(Hook::While) == Some(false)).then_some(SKIPPED)),
            RUNNING if ask(Hook::While) == Some(false) => {
                self.halt(i, leaves);
                Some(SKIPPED)
            }
            _ => None,
        };
        let s = match decided {
            Some(s) => s,
            None => self.tick_node(i, leaves),
        };
        let on = match s {
            SUCCESS => Hook::OnSuccess,
            FAILURE => Hook::OnFailure,
            _ => return s,
        };
        for hook in [on, Hook::Post] {
            if h.has(hook) {
                leaves.tick(h.core);
            }
        }
        s
    }

    /// `haltNode()` of node `i`: its `halt()`, then its `_onHalted`.
    fn halt(&mut self, i: usize, leaves: &mut dyn Leaves) {
        self.halt_only(i, leaves);
        if let Some(h) = self.tree.nodes[i].hooks
            && h.has(Hook::OnHalted)
        {
            leaves.halted_hook(h.core);
        }
    }

    /// `halt()` of node `i`.
    fn halt_only(&mut self, i: usize, leaves: &mut dyn Leaves) {
        let node = &self.tree.nodes[i];
        match node.kind {
            // Idle again, as `StatefulActionNode::halt()` leaves it (a parent resets a
            // halted child anyway; a node `_while` halts itself is reset only here).
            Kind::Action => {
                if let Some(core) = node.core {
                    leaves.halt(core);
                }
                self.reset_status(i);
            }
            Kind::Condition | Kind::AlwaysSuccess | Kind::AlwaysFailure | Kind::Script | Kind::ScriptCondition => {}
            // Its timer is cancelled; it is reset.
            Kind::Sleep(_) => self.reset_status(i),
            // The child it remembers Running first, then every child as a ControlNode's
            // halt does; its last selection is kept.
            Kind::ManualSelector { .. } => {
                if let Some(k) = self.rt[i].running_child.take() {
                    self.halt_child(i, k, leaves);
                }
                self.reset_children(i, leaves);
                self.reset_status(i);
            }
            k if k.is_decorator() => {
                let r = &mut self.rt[i];
                r.count = 0;
                self.halt_child(i, 0, leaves);
                self.reset_status(i);
            }
            kind => {
                let r = &mut self.rt[i];
                // SequenceWithMemory keeps its place when halted.
                if kind != Kind::SequenceWithMemory {
                    r.idx = 0;
                }
                r.count = 0;
                r.count2 = 0;
                r.done.iter_mut().for_each(|d| *d = false);
                self.reset_children(i, leaves);
                self.reset_status(i);
            }
        }
    }

    fn halt_child(&mut self, i: usize, k: usize, leaves: &mut dyn Leaves) {
        let c = self.child(i, k);
        if self.rt[c].status == RUNNING {
            self.halt(c, leaves);
        }
        self.reset_status(c);
    }

    fn reset_children(&mut self, i: usize, leaves: &mut dyn Leaves) {
        for k in 0..self.tree.nodes[i].children.len() {
            self.halt_child(i, k, leaves);
        }
    }
}
