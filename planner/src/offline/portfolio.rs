//! Search on threads of its own while Algorithm 1 runs ([`crate::Options::parallel`]):
//! with [`SearchOptions::lazy`], eager search with h_FF within a budget of evaluated
//! states (smaller on large groundings) beside deferred search, the eager plan taken
//! where it finds one within that budget. With landmarks, the deferred search (which
//! prefers the landmark count's helpful actions too) gets a budget as well, and once
//! eager search's is spent, a deferred search as Fast Downward's lama-first (only
//! h_FF's helpful actions preferred) starts on its thread, its plan taken where the
//! other two found none within their budgets. The plan never depends on which thread
//! ends first.

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

/// States the deferred search preferring the landmarks' helpful actions
/// ([`SearchOptions::landmark_preferred`]) may evaluate before the lama-first search's
/// plan is taken instead. Parking's plans need those helpful actions and come within
/// 2,000 evaluations; pipesworld-tankage p23's plan came from lama-first after about
/// 8,100 where the landmark-preferring search found none in 60 s.
pub const LANDMARK_PREFERRED_STATES: u64 = 20_000;

/// Entries of the goal-relevant relaxation ([`search::Relaxation::relevant_size`])
/// the landmark-preferring search's evaluations may visit, summed: a budget of a few
/// seconds, so that where it fails the lama-first search's plan does not wait long.
/// parking-sat14 p_34_3's plan (634,476 relevant entries) comes after 1,843
/// evaluations, about 1.2 billion entries, and only from this search.
pub const LANDMARK_PREFERRED_WORK: u64 = 2_000_000_000;

/// The landmark-preferring search's budget of evaluated states, from the grounding's
/// relaxation `h` only.
fn landmark_preferred_states(h: &search::Relaxation) -> u64 {
    LANDMARK_PREFERRED_STATES.min(LANDMARK_PREFERRED_WORK / h.relevant_size().max(1)).max(1)
}

/// The three searches' options, taken in this order (see the module docs): eager,
/// deferred, and lama-first where the deferred search prefers the landmarks' helpful
/// actions (`None` otherwise; the deferred search then has no budget).
fn three(g: &Grounding, options: &SearchOptions) -> (SearchOptions, SearchOptions, Option<SearchOptions>) {
    // The budgets depend only on the grounding's size, so the plan not on the machine.
    let h = search::Relaxation::new(g);
    let eager = SearchOptions { lazy: false, max_evaluated: Some(eager_states(&h)), ..options.clone() };
    if !(options.landmarks && options.landmark_preferred) {
        return (eager, options.clone(), None);
    }
    let deferred = SearchOptions { max_evaluated: Some(landmark_preferred_states(&h)), ..options.clone() };
    (eager, deferred, Some(SearchOptions { landmark_preferred: false, ..options.clone() }))
}

/// Whether a search gave up at its budget or memory bound (a later one may still find
/// a plan).
fn out_of_budget(r: &Result<Found, PlanError>) -> bool {
    matches!(r, Err(PlanError::OutOfStates { .. } | PlanError::SearchMemory { .. }))
}

/// Eager search's budget of evaluated states: [`EAGER_STATES`], fewer where they
/// would visit more than [`EAGER_WORK`] entries of the grounding's relaxation `h`.
fn eager_states(h: &search::Relaxation) -> u64 {
    EAGER_STATES.min(EAGER_WORK / h.size().max(1)).max(1)
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
    g: Arc<Grounding>,
    eager: Option<Running>,
    deferred: Option<Running>,
    /// The lama-first search's options, started once eager search ends.
    lama_first: Option<SearchOptions>,
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
            let eager = Some(Running::start(g, options)?);
            return Some(Self { g: g.clone(), eager, deferred: None, lama_first: None });
        }
        let (eager, deferred, lama_first) = three(g, &options);
        Some(Self {
            g: g.clone(),
            eager: Some(Running::start(g, eager)?),
            deferred: Some(Running::start(g, deferred)?),
            lama_first,
        })
    }

    /// Waits for the plan: eager search's where it found one within its budget (or
    /// proved there is none), else deferred search's where it found one within its
    /// budget, else lama-first's (see the module docs).
    pub(super) fn join(mut self) -> Result<Found, PlanError> {
        let eager = self.eager.take().map(Running::join);
        let Some(deferred) = self.deferred.take() else {
            return eager.unwrap_or_else(|| Err(PlanError::NoPlan("no search ran".into())));
        };
        match eager {
            Some(Ok(found)) => return Ok(found),
            Some(Err(e @ PlanError::NoPlan(_))) => return Err(e),
            _ => {}
        }
        // Eager search's thread is free: lama-first runs there while deferred search ends.
        let lama_first = self.lama_first.take().and_then(|o| Running::start(&self.g, o));
        let found = deferred.join();
        match lama_first {
            Some(l) if out_of_budget(&found) => l.join(),
            _ => found,
        }
    }
}

/// The plan of [`Searching`], searched for on this thread: each search in turn, the
/// next where one gave up at its budget.
pub(super) fn search_plan(g: &Grounding, options: &SearchOptions) -> Result<Found, PlanError> {
    if !options.lazy {
        return search::gbfs(g, options);
    }
    let (eager, deferred, lama_first) = three(g, options);
    let found = search::gbfs(g, &eager);
    if !out_of_budget(&found) {
        return found;
    }
    let found = search::gbfs(g, &deferred);
    match lama_first {
        Some(o) if out_of_budget(&found) => search::gbfs(g, &o),
        _ => found,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domains;

    #[test]
    fn the_landmark_preferring_search_has_a_budget_and_lama_first_follows_it() {
        let g = domains::blocks_world(4).unwrap();
        let options = SearchOptions { lazy: true, landmarks: true, ..SearchOptions::default() };
        let (eager, deferred, lama_first) = three(&g, &options);
        assert_eq!(eager.max_evaluated, Some(EAGER_STATES));
        assert_eq!(deferred.max_evaluated, Some(LANDMARK_PREFERRED_STATES));
        let lama_first = lama_first.unwrap();
        assert!(!lama_first.landmark_preferred && lama_first.max_evaluated.is_none());
        // Without the landmarks' helpful actions there is no second deferred search.
        let (_, deferred, lama_first) = three(&g, &SearchOptions { landmark_preferred: false, ..options.clone() });
        assert!(deferred.max_evaluated.is_none() && lama_first.is_none());
        // One thread or two, the same plan.
        let alone = search_plan(&g, &SearchOptions { lazy: true, landmarks: true, ..SearchOptions::default() });
        let beside = Searching::start(&Arc::new(g), options).map(Searching::join);
        if let Some(beside) = beside {
            assert_eq!(beside.unwrap().plan, alone.unwrap().plan);
        }
    }

    #[test]
    fn eager_search_gets_fewer_states_where_an_evaluation_costs_more() {
        let small = domains::blocks_world(4).unwrap();
        assert_eq!(eager_states(&search::Relaxation::new(&small)), EAGER_STATES);
        let large = domains::blocks_world(40).unwrap();
        let size = search::Relaxation::new(&large).size();
        assert!(size > EAGER_WORK / EAGER_STATES, "{size} entries");
        assert_eq!(eager_states(&search::Relaxation::new(&large)), EAGER_WORK / size);
    }
}
