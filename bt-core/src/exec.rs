//! The executor: iterative, with an explicit stack of `DEPTH` frames, over caller-owned
//! per-node state. No recursion, no allocation, each node visited at most once per tick.
//!
//! # Tick semantics
//!
//! 1. Statuses are Success, Failure, Running. A condition returning Running is reported
//!    as [`TickError::ConditionRunning`].
//! 2. Reactive `Sequence` ticks children from the first and returns the first Failure or
//!    Running, Success when all succeed; `Fallback` mirrors it.
//! 3. A node that was Running and is not reached, or is reached and abandoned, is halted:
//!    each Running action below it gets one `halt` call, children before parents and left
//!    to right (post-order), and the subtree's state goes back to Idle.
//! 4. Halt before start: before an action *starts* (it was not Running), every Running
//!    branch that it preempts — a later child of a reactive ancestor that was Running on
//!    the previous tick — is halted. If the tick returns to the old branch without
//!    starting an action, the old branch keeps running and is never halted.
//! 5. When the root returns Success or Failure, the next tick starts a new activation:
//!    memory, counters and parallel results are only kept for nodes that are Running.
//! 6. With-memory nodes resume at the child that was Running. `Parallel` does not re-tick
//!    children that finished in the current activation, and returns as soon as a
//!    threshold is reached, halting the children still Running.
//! 7. `Repeat`, `Retry` and `Timeout` count ticks and activations; `now` is only passed on
//!    to behaviors.
//!
//! After a tick, a node's status is what it returned when last ticked in the current
//! activation of its parent, and `Idle` for nodes that were halted or left behind:
//! children of a Sequence/Fallback after the one it returned at are reset, so what a
//! renderer shows is what happened.

use crate::behavior::{BehaviorSet, Context, Observer, TickError};
use crate::node::{Node, NodeId, NodeKind};
use crate::status::{NodeStatus, Status};
use crate::tree::Tree;

/// The runtime state of one node, kept by the caller in an array parallel to the nodes.
/// 4 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct NodeState {
    status: NodeStatus,
    /// Sequence/Fallback (with or without memory): the child it returned at when last
    /// ticked (children after it are Idle). Repeat/Retry/Timeout: the count. Else unused.
    aux: u16,
}

impl NodeState {
    /// The state of a node that has not been ticked; fill storage with it.
    pub const IDLE: NodeState = NodeState { status: NodeStatus::Idle, aux: 0 };

    /// What the node returned when last ticked, or Idle.
    #[inline(always)]
    #[must_use]
    pub const fn status(&self) -> NodeStatus {
        self.status
    }
}

/// The state array is shorter than the tree.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("state array holds {given} entries, the tree has {needed} nodes")]
pub struct StateTooSmall {
    /// Entries needed (the tree's node count).
    pub needed: usize,
    /// Entries given.
    pub given: usize,
}

#[derive(Clone, Copy, Debug, Default)]
struct Frame {
    /// The control node or decorator.
    node: u16,
    /// One past its last descendant.
    end: u16,
    /// Sequence/Fallback: the child returned at last time (0: none). Decorators: the
    /// count so far. Parallel: successes.
    a: u16,
    /// Parallel: failures.
    b: u16,
    /// Parallel: number of children.
    c: u16,
    /// The node was Running when the tick reached it (not a new activation).
    running: bool,
}

/// Ticks one validated tree against a behavior set.
///
/// Holds the stack (`DEPTH` frames) between ticks so a tick initializes nothing; the
/// per-node state lives in the caller's array.
#[derive(Debug)]
pub struct Executor<'t, 's, const DEPTH: usize> {
    tree: Tree<'t, DEPTH>,
    state: &'s mut [NodeState],
    frames: [Frame; DEPTH],
    halt_stack: [u16; DEPTH],
}

impl<'t, 's, const DEPTH: usize> Executor<'t, 's, DEPTH> {
    /// An executor over `tree` using `state` (at least one entry per node), which it
    /// resets to Idle.
    ///
    /// # Errors
    /// [`StateTooSmall`] when `state` has fewer entries than the tree has nodes.
    pub fn new(tree: Tree<'t, DEPTH>, state: &'s mut [NodeState]) -> Result<Self, StateTooSmall> {
        if state.len() < tree.len() {
            return Err(StateTooSmall { needed: tree.len(), given: state.len() });
        }
        state.fill(NodeState::IDLE);
        Ok(Self { tree, state, frames: [Frame::default(); DEPTH], halt_stack: [0; DEPTH] })
    }

    /// The tree being ticked.
    #[must_use]
    pub fn tree(&self) -> Tree<'t, DEPTH> {
        self.tree
    }

    /// The per-node states, parallel to the tree's nodes.
    #[must_use]
    pub fn states(&self) -> &[NodeState] {
        self.state.get(..self.tree.len()).unwrap_or(&[])
    }

    /// The status of node `id`.
    #[must_use]
    pub fn status(&self, id: NodeId) -> Option<NodeStatus> {
        self.states().get(usize::from(id)).map(NodeState::status)
    }

    /// Ticks the tree once.
    ///
    /// # Errors
    /// [`TickError`] when a behavior breaks the rules; the tree is then halted
    /// ([`Executor::halt_all`]) before returning.
    #[inline]
    pub fn tick<B: BehaviorSet>(&mut self, behaviors: &mut B, now: u32) -> Result<Status, TickError> {
        self.tick_observed(behaviors, now, &mut ())
    }

    /// Ticks the tree once, reporting every status change to `observer`.
    ///
    /// # Errors
    /// As [`Executor::tick`].
    pub fn tick_observed<B: BehaviorSet, O: Observer>(
        &mut self,
        behaviors: &mut B,
        now: u32,
        observer: &mut O,
    ) -> Result<Status, TickError> {
        let mut run = Run {
            nodes: self.tree.nodes(),
            state: self.state,
            halt_stack: &mut self.halt_stack,
            behaviors,
            observer,
        };
        let result = run.tick(&mut self.frames, now);
        if result.is_err() {
            // Mid-tick, nodes on the path have not taken their new status yet: scan all.
            run.reset(0, Scan::All);
        }
        result
    }

    /// Halts every Running action (post-order) and resets the whole tree to Idle.
    pub fn halt_all<B: BehaviorSet>(&mut self, behaviors: &mut B) {
        self.halt_all_observed(behaviors, &mut ());
    }

    /// As [`Executor::halt_all`], reporting status changes to `observer`.
    pub fn halt_all_observed<B: BehaviorSet, O: Observer>(&mut self, behaviors: &mut B, observer: &mut O) {
        let mut run = Run {
            nodes: self.tree.nodes(),
            state: self.state,
            halt_stack: &mut self.halt_stack,
            behaviors,
            observer,
        };
        run.reset(0, Scan::All);
    }
}

/// Which nodes [`Run::reset`] visits.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Scan {
    /// Skip subtrees whose root is Idle (their nodes are all Idle): between ticks, and
    /// mid-tick for subtrees off the current path.
    SkipIdle,
    /// Every node: when the state may not be consistent (a tick stopped half-way).
    All,
}

/// The borrowed pieces of one tick, split so that the hot loop sees plain slices.
struct Run<'r, B, O, const DEPTH: usize> {
    nodes: &'r [Node],
    state: &'r mut [NodeState],
    halt_stack: &'r mut [u16; DEPTH],
    behaviors: &'r mut B,
    observer: &'r mut O,
}

const fn oob(node: usize) -> TickError {
    TickError::OutOfRange { node }
}

impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH> {
    #[inline(always)]
    fn node(&self, i: usize) -> Result<&Node, TickError> {
        self.nodes.get(i).ok_or(oob(i))
    }

    #[inline(always)]
    fn status(&self, i: usize) -> NodeStatus {
        self.state.get(i).map_or(NodeStatus::Idle, NodeState::status)
    }

    #[inline(always)]
    fn set_status(&mut self, i: usize, new: NodeStatus) {
        if let Some(s) = self.state.get_mut(i) {
            let old = s.status;
            s.status = new;
            if O::ENABLED && old != new {
                self.observer.on_change(i as NodeId, old, new);
            }
        }
    }

    #[inline(always)]
    fn set_aux(&mut self, i: usize, aux: u16) {
        if let Some(s) = self.state.get_mut(i) {
            s.aux = aux;
        }
    }

    #[inline(always)]
    fn end_of(&self, i: usize) -> Result<usize, TickError> {
        Ok(i + usize::from(self.node(i)?.size()))
    }

    /// One tick from the root. Frames `0..sp` are the path from the root to the parent
    /// of node `idx`.
    #[inline(always)]
    fn tick(&mut self, frames: &mut [Frame; DEPTH], now: u32) -> Result<Status, TickError> {
        let mut sp = 0usize;
        let mut idx = 0usize;
        'enter: loop {
            let node = *self.node(idx)?;
            let st = self.state.get(idx).copied().unwrap_or_default();
            let running = st.status == NodeStatus::Running;
            let mut result = match *node.kind() {
                NodeKind::Condition(leaf) => {
                    let ctx = Context { node: idx as NodeId, now, starting: true };
                    let r = self.behaviors.condition(&leaf, ctx);
                    if r == Status::Running {
                        return Err(TickError::ConditionRunning { node: idx as NodeId, behavior: leaf.behavior() });
                    }
                    r
                }
                NodeKind::Action(leaf) => {
                    if !running {
                        self.preempt(frames, sp, idx)?;
                    }
                    let ctx = Context { node: idx as NodeId, now, starting: !running };
                    self.behaviors.action(&leaf, ctx)
                }
                _ => match self.enter(frames, sp, idx, node, st)? {
                    Entered::Child(first) => {
                        sp += 1;
                        idx = first;
                        continue 'enter;
                    }
                    Entered::Decided(r) => r,
                },
            };

            // Ascend: deliver `result` of node `idx` to its parent frames.
            loop {
                self.set_status(idx, result.into());
                if sp == 0 {
                    return Ok(result);
                }
                let Some(f) = frames.get(sp - 1).copied() else {
                    return Err(oob(idx));
                };
                let parent = usize::from(f.node);
                let next = self.end_of(idx)?;
                let more = next < usize::from(f.end);
                match *self.node(parent)?.kind() {
                    NodeKind::Sequence | NodeKind::SequenceWithMemory => {
                        if result == Status::Success && more {
                            idx = next;
                            continue 'enter;
                        }
                        self.finish_ordered(&f, idx, next)?;
                    }
                    NodeKind::Fallback | NodeKind::FallbackWithMemory => {
                        if result == Status::Failure && more {
                            idx = next;
                            continue 'enter;
                        }
                        self.finish_ordered(&f, idx, next)?;
                    }
                    kind @ NodeKind::Parallel { .. } => {
                        let mut f = f;
                        match result {
                            Status::Success => f.a = f.a.saturating_add(1),
                            Status::Failure => f.b = f.b.saturating_add(1),
                            Status::Running => {}
                        }
                        let step = match parallel_verdict(&f, kind) {
                            Some(v) => ParStep::Done(v, next),
                            None => self.parallel_step(&mut f, next, kind)?,
                        };
                        if let Some(slot) = frames.get_mut(sp - 1) {
                            *slot = f;
                        }
                        match step {
                            ParStep::Tick(c) => {
                                idx = c;
                                continue 'enter;
                            }
                            ParStep::Done(v, reached) => {
                                if v != Status::Running {
                                    self.finish_parallel(&f, reached)?;
                                }
                                result = v;
                            }
                        }
                    }
                    NodeKind::Inverter => {
                        result = match result {
                            Status::Success => Status::Failure,
                            Status::Failure => Status::Success,
                            Status::Running => Status::Running,
                        };
                    }
                    NodeKind::ForceSuccess => {
                        if result == Status::Failure {
                            result = Status::Success;
                        }
                    }
                    NodeKind::ForceFailure => {
                        if result == Status::Success {
                            result = Status::Failure;
                        }
                    }
                    NodeKind::Repeat(n) => {
                        if result == Status::Success {
                            let count = f.a.saturating_add(1);
                            if count < n {
                                self.set_aux(parent, count);
                                result = Status::Running;
                            }
                        } else if result == Status::Running {
                            self.set_aux(parent, f.a);
                        }
                    }
                    NodeKind::Retry(n) => {
                        if result == Status::Failure {
                            let count = f.a.saturating_add(1);
                            if count < n {
                                self.set_aux(parent, count);
                                result = Status::Running;
                            }
                        } else if result == Status::Running {
                            self.set_aux(parent, f.a);
                        }
                    }
                    NodeKind::Timeout(n) => {
                        if result == Status::Running {
                            let count = f.a.saturating_add(1);
                            if count >= n {
                                self.reset_subtree(idx);
                                result = Status::Failure;
                            } else {
                                self.set_aux(parent, count);
                            }
                        }
                    }
                    NodeKind::Condition(_) | NodeKind::Action(_) => return Err(oob(parent)),
                }
                sp -= 1;
                idx = parent;
            }
        }
    }

    /// Enters control node or decorator `idx`: pushes its frame at `sp` and says which
    /// child to tick first, or, for a parallel whose children all finished, its verdict.
    #[inline(always)]
    fn enter(
        &mut self,
        frames: &mut [Frame; DEPTH],
        sp: usize,
        idx: usize,
        node: Node,
        st: NodeState,
    ) -> Result<Entered, TickError> {
        let running = st.status == NodeStatus::Running;
        let end = idx + usize::from(node.size());
        let mut frame = Frame { node: idx as u16, end: end as u16, a: 0, b: 0, c: 0, running };
        let mut first = idx + 1;
        match *node.kind() {
            NodeKind::Sequence | NodeKind::Fallback => {
                if st.status != NodeStatus::Idle {
                    frame.a = st.aux;
                }
            }
            NodeKind::SequenceWithMemory | NodeKind::FallbackWithMemory => {
                if st.status != NodeStatus::Idle {
                    frame.a = st.aux;
                }
                if running {
                    first = usize::from(st.aux);
                }
            }
            kind @ NodeKind::Parallel { .. } => {
                let mut c = idx + 1;
                while c < end {
                    frame.c = frame.c.saturating_add(1);
                    c = self.end_of(c)?;
                }
                match self.parallel_step(&mut frame, idx + 1, kind)? {
                    ParStep::Tick(c) => first = c,
                    ParStep::Done(v, reached) => {
                        // Children that finished earlier in this activation reach a
                        // threshold on their own; or (impossible: a Running parallel has a
                        // Running child) every child finished without a verdict.
                        let v = if v == Status::Running { Status::Failure } else { v };
                        self.finish_parallel(&frame, reached)?;
                        return Ok(Entered::Decided(v));
                    }
                }
            }
            NodeKind::Repeat(_) | NodeKind::Retry(_) | NodeKind::Timeout(_) => {
                if running {
                    frame.a = st.aux;
                }
            }
            NodeKind::Inverter | NodeKind::ForceSuccess | NodeKind::ForceFailure => {}
            NodeKind::Condition(_) | NodeKind::Action(_) => return Err(oob(idx)),
        }
        let Some(slot) = frames.get_mut(sp) else {
            return Err(oob(idx));
        };
        *slot = frame;
        Ok(Entered::Child(first))
    }

    /// A Sequence or Fallback (either flavour) returns at child `child`, whose subtree
    /// ends at `next`: reset the children it reached last time beyond `child`, remember
    /// `child`.
    #[inline(always)]
    fn finish_ordered(&mut self, f: &Frame, child: usize, next: usize) -> Result<(), TickError> {
        let last = usize::from(f.a);
        if last > child {
            let mut c = next;
            while c <= last && c < usize::from(f.end) {
                let after = self.end_of(c)?;
                self.reset_subtree(c);
                c = after;
            }
        }
        self.set_aux(usize::from(f.node), child as u16);
        Ok(())
    }

    /// The next child of a parallel to tick, from `from` on. Children that finished in
    /// the current activation (the parallel was Running) are counted, not ticked, and
    /// may reach a threshold on their own: then the verdict and where counting stopped.
    /// Past the last child without a verdict: Running.
    fn parallel_step(&mut self, f: &mut Frame, from: usize, kind: NodeKind) -> Result<ParStep, TickError> {
        let mut c = from;
        while c < usize::from(f.end) {
            if !f.running {
                return Ok(ParStep::Tick(c));
            }
            match self.status(c) {
                NodeStatus::Success => f.a = f.a.saturating_add(1),
                NodeStatus::Failure => f.b = f.b.saturating_add(1),
                NodeStatus::Running | NodeStatus::Idle => return Ok(ParStep::Tick(c)),
            }
            let after = self.end_of(c)?;
            if let Some(v) = parallel_verdict(f, kind) {
                return Ok(ParStep::Done(v, after));
            }
            c = after;
        }
        Ok(ParStep::Done(Status::Running, usize::from(f.end)))
    }

    /// A parallel decided: halt its Running children and reset those not reached.
    fn finish_parallel(&mut self, f: &Frame, reached: usize) -> Result<(), TickError> {
        let mut c = usize::from(f.node) + 1;
        while c < usize::from(f.end) {
            let after = self.end_of(c)?;
            if c >= reached || self.status(c) == NodeStatus::Running {
                self.reset_subtree(c);
            }
            c = after;
        }
        Ok(())
    }

    /// Rule 4: action `idx` is about to start. Halt every branch it preempts: for each
    /// reactive ancestor on the path that was Running at a later child than the one
    /// being ticked, that child's subtree. Innermost first.
    fn preempt(&mut self, frames: &[Frame; DEPTH], sp: usize, idx: usize) -> Result<(), TickError> {
        let mut current = idx;
        let mut k = sp;
        while k > 0 {
            k -= 1;
            let Some(f) = frames.get(k) else { return Err(oob(idx)) };
            let parent = usize::from(f.node);
            if f.running && matches!(self.node(parent)?.kind(), NodeKind::Sequence | NodeKind::Fallback) {
                let old = usize::from(f.a);
                if old > current {
                    self.reset_subtree(old);
                }
            }
            current = parent;
        }
        Ok(())
    }

    /// Halts the Running actions under `root` (post-order) and resets the subtree to
    /// Idle. Skips subtrees that are already Idle.
    #[inline]
    fn reset_subtree(&mut self, root: usize) {
        if self.status(root) != NodeStatus::Idle {
            self.reset(root, Scan::SkipIdle);
        }
    }

    /// Halts the Running actions under `root` in post-order (children before parents,
    /// left to right) and sets every node of the subtree to Idle.
    fn reset(&mut self, root: usize, scan: Scan) {
        let Ok(end) = self.end_of(root) else { return };
        let mut top = 0usize;
        let mut i = root;
        loop {
            // Close the open ancestors whose subtree ends here.
            while let Some(a) = top.checked_sub(1).and_then(|t| self.halt_stack.get(t)).map(|&a| usize::from(a)) {
                match self.end_of(a) {
                    Ok(a_end) if a_end <= i => {
                        top -= 1;
                        self.set_status(a, NodeStatus::Idle);
                    }
                    _ => break,
                }
            }
            if i >= end {
                break;
            }
            let Some(node) = self.nodes.get(i).copied() else { break };
            if scan == Scan::SkipIdle && self.status(i) == NodeStatus::Idle {
                i += usize::from(node.size()).max(1);
                continue;
            }
            match node.kind() {
                NodeKind::Action(leaf) => {
                    if self.status(i) == NodeStatus::Running {
                        self.behaviors.halt(leaf, i as NodeId);
                    }
                    self.set_status(i, NodeStatus::Idle);
                }
                NodeKind::Condition(_) => self.set_status(i, NodeStatus::Idle),
                _ => match self.halt_stack.get_mut(top) {
                    Some(slot) => {
                        *slot = i as u16;
                        top += 1;
                    }
                    // Deeper than DEPTH: impossible for a validated tree.
                    None => self.set_status(i, NodeStatus::Idle),
                },
            }
            i += 1;
        }
    }
}

enum Entered {
    Child(usize),
    Decided(Status),
}

enum ParStep {
    /// Tick this child next.
    Tick(usize),
    /// The parallel returns this; children from the index on were not reached.
    Done(Status, usize),
}

/// Success or Failure once a parallel's thresholds decide, else `None`.
#[inline]
fn parallel_verdict(f: &Frame, kind: NodeKind) -> Option<Status> {
    let NodeKind::Parallel { success_threshold, failure_threshold } = kind else {
        return None;
    };
    if f.a >= success_threshold {
        Some(Status::Success)
    } else if f.b >= failure_threshold || f.c.saturating_sub(f.b) < success_threshold {
        Some(Status::Failure)
    } else {
        None
    }
}
