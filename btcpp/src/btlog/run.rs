//! A `.btlog` of one of our runs: the leaf results of each tick, replayed through
//! BehaviorTree.CPP's transition model ([`Replay`]) into a [`LogWriter`].

use std::collections::VecDeque;

use bt_core::Selection;
use bt_core::script::Hook;

use crate::btlog::LogWriter;
use crate::btlog::replay::{Leaves, Replay, Ticking, status};
use crate::btlog::tree::LogTree;

/// BehaviorTree.CPP would tick another leaf than our executor did: the log would not
/// describe our run.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("tick {tick}: {what}")]
pub struct Mismatch {
    /// The tick.
    pub tick: u32,
    /// What differed.
    pub what: String,
}

/// A log being made from a run.
#[derive(Debug)]
pub struct RunLog<'t> {
    tree: &'t LogTree,
    replay: Replay<'t>,
    writer: LogWriter,
    ticking: Ticking,
    /// The last tick where a `ManualSelector` left a child Running that bt-core halted:
    /// (tick, the `ManualSelector`, the child), indices into [`LogTree::nodes`].
    left_running: Option<(u32, usize, usize)>,
}

struct Queue<'a> {
    calls: VecDeque<(usize, u8)>,
    /// The run's `ManualSelector` selections: (bt-core node, selection).
    selections: VecDeque<(usize, Selection)>,
    wrong: Option<String>,
    tree: &'a LogTree,
    /// Guards whose `_onHalted` the run ran before BehaviorTree.CPP would in the tick
    /// (halt before start halts before the new start), not yet asked for.
    early: Vec<usize>,
}

impl Queue<'_> {
    /// Node `core` with its name, for messages.
    fn name(&self, core: usize) -> String {
        self.tree
            .nodes
            .iter()
            .find(|n| n.core == Some(core))
            .map_or_else(|| format!("node {core}"), |n| format!("node {core} ({})", n.name))
    }

    /// Whether `core` is the guard of a node with `_onHalted`.
    fn has_on_halted(&self, core: usize) -> bool {
        self.tree.nodes.iter().any(|n| n.hooks.is_some_and(|h| h.core == core && h.has(Hook::OnHalted)))
    }
}

impl Leaves for Queue<'_> {
    fn tick(&mut self, core: usize) -> u8 {
        // An `_onHalted` the run ran earlier in the tick waits for the replay to ask.
        while let Some(&(c, _)) = self.calls.front()
            && c != core
            && self.has_on_halted(c)
        {
            self.early.push(c);
            self.calls.pop_front();
        }
        match self.calls.pop_front() {
            Some((c, s)) if c == core => s,
            other => {
                if self.wrong.is_none() {
                    self.wrong = Some(match other {
                        Some((c, _)) => {
                            format!("BehaviorTree.CPP ticks {} where the run ticked {}", self.name(core), self.name(c))
                        }
                        None => {
                            format!("BehaviorTree.CPP ticks {} after the run's last leaf of the tick", self.name(core))
                        }
                    });
                }
                status::FAILURE
            }
        }
    }

    fn halt(&mut self, _: usize) {}

    fn select(&mut self, core: usize) -> Option<Selection> {
        match self.selections.pop_front() {
            Some((c, s)) if c == core => Some(s),
            other => {
                if self.wrong.is_none() {
                    let asks = format!("BehaviorTree.CPP's ManualSelector {} asks for a selection", self.name(core));
                    self.wrong = Some(match other {
                        Some((c, _)) => format!("{asks} where the run's next one was {}'s", self.name(c)),
                        None => format!("{asks}, and the run made no more in the tick"),
                    });
                }
                None
            }
        }
    }

    /// Where our executor ran it in the tick does not matter (halt before start may
    /// halt earlier in the tick than BehaviorTree.CPP does), only that it did.
    fn halted_hook(&mut self, core: usize) {
        if let Some(k) = self.early.iter().position(|&c| c == core) {
            self.early.remove(k);
            return;
        }
        match self.calls.iter().position(|&(c, _)| c == core) {
            Some(k) => {
                self.calls.remove(k);
            }
            None => {
                if self.wrong.is_none() {
                    self.wrong = Some(format!(
                        "BehaviorTree.CPP runs node {core}'s _onHalted, which the run did not in this tick"
                    ));
                }
            }
        }
    }
}

impl<'t> RunLog<'t> {
    /// A log of `tree` whose clock starts at `first_usec`, of a run ticked as
    /// `Tree::tickExactlyOnce()` (bt-core's `Executor::tick`, once per tick).
    #[must_use]
    pub fn new(tree: &'t LogTree, first_usec: i64) -> Self {
        Self {
            tree,
            replay: Replay::new(tree),
            writer: LogWriter::new(tree, first_usec),
            ticking: Ticking::default(),
            left_running: None,
        }
    }

    /// The same, for a run ticked as `ticking` says (with [`Ticking::Once`], each tick's
    /// calls are those of all its passes).
    #[must_use]
    pub fn ticked(mut self, ticking: Ticking) -> Self {
        self.ticking = ticking;
        self
    }

    /// Tick `tick` at `usec` (the log's clock), for which the run gave bt-core `now`:
    /// the leaves the run ticked, in order, with what each returned (bt-core node,
    /// [`status`] number).
    ///
    /// # Errors
    /// [`Mismatch`] when BehaviorTree.CPP's model ticks other leaves.
    pub fn tick(&mut self, tick: u32, usec: i64, now: u32, calls: &[(usize, u8)]) -> Result<u8, Mismatch> {
        self.tick_selecting(tick, usec, now, calls, &[])
    }

    /// [`RunLog::tick`] for a run whose `ManualSelector`s made `selections` in the tick,
    /// in order: (bt-core node, what [`bt_core::BehaviorSet::select`] answered).
    ///
    /// # Errors
    /// [`Mismatch`] when BehaviorTree.CPP's model ticks other leaves or asks for other
    /// selections, or cannot do what the run did (naming the node); when a
    /// `ManualSelector` had left a child Running that bt-core halted (halt before start),
    /// the message says where.
    pub fn tick_selecting(
        &mut self,
        tick: u32,
        usec: i64,
        now: u32,
        calls: &[(usize, u8)],
        selections: &[(usize, Selection)],
    ) -> Result<u8, Mismatch> {
        let q = Queue {
            calls: calls.iter().copied().collect(),
            selections: selections.iter().copied().collect(),
            wrong: None,
            tree: self.tree,
            early: Vec::new(),
        };
        self.checked(tick, usec, now, q).map_err(|mut e| {
            if let Some((at, m, c)) = self.left_running {
                let name = |i: usize| format!("`{}` (uid {})", self.tree.nodes[i].name, self.tree.nodes[i].uid);
                e.what = format!(
                    "{}; ManualSelector {} left {} Running at tick {at}, where our executor halts it before \
                     starting another child (halt before start)",
                    e.what,
                    name(m),
                    name(c)
                );
            }
            e
        })
    }

    /// Replays tick `tick` with the run's calls and selections in `q`, and writes its
    /// transitions when the replay and the run agree.
    fn checked(&mut self, tick: u32, usec: i64, now: u32, mut q: Queue<'t>) -> Result<u8, Mismatch> {
        let (root, transitions) = self.replay.tick(&mut q, now, self.ticking);
        let refusal = self.replay.refusal();
        if let Some((m, c)) = self.replay.take_left_running() {
            self.left_running = Some((tick, m, c));
        }
        // A node the replay cannot follow explains what goes wrong after it.
        if let Some(what) = refusal.or_else(|| q.wrong.take()) {
            return Err(Mismatch { tick, what });
        }
        if let Some(&c) = q.early.first() {
            return Err(Mismatch {
                tick,
                what: format!("the run ran node {c}'s _onHalted, which BehaviorTree.CPP does not"),
            });
        }
        if let Some(&(c, _)) = q.calls.front() {
            return Err(Mismatch {
                tick,
                what: format!("the run ticked node {c}, which BehaviorTree.CPP does not tick"),
            });
        }
        if let Some(&(c, _)) = q.selections.front() {
            return Err(Mismatch {
                tick,
                what: format!(
                    "the run's ManualSelector {} made a selection BehaviorTree.CPP does not ask for",
                    q.name(c)
                ),
            });
        }
        for (uid, s) in transitions {
            self.writer.transition(usec, uid, s);
        }
        Ok(root)
    }

    /// The log's bytes.
    #[must_use]
    pub fn into_bytes(self) -> Vec<u8> {
        self.writer.into_bytes()
    }
}

/// The [`status`] number of a bt-core status.
#[must_use]
pub const fn status_of(s: bt_core::Status) -> u8 {
    match s {
        bt_core::Status::Running => status::RUNNING,
        bt_core::Status::Success => status::SUCCESS,
        bt_core::Status::Failure => status::FAILURE,
        bt_core::Status::Skipped => status::SKIPPED,
    }
}
