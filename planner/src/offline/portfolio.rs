//! Search on threads of its own while Algorithm 1 runs ([`crate::Options::parallel`]):
//! with [`SearchOptions::lazy`], eager search with h_FF within a budget of evaluated
//! states (smaller on large groundings) beside deferred search, the eager plan taken where it finds one within that
//! budget (so the plan never depends on which thread ends first).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;

use crate::PlanError;
use crate::ground::Grounding;
use crate::search::{self, Found, SearchOptions};

/// States eager search may evaluate before the deferred search's plan is taken
/// instead. Eager search found the plans of parcprinter and maintenance problems
/// within it that deferred search with landmarks did not find in 20 s; past it,
/// deferred search with landmarks solved more (visitall, childsnack, tetris).
pub const EAGER_STATES: u64 = 20_000;

/// Entries of the relaxation ([`search::Relaxation::size`]) eager search may visit in
/// its evaluations, summed, before the deferred search's plan is taken instead: about
/// 1-2 s on a 2020s core. On large groundings, where one evaluation costs a
/// millisecond or more (parking: 230,000 entries), 20,000 evaluations would take
/// longer than the deferred search needs for its plan (parking-sat11 pfile08: 0.7 s),
/// and the plan waits for eager search's budget. The parcprinter and maintenance
/// plans eager search found needed at most 25 million.
pub const EAGER_WORK: u64 = 200_000_000;

/// Eager search's budget of evaluated states on `g`: [`EAGER_STATES`], fewer where
/// they would visit more than [`EAGER_WORK`] entries. It depends only on `g`, so the
/// plan does not depend on the machine.
fn eager_states(g: &Grounding) -> u64 {
    let size = search::Relaxation::new(g).size().max(1);
    EAGER_STATES.min(EAGER_WORK / size).max(1)
}

/// One search on its own thread; dropped, it is stopped and joined.
struct Running {
    stop: Arc<AtomicBool>,
    handle: Option<JoinHandle<Result<Found, PlanError>>>,
}

impl Running {
    fn start(g: &Arc<Grounding>, options: SearchOptions) -> Option<Self> {
        let stop = Arc::new(AtomicBool::new(false));
        let options = SearchOptions { stop: Some(stop.clone()), ..options };
        let g = g.clone();
        let handle =
            std::thread::Builder::new().name("planner-search".into()).spawn(move || search::gbfs(&g, &options)).ok()?;
        Some(Self { stop, handle: Some(handle) })
    }

    fn join(mut self) -> Result<Found, PlanError> {
        match self.handle.take().map(JoinHandle::join) {
            Some(Ok(found)) => found,
            _ => Err(PlanError::NoPlan("the search thread ended without a result".into())),
        }
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(h) = self.handle.take() {
            // It stops within 256 expansions; its result is not wanted.
            let _ = h.join();
        }
    }
}

/// The searches for a plan, running.
pub(super) struct Searching {
    eager: Option<Running>,
    deferred: Option<Running>,
}

impl Searching {
    /// Starts the searches on threads of their own, when the machine has two cores or
    /// more (`None` otherwise, or when no thread can be made: the caller then searches
    /// itself with [`search_plan`], after Algorithm 1).
    pub(super) fn start(g: &Arc<Grounding>, options: SearchOptions) -> Option<Self> {
        if std::thread::available_parallelism().map_or(1, usize::from) < 2 {
            return None;
        }
        if !options.lazy {
            return Some(Self { eager: Some(Running::start(g, options)?), deferred: None });
        }
        let eager = SearchOptions { lazy: false, max_evaluated: Some(eager_states(g)), ..options.clone() };
        Some(Self { eager: Some(Running::start(g, eager)?), deferred: Some(Running::start(g, options)?) })
    }

    /// Waits for the plan: eager search's where it found one within its budget (or
    /// proved there is none), else deferred search's (past eager search's budget, its
    /// memory bound or the deadline).
    pub(super) fn join(mut self) -> Result<Found, PlanError> {
        let eager = self.eager.take().map(Running::join);
        match (eager, self.deferred.take()) {
            (Some(Ok(found)), _) => Ok(found),
            (Some(Err(e @ PlanError::NoPlan(_))), _) | (Some(Err(e)), None) => Err(e),
            (_, Some(deferred)) => deferred.join(),
            (None, None) => Err(PlanError::NoPlan("no search ran".into())),
        }
    }
}

/// The plan of [`Searching`], searched for on this thread: eager search within its
/// budget, then deferred search.
pub(super) fn search_plan(g: &Grounding, options: &SearchOptions) -> Result<Found, PlanError> {
    if !options.lazy {
        return search::gbfs(g, options);
    }
    let eager = SearchOptions { lazy: false, max_evaluated: Some(eager_states(g)), ..options.clone() };
    match search::gbfs(g, &eager) {
        Err(PlanError::OutOfStates { .. } | PlanError::SearchMemory { .. }) => search::gbfs(g, options),
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domains;

    #[test]
    fn eager_search_gets_fewer_states_where_an_evaluation_costs_more() {
        let small = domains::blocks_world(4).unwrap();
        assert_eq!(eager_states(&small), EAGER_STATES);
        let large = domains::blocks_world(40).unwrap();
        let size = search::Relaxation::new(&large).size();
        assert!(size > EAGER_WORK / EAGER_STATES, "{size} entries");
        assert_eq!(eager_states(&large), EAGER_WORK / size);
    }
}
