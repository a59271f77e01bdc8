//! The kinds that stand for BehaviorTree.CPP's and Nav2's nodes, off the hot path: they
//! are entered through [`Run::enter_other`] and ascended through [`Run::ascend_other`].
//!
//! Each follows its original step by step (the rules are in the module docs of
//! [`exec`](super)), including when it resets its children: a child that finishes is
//! reset at once, except where BehaviorTree.CPP keeps its status (the children a
//! `PipelineSequence` or `SequenceStar` has passed, a `WhileDoElse`'s condition, ...).
//!
//! What each keeps in its [`NodeState`] (`aux`, `ext`) and its [`Frame`]/[`Extra`]:
//!
//! | kind | state | frame, side entry |
//! |---|---|---|
//! | `SequenceStar` | `aux`: the child to resume at (0: the first); kept through halts | `a`: the child ticked was Idle |
//! | `IfThenElse` | `aux`: the branch Running (0: none) | `a`: 0 condition, 1 branch |
//! | `WhileDoElse` | — | `a`: 0 condition, 1 branch |
//! | `ParallelAll` | — | `ok` finished, `failed`, `skipped`, `children`, `failure` |
//! | `PipelineSequence` | `aux`: the furthest child that ran (0: the first) | `ok` that child, `skipped`, `children` |
//! | `Recovery` | `aux`: recoveries so far, `ext`: the child (0/1); kept unless halted Running | `a` recoveries, `ok` limit, `failed` child |
//! | `RoundRobin` | `aux`: the next child (0-based), `ext`: failures; kept unless halted Running | `ok` next, `failed`, `skipped`, `children` |
//! | `RepeatCycles`, `RetryUntilSuccessful` | `aux`: the count | `a` count, `ok` limit, `child_was_idle` |
//! | `RunOnce` | `aux`: 0 not yet, 1 succeeded, 2 failed; kept for ever | — |
//! | `Precondition` | `aux`: 1 while its child is under way; kept for ever | — |
//! | `Loop` | `aux`: elements taken from a literal queue, `ext`: 1 while its child runs | — |
//! | `ManualSelector` | `aux`: the last selection ([`remembered`]); kept for ever | `a`: 1 when it asked on this tick |
//! | `TimeLimit`, `Delay`, `RateController`, `Sleep` | `aux` + `ext`: start time (24 bits of `now`) | — |

use super::{Ascent, Entered, Extra, Frame, FrameKind, NodeState, Run};
use crate::behavior::{BehaviorSet, Context, Observer, Selection, TickError};
use crate::node::{Code, Node, NodeId, NodeKind, Span};
use crate::script::{Hook, Queue, Value, element, hook, queue, truth};
use crate::status::{NodeStatus, Status};

/// Start times are kept in 24 bits.
const TIME_MASK: u32 = Span::MAX;

/// A `ManualSelector`'s last selection as its `aux` keeps it: 0 none, `1 + k` child
/// `k`, `0x101` to `0x103` Success, Failure, Running.
const fn selection_aux(s: Selection) -> u16 {
    match s {
        Selection::Child(k) => 1 + k as u16,
        Selection::Success => 0x101,
        Selection::Failure => 0x102,
        Selection::Running => 0x103,
    }
}

/// The selection [`selection_aux`] kept, if any.
const fn remembered(aux: u16) -> Option<Selection> {
    match aux {
        0 => None,
        0x101 => Some(Selection::Success),
        0x102 => Some(Selection::Failure),
        0x103 => Some(Selection::Running),
        1..=0x100 => Some(Selection::Child((aux - 1) as u8)),
        _ => None,
    }
}

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH> {
    /// Whether a `RateController` or `Gate` starts afresh: it is Idle, or it finished
    /// under a parent that BehaviorTree.CPP would have reset it under (every parent but
    /// the kinds of this module, which keep exactly the statuses BehaviorTree.CPP keeps).
    fn fresh(st: NodeState, parent_mirrors: bool) -> bool {
        match st.status {
            NodeStatus::Idle => true,
            NodeStatus::Running => false,
            NodeStatus::Success | NodeStatus::Failure => !parent_mirrors,
        }
    }

    /// A node that starts afresh after finishing is Idle, as BehaviorTree.CPP's parent
    /// left it: for the kinds whose status a Skipped result keeps (`Loop`, `Precondition`).
    fn forget_result(&mut self, i: usize, st: NodeState, fresh: bool) {
        if fresh && matches!(st.status, NodeStatus::Success | NodeStatus::Failure) {
            self.set_status(i, NodeStatus::Idle);
        }
    }

    fn start_time(st: NodeState) -> u32 {
        u32::from(st.aux) | u32::from(st.ext) << 16
    }

    fn set_start(&mut self, i: usize, now: u32) {
        self.set_memory(i, now as u16, (now >> 16) as u8);
    }

    fn elapsed(st: NodeState, now: u32) -> u32 {
        now.wrapping_sub(Self::start_time(st)) & TIME_MASK
    }

    /// The number of children of a node ending at `end`, and its child number `k`
    /// (0-based), if any.
    fn children_of(&self, node: usize, end: usize, k: u16) -> Result<(u16, Option<usize>), TickError> {
        let mut n = 0u16;
        let mut found = None;
        let mut c = node + 1;
        while c < end {
            if n == k {
                found = Some(c);
            }
            n = n.saturating_add(1);
            c = self.end_of(c)?;
        }
        Ok((n, found))
    }

    /// BehaviorTree.CPP's `haltChild`: a Running child is halted (its subtree reset);
    /// any other child only becomes Idle, keeping its memory and its own children's
    /// statuses as they are.
    pub(super) fn halt_child(&mut self, c: usize) {
        if self.status(c) == NodeStatus::Running {
            self.reset_subtree(c);
        } else {
            self.set_status(c, NodeStatus::Idle);
        }
    }

    /// [`Run::halt_child`] for every child of `node` (subtree ending at `end`), in order.
    pub(super) fn reset_children(&mut self, node: usize, end: usize) -> Result<(), TickError> {
        let mut c = node + 1;
        while c < end {
            let after = self.end_of(c)?;
            self.halt_child(c);
            c = after;
        }
        Ok(())
    }

    /// Before a tick of a tree with clocked kinds: what BehaviorTree.CPP's timers did
    /// since the last tick. A `TimeLimit` whose span has passed while its child runs
    /// halts the child now (the tick then finds it expired and fails it), and asks for a
    /// tick; a `Delay` whose span has passed asks for one. Pre-order.
    #[cold]
    #[inline(never)]
    pub(super) fn timers(&mut self, now: u32) {
        for i in 0..self.nodes.len() {
            let Some(&node) = self.nodes.get(i) else { return };
            let st = self.state.get(i).copied().unwrap_or_default();
            if st.status != NodeStatus::Running {
                continue;
            }
            let first = i + 1;
            match *node.kind() {
                NodeKind::TimeLimit(d)
                    if d.get() > 0
                        && Self::elapsed(st, now) >= d.get()
                        && self.status(first) == NodeStatus::Running =>
                {
                    self.reset_subtree(first);
                    self.side.woken = true;
                }
                NodeKind::Delay(d) if Self::elapsed(st, now) >= d.get() && self.status(first) == NodeStatus::Idle => {
                    self.side.woken = true;
                }
                NodeKind::Sleep(d) if Self::elapsed(st, now) >= d.get() => self.side.woken = true,
                _ => {}
            }
        }
    }

    /// Runs a script of node `idx` through the behavior set; a fault ends the tick.
    fn run_script(&mut self, idx: usize, program: &[u16], now: u32) -> Result<Value, TickError> {
        let ctx = Context { node: idx as NodeId, now, starting: true, values: self.values };
        self.behaviors.script(program, ctx).map_err(|fault| TickError::Script { node: idx as NodeId, fault })
    }

    /// Runs a script of node `idx` and says whether its result holds.
    fn holds(&mut self, idx: usize, program: &[u16], now: u32) -> Result<bool, TickError> {
        let v = self.run_script(idx, program, now)?;
        truth(v).map_err(|fault| TickError::Script { node: idx as NodeId, fault })
    }

    /// Runs hook `h` of the guard at `idx`, if it has one.
    fn run_hook(&mut self, idx: usize, table: Code, h: Hook, now: u32) -> Result<(), TickError> {
        if let Some(program) = hook(table.words(self.values), h) {
            self.run_script(idx, program, now)?;
        }
        Ok(())
    }

    /// A guard's checks before its node starts: `_failureIf`, `_successIf`, `_skipIf`,
    /// then `_while`, as BehaviorTree.CPP asks them; the status they decide, if any.
    fn guard_before(&mut self, idx: usize, table: Code, now: u32) -> Result<Option<Status>, TickError> {
        let t = table.words(self.values);
        for (h, then) in
            [(Hook::FailureIf, Status::Failure), (Hook::SuccessIf, Status::Success), (Hook::SkipIf, Status::Skipped)]
        {
            if let Some(p) = hook(t, h)
                && self.holds(idx, p, now)?
            {
                return Ok(Some(then));
            }
        }
        match hook(t, Hook::While) {
            Some(p) if !self.holds(idx, p, now)? => Ok(Some(Status::Skipped)),
            _ => Ok(None),
        }
    }

    /// A guard's hooks after its node returned `r`: `_onSuccess` or `_onFailure`, then
    /// `_post`, when it finished.
    fn guard_after(&mut self, idx: usize, table: Code, r: Status, now: u32) -> Result<(), TickError> {
        match r {
            Status::Success => self.run_hook(idx, table, Hook::OnSuccess, now)?,
            Status::Failure => self.run_hook(idx, table, Hook::OnFailure, now)?,
            _ => return Ok(()),
        }
        self.run_hook(idx, table, Hook::Post, now)
    }

    /// The guard at `idx`, Running, is halted: its `_onHalted`, after its subtree (its
    /// script is told `now` 0: halts have no clock). A fault is kept for the tick to
    /// return.
    /// The tick's result, or the fault of a guard's `_onHalted` that failed while the
    /// tick halted its node (which it clears).
    #[cold]
    #[inline(never)]
    pub(super) fn guard_fault(&mut self, result: Result<Status, TickError>) -> Result<Status, TickError> {
        match self.side.fault.take() {
            Some(f) if result.is_ok() => Err(f),
            _ => result,
        }
    }

    #[cold]
    #[inline(never)]
    pub(super) fn guard_halted(&mut self, idx: usize, table: Code) {
        if self.status(idx) != NodeStatus::Running {
            return;
        }
        if let Err(e) = self.run_hook(idx, table, Hook::OnHalted, 0)
            && self.side.fault.is_none()
        {
            self.side.fault = Some(e);
        }
    }

    /// Enters a kind of this module.
    pub(super) fn enter_btcpp(
        &mut self,
        kind: &NodeKind,
        st: NodeState,
        frame: &mut Frame,
        x: &mut Extra,
        parent_mirrors: bool,
        now: u32,
    ) -> Result<Entered, TickError> {
        let idx = usize::from(frame.node);
        let end = usize::from(frame.end);
        let first = idx + 1;
        let running = frame.running;
        let child = |aux: u16| if aux == 0 { first } else { usize::from(aux) };
        let entered = match *kind {
            NodeKind::SequenceStar => {
                frame.kind = FrameKind::SequenceStar;
                let c = child(st.aux);
                frame.a = u16::from(self.status(c) == NodeStatus::Idle);
                Entered::Child(c)
            }
            NodeKind::IfThenElse => {
                frame.kind = FrameKind::IfThenElse;
                if running && st.aux != 0 {
                    frame.a = 1;
                    Entered::Child(usize::from(st.aux))
                } else {
                    frame.a = 0;
                    Entered::Child(first)
                }
            }
            NodeKind::WhileDoElse => {
                frame.kind = FrameKind::WhileDoElse;
                frame.a = 0;
                Entered::Child(first)
            }
            NodeKind::ParallelAll { max_failures } => {
                frame.kind = FrameKind::ParallelAll;
                *x = Extra { failure: max_failures, ..Extra::default() };
                let mut next = None;
                let mut c = first;
                while c < end {
                    x.children = x.children.saturating_add(1);
                    match self.status(c) {
                        NodeStatus::Success if running => x.ok = x.ok.saturating_add(1),
                        NodeStatus::Failure if running => {
                            x.ok = x.ok.saturating_add(1);
                            x.failed = x.failed.saturating_add(1);
                        }
                        _ => {
                            if next.is_none() {
                                next = Some(c);
                            }
                        }
                    }
                    c = self.end_of(c)?;
                }
                match next {
                    Some(c) => Entered::Child(c),
                    // Impossible for a node Running: it would have finished.
                    None => Entered::Decided(self.parallel_all_done(idx, end, x)?),
                }
            }
            NodeKind::PipelineSequence => {
                frame.kind = FrameKind::PipelineSequence;
                let (children, _) = self.children_of(idx, end, 0)?;
                *x = Extra {
                    ok: if running { child(st.aux) as u16 } else { first as u16 },
                    children,
                    ..Extra::default()
                };
                Entered::Child(first)
            }
            NodeKind::Recovery { retries } => {
                frame.kind = FrameKind::Recovery;
                frame.a = st.aux;
                *x = Extra { ok: retries, failed: u16::from(st.ext), ..Extra::default() };
                if x.failed > 1 || frame.a > retries {
                    self.reset_children(idx, end)?;
                    self.set_memory(idx, 0, 0);
                    Entered::Decided(Status::Failure)
                } else {
                    let (_, c) = self.children_of(idx, end, x.failed)?;
                    Entered::Child(c.ok_or(super::oob(idx))?)
                }
            }
            NodeKind::RoundRobin => {
                frame.kind = FrameKind::RoundRobin;
                let (children, c) = self.children_of(idx, end, st.aux)?;
                *x = Extra { ok: st.aux, failed: u16::from(st.ext), children, ..Extra::default() };
                match c {
                    Some(c) if x.failed < children => Entered::Child(c),
                    _ => {
                        self.reset_children(idx, end)?;
                        self.set_memory(idx, 0, 0);
                        Entered::Decided(Status::Failure)
                    }
                }
            }
            NodeKind::RepeatCycles(n) | NodeKind::RetryUntilSuccessful(n) => {
                let repeat = matches!(kind, NodeKind::RepeatCycles(_));
                frame.kind = if repeat { FrameKind::RepeatCycles } else { FrameKind::RetryUntilSuccessful };
                frame.a = if running { st.aux } else { 0 };
                *x = Extra { ok: n, child_was_idle: self.status(first) == NodeStatus::Idle, ..Extra::default() };
                if frame.a < n || n == NodeKind::FOREVER {
                    Entered::Child(first)
                } else {
                    self.set_memory(idx, 0, 0);
                    Entered::Decided(if repeat { Status::Success } else { Status::Failure })
                }
            }
            NodeKind::KeepRunningUntilFailure => {
                frame.kind = FrameKind::KeepRunningUntilFailure;
                Entered::Child(first)
            }
            NodeKind::RunOnce { then_skip } => {
                frame.kind = FrameKind::RunOnce;
                match st.aux {
                    0 => Entered::Child(first),
                    _ if then_skip => Entered::Decided(Status::Skipped),
                    1 => Entered::Decided(Status::Success),
                    _ => Entered::Decided(Status::Failure),
                }
            }
            NodeKind::TimeLimit(d) => {
                frame.kind = FrameKind::TimeLimit;
                if !running {
                    self.set_start(idx, now);
                    Entered::Child(first)
                } else if d.get() > 0 && Self::elapsed(st, now) >= d.get() {
                    // Expired: its child was halted before the tick (see `timers`).
                    self.halt_child(first);
                    Entered::Decided(Status::Failure)
                } else {
                    Entered::Child(first)
                }
            }
            NodeKind::Delay(d) => {
                frame.kind = FrameKind::Delay;
                let elapsed = if running { Self::elapsed(st, now) } else { 0 };
                if !running {
                    self.set_start(idx, now);
                }
                if elapsed >= d.get() || self.status(first) == NodeStatus::Running {
                    Entered::Child(first)
                } else {
                    Entered::Decided(Status::Running)
                }
            }
            NodeKind::RateController(d) => {
                frame.kind = FrameKind::RateController;
                let fresh = Self::fresh(st, parent_mirrors);
                if fresh {
                    self.set_start(idx, now);
                }
                if fresh || self.status(first) == NodeStatus::Running || Self::elapsed(st, now) >= d.get() {
                    Entered::Child(first)
                } else {
                    Entered::Decided(Status::Running)
                }
            }
            NodeKind::Gate(ref leaf) => {
                frame.kind = FrameKind::Gate;
                let starting = Self::fresh(st, parent_mirrors);
                let open =
                    self.behaviors.action(leaf, Context { node: idx as NodeId, now, starting, values: self.values });
                if self.status(first) == NodeStatus::Running {
                    Entered::Child(first)
                } else {
                    match open {
                        Status::Success => Entered::Child(first),
                        other => Entered::Decided(other),
                    }
                }
            }
            NodeKind::AlwaysSuccess => Entered::Decided(Status::Success),
            NodeKind::AlwaysFailure => Entered::Decided(Status::Failure),
            NodeKind::Guard(table) => {
                frame.kind = FrameKind::Guard;
                let decided = if Self::fresh(st, parent_mirrors) {
                    self.guard_before(idx, table, now)?
                } else if running {
                    // `_while` is the one hook asked while the node runs.
                    match hook(table.words(self.values), Hook::While) {
                        Some(p) if !self.holds(idx, p, now)? => {
                            self.reset_subtree(first);
                            self.run_hook(idx, table, Hook::OnHalted, now)?;
                            Some(Status::Skipped)
                        }
                        _ => None,
                    }
                } else {
                    None
                };
                match decided {
                    Some(d) => {
                        self.guard_after(idx, table, d, now)?;
                        Entered::Decided(d)
                    }
                    None => Entered::Child(first),
                }
            }
            NodeKind::Sleep(d) => {
                if !running {
                    if d.get() == 0 {
                        return Ok(Entered::Decided(Status::Success));
                    }
                    self.set_start(idx, now);
                    Entered::Decided(Status::Running)
                } else if Self::elapsed(st, now) >= d.get() {
                    Entered::Decided(Status::Success)
                } else {
                    Entered::Decided(Status::Running)
                }
            }
            NodeKind::Precondition { code, otherwise } => {
                frame.kind = FrameKind::Precondition;
                self.forget_result(idx, st, Self::fresh(st, parent_mirrors));
                if st.aux == 1 {
                    Entered::Child(first)
                } else if self.holds(idx, code.words(self.values), now)? {
                    self.set_memory(idx, 1, 0);
                    Entered::Child(first)
                } else {
                    Entered::Decided(otherwise)
                }
            }
            NodeKind::Loop { table, if_empty } => {
                frame.kind = FrameKind::Loop;
                // BehaviorTree.CPP's loop starts over from Idle (or finished, under a
                // parent that resets it) and pops only while its child is not Running.
                let fresh = Self::fresh(st, parent_mirrors);
                if !fresh && st.status == NodeStatus::Running && st.ext == 1 {
                    return Ok(Entered::Child(first));
                }
                self.forget_result(idx, st, fresh);
                let taken = if fresh { 0 } else { st.aux };
                let fault = |fault| TickError::Script { node: idx as NodeId, fault };
                let popped = match queue(table.words(self.values)) {
                    Some(Queue::Key { queue, value }) => {
                        let ctx = Context { node: idx as NodeId, now, starting: fresh, values: self.values };
                        self.behaviors.pop(queue, value, ctx).map_err(fault)?
                    }
                    Some(Queue::Literal(literal)) => match element(literal, taken) {
                        Some(program) => {
                            self.run_script(idx, program, now)?;
                            true
                        }
                        None => false,
                    },
                    None => return Err(fault(crate::script::ScriptFault::Malformed { at: 0 })),
                };
                if popped {
                    self.set_memory(idx, taken.saturating_add(1), 0);
                    Entered::Child(first)
                } else {
                    self.set_memory(idx, taken, 0);
                    Entered::Decided(if_empty)
                }
            }
            NodeKind::ManualSelector { repeat_last } => {
                frame.kind = FrameKind::ManualSelector;
                let fresh = Self::fresh(st, parent_mirrors);
                self.forget_result(idx, st, fresh);
                let (count, _) = self.children_of(idx, end, 0)?;
                // At most 255 children: validation refuses more.
                let children = u8::try_from(count).map_err(|_| super::oob(idx))?;
                let (selection, asked) = match remembered(st.aux) {
                    Some(s) if repeat_last && children > 0 => (s, false),
                    _ => {
                        let ctx = Context { node: idx as NodeId, now, starting: fresh, values: self.values };
                        let s = self
                            .behaviors
                            .select(children, ctx)
                            .map_err(|fault| TickError::Script { node: idx as NodeId, fault })?;
                        (s, true)
                    }
                };
                frame.a = u16::from(asked);
                let chosen = match selection {
                    Selection::Child(k) => match self.children_of(idx, end, u16::from(k))? {
                        (_, Some(c)) => Some(c),
                        (_, None) => return Err(TickError::NoSuchChild { node: idx as NodeId, child: k, children }),
                    },
                    _ => None,
                };
                // BehaviorTree.CPP remembers what it was told only when it has children.
                if children > 0 {
                    self.set_memory(idx, selection_aux(selection), 0);
                }
                // Halt before start: a child still Running that was not chosen is halted
                // first (BehaviorTree.CPP leaves it Running), and so is one under a node
                // that finishes now. Returning Running leaves it as it is.
                if selection != Selection::Running {
                    let mut c = first;
                    while c < end {
                        let after = self.end_of(c)?;
                        if Some(c) != chosen && self.status(c) == NodeStatus::Running {
                            self.reset_subtree(c);
                        }
                        c = after;
                    }
                }
                match (chosen, selection) {
                    (Some(c), _) => Entered::Child(c),
                    (None, Selection::Success) => Entered::Decided(Status::Success),
                    (None, Selection::Failure) => Entered::Decided(Status::Failure),
                    (None, _) => Entered::Decided(Status::Running),
                }
            }
            NodeKind::Script(code) => {
                self.run_script(idx, code.words(self.values), now)?;
                Entered::Decided(Status::Success)
            }
            NodeKind::ScriptCondition(code) => {
                let holds = self.holds(idx, code.words(self.values), now)?;
                Entered::Decided(if holds { Status::Success } else { Status::Failure })
            }
            _ => return Err(super::oob(idx)),
        };
        Ok(entered)
    }

    /// `ParallelAll` at `node` has ticked or passed every child this tick.
    fn parallel_all_done(&mut self, node: usize, end: usize, x: &Extra) -> Result<Status, TickError> {
        if x.skipped == x.children {
            return Ok(Status::Skipped);
        }
        if x.skipped.saturating_add(x.ok) >= x.children {
            self.reset_children(node, end)?;
            return Ok(if x.failed >= x.failure { Status::Failure } else { Status::Success });
        }
        Ok(Status::Running)
    }

    /// Child `c` (ending at `child_end`) returned `r` to a frame of this module.
    pub(super) fn ascend_btcpp(
        &mut self,
        top: &mut Frame,
        x: &mut Extra,
        c: usize,
        child_end: usize,
        r: Status,
        now: u32,
    ) -> Result<Ascent, TickError> {
        let node = usize::from(top.node);
        let end = usize::from(top.end);
        let first = node + 1;
        let more = child_end < end;
        let done = |v| Ok(Ascent::Return(v));
        match top.kind {
            FrameKind::SequenceStar => match r {
                Status::Success if more && top.a == 1 => {
                    // BehaviorTree.CPP's wake-up: return, ask to be ticked again.
                    self.set_memory(node, child_end as u16, 0);
                    self.side.woken = true;
                    done(Status::Running)
                }
                Status::Success | Status::Skipped if more => {
                    top.a = u16::from(self.status(child_end) == NodeStatus::Idle);
                    Ok(Ascent::Tick(child_end))
                }
                Status::Success | Status::Skipped => {
                    let all_skipped = !self.any_child(node, end, NodeStatus::Success)? && r == Status::Skipped;
                    self.reset_children(node, end)?;
                    self.set_memory(node, 0, 0);
                    done(if all_skipped { Status::Skipped } else { Status::Success })
                }
                Status::Running => {
                    self.set_memory(node, c as u16, 0);
                    done(Status::Running)
                }
                Status::Failure => {
                    // Keeps its place: the failed child is where it resumes.
                    let mut k = c;
                    while k < end {
                        let after = self.end_of(k)?;
                        self.halt_child(k);
                        k = after;
                    }
                    self.set_memory(node, c as u16, 0);
                    done(Status::Failure)
                }
            },
            FrameKind::IfThenElse => {
                if top.a == 0 {
                    // The condition is the first child: `child_end` is the second.
                    let branch = match r {
                        Status::Success => child_end,
                        Status::Failure => self.end_of(child_end)?,
                        Status::Running | Status::Skipped => {
                            self.set_memory(node, 0, 0);
                            return done(r);
                        }
                    };
                    if branch >= end {
                        // Two children: the condition's Failure is the result, and
                        // BehaviorTree.CPP leaves the children as they are.
                        return done(Status::Failure);
                    }
                    top.a = 1;
                    return Ok(Ascent::Tick(branch));
                }
                if r == Status::Running {
                    self.set_memory(node, c as u16, 0);
                } else {
                    self.reset_children(node, end)?;
                    self.set_memory(node, 0, 0);
                }
                done(r)
            }
            FrameKind::WhileDoElse => {
                if top.a == 0 {
                    let third = if more { self.end_of(child_end).ok().filter(|&t| t < end) } else { None };
                    match (r, third) {
                        (Status::Running, _) => return done(Status::Running),
                        (Status::Success, third) => {
                            if let Some(t) = third {
                                self.halt_child(t);
                            }
                            top.a = 1;
                            return Ok(Ascent::Tick(child_end));
                        }
                        (Status::Failure, Some(t)) => {
                            self.halt_child(child_end);
                            top.a = 1;
                            return Ok(Ascent::Tick(t));
                        }
                        (Status::Failure, None) | (Status::Skipped, _) => {
                            self.reset_children(node, end)?;
                            return done(r);
                        }
                    }
                }
                if r != Status::Running {
                    self.reset_children(node, end)?;
                }
                done(r)
            }
            FrameKind::ParallelAll => {
                match r {
                    Status::Success => x.ok = x.ok.saturating_add(1),
                    Status::Failure => {
                        x.ok = x.ok.saturating_add(1);
                        x.failed = x.failed.saturating_add(1);
                    }
                    Status::Skipped => x.skipped = x.skipped.saturating_add(1),
                    Status::Running => {}
                }
                let mut k = child_end;
                while k < end {
                    let finished = matches!(self.status(k), NodeStatus::Success | NodeStatus::Failure);
                    if !(top.running && finished) {
                        return Ok(Ascent::Tick(k));
                    }
                    k = self.end_of(k)?;
                }
                done(self.parallel_all_done(node, end, x)?)
            }
            FrameKind::PipelineSequence => {
                match r {
                    Status::Failure => {
                        self.reset_children(node, end)?;
                        self.set_memory(node, 0, 0);
                        return done(Status::Failure);
                    }
                    Status::Skipped => x.skipped = x.skipped.saturating_add(1),
                    Status::Running if c >= usize::from(x.ok) => {
                        self.set_memory(node, c as u16, 0);
                        return done(Status::Running);
                    }
                    Status::Success | Status::Running => {}
                }
                if more {
                    return Ok(Ascent::Tick(child_end));
                }
                self.reset_children(node, end)?;
                self.set_memory(node, 0, 0);
                done(if x.skipped == x.children { Status::Skipped } else { Status::Success })
            }
            FrameKind::Recovery => {
                let second = self.end_of(first)?;
                let retries = x.ok;
                let give_up = |run: &mut Self, v| {
                    run.reset_children(node, end)?;
                    run.set_memory(node, 0, 0);
                    done(v)
                };
                if x.failed == 0 {
                    match r {
                        Status::Skipped | Status::Success => give_up(self, r),
                        Status::Running => {
                            self.set_memory(node, top.a, 0);
                            done(Status::Running)
                        }
                        Status::Failure if top.a < retries => {
                            self.halt_child(first);
                            x.failed = 1;
                            Ok(Ascent::Tick(second))
                        }
                        Status::Failure => give_up(self, Status::Failure),
                    }
                } else {
                    match r {
                        Status::Skipped => {
                            // Nav2 leaves the count of recoveries as it is here.
                            self.halt_child(second);
                            self.set_memory(node, top.a, 0);
                            done(Status::Failure)
                        }
                        Status::Running => {
                            self.set_memory(node, top.a, 1);
                            done(Status::Running)
                        }
                        Status::Success => {
                            self.halt_child(second);
                            top.a = top.a.saturating_add(1);
                            x.failed = 0;
                            if top.a <= retries { Ok(Ascent::Tick(first)) } else { give_up(self, Status::Failure) }
                        }
                        Status::Failure => give_up(self, Status::Failure),
                    }
                }
            }
            FrameKind::RoundRobin => {
                if r != Status::Running {
                    x.ok = if x.ok.saturating_add(1) >= x.children { 0 } else { x.ok + 1 };
                }
                match r {
                    Status::Success => {
                        self.reset_children(node, end)?;
                        self.set_memory(node, x.ok, 0);
                        return done(Status::Success);
                    }
                    Status::Failure => x.failed = x.failed.saturating_add(1),
                    Status::Skipped => x.skipped = x.skipped.saturating_add(1),
                    Status::Running => {
                        self.set_memory(node, x.ok, x.failed as u8);
                        return done(Status::Running);
                    }
                }
                if x.failed.saturating_add(x.skipped) < x.children {
                    let (_, next) = self.children_of(node, end, x.ok)?;
                    return Ok(Ascent::Tick(next.ok_or(super::oob(node))?));
                }
                self.reset_children(node, end)?;
                self.set_memory(node, 0, 0);
                done(if x.skipped == x.children { Status::Skipped } else { Status::Failure })
            }
            FrameKind::RepeatCycles | FrameKind::RetryUntilSuccessful => {
                let again = if top.kind == FrameKind::RepeatCycles { Status::Success } else { Status::Failure };
                match r {
                    Status::Running => {
                        self.set_memory(node, top.a, 0);
                        done(Status::Running)
                    }
                    Status::Skipped => {
                        self.halt_child(first);
                        self.set_memory(node, top.a, 0);
                        done(Status::Skipped)
                    }
                    r if r == again => {
                        self.halt_child(first);
                        top.a = top.a.saturating_add(1);
                        if top.a < x.ok || x.ok == NodeKind::FOREVER {
                            if x.child_was_idle {
                                // BehaviorTree.CPP's wake-up: return, ask to be ticked
                                // again. A child that had been Running goes again now.
                                self.set_memory(node, top.a, 0);
                                self.side.woken = true;
                                return done(Status::Running);
                            }
                            x.child_was_idle = true;
                            return Ok(Ascent::Tick(first));
                        }
                        self.set_memory(node, 0, 0);
                        done(r)
                    }
                    r => {
                        self.halt_child(first);
                        self.set_memory(node, 0, 0);
                        done(r)
                    }
                }
            }
            FrameKind::KeepRunningUntilFailure => match r {
                Status::Failure => {
                    self.halt_child(first);
                    done(Status::Failure)
                }
                Status::Success => {
                    self.halt_child(first);
                    done(Status::Running)
                }
                Status::Running | Status::Skipped => done(Status::Running),
            },
            FrameKind::Guard => {
                if let Some(&NodeKind::Guard(table)) = self.nodes.get(node).map(Node::kind) {
                    self.guard_after(node, table, r, now)?;
                }
                // The guard now holds the node's result; the node is reset as its parent
                // in BehaviorTree.CPP resets a finished child: its status only.
                if matches!(r, Status::Success | Status::Failure) {
                    self.halt_child(first);
                }
                done(r)
            }
            FrameKind::Loop => {
                let taken = self.state.get(node).map_or(0, |s| s.aux);
                match r {
                    // The next element on the next tick.
                    Status::Success => {
                        self.halt_child(first);
                        self.set_memory(node, taken, 0);
                        done(Status::Running)
                    }
                    Status::Failure => {
                        self.halt_child(first);
                        self.set_memory(node, taken, 0);
                        done(Status::Failure)
                    }
                    Status::Running => {
                        self.set_memory(node, taken, 1);
                        done(Status::Running)
                    }
                    // Not finished, not Running: the next element on the next tick.
                    Status::Skipped => {
                        self.set_memory(node, taken, 0);
                        done(Status::Running)
                    }
                }
            }
            FrameKind::ManualSelector => {
                // BehaviorTree.CPP's node marks itself Running before it asks, so a child
                // that skips leaves it Running; when it repeats its last selection
                // without asking, it keeps its status (see `skipped_status`). Its
                // children keep what they returned, as BehaviorTree.CPP's do.
                if r == Status::Skipped && top.a == 1 {
                    self.set_status(node, NodeStatus::Running);
                }
                done(r)
            }
            FrameKind::Precondition => {
                if matches!(r, Status::Success | Status::Failure) {
                    self.set_memory(node, 0, 0);
                    self.halt_child(first);
                }
                done(r)
            }
            FrameKind::RunOnce => {
                if matches!(r, Status::Success | Status::Failure) {
                    self.set_memory(node, if r == Status::Success { 1 } else { 2 }, 0);
                    self.halt_child(first);
                }
                done(r)
            }
            FrameKind::RateController => {
                if r == Status::Success {
                    self.set_start(node, now);
                }
                if matches!(r, Status::Success | Status::Failure) {
                    self.halt_child(first);
                }
                done(r)
            }
            FrameKind::TimeLimit | FrameKind::Delay | FrameKind::Gate => {
                if matches!(r, Status::Success | Status::Failure) {
                    self.halt_child(first);
                }
                done(r)
            }
            _ => Err(super::oob(node)),
        }
    }
}
