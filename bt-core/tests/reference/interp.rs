//! The reference interpreter: the tick rules of `bt_core::exec` read literally, one
//! recursive call per node; the kinds that stand for BehaviorTree.CPP's and Nav2's nodes
//! are in [`btcpp_kinds`].

use std::ops::ControlFlow;

use bt_core::{Node, NodeKind, NodeStatus, Selection, Span, Status};

use super::{Ev, outcome};

mod btcpp_kinds;

#[derive(Clone, Copy, Default, Debug)]
pub(super) struct RState {
    pub(super) status: NodeStatus,
    /// Sequence/Fallback: the child it returned at.
    last: Option<usize>,
    /// Repeat/Retry/Timeout count; RepeatCycles/RetryUntilSuccessful count; Recovery
    /// recoveries; RoundRobin failures.
    count: u16,
    /// SequenceStar: child to resume at; IfThenElse: the branch; PipelineSequence: the
    /// furthest child Running; RoundRobin: the next child (0-based); Recovery: the child.
    mem: usize,
    /// TimeLimit, Delay, RateController: when it started.
    start: u32,
    /// RunOnce: its result, once it has one.
    done: Option<Status>,
    /// ManualSelector: the last selection it was told (with children).
    choice: Option<Selection>,
}

/// Recursive, straight from the rules; no shortcuts.
pub(super) struct Reference<'a> {
    nodes: &'a [Node],
    pub(super) st: Vec<RState>,
    pub(super) log: Vec<Ev>,
    script: Vec<u8>,
    now: u32,
    pub(super) woken: bool,
    /// For each reactive Sequence/Fallback being ticked: the later child that was
    /// Running on the previous tick, which an action starting below must halt first.
    preempted: Vec<Option<usize>>,
}

fn is_reactive_or_reused(kind: &NodeKind) -> bool {
    matches!(
        kind,
        NodeKind::Sequence
            | NodeKind::Fallback
            | NodeKind::SequenceWithMemory
            | NodeKind::FallbackWithMemory
            | NodeKind::Parallel { .. }
            | NodeKind::Inverter
            | NodeKind::ForceSuccess
            | NodeKind::ForceFailure
            | NodeKind::Repeat(_)
            | NodeKind::Retry(_)
            | NodeKind::Timeout(_)
    )
}

impl<'a> Reference<'a> {
    pub(super) fn new(nodes: &'a [Node]) -> Self {
        Self {
            nodes,
            st: vec![RState::default(); nodes.len()],
            log: vec![],
            script: vec![],
            now: 0,
            woken: false,
            preempted: vec![],
        }
    }

    fn kids(&self, i: usize) -> Vec<usize> {
        let end = i + usize::from(self.nodes[i].size());
        let mut v = vec![];
        let mut c = i + 1;
        while c < end {
            v.push(c);
            c += usize::from(self.nodes[c].size());
        }
        v
    }

    fn status(&self, i: usize) -> NodeStatus {
        self.st[i].status
    }

    fn runs_an_action(&self, i: usize) -> bool {
        (matches!(self.nodes[i].kind(), NodeKind::Action(_)) && self.status(i) == NodeStatus::Running)
            || self.kids(i).into_iter().any(|c| self.runs_an_action(c))
    }

    pub(super) fn tick_root(&mut self, script: &[u8], now: u32) -> Status {
        self.script = script.to_vec();
        self.now = now;
        self.timers();
        self.tick(0, false)
    }

    /// What BehaviorTree.CPP's timers did since the last tick, in pre-order.
    fn timers(&mut self) {
        for i in 0..self.nodes.len() {
            if self.status(i) != NodeStatus::Running {
                continue;
            }
            let elapsed = self.now.wrapping_sub(self.st[i].start) & Span::MAX;
            match *self.nodes[i].kind() {
                NodeKind::TimeLimit(d)
                    if d.get() > 0 && elapsed >= d.get() && self.status(i + 1) == NodeStatus::Running =>
                {
                    self.halt(i + 1);
                    self.woken = true;
                }
                NodeKind::Delay(d) if elapsed >= d.get() && self.status(i + 1) == NodeStatus::Idle => self.woken = true,
                NodeKind::Sleep(d) if elapsed >= d.get() => self.woken = true,
                _ => {}
            }
        }
    }

    /// Rule 3: halt every Running action below `i`, children first, and reset to Idle,
    /// keeping the memory that survives a halt. An Idle node's subtree is left as it is.
    fn halt(&mut self, i: usize) {
        if self.status(i) == NodeStatus::Idle {
            return;
        }
        for c in self.kids(i) {
            self.halt(c);
        }
        if matches!(self.nodes[i].kind(), NodeKind::Guard(_)) && self.status(i) == NodeStatus::Running {
            self.log.push(Ev::Hook { node: i, hook: 4 });
        }
        if matches!(self.nodes[i].kind(), NodeKind::Action(_)) && self.status(i) == NodeStatus::Running {
            self.log.push(Ev::Halt { node: i });
        }
        let was = self.st[i];
        let mut fresh = RState::default();
        match self.nodes[i].kind() {
            NodeKind::SequenceStar => fresh.mem = was.mem,
            // BehaviorTree.CPP 3's forgets its place when halted Running.
            NodeKind::SequenceStarV3 if was.status != NodeStatus::Running => fresh.mem = was.mem,
            NodeKind::RunOnce { .. } => fresh.done = was.done,
            NodeKind::Precondition { .. } => fresh.mem = was.mem,
            NodeKind::ManualSelector { .. } => fresh.choice = was.choice,
            NodeKind::RoundRobin | NodeKind::Recovery { .. } if was.status != NodeStatus::Running => {
                fresh.mem = was.mem;
                fresh.count = was.count;
            }
            _ => {}
        }
        self.st[i] = fresh;
    }

    /// BehaviorTree.CPP's haltChild: halt a Running child, else only make it Idle.
    fn halt_child(&mut self, c: usize) {
        if self.status(c) == NodeStatus::Running {
            self.halt(c);
        } else {
            self.st[c].status = NodeStatus::Idle;
        }
    }

    fn halt_children(&mut self, i: usize) {
        for c in self.kids(i) {
            self.halt_child(c);
        }
    }

    /// Whether a RateController or Gate at `i` starts afresh.
    fn fresh(&self, i: usize, parent_mirrors: bool) -> bool {
        match self.status(i) {
            NodeStatus::Idle => true,
            NodeStatus::Running => false,
            _ => !parent_mirrors,
        }
    }

    /// A Loop or Precondition starting afresh after it finished is Idle (BT.CPP's parent
    /// reset it), which a Skipped result keeps.
    fn forget_result(&mut self, i: usize, fresh: bool) {
        if fresh && matches!(self.status(i), NodeStatus::Success | NodeStatus::Failure) {
            self.st[i].status = NodeStatus::Idle;
        }
    }

    fn elapsed(&self, i: usize) -> u32 {
        self.now.wrapping_sub(self.st[i].start) & Span::MAX
    }

    fn tick(&mut self, i: usize, parent_mirrors: bool) -> Status {
        let was = self.st[i];
        let running = was.status == NodeStatus::Running;
        let mirrors = !is_reactive_or_reused(self.nodes[i].kind());
        let r = match *self.nodes[i].kind() {
            NodeKind::Condition(_) => {
                self.log.push(Ev::Tick { node: i, starting: true });
                outcome(self.nodes, &self.script, i)
            }
            NodeKind::Action(_) => {
                if !running {
                    // Rule 4: halt before start, innermost first, the branches where an
                    // action runs.
                    for p in self.preempted.clone().into_iter().rev().flatten() {
                        if self.runs_an_action(p) {
                            self.halt(p);
                        }
                    }
                }
                self.log.push(Ev::Tick { node: i, starting: !running });
                outcome(self.nodes, &self.script, i)
            }
            NodeKind::AlwaysSuccess => Status::Success,
            NodeKind::AlwaysFailure => Status::Failure,
            // Rule 10: Running from its start until the span has passed.
            NodeKind::Sleep(d) => {
                if !running {
                    if d.get() == 0 {
                        return self.set(i, Status::Success);
                    }
                    self.st[i].start = self.now;
                    Status::Running
                } else if self.elapsed(i) >= d.get() {
                    Status::Success
                } else {
                    Status::Running
                }
            }
            // Rule 12: a script runs once per tick, as a condition.
            NodeKind::Script(_) | NodeKind::ScriptCondition(_) => {
                self.log.push(Ev::Tick { node: i, starting: true });
                outcome(self.nodes, &self.script, i)
            }
            kind @ (NodeKind::Sequence
            | NodeKind::Fallback
            | NodeKind::SequenceWithMemory
            | NodeKind::FallbackWithMemory) => {
                let is_seq = matches!(kind, NodeKind::Sequence | NodeKind::SequenceWithMemory);
                let memory = matches!(kind, NodeKind::SequenceWithMemory | NodeKind::FallbackWithMemory);
                let go_on = if is_seq { Status::Success } else { Status::Failure };
                let kids = self.kids(i);
                let start = if memory && running { kids.iter().position(|&c| Some(c) == was.last).unwrap() } else { 0 };
                let mut result = None;
                let mut at = *kids.last().unwrap();
                for &c in &kids[start..] {
                    let old = if !memory && running && was.last.is_some_and(|l| l > c) { was.last } else { None };
                    if !memory {
                        self.preempted.push(old);
                    }
                    let s = self.tick(c, false);
                    if !memory {
                        self.preempted.pop();
                    }
                    if s == Status::Skipped {
                        // Reactive nodes halt a child that skipped.
                        if !memory {
                            self.halt(c);
                        }
                        continue;
                    }
                    if s != go_on {
                        result = Some(s);
                        at = c;
                        break;
                    }
                }
                for c in kids.iter().copied().filter(|&c| c > at) {
                    self.halt(c);
                }
                let result = result.unwrap_or_else(|| {
                    // No child stopped it: all skipped (none returned `go_on` in this
                    // activation), or `go_on`.
                    if kids.iter().any(|&c| self.status(c) == go_on.into()) { go_on } else { Status::Skipped }
                });
                if memory && result != Status::Running {
                    // Finished: children that skipped and stayed Running are reset.
                    for c in kids.iter().copied().filter(|&c| c < at || result == Status::Skipped || c == at) {
                        if self.status(c) == NodeStatus::Running {
                            self.halt(c);
                        }
                    }
                }
                self.st[i].last = Some(if result == Status::Skipped && memory { kids[0] } else { at });
                result
            }
            NodeKind::Parallel { success_threshold, failure_threshold, count_skipped } => {
                // Counts are totals of the activation; the verdict is checked after each
                // child, ticked or passed over.
                let kids = self.kids(i);
                let n = kids.len() as u16;
                let finished = |me: &Self, c: usize, s: NodeStatus| running && me.st[c].status == s;
                let mut ok = kids.iter().filter(|&&c| finished(self, c, NodeStatus::Success)).count() as u16;
                let mut failed = kids.iter().filter(|&&c| finished(self, c, NodeStatus::Failure)).count() as u16;
                let mut skipped = 0u16;
                let mut verdict = None;
                let mut reached = kids.len();
                for (k, &c) in kids.iter().enumerate() {
                    let done = finished(self, c, NodeStatus::Success) || finished(self, c, NodeStatus::Failure);
                    if !done {
                        match self.tick(c, false) {
                            Status::Success => ok += 1,
                            Status::Failure => failed += 1,
                            Status::Skipped => skipped += 1,
                            Status::Running => {}
                        }
                    }
                    if ok >= success_threshold || (count_skipped && ok + skipped >= success_threshold) {
                        verdict = Some(Status::Success);
                    } else if failed >= failure_threshold || n - failed < success_threshold {
                        verdict = Some(Status::Failure);
                    }
                    if verdict.is_some() {
                        reached = k + 1;
                        break;
                    }
                }
                match verdict {
                    Some(v) => {
                        for (k, &c) in kids.iter().enumerate() {
                            if k >= reached || self.st[c].status == NodeStatus::Running {
                                self.halt(c);
                            }
                        }
                        v
                    }
                    None if skipped == n => Status::Skipped,
                    None => Status::Running,
                }
            }
            NodeKind::Inverter => match self.tick(i + 1, false) {
                Status::Success => Status::Failure,
                Status::Failure => Status::Success,
                s => s,
            },
            NodeKind::ForceSuccess => match self.tick(i + 1, false) {
                Status::Success | Status::Failure => Status::Success,
                s => s,
            },
            NodeKind::ForceFailure => match self.tick(i + 1, false) {
                Status::Success | Status::Failure => Status::Failure,
                s => s,
            },
            NodeKind::Repeat(n) | NodeKind::Retry(n) => {
                let repeat = matches!(self.nodes[i].kind(), NodeKind::Repeat(_));
                let count = if running { was.count } else { 0 };
                let s = self.tick(i + 1, false);
                let again = if repeat { Status::Success } else { Status::Failure };
                if s == again {
                    if count + 1 >= n {
                        s
                    } else {
                        self.st[i].count = count + 1;
                        Status::Running
                    }
                } else {
                    if s == Status::Running {
                        self.st[i].count = count;
                    }
                    s
                }
            }
            NodeKind::Timeout(n) => {
                let count = if running { was.count } else { 0 };
                let s = self.tick(i + 1, false);
                if s == Status::Running {
                    if count + 1 >= n {
                        self.halt(i + 1);
                        Status::Failure
                    } else {
                        self.st[i].count = count + 1;
                        Status::Running
                    }
                } else {
                    s
                }
            }
            // ------------------------------------------- BehaviorTree.CPP's and Nav2's
            kind @ (NodeKind::SequenceStar | NodeKind::SequenceStarV3) => {
                // Version 3 goes on to the next child where version 4 wakes up.
                let v3 = kind == NodeKind::SequenceStarV3;
                let kids = self.kids(i);
                let mut idx = kids.iter().position(|&c| c == was.mem).unwrap_or(0);
                loop {
                    if idx == kids.len() {
                        let all_skipped = !kids.iter().any(|&c| self.status(c) == NodeStatus::Success);
                        self.halt_children(i);
                        self.st[i].mem = 0;
                        break if all_skipped { Status::Skipped } else { Status::Success };
                    }
                    let c = kids[idx];
                    let was_idle = self.status(c) == NodeStatus::Idle;
                    match self.tick(c, true) {
                        Status::Running => {
                            self.st[i].mem = c;
                            break Status::Running;
                        }
                        Status::Failure => {
                            for &k in &kids[idx..] {
                                self.halt_child(k);
                            }
                            self.st[i].mem = c;
                            break Status::Failure;
                        }
                        Status::Success => {
                            idx += 1;
                            if was_idle && idx < kids.len() && !v3 {
                                self.st[i].mem = kids[idx];
                                self.woken = true;
                                break Status::Running;
                            }
                        }
                        Status::Skipped => idx += 1,
                    }
                }
            }
            kind => match self.tick_btcpp(i, kind, was, running, parent_mirrors) {
                ControlFlow::Break(done) => return done,
                ControlFlow::Continue(r) => r,
            },
        };
        let _ = mirrors;
        let new = match r {
            // A Precondition that skips keeps its status (BehaviorTree.CPP's does not
            // mark itself Running).
            Status::Skipped
                if matches!(self.nodes[i].kind(), NodeKind::Precondition { .. } | NodeKind::ManualSelector { .. }) =>
            {
                self.st[i].status
            }
            // A control node or decorator that skips stays Running; a leaf is Idle.
            Status::Skipped if self.nodes[i].kind().arity() != bt_core::Arity::Leaf => NodeStatus::Running,
            r => r.into(),
        };
        self.st[i].status = new;
        r
    }

    /// Sets the status `r` gives and returns `r` (Skipped: Idle).
    fn set(&mut self, i: usize, r: Status) -> Status {
        self.st[i].status = r.into();
        r
    }
}
