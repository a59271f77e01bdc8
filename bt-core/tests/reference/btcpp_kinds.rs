//! The reference's rules for the kinds that stand for BehaviorTree.CPP's and Nav2's
//! nodes, each a reading of that node's C++ `tick()`.

use std::ops::ControlFlow;

use bt_core::{NodeKind, NodeStatus, Selection, Status};

use super::{RState, Reference};
use crate::{Ev, KEY_QUEUE, LITERAL_ELEMENTS, hook_holds, outcome, selection};

impl Reference<'_> {
    /// Ticks node `i` of `kind` (one of BehaviorTree.CPP's or Nav2's), whose state before
    /// the tick was `was`: `Continue` with what [`Reference::tick`] records as its
    /// status, or `Break` with a status it returns at once.
    pub(super) fn tick_btcpp(
        &mut self,
        i: usize,
        kind: NodeKind,
        was: RState,
        running: bool,
        parent_mirrors: bool,
    ) -> ControlFlow<Status, Status> {
        let r = match kind {
            NodeKind::IfThenElse => {
                let kids = self.kids(i);
                let mut branch = if running { was.mem } else { 0 };
                let mut early = None;
                if branch == 0 {
                    match self.tick(kids[0], true) {
                        Status::Success => branch = kids[1],
                        Status::Failure if kids.len() == 3 => branch = kids[2],
                        s => {
                            if s != Status::Failure {
                                self.st[i].mem = 0;
                            }
                            early = Some(s);
                        }
                    }
                }
                match early {
                    Some(s) => s,
                    None => {
                        let s = self.tick(branch, true);
                        if s == Status::Running {
                            self.st[i].mem = branch;
                        } else {
                            self.halt_children(i);
                            self.st[i].mem = 0;
                        }
                        s
                    }
                }
            }
            NodeKind::WhileDoElse => {
                let kids = self.kids(i);
                let s = match self.tick(kids[0], true) {
                    Status::Running => return ControlFlow::Break(self.set(i, Status::Running)),
                    Status::Success => {
                        if kids.len() == 3 {
                            self.halt_child(kids[2]);
                        }
                        self.tick(kids[1], true)
                    }
                    Status::Failure if kids.len() == 3 => {
                        self.halt_child(kids[1]);
                        self.tick(kids[2], true)
                    }
                    other => other,
                };
                if s != Status::Running {
                    self.halt_children(i);
                }
                s
            }
            NodeKind::ParallelAll { max_failures } => {
                let kids = self.kids(i);
                let (mut done, mut failed, mut skipped) = (0u16, 0u16, 0u16);
                for &c in &kids {
                    let prior = self.status(c);
                    let s = match prior {
                        NodeStatus::Success if running => Status::Success,
                        NodeStatus::Failure if running => Status::Failure,
                        _ => self.tick(c, true),
                    };
                    match s {
                        Status::Success => done += 1,
                        Status::Failure => {
                            done += 1;
                            failed += 1;
                        }
                        Status::Skipped => skipped += 1,
                        Status::Running => {}
                    }
                }
                let n = kids.len() as u16;
                if skipped == n {
                    Status::Skipped
                } else if skipped + done >= n {
                    self.halt_children(i);
                    if failed >= max_failures { Status::Failure } else { Status::Success }
                } else {
                    Status::Running
                }
            }
            // Counts anew each tick, in child order, finished children where they stand.
            NodeKind::ParallelV3 { success_threshold, failure_threshold } => {
                let kids = self.kids(i);
                let n = kids.len() as u16;
                let (mut ok, mut failed) = (0u16, 0u16);
                let mut verdict = None;
                for &c in &kids {
                    let r = match self.status(c) {
                        NodeStatus::Success if running => Status::Success,
                        NodeStatus::Failure if running => Status::Failure,
                        _ => self.tick(c, true),
                    };
                    match r {
                        Status::Success => ok += 1,
                        Status::Failure => failed += 1,
                        Status::Running | Status::Skipped => continue,
                    }
                    if ok >= success_threshold {
                        verdict = Some(Status::Success);
                    } else if failed >= failure_threshold || failed > n - success_threshold {
                        verdict = Some(Status::Failure);
                    }
                    if verdict.is_some() {
                        break;
                    }
                }
                match verdict {
                    Some(v) => {
                        self.halt_children(i);
                        v
                    }
                    None => Status::Running,
                }
            }
            NodeKind::PipelineSequence => {
                let kids = self.kids(i);
                let last = if running && was.mem != 0 { was.mem } else { kids[0] };
                let mut skipped = 0;
                let mut result = None;
                for &c in &kids {
                    match self.tick(c, true) {
                        Status::Failure => {
                            self.halt_children(i);
                            self.st[i].mem = 0;
                            result = Some(Status::Failure);
                            break;
                        }
                        Status::Skipped => skipped += 1,
                        Status::Running if c >= last => {
                            self.st[i].mem = c;
                            result = Some(Status::Running);
                            break;
                        }
                        _ => {}
                    }
                }
                result.unwrap_or_else(|| {
                    self.halt_children(i);
                    self.st[i].mem = 0;
                    if skipped == kids.len() { Status::Skipped } else { Status::Success }
                })
            }
            NodeKind::Recovery { retries } => {
                let kids = self.kids(i);
                let mut idx = was.mem;
                let mut retry = was.count;
                let give_up = |me: &mut Self, s| {
                    me.halt_children(i);
                    me.st[i].mem = 0;
                    me.st[i].count = 0;
                    s
                };
                loop {
                    if idx >= 2 || retry > retries {
                        break give_up(self, Status::Failure);
                    }
                    let s = self.tick(kids[idx], true);
                    if idx == 0 {
                        match s {
                            Status::Skipped | Status::Success => break give_up(self, s),
                            Status::Running => {
                                self.st[i].mem = 0;
                                self.st[i].count = retry;
                                break Status::Running;
                            }
                            Status::Failure if retry < retries => {
                                self.halt_child(kids[0]);
                                idx = 1;
                            }
                            Status::Failure => break give_up(self, Status::Failure),
                        }
                    } else {
                        match s {
                            Status::Skipped => {
                                self.halt_child(kids[1]);
                                self.st[i].mem = 0;
                                self.st[i].count = retry;
                                break Status::Failure;
                            }
                            Status::Running => {
                                self.st[i].mem = 1;
                                self.st[i].count = retry;
                                break Status::Running;
                            }
                            Status::Success => {
                                self.halt_child(kids[1]);
                                retry += 1;
                                idx = 0;
                            }
                            Status::Failure => break give_up(self, Status::Failure),
                        }
                    }
                }
            }
            NodeKind::RoundRobin => {
                let kids = self.kids(i);
                let n = kids.len() as u16;
                let mut idx = was.mem;
                let mut failed = was.count;
                let mut skipped = 0u16;
                loop {
                    if failed + skipped >= n {
                        self.halt_children(i);
                        self.st[i].mem = 0;
                        self.st[i].count = 0;
                        break if skipped == n { Status::Skipped } else { Status::Failure };
                    }
                    let s = self.tick(kids[idx], true);
                    if s != Status::Running {
                        idx = (idx + 1) % kids.len();
                    }
                    match s {
                        Status::Success => {
                            self.halt_children(i);
                            self.st[i].mem = idx;
                            self.st[i].count = 0;
                            break Status::Success;
                        }
                        Status::Failure => failed += 1,
                        Status::Skipped => skipped += 1,
                        Status::Running => {
                            self.st[i].mem = idx;
                            self.st[i].count = failed;
                            break Status::Running;
                        }
                    }
                }
            }
            kind @ (NodeKind::RepeatCycles(_) | NodeKind::RetryUntilSuccessful(_) | NodeKind::Cycles { .. }) => {
                let again = if matches!(kind, NodeKind::RepeatCycles(_) | NodeKind::Cycles { retry: false, .. }) {
                    Status::Success
                } else {
                    Status::Failure
                };
                let v3 = matches!(kind, NodeKind::Cycles { v3: true, .. });
                let n = match kind {
                    NodeKind::RepeatCycles(n) | NodeKind::RetryUntilSuccessful(n) => n,
                    // A count from a slot: the scripted set's truth, 0 or 1.
                    NodeKind::Cycles { from_slot: true, .. } => {
                        self.log.push(Ev::Tick { node: i, starting: true });
                        u16::from(outcome(self.nodes, &self.script, i) == Status::Success)
                    }
                    NodeKind::Cycles { count, .. } => count,
                    _ => unreachable!(),
                };
                let mut count = if running { was.count } else { 0 };
                let mut in_tick = 0u16;
                loop {
                    if !(count < n || n == NodeKind::FOREVER) {
                        if self.status(i + 1) == NodeStatus::Running {
                            self.halt(i + 1);
                        }
                        self.st[i].count = 0;
                        break again;
                    }
                    let was_idle = self.status(i + 1) == NodeStatus::Idle;
                    let s = self.tick(i + 1, true);
                    if s == Status::Running {
                        self.st[i].count = count;
                        break s;
                    }
                    self.halt_child(i + 1);
                    if s == Status::Skipped {
                        self.st[i].count = count;
                        break s;
                    }
                    if s != again {
                        self.st[i].count = 0;
                        break s;
                    }
                    count += 1;
                    in_tick += 1;
                    let yields = if v3 { in_tick == u16::MAX } else { was_idle };
                    if yields && (count < n || n == NodeKind::FOREVER) {
                        self.st[i].count = count;
                        self.woken = true;
                        break Status::Running;
                    }
                }
            }
            NodeKind::KeepRunningUntilFailure => match self.tick(i + 1, true) {
                Status::Failure => {
                    self.halt_child(i + 1);
                    Status::Failure
                }
                Status::Success => {
                    self.halt_child(i + 1);
                    Status::Running
                }
                _ => Status::Running,
            },
            // Rule 12: BT.CPP's scripted attributes around the node that is its child.
            NodeKind::Guard(_) => {
                let hold = |r: &mut Self, h: u16| {
                    r.log.push(Ev::Hook { node: i, hook: h });
                    hook_holds(&r.script, i, h)
                };
                let decided = if self.fresh(i, parent_mirrors) {
                    if hold(self, 0) {
                        Some(Status::Failure)
                    } else if hold(self, 1) {
                        Some(Status::Success)
                    } else if hold(self, 2) || !hold(self, 3) {
                        Some(Status::Skipped)
                    } else {
                        None
                    }
                } else if running && !hold(self, 3) {
                    self.halt(i + 1);
                    self.log.push(Ev::Hook { node: i, hook: 4 });
                    Some(Status::Skipped)
                } else {
                    None
                };
                let (r, from_child) = match decided {
                    Some(d) => (d, false),
                    None => (self.tick(i + 1, true), true),
                };
                match r {
                    Status::Success => self.log.push(Ev::Hook { node: i, hook: 6 }),
                    Status::Failure => self.log.push(Ev::Hook { node: i, hook: 5 }),
                    _ => {}
                }
                if matches!(r, Status::Success | Status::Failure) {
                    self.log.push(Ev::Hook { node: i, hook: 7 });
                    if from_child {
                        self.halt_child(i + 1);
                    }
                }
                if r == Status::Skipped {
                    // Its status is what the child kept, or Idle when it decided.
                    self.st[i].status = if from_child { self.status(i + 1) } else { NodeStatus::Idle };
                    return ControlFlow::Break(r);
                }
                r
            }
            // Rule 12: asks its script only while its child is not under way.
            NodeKind::Precondition { otherwise, .. } => {
                let fresh = self.fresh(i, parent_mirrors);
                self.forget_result(i, fresh);
                let go = was.mem == 1 || {
                    self.log.push(Ev::Tick { node: i, starting: true });
                    outcome(self.nodes, &self.script, i) == Status::Success
                };
                if !go {
                    // Decided without the child: the status it returns (Skipped: Idle).
                    return ControlFlow::Break(self.set(i, otherwise));
                }
                self.st[i].mem = 1;
                let s = self.tick(i + 1, true);
                if matches!(s, Status::Success | Status::Failure) {
                    self.st[i].mem = 0;
                    self.halt_child(i + 1);
                }
                s
            }
            // Asks on every tick; a mismatch halts a Running child.
            NodeKind::Check { otherwise, .. } => {
                self.log.push(Ev::Tick { node: i, starting: true });
                if outcome(self.nodes, &self.script, i) == Status::Success {
                    let s = self.tick(i + 1, true);
                    if matches!(s, Status::Success | Status::Failure) {
                        self.halt_child(i + 1);
                    }
                    s
                } else {
                    if self.status(i + 1) == NodeStatus::Running {
                        self.halt(i + 1);
                    }
                    if otherwise == Status::Skipped {
                        return ControlFlow::Break(self.set(i, otherwise));
                    }
                    otherwise
                }
            }
            NodeKind::RunOnce { then_skip } => match was.done {
                // A RunOnce that skips keeps no status: Idle.
                Some(_) if then_skip => return ControlFlow::Break(self.set(i, Status::Skipped)),
                Some(done) => done,
                None => {
                    let s = self.tick(i + 1, true);
                    if matches!(s, Status::Success | Status::Failure) {
                        self.st[i].done = Some(s);
                        self.halt_child(i + 1);
                    }
                    s
                }
            },
            NodeKind::TimeLimit(d) => {
                if !running {
                    self.st[i].start = self.now;
                }
                if running && d.get() > 0 && self.elapsed(i) >= d.get() {
                    self.halt_child(i + 1);
                    Status::Failure
                } else {
                    let s = self.tick(i + 1, true);
                    if matches!(s, Status::Success | Status::Failure) {
                        self.halt_child(i + 1);
                    }
                    s
                }
            }
            NodeKind::Delay(d) => {
                if !running {
                    self.st[i].start = self.now;
                }
                if self.elapsed(i) >= d.get() || self.status(i + 1) == NodeStatus::Running {
                    let s = self.tick(i + 1, true);
                    if matches!(s, Status::Success | Status::Failure) {
                        self.halt_child(i + 1);
                    }
                    s
                } else {
                    Status::Running
                }
            }
            // Rule 12: takes an element while its child is not Running, then ticks it.
            NodeKind::Loop { table, if_empty } => {
                let fresh = self.fresh(i, parent_mirrors);
                self.forget_result(i, fresh);
                if fresh || !running || was.mem != 1 {
                    let taken = if fresh { 0 } else { was.count };
                    let popped = if table == KEY_QUEUE {
                        self.log.push(Ev::Tick { node: i, starting: fresh });
                        outcome(self.nodes, &self.script, i) == Status::Success
                    } else if taken < LITERAL_ELEMENTS {
                        self.log.push(Ev::Tick { node: i, starting: true });
                        true
                    } else {
                        false
                    };
                    if !popped {
                        self.st[i].count = taken;
                        // Skipping keeps its status, whatever it was.
                        return ControlFlow::Break(if if_empty == Status::Skipped {
                            if_empty
                        } else {
                            self.set(i, if_empty)
                        });
                    }
                    self.st[i].count = taken + 1;
                }
                let s = self.tick(i + 1, true);
                self.st[i].mem = usize::from(s == Status::Running);
                if matches!(s, Status::Success | Status::Failure) {
                    self.halt_child(i + 1);
                }
                if s == Status::Failure { s } else { Status::Running }
            }
            // Rule 13: asks on every tick (with repeat_last_selection once, ever) which
            // child to tick or which status to return; a child Running that is not
            // chosen is halted first, unless it returns Running without a child.
            NodeKind::ManualSelector { repeat_last } => {
                let kids = self.kids(i);
                let fresh = self.fresh(i, parent_mirrors);
                self.forget_result(i, fresh);
                let (choice, asked) = match was.choice {
                    Some(c) if repeat_last && !kids.is_empty() => (c, false),
                    _ => {
                        self.log.push(Ev::Tick { node: i, starting: fresh });
                        let c = selection(&self.script, i, kids.len());
                        if !kids.is_empty() {
                            self.st[i].choice = Some(c);
                        }
                        (c, true)
                    }
                };
                let chosen = match choice {
                    Selection::Child(k) => Some(kids[usize::from(k)]),
                    _ => None,
                };
                if choice != Selection::Running {
                    for &c in &kids {
                        if Some(c) != chosen && self.status(c) == NodeStatus::Running {
                            self.halt(c);
                        }
                    }
                }
                match (chosen, choice) {
                    (Some(c), _) => {
                        // BehaviorTree.CPP marks it Running when it asks.
                        if asked {
                            self.st[i].status = NodeStatus::Running;
                        }
                        self.tick(c, true)
                    }
                    (None, Selection::Success) => Status::Success,
                    (None, Selection::Failure) => Status::Failure,
                    (None, _) => Status::Running,
                }
            }
            NodeKind::RateController(d) => {
                let fresh = self.fresh(i, parent_mirrors);
                if fresh {
                    self.st[i].start = self.now;
                }
                if fresh || self.status(i + 1) == NodeStatus::Running || self.elapsed(i) >= d.get() {
                    let s = self.tick(i + 1, true);
                    if s == Status::Success {
                        self.st[i].start = self.now;
                    }
                    if matches!(s, Status::Success | Status::Failure) {
                        self.halt_child(i + 1);
                    }
                    s
                } else {
                    Status::Running
                }
            }
            NodeKind::Gate(_) => {
                let starting = self.fresh(i, parent_mirrors);
                self.log.push(Ev::Tick { node: i, starting });
                let open = outcome(self.nodes, &self.script, i);
                if self.status(i + 1) == NodeStatus::Running || open == Status::Success {
                    let s = self.tick(i + 1, true);
                    if matches!(s, Status::Success | Status::Failure) {
                        self.halt_child(i + 1);
                    }
                    s
                } else {
                    // The gate decides without the child: no status kept for Skipped.
                    if open == Status::Skipped {
                        return ControlFlow::Break(self.set(i, Status::Skipped));
                    }
                    open
                }
            }
            other => unreachable!("{other:?} is one of the papers' kinds, ticked by `Reference::tick`"),
        };
        ControlFlow::Continue(r)
    }
}
