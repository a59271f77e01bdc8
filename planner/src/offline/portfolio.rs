//! Search on a second thread while Algorithm 1 runs ([`crate::Options::parallel`]).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;

use crate::PlanError;
use crate::ground::Grounding;
use crate::search::{self, Found, SearchOptions};

/// A search for a plan running on its own thread; dropped, it is stopped and joined.
pub(super) struct Searching {
    stop: Arc<AtomicBool>,
    handle: Option<JoinHandle<Result<Found, PlanError>>>,
}

impl Searching {
    /// Starts greedy best-first search ([`search::gbfs`]) on a thread of its own, when
    /// the machine has two cores or more (`None` otherwise, or when no thread can be
    /// made: the caller then searches itself, after Algorithm 1).
    pub(super) fn start(g: &Arc<Grounding>, options: SearchOptions) -> Option<Self> {
        if std::thread::available_parallelism().map_or(1, usize::from) < 2 {
            return None;
        }
        let stop = Arc::new(AtomicBool::new(false));
        let options = SearchOptions { stop: Some(stop.clone()), ..options };
        let g = g.clone();
        let handle =
            std::thread::Builder::new().name("planner-search".into()).spawn(move || search::gbfs(&g, &options)).ok()?;
        Some(Self { stop, handle: Some(handle) })
    }

    /// Waits for the search's result.
    pub(super) fn join(mut self) -> Result<Found, PlanError> {
        let handle = self.handle.take();
        match handle.map(JoinHandle::join) {
            Some(Ok(found)) => found,
            _ => Err(PlanError::NoPlan("the search thread ended without a result".into())),
        }
    }
}

impl Drop for Searching {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(h) = self.handle.take() {
            // It stops within 256 expansions; its result is not wanted.
            let _ = h.join();
        }
    }
}
