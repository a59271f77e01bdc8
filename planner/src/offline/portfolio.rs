//! Search on threads of its own while Algorithm 1 runs ([`crate::Options::parallel`]):
//! with [`SearchOptions::lazy`], eager search with h_FF within a budget of evaluated
//! states (smaller on large groundings), and after it, with landmarks, deferred search
//! as Fast Downward's lama-first within a budget of its own, beside deferred search;
//! the first of them in that order to find a plan within its budget gives it (so the
//! plan never depends on which thread ends first).

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

/// States the deferred search as Fast Downward's lama-first (the landmark count's
/// helpful actions not preferred: [`SearchOptions::landmark_preferred`]) may evaluate
/// before the deferred search's plan is taken instead. It found pipesworld-tankage
/// p23's plan in about 8,100 evaluations where the landmark-preferring search found
/// none in 60 s; parking's plans need the landmarks' helpful actions.
pub const LAMA_FIRST_STATES: u64 = 20_000;

/// Entries of the goal-relevant relaxation ([`search::Relaxation::relevant_size`]) the
/// lama-first search's evaluations may visit, summed: a budget of a few seconds
/// (pipesworld-tankage p23 needed about 610 million).
pub const LAMA_FIRST_WORK: u64 = 1_000_000_000;

/// The lama-first search's budget of evaluated states on `g`, from its grounding only.
fn lama_first_states(g: &Grounding) -> u64 {
    let size = search::Relaxation::new(g).relevant_size().max(1);
    LAMA_FIRST_STATES.min(LAMA_FIRST_WORK / size).max(1)
}

/// The searches whose plans are taken before the deferred search's, one after the
/// other: eager search within its budget, then, where the deferred search prefers the
/// landmarks' helpful actions, lama-first within its own. [`PlanError::OutOfStates`]
/// or [`PlanError::SearchMemory`] when neither found a plan within its budget.
fn first_searches(g: &Grounding, options: &SearchOptions) -> Result<Found, PlanError> {
    let eager = SearchOptions { lazy: false, max_evaluated: Some(eager_states(g)), ..options.clone() };
    let found = search::gbfs(g, &eager);
    if !(options.lazy && options.landmarks && options.landmark_preferred) {
        return found;
    }
    match found {
        Err(PlanError::OutOfStates { .. } | PlanError::SearchMemory { .. }) => {
            let lama_first = SearchOptions {
                landmark_preferred: false,
                max_evaluated: Some(lama_first_states(g)),
                ..options.clone()
            };
            search::gbfs(g, &lama_first)
        }
        other => other,
    }
}

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
    fn start(
        g: &Arc<Grounding>,
        options: SearchOptions,
        search: fn(&Grounding, &SearchOptions) -> Result<Found, PlanError>,
    ) -> Option<Self> {
        let stop = Arc::new(AtomicBool::new(false));
        let options = SearchOptions { stop: Some(stop.clone()), ..options };
        let g = g.clone();
        let handle =
            std::thread::Builder::new().name("planner-search".into()).spawn(move || search(&g, &options)).ok()?;
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
            return Some(Self { eager: Some(Running::start(g, options, search::gbfs)?), deferred: None });
        }
        Some(Self {
            eager: Some(Running::start(g, options.clone(), first_searches)?),
            deferred: Some(Running::start(g, options, search::gbfs)?),
        })
    }

    /// Waits for the plan: that of the searches on the first thread ([`first_searches`])
    /// where one found it within its budget (or proved there is none), else deferred
    /// search's (past their budgets, their memory bound or the deadline).
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

/// The plan of [`Searching`], searched for on this thread: [`first_searches`] within
/// their budgets, then deferred search.
pub(super) fn search_plan(g: &Grounding, options: &SearchOptions) -> Result<Found, PlanError> {
    if !options.lazy {
        return search::gbfs(g, options);
    }
    match first_searches(g, options) {
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
