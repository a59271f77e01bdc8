//! How long the closure over disturbances may take: in proportion to the first tree's
//! time when planning has a deadline ([`closure_deadline`]).

use std::time::Instant;

use crate::options::Options;

/// The closure's budget: [`Options::close_nodes`], and the time up to `until`
/// ([`closure_deadline`]).
pub(super) fn close_budget(options: Options, until: Option<Instant>) -> crate::regress::Budget {
    crate::regress::Budget { deadline: until, nodes: options.close_nodes, ..crate::regress::Budget::default() }
}

/// The least time the closure over disturbances gets with a deadline
/// ([`closure_deadline`]): a tree found at once is still closed over the disturbances
/// of its first levels.
const MIN_CLOSURE: std::time::Duration = std::time::Duration::from_millis(600);

/// When the closure over disturbances of a tree first ready at `first` must stop, with
/// [`Options::deadline`] (`None` without one: the closure then stops only at its budget
/// of states, plans and nodes, and the tree does not depend on the machine's speed).
///
/// The closure gets as long as the first tree took since `started` (at least
/// [`MIN_CLOSURE`]), and at most half the time left (the rest for the checks): the
/// closed tree comes at most about twice as late as the first one. The closure looks at
/// the states with fewer disturbances first and the tree is correct at every point, so
/// the tree it stops with is the one that copes with the likeliest disturbances. Every
/// closure of the same plan (the cuts to fit, the regression tree compared with a
/// guided one) shares this one deadline.
pub(super) fn closure_deadline(options: Options, started: Instant, first: Instant) -> Option<Instant> {
    options.deadline.map(|d| {
        let half = first + d.saturating_duration_since(first) / 2;
        let own = first + first.saturating_duration_since(started).max(MIN_CLOSURE);
        half.min(own)
    })
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    #[test]
    fn the_closure_gets_the_first_trees_time_at_least_the_minimum_at_most_half_the_rest() {
        let started = Instant::now();
        let s = |ms: u64| started + Duration::from_millis(ms);
        let with = |deadline_ms: u64| Options { deadline: Some(s(deadline_ms)), ..Options::default() };
        // Without a deadline, no time limit: the tree does not depend on the machine.
        assert_eq!(closure_deadline(Options::default(), started, s(1_000)), None);
        // A first tree after 1 s: the closure until 2 s.
        assert_eq!(closure_deadline(with(10_000), started, s(1_000)), Some(s(2_000)));
        // One found at once: the minimum.
        assert_eq!(closure_deadline(with(10_000), started, s(10)), Some(s(10) + MIN_CLOSURE));
        // One after 6 s of 10: half the 4 s left.
        assert_eq!(closure_deadline(with(10_000), started, s(6_000)), Some(s(8_000)));
        // The budget carries the deadline and the node budget.
        let b = close_budget(Options { close_nodes: 100, ..Options::default() }, Some(s(5)));
        assert_eq!((b.deadline, b.nodes), (Some(s(5)), 100));
    }
}
