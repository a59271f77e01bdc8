//! Search on threads of its own while Algorithm 1 runs ([`crate::Options::parallel`]):
//! with [`SearchOptions::lazy`], eager search with h_FF within a budget of evaluated
//! states (smaller on large groundings) beside deferred search, the eager plan taken
//! where it finds one within that budget. With landmarks, the deferred search (which
//! prefers the landmark count's helpful actions too) has a budget as well, and once
//! eager search's is spent, a deferred search as Fast Downward's lama-first (only
//! h_FF's helpful actions preferred) starts on its thread. The landmark-preferring
//! search's plan is taken where it comes within its budget; past it, both deferred
//! searches go on, and the plan of the one that needs fewer evaluations is taken
//! (the landmark-preferring one's on a tie): whichever ends first lowers the other's
//! bound of evaluated states to its own count. The plan never depends on which
//! thread ends first.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc;
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
/// ([`SearchOptions::landmark_preferred`]) may evaluate before its plan has to need
/// fewer evaluations than the lama-first search's to be taken. Parking's plans need
/// those helpful actions and come within 2,000 evaluations; pipesworld-tankage p23's
/// plan came from lama-first after about 8,100 where the landmark-preferring search
/// found none in 60 s; tetris-sat14 p029's comes from the landmark-preferring search
/// after 98,999 where lama-first found none in 60 s.
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

/// The three searches, in the order their plans are taken (see the module docs).
struct Three {
    eager: SearchOptions,
    /// The deferred search, with no bound of its own.
    deferred: SearchOptions,
    /// Where the deferred search prefers the landmarks' helpful actions: its budget of
    /// evaluated states and the lama-first search's options (`None` otherwise; the
    /// deferred search's plan is then the only one after eager search's).
    lama_first: Option<(u64, SearchOptions)>,
}

impl Three {
    fn new(g: &Grounding, options: &SearchOptions) -> Self {
        // The budgets depend only on the grounding's size, so the plan not on the machine.
        let h = search::Relaxation::new(g);
        let eager = SearchOptions { lazy: false, max_evaluated: Some(eager_states(&h)), ..options.clone() };
        let lama_first = (options.landmarks && options.landmark_preferred)
            .then(|| (landmark_preferred_states(&h), SearchOptions { landmark_preferred: false, ..options.clone() }));
        Self { eager, deferred: options.clone(), lama_first }
    }
}

/// Whether a search gave up at its budget or memory bound (a later one may still find
/// a plan).
fn out_of_budget(r: &Result<Found, PlanError>) -> bool {
    matches!(r, Err(PlanError::OutOfStates { .. } | PlanError::SearchMemory { .. }))
}

/// The plan taken from the landmark-preferring search (`deferred`, its budget
/// `budget`) and the lama-first search: the first's where it needs at most `budget`
/// evaluations or no more than the second's, else the second's where it found one,
/// else the first's outcome (an error; the second's where the first's is only that it
/// was stopped or ran out of memory).
fn taken(
    deferred: Result<Found, PlanError>,
    lama_first: Result<Found, PlanError>,
    budget: u64,
) -> Result<Found, PlanError> {
    match (deferred, lama_first) {
        (Ok(d), Ok(l)) => Ok(if d.evaluated <= budget.max(l.evaluated) { d } else { l }),
        (Ok(d), Err(_)) => Ok(d),
        (Err(e @ PlanError::NoPlan(_)), _) => Err(e),
        (Err(_), l @ Ok(_)) => l,
        (d, Err(l)) => {
            if out_of_budget(&d) {
                Err(l)
            } else {
                d
            }
        }
    }
}

/// Eager search's budget of evaluated states: [`EAGER_STATES`], fewer where they
/// would visit more than [`EAGER_WORK`] entries of the grounding's relaxation `h`.
fn eager_states(h: &search::Relaxation) -> u64 {
    EAGER_STATES.min(EAGER_WORK / h.size().max(1)).max(1)
}

/// One search on its own thread; dropped, it is stopped and joined.
struct Running {
    stop: Arc<AtomicBool>,
    /// Its bound of evaluated states ([`SearchOptions::max_evaluated_live`]).
    bound: Arc<AtomicU64>,
    handle: Option<JoinHandle<Result<Found, PlanError>>>,
}

impl Running {
    /// Starts `options`' search; once it ends, `ended`'s channel is sent its tag.
    fn start(g: &Arc<Grounding>, options: SearchOptions, ended: Option<(mpsc::Sender<u8>, u8)>) -> Option<Self> {
        let stop = Arc::new(AtomicBool::new(false));
        let bound = Arc::new(AtomicU64::new(u64::MAX));
        let options = SearchOptions { stop: Some(stop.clone()), max_evaluated_live: Some(bound.clone()), ..options };
        let g = g.clone();
        let handle = std::thread::Builder::new()
            .name("planner-search".into())
            .spawn(move || {
                let found = search::gbfs(&g, &options);
                if let Some((to, tag)) = ended {
                    // The receiver may be gone: the plan is no longer wanted.
                    let _ = to.send(tag);
                }
                found
            })
            .ok()?;
        Some(Self { stop, bound, handle: Some(handle) })
    }

    /// Lowers the most states the (deferred) search may evaluate to `n`.
    fn bound(&self, n: u64) {
        self.bound.fetch_min(n, Ordering::Relaxed);
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

/// Tags of the deferred searches on the channel they say they ended on.
const DEFERRED: u8 = 0;
const LAMA_FIRST: u8 = 1;

/// The searches for a plan, running.
pub(super) struct Searching {
    g: Arc<Grounding>,
    eager: Option<Running>,
    deferred: Option<Running>,
    /// The landmark-preferring search's budget and the lama-first search's options,
    /// started once eager search ends.
    lama_first: Option<(u64, SearchOptions)>,
    /// The channel the deferred searches say they ended on.
    ended: (mpsc::Sender<u8>, mpsc::Receiver<u8>),
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
            let eager = Some(Running::start(g, options, None)?);
            return Some(Self { g: g.clone(), eager, deferred: None, lama_first: None, ended: mpsc::channel() });
        }
        Self::start_three(g, Three::new(g, &options))
    }

    fn start_three(g: &Arc<Grounding>, three: Three) -> Option<Self> {
        let ended = mpsc::channel();
        Some(Self {
            g: g.clone(),
            eager: Some(Running::start(g, three.eager, None)?),
            deferred: Some(Running::start(g, three.deferred, Some((ended.0.clone(), DEFERRED)))?),
            lama_first: three.lama_first,
            ended,
        })
    }

    /// Waits for the plan: eager search's where it found one within its budget (or
    /// proved there is none), else the deferred searches' (see the module docs).
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
        // Eager search's thread is free: lama-first runs there beside deferred search.
        let (to, ended) = self.ended;
        let Some((budget, options)) = self.lama_first.take() else {
            return deferred.join();
        };
        let Some(lama_first) = Running::start(&self.g, options, Some((to, LAMA_FIRST))) else {
            return deferred.join();
        };
        if ended.recv() == Ok(LAMA_FIRST) {
            let l = lama_first.join();
            if let Ok(found) = &l {
                deferred.bound(budget.max(found.evaluated));
            }
            return taken(deferred.join(), l, budget);
        }
        let d = deferred.join();
        match &d {
            Ok(found) if found.evaluated <= budget => return d,
            Err(PlanError::NoPlan(_)) => return d,
            Ok(found) => lama_first.bound(found.evaluated - 1),
            Err(_) => {}
        }
        taken(d, lama_first.join(), budget)
    }
}

/// The plan of [`Searching`], searched for on this thread: eager search within its
/// budget, then the deferred searches. Past the landmark-preferring search's budget,
/// each deferred search runs again from the start with twice the bound of evaluated
/// states until one finds a plan within it, so the plan is the one [`Searching`]
/// takes.
pub(super) fn search_plan(g: &Grounding, options: &SearchOptions) -> Result<Found, PlanError> {
    if !options.lazy {
        return search::gbfs(g, options);
    }
    search_three(g, Three::new(g, options))
}

fn search_three(g: &Grounding, three: Three) -> Result<Found, PlanError> {
    let found = search::gbfs(g, &three.eager);
    if !out_of_budget(&found) {
        return found;
    }
    let Some((budget, lama_first)) = three.lama_first else {
        return search::gbfs(g, &three.deferred);
    };
    let within = |o: &SearchOptions, n: u64| search::gbfs(g, &SearchOptions { max_evaluated: Some(n), ..o.clone() });
    let found = within(&three.deferred, budget);
    if !out_of_budget(&found) {
        return found;
    }
    if !matches!(found, Err(PlanError::OutOfStates { .. })) {
        return taken(found, search::gbfs(g, &lama_first), budget);
    }
    let mut bound = budget;
    loop {
        bound = bound.saturating_mul(2);
        let l = within(&lama_first, bound);
        let d = within(&three.deferred, bound);
        let l_over = matches!(l, Err(PlanError::OutOfStates { .. }));
        let d_over = matches!(d, Err(PlanError::OutOfStates { .. }));
        match (d_over, l_over) {
            // Neither ended within the bound: both go on.
            (true, true) => {}
            // The lama-first search ended without a plan: the other's, unbounded.
            (true, false) if l.is_err() => return taken(search::gbfs(g, &three.deferred), l, budget),
            // The landmark-preferring search ended without a plan, or gave up.
            (false, true) if d.is_err() => return taken(d, search::gbfs(g, &lama_first), budget),
            _ => return taken(d, l, budget),
        }
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
        let three = Three::new(&g, &options);
        assert_eq!(three.eager.max_evaluated, Some(EAGER_STATES));
        assert!(three.deferred.max_evaluated.is_none());
        let (budget, lama_first) = three.lama_first.unwrap();
        assert_eq!(budget, LANDMARK_PREFERRED_STATES);
        assert!(!lama_first.landmark_preferred && lama_first.max_evaluated.is_none());
        // Without the landmarks' helpful actions there is no second deferred search.
        let three = Three::new(&g, &SearchOptions { landmark_preferred: false, ..options.clone() });
        assert!(three.deferred.max_evaluated.is_none() && three.lama_first.is_none());
        // One thread or two, the same plan.
        let alone = search_plan(&g, &options);
        let beside = Searching::start(&Arc::new(g), options).map(Searching::join);
        if let Some(beside) = beside {
            assert_eq!(beside.unwrap().plan, alone.unwrap().plan);
        }
    }

    /// The portfolio's options on blocks world with `blocks` blocks, eager search given
    /// one state and the first deferred search `budget`, with the plans of the first and
    /// the second deferred search. `swapped`: the lama-first search first (the rule
    /// does not ask which search is which, and on blocks world lama-first needs fewer
    /// evaluations).
    fn deferred_pair(blocks: usize, budget: u64, swapped: bool) -> (Grounding, Found, Found, Three) {
        let g = domains::blocks_world(blocks).unwrap();
        let options = SearchOptions { lazy: true, landmarks: true, ..SearchOptions::default() };
        let mut three = Three::new(&g, &options);
        three.eager.max_evaluated = Some(1);
        let mut second = three.lama_first.take().unwrap().1;
        if swapped {
            std::mem::swap(&mut three.deferred, &mut second);
        }
        let d = search::gbfs(&g, &three.deferred).unwrap();
        let l = search::gbfs(&g, &second).unwrap();
        three.lama_first = Some((budget, second));
        (g, d, l, three)
    }

    /// The portfolio's plan on one thread and on two (the same where the machine has two
    /// cores).
    fn portfolio(g: Grounding, three: &Three) -> Found {
        let copy = || Three {
            eager: three.eager.clone(),
            deferred: three.deferred.clone(),
            lama_first: three.lama_first.clone(),
        };
        let alone = search_three(&g, copy()).unwrap();
        if std::thread::available_parallelism().map_or(1, usize::from) >= 2 {
            let beside = Searching::start_three(&Arc::new(g), copy()).unwrap().join().unwrap();
            assert_eq!(beside, alone);
        }
        alone
    }

    #[test]
    fn past_its_budget_the_deferred_search_needing_fewer_evaluations_gives_the_plan() {
        // The first search needs more evaluations than the second: the second's plan,
        // unless the first's comes within the first's budget.
        let (g, d, l, mut three) = deferred_pair(8, 3, false);
        assert!(3 < l.evaluated && l.evaluated < d.evaluated, "{} {}", d.evaluated, l.evaluated);
        assert_eq!(portfolio(g, &three), l);
        three.lama_first.as_mut().unwrap().0 = d.evaluated;
        assert_eq!(portfolio(domains::blocks_world(8).unwrap(), &three), d);
        // The first needs fewer: its plan, past its budget too (tetris-sat14 p029, where
        // the landmark-preferring search needs 98,999 evaluations and lama-first finds
        // none in 60 s).
        let (g, d, l, three) = deferred_pair(8, 3, true);
        assert!(3 < d.evaluated && d.evaluated < l.evaluated, "{} {}", d.evaluated, l.evaluated);
        assert_eq!(portfolio(g, &three), d);
    }

    #[test]
    fn the_plan_taken_from_the_two_deferred_searches() {
        let found = |evaluated: u64| Ok(Found { plan: vec![], expanded: 0, stored: 0, evaluated, initial_h: 0 });
        let evaluated = |r: Result<Found, PlanError>| r.map(|f| f.evaluated);
        // Within budget the landmark-preferring search's, past it the fewer evaluations'
        // (a tie to the landmark-preferring search's).
        assert_eq!(evaluated(taken(found(90), found(10), 100)), Ok(90));
        assert_eq!(evaluated(taken(found(190), found(150), 100)), Ok(150));
        assert_eq!(evaluated(taken(found(150), found(150), 100)), Ok(150));
        assert_eq!(evaluated(taken(found(150), found(190), 100)), Ok(150));
        let stopped = || Err(PlanError::OutOfStates { evaluated: 5 });
        assert_eq!(evaluated(taken(stopped(), found(190), 100)), Ok(190));
        assert_eq!(evaluated(taken(found(190), stopped(), 100)), Ok(190));
        let none = || Err(PlanError::NoPlan("none".into()));
        assert!(matches!(taken(none(), found(190), 100), Err(PlanError::NoPlan(_))));
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
