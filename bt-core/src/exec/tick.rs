//! The tick loop: down the tree to a leaf or a node that decides, then back up through
//! the frames, until the root returns. Iterative, over the explicit stack of
//! `frame.rs`; each node visited at most once.
//!
//! The loop itself ticks leaves and reactive Sequences and Fallbacks, the hot path (their
//! helpers are in `ordered.rs`), and ascends through their frames; every other kind is
//! entered and ascended by its family, out of line ([`Run::enter_other`],
//! [`Run::ascend_other`]).
//!
//! The loop is one function on purpose. Split into functions, even ones always inlined,
//! the compiler allocates its registers differently and the plain loop took 5 to 30 %
//! more instructions per tick on the benchmark trees (`benches/trees`); so it is one
//! function in three parts: the node, the child loop of a reactive Sequence or Fallback,
//! and the way up.

#[cfg(feature = "btcpp")]
use super::btcpp::Entering;
use super::frame::{Ascent, Entered, Extra, Frame, FrameKind, Returned};
#[cfg(feature = "btcpp")]
use super::halting::Scan;
use super::run::Run;
use super::{BTCPP, NodeState, oob};
use crate::behavior::{BehaviorSet, Context, Observer, TickError};
use crate::node::{Leaf, NodeId, NodeKind};
use crate::status::{NodeStatus, Status};

impl<B: BehaviorSet, O: Observer, const DEPTH: usize, const FULL: bool> Run<'_, B, O, DEPTH, FULL> {
    /// Ticks from node `c` until the tick is over, `frames[..depth]` being the path from
    /// the root to its parent (a tick from the root starts at 0 and 0).
    ///
    /// `extra[d]` belongs to the frame at depth `d` when it is a Parallel or a counting
    /// decorator. While a reactive Sequence or Fallback ticks its children in place, its
    /// index is in `frames[depth].node`, the frame it pushes if a child needs one.
    #[inline(always)]
    pub(super) fn run_loop(
        &mut self,
        frames: &mut [Frame; DEPTH],
        extra: &mut [Extra; DEPTH],
        now: u32,
        mut depth: usize,
        mut c: usize,
        pending: Option<Returned>,
    ) -> Result<Status, TickError> {
        let nodes = self.nodes;
        let values = self.values;
        let mut pending = pending;
        'descend: loop {
            let (r, child_end) = if let Some(returned) = pending.take() {
                // The full loop taking over from the plain one: a leaf returned.
                c = returned.node;
                (returned.r, returned.end)
            } else {
                let Some(node) = nodes.get(c) else {
                    return Err(oob(c));
                };
                // Tick node `c`: a leaf returns at once; a control node or decorator pushes a
                // frame and descends into a child, or decides without one.
                match node.kind() {
                    NodeKind::Condition(leaf) => {
                        let r =
                            self.behaviors.condition(leaf, Context { node: c as NodeId, now, starting: true, values });
                        // Running or Skipped.
                        if r as u8 >= Status::Running as u8 {
                            if !BTCPP {
                                return Err(leaf_error(c, leaf, r));
                            }
                            match self.cold().leaf_odd(frames, extra, now, depth, c, leaf, r)? {
                                Some(done) => return Ok(done),
                                None => (Status::Skipped, c + 1),
                            }
                        } else {
                            self.set_status(c, r.into());
                            (r, c + 1)
                        }
                    }
                    NodeKind::Action(leaf) => {
                        let starting = self.status(c) != NodeStatus::Running;
                        if starting {
                            self.cold().preempt(frames, depth, c);
                        }
                        let r = self.behaviors.action(leaf, Context { node: c as NodeId, now, starting, values });
                        if r == Status::Running {
                            if !starting && self.still_running {
                                return Ok(r);
                            }
                        } else if !FULL && r == Status::Skipped {
                            if !BTCPP {
                                return Err(leaf_error(c, leaf, r));
                            }
                            if let Some(done) = self.cold().leaf_odd(frames, extra, now, depth, c, leaf, r)? {
                                return Ok(done);
                            }
                        }
                        self.set_status(c, r.into());
                        (r, c + 1)
                    }
                    kind @ (NodeKind::Sequence | NodeKind::Fallback) => 'ordered: {
                        // Ticks the leading leaf children in place: a frame is pushed only
                        // when a child is itself a control node or decorator. The node's
                        // state stays as the tick found it until it returns, so what the
                        // frame and the return need of it is read then, not kept in
                        // registers through the loop.
                        let mut end = c + usize::from(node.size());
                        let mut go_on =
                            if matches!(kind, NodeKind::Fallback) { Status::Failure } else { Status::Success };
                        let mut k = c + 1;
                        // The node being ticked is kept in the frame it would push, not in a
                        // register through the loop.
                        Self::ticking(frames, depth, c)?;
                        loop {
                            let Some(child) = nodes.get(k) else {
                                return Err(oob(k));
                            };
                            let r = match child.kind() {
                                NodeKind::Condition(leaf) => {
                                    let r = self
                                        .behaviors
                                        .condition(leaf, Context { node: k as NodeId, now, starting: true, values });
                                    // Running or Skipped: an error, or on under a frame.
                                    if r as u8 >= Status::Running as u8 {
                                        if !BTCPP {
                                            return Err(leaf_error(k, leaf, r));
                                        }
                                        let odd = Odd { k, end, go_on, r };
                                        if let Some(done) =
                                            self.cold().child_odd(frames, extra, now, depth, leaf, odd)?
                                        {
                                            return Ok(done);
                                        }
                                        depth += 1;
                                        c = k;
                                        break 'ordered (Status::Skipped, k + 1);
                                    }
                                    r
                                }
                                NodeKind::Action(leaf) if self.status(k) == NodeStatus::Running => {
                                    let r = self
                                        .behaviors
                                        .action(leaf, Context { node: k as NodeId, now, starting: false, values });
                                    if r == Status::Running {
                                        if self.still_running {
                                            return Ok(r);
                                        }
                                    } else if r == Status::Skipped {
                                        if !BTCPP {
                                            return Err(leaf_error(k, leaf, r));
                                        }
                                        let odd = Odd { k, end, go_on, r };
                                        if let Some(done) =
                                            self.cold().child_odd(frames, extra, now, depth, leaf, odd)?
                                        {
                                            return Ok(done);
                                        }
                                        depth += 1;
                                        c = k;
                                        break 'ordered (Status::Skipped, k + 1);
                                    }
                                    r
                                }
                                // A control child, or an action about to start (rule 4 may
                                // halt others first): ticked on the general path, under a
                                // frame for this node.
                                child_kind => {
                                    let child_end = k + usize::from(child.size());
                                    Self::push_ordered(frames, depth, end, go_on, child_end >= end)?;
                                    depth += 1;
                                    // A reactive Sequence or Fallback child is ticked by this
                                    // same loop, without going back to the dispatch above.
                                    match child_kind {
                                        NodeKind::Sequence => go_on = Status::Success,
                                        NodeKind::Fallback => go_on = Status::Failure,
                                        _ => {
                                            c = k;
                                            continue 'descend;
                                        }
                                    }
                                    Self::ticking(frames, depth, k)?;
                                    end = child_end;
                                    k += 1;
                                    continue;
                                }
                            };
                            self.set_status(k, r.into());
                            if r == go_on && k + 1 < end {
                                k += 1;
                                continue;
                            }
                            c = frames.get(depth).map_or(0, |f| usize::from(f.node));
                            // Returns at child `k`: reset the children it reached last
                            // time beyond `k`.
                            self.finish_ordered(c, end, k, k + 1, r)?;
                            // Its parent goes on to the next child, a reactive Sequence or
                            // Fallback: ticked by this loop at once (the way back would
                            // come to the same).
                            if let Some(f) = depth.checked_sub(1).and_then(|top| frames.get(top))
                                && f.kind.is_ordered()
                                && r == f.kind.goes_on_after()
                                && end < usize::from(f.end)
                                && let Some(next) = nodes.get(end)
                            {
                                go_on = match next.kind() {
                                    NodeKind::Sequence => Status::Success,
                                    NodeKind::Fallback => Status::Failure,
                                    _ => break 'ordered (r, end),
                                };
                                Self::ticking(frames, depth, end)?;
                                k = end + 1;
                                end += usize::from(next.size());
                                continue;
                            }
                            break 'ordered (r, end);
                        }
                    }
                    kind => 'enter: {
                        let parent_mirrors = FULL
                            && depth.checked_sub(1).and_then(|d| frames.get(d)).is_some_and(|f| f.kind.mirrors_btcpp());
                        let Some(slot) = frames.get_mut(depth) else {
                            return Err(oob(c));
                        };
                        let st = self.state.get(c).copied().unwrap_or_default();
                        let end = c + usize::from(node.size());
                        *slot = Frame {
                            node: c as u16,
                            end: end as u16,
                            a: 0,
                            kind: FrameKind::Sequence,
                            running: st.status == NodeStatus::Running,
                        };
                        let Some(x) = extra.get_mut(depth) else {
                            return Err(oob(c));
                        };
                        let first = match self.cold().enter_other(
                            kind,
                            st,
                            slot,
                            x,
                            parent_mirrors,
                            if FULL { now } else { 0 },
                        )? {
                            Entered::Child(first) => first,
                            Entered::Decided(v) => {
                                #[cfg(feature = "btcpp")]
                                if FULL && v == Status::Skipped {
                                    self.full().decided_skipped(c);
                                    break 'enter (v, end);
                                }
                                self.set_status(c, v.into());
                                break 'enter (v, end);
                            }
                        };
                        depth += 1;
                        c = first;
                        continue 'descend;
                    }
                }
            };
            let mut r = r;
            let mut child_end = child_end;
            // Ascend: node `c` (ending at `child_end`) returned `r` to the frame at
            // `depth - 1`.
            while let Some(top) = depth.checked_sub(1) {
                let Some(f) = frames.get(top) else {
                    return Err(oob(c));
                };
                if f.kind == FrameKind::Last {
                    // Its subtree ends where its last child's does.
                    let node = usize::from(f.node);
                    if FULL && r == Status::Skipped {
                        r = self.cold().last_skipped(node, c)?;
                    } else {
                        self.set_state(node, r.into(), c as u16);
                    }
                    c = node;
                    depth = top;
                    continue;
                }
                let f = *f;
                let more = child_end < usize::from(f.end);
                if f.kind.is_ordered() {
                    // Sequence goes on after Success, Fallback after Failure.
                    if r == f.kind.goes_on_after() && more {
                        c = child_end;
                        continue 'descend;
                    }
                    if FULL && r == Status::Skipped {
                        match self.cold().ordered_skipped(&f, c, child_end)? {
                            Ascent::Tick(next) => {
                                c = next;
                                continue 'descend;
                            }
                            Ascent::Return(v) => r = v,
                        }
                    } else {
                        if FULL && f.kind.is_memory() && r != Status::Running {
                            self.cold().reset_running(usize::from(f.node) + 1, c);
                        }
                        self.finish_ordered(usize::from(f.node), usize::from(f.end), c, child_end, r)?;
                    }
                } else {
                    match self.cold().ascend_other(frames, extra, top, c, child_end, r, if FULL { now } else { 0 })? {
                        Ascent::Tick(next) => {
                            c = next;
                            continue 'descend;
                        }
                        Ascent::Return(v) => r = v,
                    }
                    self.set_returned(usize::from(f.node), r);
                }
                // The frame's node returns `r` to the frame below.
                c = usize::from(f.node);
                child_end = usize::from(f.end);
                depth = top;
            }
            return Ok(r);
        }
    }

    /// Leaf child `odd.k` of the reactive Sequence or Fallback that the child loop ticks
    /// at `depth` returned Running (a condition) or Skipped: [`Run::leaf_odd`], under the
    /// frame the node pushes for it.
    #[cold]
    #[inline(never)]
    fn child_odd(
        &mut self,
        frames: &mut [Frame; DEPTH],
        extra: &mut [Extra; DEPTH],
        now: u32,
        depth: usize,
        leaf: &Leaf,
        odd: Odd,
    ) -> Result<Option<Status>, TickError> {
        let Odd { k, end, go_on, r } = odd;
        Self::push_ordered(frames, depth, end, go_on, k + 1 >= end)?;
        self.leaf_odd(frames, extra, now, depth + 1, k, leaf, r)
    }

    /// Leaf `c`, under the frame at `depth - 1`, returned a status it may not: Running
    /// from a condition breaks rule 1 ([`leaf_error`]); Skipped (rule 8) leaves the leaf
    /// Idle, and its parent goes on as the full loop says: `None` in the full loop
    /// (ascend with Skipped), the tick's result in the plain one, which hands the rest of
    /// the tick to the full loop.
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn leaf_odd(
        &mut self,
        frames: &mut [Frame; DEPTH],
        extra: &mut [Extra; DEPTH],
        now: u32,
        depth: usize,
        c: usize,
        leaf: &Leaf,
        r: Status,
    ) -> Result<Option<Status>, TickError> {
        #[cfg(not(feature = "btcpp"))]
        {
            let _ = (frames, extra, now, depth);
            Err(leaf_error(c, leaf, r))
        }
        #[cfg(feature = "btcpp")]
        {
            if r == Status::Running {
                return Err(leaf_error(c, leaf, r));
            }
            self.set_status(c, NodeStatus::Idle);
            if FULL {
                return Ok(None);
            }
            // The plain loop knows nothing of Skipped: the full loop takes over at the
            // frame the leaf returns to, for the rest of this tick and every later one.
            self.side.full = true;
            let returned = Returned { node: c, end: c + 1, r };
            self.full().run_full(frames, extra, now, depth, Some(returned)).map(Some)
        }
    }

    /// Enters a node other than a leaf or a reactive Sequence or Fallback: its family
    /// fills in its frame and side entry, and says which child to tick first.
    #[cold]
    #[inline(never)]
    fn enter_other(
        &mut self,
        kind: &NodeKind,
        st: NodeState,
        frame: &mut Frame,
        x: &mut Extra,
        parent_mirrors: bool,
        now: u32,
    ) -> Result<Entered, TickError> {
        // The papers' families by kind: the lean dispatch a controller's flash wants.
        match *kind {
            NodeKind::SequenceWithMemory | NodeKind::FallbackWithMemory => Ok(self.enter_memory(kind, st, frame)),
            NodeKind::Parallel { success_threshold, failure_threshold, count_skipped } => {
                self.enter_parallel(success_threshold, failure_threshold, count_skipped, frame, x)
            }
            NodeKind::Inverter
            | NodeKind::ForceSuccess
            | NodeKind::ForceFailure
            | NodeKind::Repeat(_)
            | NodeKind::Retry(_)
            | NodeKind::Timeout(_) => Ok(self.enter_decorator(kind, st, frame, x)),
            // The tick loop's own.
            NodeKind::Sequence | NodeKind::Fallback | NodeKind::Condition(_) | NodeKind::Action(_) => {
                Err(oob(usize::from(frame.node)))
            }
            #[cfg(feature = "btcpp")]
            _ if FULL => self.full().enter_btcpp(Entering { kind, st, frame, x, parent_mirrors, now }),
            // The plain loop runs no other kind.
            _ => {
                let _ = (parent_mirrors, now);
                Err(oob(usize::from(frame.node)))
            }
        }
    }

    /// Child `c` (its subtree ending at `child_end`) returned `r` to the frame at
    /// `depth`, neither a Sequence nor a Fallback: its family ticks another child, or says
    /// what the frame's node returns.
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn ascend_other(
        &mut self,
        frames: &mut [Frame; DEPTH],
        extra: &mut [Extra; DEPTH],
        depth: usize,
        c: usize,
        child_end: usize,
        r: Status,
        now: u32,
    ) -> Result<Ascent, TickError> {
        let returned = Returned { node: c, end: child_end, r };
        let (Some(top), Some(x)) = (frames.get_mut(depth), extra.get_mut(depth)) else {
            return Err(oob(returned.node));
        };
        match top.kind {
            FrameKind::Parallel => self.ascend_parallel(top, x, returned),
            #[cfg(feature = "btcpp")]
            FrameKind::Btcpp if FULL => self.full().ascend_btcpp(top, x, returned, now),
            FrameKind::Btcpp => {
                let _ = now;
                Err(oob(returned.node))
            }
            _ => Ok(Ascent::Return(self.ascend_decorator(top, x, returned))),
        }
    }
}

/// What a leaf that returned a status it may not is: a condition that returned Running
/// (rule 1), or a leaf that returned Skipped in a build without the `btcpp` feature,
/// which leaves Skipped out of the tick loop: its paths cost a controller's flash.
#[cold]
#[inline(never)]
fn leaf_error(node: usize, leaf: &Leaf, r: Status) -> TickError {
    let (node, behavior) = (node as NodeId, leaf.behavior());
    if r == Status::Running {
        TickError::ConditionRunning { node, behavior }
    } else {
        TickError::LeafSkipped { node, behavior }
    }
}

/// A leaf child of the node the child loop ticks returned a status it may not.
struct Odd {
    /// The child.
    k: usize,
    /// One past the node's subtree.
    end: usize,
    /// The status after which the node goes on.
    go_on: Status,
    /// What the child returned.
    r: Status,
}

#[cfg(feature = "btcpp")]
impl<B: BehaviorSet, O: Observer, const DEPTH: usize> Run<'_, B, O, DEPTH, true> {
    /// A tick from the root with the full loop: the timers of rule 10 first, and last
    /// the fault of a guard's `_onHalted` that failed while the tick halted its node.
    #[inline(always)]
    pub(super) fn tick_full(
        &mut self,
        frames: &mut [Frame; DEPTH],
        extra: &mut [Extra; DEPTH],
        now: u32,
        timers: bool,
        guards: bool,
    ) -> Result<Status, TickError> {
        if timers {
            self.timers(now);
        }
        let result = self.run_full(frames, extra, now, 0, None);
        let result = if guards { self.guard_fault(result) } else { result };
        if result.is_err() {
            // Mid-tick, nodes on the path have not taken their new status yet: scan all.
            self.reset(0, Scan::All);
        }
        result
    }

    /// The full loop, out of line: one copy, whether a tick starts in it (from the root)
    /// or the plain loop hands over to it (`pending`: a leaf returned to the frame at
    /// `depth - 1`).
    #[inline(never)]
    pub(super) fn run_full(
        &mut self,
        frames: &mut [Frame; DEPTH],
        extra: &mut [Extra; DEPTH],
        now: u32,
        depth: usize,
        pending: Option<Returned>,
    ) -> Result<Status, TickError> {
        self.run_loop(frames, extra, now, depth, 0, pending)
    }
}
