//! How each kind ticks, as BehaviorTree.CPP 4.10's nodes (and Nav2's on it) do: what
//! [`Replay`] runs for one node.

use super::status::{FAILURE, IDLE, RUNNING, SKIPPED, SUCCESS};
use super::{Leaves, Replay};
use crate::btlog::tree::Kind;
use bt_core::Selection;

impl Replay<'_> {
    pub(super) fn tick_node(&mut self, i: usize, leaves: &mut dyn Leaves) -> u8 {
        let node = &self.tree.nodes[i];
        let n = node.children.len();
        match node.kind {
            Kind::Condition | Kind::Action => node.core.map_or(FAILURE, |c| leaves.tick(c)),
            // A script's result is the run's, asked as a leaf's.
            Kind::ScriptCondition => node.core.map_or(FAILURE, |c| leaves.tick(c)),
            Kind::Script => {
                if let Some(c) = node.core {
                    leaves.tick(c);
                }
                SUCCESS
            }
            Kind::Sleep(ms) => {
                // A StatefulActionNode: Running from its start (set in onStart) until
                // its timer fires.
                if self.rt[i].status != RUNNING {
                    if ms == 0 {
                        return SUCCESS;
                    }
                    self.rt[i].start = self.now;
                    self.set_status(i, RUNNING);
                    RUNNING
                } else if self.elapsed(i) >= ms {
                    SUCCESS
                } else {
                    RUNNING
                }
            }
            Kind::Precondition(otherwise) => {
                // Asks its script only until it has let its child go (`count`: 1),
                // which survives halts.
                if self.rt[i].count2 == 0 {
                    let holds = node.core.is_some_and(|c| leaves.tick(c) == SUCCESS);
                    if !holds {
                        return otherwise;
                    }
                    self.rt[i].count2 = 1;
                }
                let s = self.execute(self.child(i, 0), leaves);
                if s == SUCCESS || s == FAILURE {
                    self.halt_child(i, 0, leaves);
                    self.rt[i].count2 = 0;
                }
                s
            }
            Kind::Loop { elements, if_empty } => {
                // From Idle its queue starts over (`count`: elements taken); it takes the
                // next element only while its child is not Running (`count2`: 1 when it
                // is), and marks itself Running before it ticks the child.
                if self.rt[i].status == IDLE {
                    self.rt[i].count = 0;
                    self.rt[i].count2 = 0;
                }
                if self.rt[i].count2 == 0 {
                    let popped = match elements {
                        // The run's assignment of the element, consumed as a leaf's call.
                        Some(k) => {
                            let more = u16::try_from(self.rt[i].count).is_ok_and(|taken| taken < k);
                            if let (true, Some(c)) = (more, node.core) {
                                leaves.tick(c);
                            }
                            more
                        }
                        // A blackboard queue's pop, answered by the run as a leaf's.
                        None => node.core.is_some_and(|c| leaves.tick(c) == SUCCESS),
                    };
                    if !popped {
                        return if_empty;
                    }
                    self.rt[i].count += 1;
                }
                if self.rt[i].status == IDLE {
                    self.set_status(i, RUNNING);
                }
                let s = self.execute(self.child(i, 0), leaves);
                self.rt[i].count2 = usize::from(s == RUNNING) as _;
                if s == SUCCESS || s == FAILURE {
                    self.halt_child(i, 0, leaves);
                }
                if s == FAILURE { FAILURE } else { RUNNING }
            }
            Kind::SequenceStarV3 | Kind::ParallelV3 { .. } | Kind::Cycles { .. } | Kind::Check(_) | Kind::Gate => {
                self.tick_v3(i, leaves)
            }
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
            Kind::PipelineSequence => {
                // Nav2: every child every tick; Running stops the tick only at the
                // furthest child reached (`idx`). It sets no status of its own first.
                let mut skipped = 0;
                for k in 0..n {
                    match self.execute(self.child(i, k), leaves) {
                        FAILURE => {
                            self.reset_children(i, leaves);
                            self.rt[i].idx = 0;
                            return FAILURE;
                        }
                        SKIPPED => skipped += 1,
                        RUNNING if k >= self.rt[i].idx => {
                            self.rt[i].idx = k;
                            return RUNNING;
                        }
                        _ => {}
                    }
                }
                self.reset_children(i, leaves);
                self.rt[i].idx = 0;
                if skipped == n { SKIPPED } else { SUCCESS }
            }
            Kind::Recovery(retries) => self.recovery(i, retries, leaves),
            Kind::ManualSelector { repeat_last } => self.manual_selector(i, repeat_last, leaves),
            Kind::RoundRobin => {
                // Nav2: one child per turn (`idx`), failures counted (`count`) until
                // every child has failed in turn.
                self.set_status(i, RUNNING);
                let mut skipped = 0;
                while (self.rt[i].count + skipped) < n as i32 {
                    let s = self.execute(self.child(i, self.rt[i].idx), leaves);
                    if s != RUNNING {
                        self.rt[i].idx = (self.rt[i].idx + 1) % n;
                    }
                    match s {
                        SUCCESS => {
                            self.rt[i].count = 0;
                            self.reset_children(i, leaves);
                            return SUCCESS;
                        }
                        FAILURE => self.rt[i].count += 1,
                        SKIPPED => skipped += 1,
                        _ => return RUNNING,
                    }
                }
                // `halt()`: children and the node itself reset, the turn back to the first.
                self.halt(i, leaves);
                if skipped == n as i32 { SKIPPED } else { FAILURE }
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

    /// Nav2's `RecoveryNode`: the child ticked is `idx`, the recoveries made `count`.
    /// Where it finishes it calls its own `halt()`, which resets the node to Idle before
    /// it takes its result.
    fn recovery(&mut self, i: usize, retries: i32, leaves: &mut dyn Leaves) -> u8 {
        self.set_status(i, RUNNING);
        while self.rt[i].idx < 2 && self.rt[i].count <= retries {
            let k = self.rt[i].idx;
            let s = self.execute(self.child(i, k), leaves);
            match (k, s) {
                (_, RUNNING) => return RUNNING,
                (0, SKIPPED) => {
                    self.halt(i, leaves);
                    return SKIPPED;
                }
                (0, SUCCESS) => {
                    self.halt_child(i, 1, leaves);
                    self.halt(i, leaves);
                    return SUCCESS;
                }
                (0, _) if self.rt[i].count < retries => {
                    self.halt_child(i, 0, leaves);
                    self.rt[i].idx = 1;
                }
                (0, _) => {
                    self.halt(i, leaves);
                    return FAILURE;
                }
                // A recovery that skipped: no recovery possible, not counted.
                (_, SKIPPED) => {
                    self.rt[i].idx = 0;
                    self.halt_child(i, 1, leaves);
                    return FAILURE;
                }
                (_, SUCCESS) => {
                    self.halt_child(i, 1, leaves);
                    self.rt[i].count += 1;
                    self.rt[i].idx = 0;
                }
                _ => {
                    self.halt(i, leaves);
                    return FAILURE;
                }
            }
        }
        self.halt(i, leaves);
        FAILURE
    }

    /// BehaviorTree.CPP 4.10's `ManualSelectorNode::tick()`, told the run's selections.
    /// Without children it asks for a status and returns it (it does not mark itself
    /// Running first). With children: unless `repeat_last_selection` and it has made a
    /// selection before, it marks itself Running, asks, remembers the answer and returns
    /// a status answered; then it ticks the child (remembered or answered) and returns
    /// what it returns, remembering it as its running child when Running. It halts no
    /// other child, and resets none when it finishes.
    fn manual_selector(&mut self, i: usize, repeat_last: bool, leaves: &mut dyn Leaves) -> u8 {
        let n = self.tree.nodes[i].children.len();
        let remembered = self.rt[i].selected.filter(|_| repeat_last && n > 0);
        let selection = match remembered {
            Some(s) => s,
            None => {
                if n > 0 {
                    self.set_status(i, RUNNING);
                }
                let Some(s) = self.tree.nodes[i].core.and_then(|c| leaves.select(c)) else {
                    self.refuse(i, "asks for a selection, and the run made none there");
                    return FAILURE;
                };
                if n > 0 {
                    self.rt[i].selected = Some(s);
                }
                s
            }
        };
        let k = match (selection, remembered.is_some()) {
            (Selection::Child(k), _) => usize::from(k),
            // BehaviorTree.CPP keeps a status answered as the child index 253 to 255 and,
            // repeating it, ticks that child: past its children (ours returns it again).
            (s, true) => {
                self.refuse(i, &format!("repeats its last selection, {s:?}, which BehaviorTree.CPP would take as a child index past its children"));
                return FAILURE;
            }
            (Selection::Running, false) => return RUNNING,
            (s, false) => {
                self.note_left_running(i, None);
                return if s == Selection::Success { SUCCESS } else { FAILURE };
            }
        };
        if k >= n {
            self.refuse(i, &format!("is told to tick child {k} of its {n}"));
            return FAILURE;
        }
        // Its operator's menu answers in a byte, 253 to 255 meaning statuses.
        if k >= 253 {
            self.refuse(
                i,
                &format!("is told to tick child {k}, which BehaviorTree.CPP's selection takes for a status"),
            );
            return FAILURE;
        }
        self.note_left_running(i, Some(k));
        let s = self.execute(self.child(i, k), leaves);
        if s == RUNNING {
            self.rt[i].running_child = Some(k);
        }
        s
    }

    /// Notes a child of `ManualSelector` `i` other than `chosen` that is Running: bt-core
    /// halts it here, BehaviorTree.CPP leaves it Running.
    fn note_left_running(&mut self, i: usize, chosen: Option<usize>) {
        let children = &self.tree.nodes[i].children;
        if let Some(k) = (0..children.len()).find(|&k| Some(k) != chosen && self.rt[children[k]].status == RUNNING) {
            self.left_running = Some((i, children[k]));
        }
    }

    fn clear_parallel(&mut self, i: usize) {
        let r = &mut self.rt[i];
        r.done.iter_mut().for_each(|d| *d = false);
        r.count = 0;
        r.count2 = 0;
    }
}
