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
//! Where bt-core's decisions differ from BehaviorTree.CPP's in documented corner cases
//! (a `Timeout` found expired with a child that is not Running fails; timers are read
//! at ticks), the replay takes bt-core's, so that it asks for the leaves the run ticked;
//! the transitions are BehaviorTree.CPP's.

use crate::btlog::tree::{Kind, LogTree};

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
}

impl<'t> Replay<'t> {
    /// A replay with every node Idle.
    #[must_use]
    pub fn new(tree: &'t LogTree) -> Self {
        let rt = tree.nodes.iter().map(|n| Rt { done: vec![false; n.children.len()], ..Rt::default() }).collect();
        Self { tree, rt, transitions: Vec::new(), woken: false, now: 0 }
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
                Kind::Delay(ms) => ms,
                _ => continue,
            };
            let elapsed = self.elapsed(i);
            if elapsed >= span {
                due.push((elapsed - span, i));
            }
        }
        due.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
        for (_, i) in due {
            let c = self.child(i, 0);
            if self.rt[i].status != RUNNING {
                continue;
            }
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

    fn execute(&mut self, i: usize, leaves: &mut dyn Leaves) -> u8 {
        let s = self.tick_node(i, leaves);
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

    /// `haltNode()` of node `i`.
    fn halt(&mut self, i: usize, leaves: &mut dyn Leaves) {
        let node = &self.tree.nodes[i];
        match node.kind {
            Kind::Action => {
                if let Some(core) = node.core {
                    leaves.halt(core);
                }
            }
            Kind::Condition | Kind::AlwaysSuccess | Kind::AlwaysFailure => {}
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

    fn tick_node(&mut self, i: usize, leaves: &mut dyn Leaves) -> u8 {
        let node = &self.tree.nodes[i];
        let n = node.children.len();
        match node.kind {
            Kind::Condition | Kind::Action => node.core.map_or(FAILURE, |c| leaves.tick(c)),
            Kind::AlwaysSuccess => SUCCESS,
            Kind::AlwaysFailure => FAILURE,
            Kind::Sequence | Kind::SequenceWithMemory | Kind::Fallback => {
                let memory = node.kind == Kind::SequenceWithMemory;
                let (go_on, stop) = if node.kind == Kind::Fallback { (FAILURE, SUCCESS) } else { (SUCCESS, FAILURE) };
                // Children that skipped are counted through the activation.
                if self.rt[i].status == IDLE {
                    self.rt[i].skipped = 0;
                }
                self.set_status(i, RUNNING);
                while self.rt[i].idx < n {
                    let k = self.rt[i].idx;
                    let c = self.child(i, k);
                    let was = self.rt[c].status;
                    let s = self.execute(c, leaves);
                    if s == RUNNING {
                        return RUNNING;
                    }
                    if s == stop {
                        if memory {
                            for j in k..n {
                                self.halt_child(i, j, leaves);
                            }
                        } else {
                            self.reset_children(i, leaves);
                            self.rt[i].idx = 0;
                        }
                        return s;
                    }
                    // go_on or skipped
                    self.rt[i].idx += 1;
                    if s == SKIPPED {
                        self.rt[i].skipped += 1;
                    }
                    // SequenceWithMemory: a child that was Idle succeeded, more to go.
                    if memory && s == SUCCESS && was == IDLE && self.rt[i].idx < n {
                        self.woken = true;
                        return RUNNING;
                    }
                }
                let all_skipped = self.rt[i].skipped == n;
                self.reset_children(i, leaves);
                self.rt[i].idx = 0;
                self.rt[i].skipped = 0;
                if all_skipped { SKIPPED } else { go_on }
            }
            Kind::ReactiveSequence | Kind::ReactiveFallback => {
                let (go_on, stop) =
                    if node.kind == Kind::ReactiveFallback { (FAILURE, SUCCESS) } else { (SUCCESS, FAILURE) };
                self.set_status(i, RUNNING);
                let mut all_skipped = true;
                for k in 0..n {
                    let s = self.execute(self.child(i, k), leaves);
                    all_skipped &= s == SKIPPED;
                    if s == RUNNING {
                        for j in (0..n).filter(|&j| j != k) {
                            self.halt_child(i, j, leaves);
                        }
                        return RUNNING;
                    }
                    if s == stop {
                        self.reset_children(i, leaves);
                        return s;
                    }
                    if s == SKIPPED {
                        self.halt_child(i, k, leaves);
                    }
                }
                self.reset_children(i, leaves);
                if all_skipped { SKIPPED } else { go_on }
            }
            Kind::Parallel { success, failure } => {
                let threshold = |t: i32| if t < 0 { (n as i32 + t + 1).max(0) } else { t };
                let (need, fail) = (threshold(success), threshold(failure));
                self.set_status(i, RUNNING);
                // Children that skipped in this tick (they are ticked again next tick).
                let mut skipped = 0;
                for k in 0..n {
                    if !self.rt[i].done[k] {
                        let s = self.execute(self.child(i, k), leaves);
                        if s == SUCCESS {
                            self.rt[i].done[k] = true;
                            self.rt[i].count += 1;
                        } else if s == FAILURE {
                            self.rt[i].done[k] = true;
                            self.rt[i].count2 += 1;
                        } else if s == SKIPPED {
                            skipped += 1;
                        }
                    }
                    let (ok, failed) = (self.rt[i].count, self.rt[i].count2);
                    // A negative success_count counts the children that skipped.
                    if ok >= need || (success < 0 && ok + skipped >= need) {
                        self.clear_parallel(i);
                        self.reset_children(i, leaves);
                        return SUCCESS;
                    }
                    if n as i32 - failed < need || failed == fail {
                        self.clear_parallel(i);
                        self.reset_children(i, leaves);
                        return FAILURE;
                    }
                }
                if skipped == n as i32 { SKIPPED } else { RUNNING }
            }
            Kind::ParallelAll { max_failures } => {
                self.set_status(i, RUNNING);
                // Children that skipped in this tick count as finished for this tick.
                let mut skipped = 0;
                for k in 0..n {
                    if self.rt[i].done[k] {
                        continue;
                    }
                    let s = self.execute(self.child(i, k), leaves);
                    if s == SUCCESS || s == FAILURE {
                        self.rt[i].done[k] = true;
                    }
                    if s == FAILURE {
                        self.rt[i].count += 1;
                    }
                    if s == SKIPPED {
                        skipped += 1;
                    }
                }
                if skipped == n {
                    return SKIPPED;
                }
                if skipped + self.rt[i].done.iter().filter(|&&d| d).count() >= n {
                    self.reset_children(i, leaves);
                    self.rt[i].done.iter_mut().for_each(|d| *d = false);
                    let failed = std::mem::take(&mut self.rt[i].count);
                    return if failed >= max_failures { FAILURE } else { SUCCESS };
                }
                RUNNING
            }
            Kind::IfThenElse => {
                self.set_status(i, RUNNING);
                if self.rt[i].idx == 0 {
                    let s = self.execute(self.child(i, 0), leaves);
                    if s == RUNNING {
                        return RUNNING;
                    }
                    if s == SUCCESS {
                        self.rt[i].idx = 1;
                    } else if n == 3 {
                        self.rt[i].idx = 2;
                    } else {
                        return s;
                    }
                }
                let s = self.execute(self.child(i, self.rt[i].idx), leaves);
                if s == RUNNING {
                    return RUNNING;
                }
                self.reset_children(i, leaves);
                self.rt[i].idx = 0;
                s
            }
            Kind::WhileDoElse => {
                self.set_status(i, RUNNING);
                let c = self.execute(self.child(i, 0), leaves);
                if c == RUNNING {
                    return RUNNING;
                }
                let s = if c == SUCCESS {
                    if n == 3 {
                        self.halt_child(i, 2, leaves);
                    }
                    self.execute(self.child(i, 1), leaves)
                } else if n == 3 {
                    self.halt_child(i, 1, leaves);
                    self.execute(self.child(i, 2), leaves)
                } else {
                    FAILURE
                };
                if s == RUNNING {
                    return RUNNING;
                }
                self.reset_children(i, leaves);
                s
            }
            Kind::Inverter | Kind::ForceSuccess | Kind::ForceFailure | Kind::KeepRunningUntilFailure => {
                self.set_status(i, RUNNING);
                let s = self.execute(self.child(i, 0), leaves);
                let done = s == SUCCESS || s == FAILURE;
                if done {
                    self.halt_child(i, 0, leaves);
                }
                match (node.kind, s) {
                    // It returns its own status, Running, for a child that skipped.
                    (Kind::KeepRunningUntilFailure, SKIPPED) => RUNNING,
                    (_, RUNNING) | (_, SKIPPED) => s,
                    (Kind::Inverter, SUCCESS) => FAILURE,
                    (Kind::Inverter, _) => SUCCESS,
                    (Kind::ForceSuccess, _) => SUCCESS,
                    (Kind::ForceFailure, _) => FAILURE,
                    (_, SUCCESS) => RUNNING,
                    _ => FAILURE,
                }
            }
            Kind::Repeat(cycles) => {
                let mut go = self.rt[i].count < cycles || cycles == -1;
                self.set_status(i, RUNNING);
                while go {
                    let was = self.rt[self.child(i, 0)].status;
                    let s = self.execute(self.child(i, 0), leaves);
                    match s {
                        SUCCESS => {
                            self.rt[i].count += 1;
                            go = self.rt[i].count < cycles || cycles == -1;
                            self.halt_child(i, 0, leaves);
                            if was == IDLE && go {
                                self.woken = true;
                                return RUNNING;
                            }
                        }
                        FAILURE => {
                            self.rt[i].count = 0;
                            self.halt_child(i, 0, leaves);
                            return FAILURE;
                        }
                        SKIPPED => {
                            self.halt_child(i, 0, leaves);
                            return SKIPPED;
                        }
                        _ => return RUNNING,
                    }
                }
                self.rt[i].count = 0;
                SUCCESS
            }
            Kind::Retry(attempts) => {
                let mut go = self.rt[i].count < attempts || attempts == -1;
                self.set_status(i, RUNNING);
                while go {
                    let was = self.rt[self.child(i, 0)].status;
                    let s = self.execute(self.child(i, 0), leaves);
                    match s {
                        SUCCESS => {
                            self.rt[i].count = 0;
                            self.halt_child(i, 0, leaves);
                            return SUCCESS;
                        }
                        FAILURE => {
                            self.rt[i].count += 1;
                            go = self.rt[i].count < attempts || attempts == -1;
                            self.halt_child(i, 0, leaves);
                            if was == IDLE && go {
                                self.woken = true;
                                return RUNNING;
                            }
                        }
                        SKIPPED => {
                            self.halt_child(i, 0, leaves);
                            return SKIPPED;
                        }
                        _ => return RUNNING,
                    }
                }
                self.rt[i].count = 0;
                FAILURE
            }
            Kind::RunOnce { then_skip } => {
                if let Some(s) = self.rt[i].once {
                    return if then_skip { SKIPPED } else { s };
                }
                self.set_status(i, RUNNING);
                let s = self.execute(self.child(i, 0), leaves);
                if s == SUCCESS || s == FAILURE {
                    self.rt[i].once = Some(s);
                    self.halt_child(i, 0, leaves);
                }
                s
            }
            Kind::Timeout(ms) => {
                if self.rt[i].status != RUNNING {
                    self.rt[i].start = self.now;
                    self.set_status(i, RUNNING);
                } else if ms > 0 && self.elapsed(i) >= ms {
                    // Expired: its child was halted before the pass (`timers`).
                    self.halt_child(i, 0, leaves);
                    return FAILURE;
                }
                let s = self.execute(self.child(i, 0), leaves);
                if s == SUCCESS || s == FAILURE {
                    self.halt_child(i, 0, leaves);
                }
                s
            }
            Kind::Delay(ms) => {
                let elapsed = if self.rt[i].status == RUNNING {
                    self.elapsed(i)
                } else {
                    self.rt[i].start = self.now;
                    self.set_status(i, RUNNING);
                    0
                };
                if elapsed < ms && self.rt[self.child(i, 0)].status != RUNNING {
                    return RUNNING;
                }
                let s = self.execute(self.child(i, 0), leaves);
                if s == SUCCESS || s == FAILURE {
                    self.halt_child(i, 0, leaves);
                }
                s
            }
            Kind::RateController(ms) => {
                // Nav2: a new activation (Idle) ticks the child at once and starts the
                // period; later, the child is ticked while it runs or once the period
                // since its last success has passed.
                let fresh = self.rt[i].status == IDLE;
                if fresh {
                    self.rt[i].start = self.now;
                }
                self.set_status(i, RUNNING);
                if !fresh && self.rt[self.child(i, 0)].status != RUNNING && self.elapsed(i) < ms {
                    return RUNNING;
                }
                let s = self.execute(self.child(i, 0), leaves);
                if s == SUCCESS {
                    self.rt[i].start = self.now;
                }
                s
            }
            Kind::SubTree => {
                if self.rt[i].status == IDLE {
                    self.set_status(i, RUNNING);
                }
                let s = self.execute(self.child(i, 0), leaves);
                if s == SUCCESS || s == FAILURE {
                    self.halt_child(i, 0, leaves);
                }
                s
            }
        }
    }

    fn clear_parallel(&mut self, i: usize) {
        let r = &mut self.rt[i];
        r.done.iter_mut().for_each(|d| *d = false);
        r.count = 0;
        r.count2 = 0;
    }
}
