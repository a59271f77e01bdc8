//! Heuristic search for a plan: greedy best-first search over the ground actions of
//! a [`Grounding`], with h_FF and helpful actions, and with LAMA's ideas (deferred
//! evaluation, the landmark count alternating with h_FF: [`SearchOptions::lazy`],
//! [`SearchOptions::landmarks`], [`landmarks`]).
//!
//! The eager search evaluates every new state when it is generated. Two open lists
//! are kept, one with every state and one with the states reached by a helpful action
//! of their parent; the search takes from them in turn, and from the helpful one for
//! a while after each improvement of the best h (the boost of Fast Downward's and
//! LAMA's searches, in our own code). Ties go to the state generated first, so a run
//! is deterministic.
//!
//! States are stored once, as the sorted list of their true atoms, in one arena;
//! [`SearchOptions::memory`] bounds it. The plan's actions are the leaves the
//! backchaining tree then uses ([`crate::guide`]); the search never emits a tree.
//!
//! ```
//! use planner::{domains, search};
//! let g = domains::blocks_world(4)?;
//! let found = search::gbfs(&g, &search::SearchOptions::default())?;
//! assert!(g.goal_holds(&search::execute(&g, &found.plan).unwrap()));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod heuristic;
pub mod landmarks;
mod lazy;
mod registry;
mod successors;

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

pub use heuristic::{INFINITE, Relaxation};

use crate::PlanError;
use crate::ground::{ActionId, Grounding};
use crate::state::State;
use registry::Registry;
use successors::Successors;

/// Bounds of a search.
#[derive(Clone, Debug)]
pub struct SearchOptions {
    /// Give up at this instant.
    pub deadline: Option<Instant>,
    /// Most bytes of stored states.
    pub memory: usize,
    /// Expansions from the helpful list after each improvement of the best h.
    pub boost: u32,
    /// Deferred evaluation, as LAMA searches: a state is evaluated when it is taken from an
    /// open list, not when it is generated.
    pub lazy: bool,
    /// Give up ([`PlanError::OutOfStates`]) once this many states were evaluated.
    pub max_evaluated: Option<u64>,
    /// With [`SearchOptions::lazy`]: as [`SearchOptions::max_evaluated`], but another
    /// thread may lower it while the search runs. The outcome is the same as with the
    /// lowered bound from the start (a plan found within it, or
    /// [`PlanError::OutOfStates`]), however late it is lowered, so a portfolio can
    /// compare searches by their evaluations and not by which thread ends first.
    pub max_evaluated_live: Option<Arc<AtomicU64>>,
    /// With [`SearchOptions::lazy`]: alternate h_FF with the landmark count
    /// ([`landmarks`]), as LAMA does.
    pub landmarks: bool,
    /// With [`SearchOptions::landmarks`]: the landmark count's helpful actions lead to
    /// preferred successors as h_FF's do. Without, only h_FF's do, as in Fast
    /// Downward's lama-first (its landmark heuristic with `pref=false`).
    pub landmark_preferred: bool,
    /// Give up as soon as this is set (another thread found what the search was for:
    /// [`crate::plan`] runs search beside Algorithm 1 and stops it when Algorithm 1
    /// finishes first).
    pub stop: Option<Arc<AtomicBool>>,
}

impl Default for SearchOptions {
    fn default() -> Self {
        Self {
            deadline: None,
            memory: 2 << 30,
            boost: 1000,
            lazy: false,
            landmarks: false,
            landmark_preferred: true,
            max_evaluated: None,
            max_evaluated_live: None,
            stop: None,
        }
    }
}

impl SearchOptions {
    /// Whether the search must end now: past its deadline, or told to stop.
    fn over(&self) -> bool {
        self.deadline.is_some_and(|d| Instant::now() >= d)
            || self.stop.as_ref().is_some_and(|s| s.load(Ordering::Relaxed))
    }

    /// Whether a deferred search that has evaluated `evaluated` states must give up
    /// before evaluating another: at [`SearchOptions::max_evaluated`] or
    /// [`SearchOptions::max_evaluated_live`].
    fn evaluated_enough(&self, evaluated: u64) -> bool {
        self.max_evaluated.is_some_and(|m| evaluated >= m)
            || self.max_evaluated_live.as_ref().is_some_and(|m| evaluated >= m.load(Ordering::Relaxed))
    }
}

/// A plan found by search, with what the search did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Found {
    /// The actions, in order.
    pub plan: Vec<ActionId>,
    /// States expanded.
    pub expanded: u64,
    /// States stored (reached for the first time).
    pub stored: u64,
    /// States whose heuristic values were computed.
    pub evaluated: u64,
    /// h_FF of the initial state.
    pub initial_h: u32,
}

/// The state after applying `plan` from the initial state, or `None` when an action
/// is not applicable where the plan uses it.
#[must_use]
pub fn execute(g: &Grounding, plan: &[ActionId]) -> Option<State> {
    let mut s = g.init().clone();
    for &a in plan {
        let x = g.action(a)?;
        if !x.applicable(&s) {
            return None;
        }
        g.apply(x, &mut s);
    }
    Some(s)
}

struct Node {
    parent: u32,
    action: ActionId,
}

/// Greedy best-first search with h_FF and helpful actions (see the module docs).
///
/// # Errors
/// [`PlanError::NoPlan`] when every reachable state was expanded without reaching
/// the goal, or the relaxation shows none can; [`PlanError::Timeout`];
/// [`PlanError::SearchMemory`] when the stored states pass [`SearchOptions::memory`].
pub fn gbfs(g: &Grounding, options: &SearchOptions) -> Result<Found, PlanError> {
    gbfs_from(g, g.init(), options)
}

/// [`gbfs`] from `start` instead of the initial state.
///
/// # Errors
/// As [`gbfs`].
pub fn gbfs_from(g: &Grounding, start: &State, options: &SearchOptions) -> Result<Found, PlanError> {
    if options.lazy {
        return lazy::lazy_gbfs_from(g, start, options);
    }
    let mut h = Relaxation::new(g);
    let succ = Successors::new(g);
    let mut reg = Registry::new(g, start);
    let mut nodes: Vec<Node> = Vec::new();
    let mut helpful = Vec::new();
    let init = start.clone();
    let h0 = h.h_ff(&init, &mut helpful);
    if h0 == INFINITE {
        return Err(PlanError::NoPlan("the goal is unreachable even when deletes are ignored".into()));
    }
    let (root, _) = reg.insert(&init);
    nodes.push(Node { parent: u32::MAX, action: 0 });
    if g.goal_holds(&init) {
        return Ok(Found { plan: Vec::new(), expanded: 0, stored: 1, evaluated: 1, initial_h: h0 });
    }
    // Open lists: (h, generation order, state).
    let mut open: BinaryHeap<Reverse<(u32, u64, u32)>> = BinaryHeap::new();
    let mut preferred: BinaryHeap<Reverse<(u32, u64, u32)>> = BinaryHeap::new();
    let mut order: u64 = 0;
    open.push(Reverse((h0, order, root)));
    preferred.push(Reverse((h0, order, root)));
    let mut helpful_of: Vec<Vec<ActionId>> = vec![helpful.clone()];
    let mut closed = vec![false];
    let mut best = h0;
    let mut boost = 0u32;
    let mut turn = false;
    let mut expanded: u64 = 0;
    let mut evaluated: u64 = 1;
    let mut state = State::new(g.atom_count());
    let mut next = State::new(g.atom_count());
    let mut applicable = Vec::new();
    loop {
        let from_preferred = !preferred.is_empty() && (boost > 0 || turn || open.is_empty());
        turn = !turn;
        let popped = if from_preferred {
            boost = boost.saturating_sub(1);
            preferred.pop()
        } else {
            open.pop()
        };
        let Some(Reverse((_, _, id))) = popped else {
            return Err(PlanError::NoPlan(format!("every reachable state was expanded ({} states)", reg.len())));
        };
        if closed[id as usize] {
            continue;
        }
        closed[id as usize] = true;
        expanded += 1;
        if expanded & 0xFF == 0 && options.over() {
            return Err(PlanError::Timeout { stage: "searching for a plan" });
        }
        reg.load(id, &mut state);
        let helpful_here = std::mem::take(&mut helpful_of[id as usize]);
        succ.applicable(g, &state, &mut applicable);
        for &a in &applicable {
            let Some(sid) = child(g, &mut reg, &state, a, &mut next) else { continue };
            if reg.bytes() > options.memory {
                return Err(PlanError::SearchMemory { states: reg.len() as u64, limit: options.memory as u64 });
            }
            nodes.push(Node { parent: id, action: a });
            closed.push(false);
            if g.goal_holds(&next) {
                let plan = path(&nodes, sid);
                return Ok(Found { plan, expanded, stored: reg.len() as u64, evaluated, initial_h: h0 });
            }
            if options.over() {
                return Err(PlanError::Timeout { stage: "searching for a plan" });
            }
            if options.max_evaluated.is_some_and(|m| reg.len() as u64 > m) {
                return Err(PlanError::OutOfStates { evaluated: reg.len() as u64 });
            }
            let hv = h.h_ff(&next, &mut helpful);
            evaluated += 1;
            helpful_of.push(if hv == INFINITE { Vec::new() } else { helpful.clone() });
            if hv == INFINITE {
                closed[sid as usize] = true;
                continue;
            }
            order += 1;
            open.push(Reverse((hv, order, sid)));
            if helpful_here.contains(&a) {
                preferred.push(Reverse((hv, order, sid)));
            }
            if hv < best {
                best = hv;
                boost = boost.saturating_add(options.boost);
            }
        }
    }
}

/// Best-first search from `start` for a state whose `score` is 0, lowest `score` plus
/// `step` per action from `start` first (ties: generated first; `step` 0 is greedy
/// search), with the actions `allowed` marks (all when `None`), storing at most
/// `max_states` states: the plan, or `None` when none was found within those bounds.
/// [`crate::regress`] uses it to lead a disturbed state back to one of a tree's rules,
/// scored by the conditions of the nearest rule that do not hold.
#[must_use]
pub fn best_first_to(
    g: &Grounding,
    start: &State,
    allowed: Option<&[bool]>,
    step: u64,
    max_states: usize,
    deadline: Option<Instant>,
    mut score: impl FnMut(&State) -> u64,
) -> Option<Vec<ActionId>> {
    let first = score(start);
    if first == 0 {
        return Some(Vec::new());
    }
    let succ = Successors::new(g);
    let mut reg = Registry::new(g, start);
    let (root, _) = reg.insert(start);
    let mut nodes = vec![Node { parent: u32::MAX, action: 0 }];
    let mut depth: Vec<u64> = vec![0];
    let mut open: BinaryHeap<Reverse<(u64, u32)>> = BinaryHeap::new();
    open.push(Reverse((first, root)));
    let mut state = State::new(g.atom_count());
    let mut next = State::new(g.atom_count());
    let mut applicable = Vec::new();
    while let Some(Reverse((_, id))) = open.pop() {
        if deadline.is_some_and(|d| Instant::now() >= d) {
            return None;
        }
        reg.load(id, &mut state);
        succ.applicable(g, &state, &mut applicable);
        for &a in &applicable {
            if allowed.is_some_and(|ok| !ok.get(a as usize).copied().unwrap_or(false)) {
                continue;
            }
            let Some(sid) = child(g, &mut reg, &state, a, &mut next) else { continue };
            nodes.push(Node { parent: id, action: a });
            let d = depth.get(id as usize).map_or(0, |d| d + 1);
            depth.push(d);
            let v = score(&next);
            if v == 0 {
                return Some(path(&nodes, sid));
            }
            if reg.len() >= max_states {
                return None;
            }
            open.push(Reverse((v.saturating_add(d.saturating_mul(step)), sid)));
        }
    }
    None
}

/// The state action `a` leads to from `state`, written to `next` and stored: its id
/// when it was not stored before.
#[inline]
fn child(g: &Grounding, reg: &mut Registry, state: &State, a: ActionId, next: &mut State) -> Option<u32> {
    let action = g.action(a)?;
    next.clone_from(state);
    g.apply(action, next);
    let (sid, new) = reg.insert(next);
    new.then_some(sid)
}

/// The actions from the root to state `id`.
fn path(nodes: &[Node], mut id: u32) -> Vec<ActionId> {
    let mut plan = Vec::new();
    while let Some(n) = nodes.get(id as usize) {
        if n.parent == u32::MAX {
            break;
        }
        plan.push(n.action);
        id = n.parent;
    }
    plan.reverse();
    plan
}
