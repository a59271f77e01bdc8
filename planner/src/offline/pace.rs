//! How long guided backchaining may take when planning has a deadline: a share of the
//! time left, and no longer than its own progress through the plan promises
//! ([`Pace`]), so that the plan's regression tree is still made in time.

use std::time::{Duration, Instant};

use crate::PlanError;

/// The least time a guided tree grows before its pace is judged: its first runs say
/// little about the rest.
const FIRST_LOOK: Duration = Duration::from_millis(250);

/// The pace of guided backchaining against a deadline of its own: after each run that
/// fails, how far the tree got along the plan (the actions it executed from the initial
/// state), and from that when it would be done.
///
/// Each run of the tree starts again from the initial state, and the tree grows as it
/// gets further, so a tree that got a fraction `f` of the way in time `t` takes about
/// `t / f²` in all; one that will not be done by its deadline gives way at once to the
/// plan's regression tree instead of using the time that tree needs (visitall's guided
/// trees cycled for 20 s among the first four of a 900-step plan).
#[derive(Clone, Copy, Debug)]
pub(super) struct Pace {
    steps: usize,
    since: Instant,
    until: Instant,
    best: usize,
}

impl Pace {
    /// A guided tree for a plan of `steps` actions, starting now, that gets half the
    /// time left before `deadline`.
    pub(super) fn new(steps: usize, deadline: Instant) -> Self {
        let since = Instant::now();
        Self { steps: steps.max(1), since, until: since + deadline.saturating_duration_since(since) / 2, best: 0 }
    }

    /// When the guided tree must be done.
    pub(super) fn until(&self) -> Instant {
        self.until
    }

    /// After a run that executed `done` actions before the tree failed:
    /// [`PlanError::Behind`] where the tree will not be done in its time at this pace.
    ///
    /// # Errors
    /// As above.
    pub(super) fn check(&mut self, done: usize) -> Result<(), PlanError> {
        self.best = self.best.max(done);
        let spent = self.since.elapsed();
        if spent < FIRST_LOOK {
            return Ok(());
        }
        let f = (self.best.max(1) as f64 / self.steps as f64).min(1.0);
        let projected = spent.as_secs_f64() / (f * f);
        let allowed = self.until.saturating_duration_since(self.since);
        if projected > allowed.as_secs_f64() {
            return Err(PlanError::Behind { done: self.best, steps: self.steps, spent, allowed });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tree_that_got_nowhere_gives_way_once_judged() {
        let mut pace = Pace::new(900, Instant::now() + Duration::from_secs(10));
        assert!(pace.check(4).is_ok(), "not judged before its first look");
        pace.since -= FIRST_LOOK;
        let e = pace.check(4).unwrap_err();
        assert!(matches!(e, PlanError::Behind { done: 4, steps: 900, .. }), "{e}");
    }

    #[test]
    fn a_tree_on_pace_goes_on() {
        let mut pace = Pace::new(100, Instant::now() + Duration::from_secs(10));
        pace.since -= FIRST_LOOK;
        // A quarter of the way in a quarter second: about 4 s in all, within its 5 s.
        assert!(pace.check(25).is_ok());
        assert!(pace.until() <= Instant::now() + Duration::from_secs(5));
    }
}
