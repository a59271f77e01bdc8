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
}

/// A replay of one tree.
#[derive(Debug)]
pub struct Replay<'t> {
    tree: &'t LogTree,
    rt: Vec<Rt>,
    transitions: Vec<(u16, u8)>,
}

impl<'t> Replay<'t> {
    /// A replay with every node Idle.
    #[must_use]
    pub fn new(tree: &'t LogTree) -> Self {
        let rt = tree.nodes.iter().map(|n| Rt { done: vec![false; n.children.len()], ..Rt::default() }).collect();
        Self { tree, rt, transitions: Vec::new() }
    }

    /// One tick of the root, as `Tree::tickExactlyOnce`: the root's status, and the
    /// transitions (uid, new status) made, in order.
    pub fn tick(&mut self, leaves: &mut dyn Leaves) -> (u8, Vec<(u16, u8)>) {
        self.transitions.clear();
        let root = if self.tree.nodes.is_empty() { IDLE } else { self.execute(0, leaves) };
        if root == SUCCESS || root == FAILURE {
            self.reset_status(0);
        }
        (root, std::mem::take(&mut self.transitions))
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
                self.set_status(i, RUNNING);
                while self.rt[i].idx < n {
                    let k = self.rt[i].idx;
                    let s = self.execute(self.child(i, k), leaves);
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
                    let _ = go_on;
                    self.rt[i].idx += 1;
                }
                self.reset_children(i, leaves);
                self.rt[i].idx = 0;
                go_on
            }
            Kind::ReactiveSequence | Kind::ReactiveFallback => {
                let (go_on, stop) =
                    if node.kind == Kind::ReactiveFallback { (FAILURE, SUCCESS) } else { (SUCCESS, FAILURE) };
                self.set_status(i, RUNNING);
                for k in 0..n {
                    let s = self.execute(self.child(i, k), leaves);
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
                go_on
            }
            Kind::Parallel { success, failure } => {
                let threshold = |t: i32| if t < 0 { (n as i32 + t + 1).max(0) } else { t };
                let (need, fail) = (threshold(success), threshold(failure));
                self.set_status(i, RUNNING);
                for k in 0..n {
                    if !self.rt[i].done[k] {
                        let s = self.execute(self.child(i, k), leaves);
                        if s == SUCCESS {
                            self.rt[i].done[k] = true;
                            self.rt[i].count += 1;
                        } else if s == FAILURE {
                            self.rt[i].done[k] = true;
                            self.rt[i].count2 += 1;
                        }
                    }
                    let (ok, failed) = (self.rt[i].count, self.rt[i].count2);
                    if ok >= need {
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
                RUNNING
            }
            Kind::ParallelAll { max_failures } => {
                self.set_status(i, RUNNING);
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
                }
                if self.rt[i].done.iter().all(|&d| d) {
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
                    let s = self.execute(self.child(i, 0), leaves);
                    match s {
                        SUCCESS => {
                            self.rt[i].count += 1;
                            go = self.rt[i].count < cycles || cycles == -1;
                            self.halt_child(i, 0, leaves);
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
