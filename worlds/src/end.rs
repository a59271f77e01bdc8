//! End rules: what ends an episode besides the tick limit.
//!
//! A rule looks at each tick's root status (and the world) and may stop the episode.
//! Rules combine as tuples, checked in order: `(Failures::first(), SuccessTwice::default())`
//! is an episode of Styrud et al. ("aborted if the root returns Failure or if it returns
//! Success twice in a row"); `(Failures::in_a_row(2), GoalReached, Loops::default())` is
//! a robot that ticks on after one failed tick until the goal holds, and stops as soon as
//! a deterministic world comes back to where it was.

use std::collections::HashMap;
use std::hash::Hash;

use bt_core::Status;

/// Why an episode ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stop {
    /// An end rule saw the root fail ([`Failures`], [`Finished`]).
    Failure,
    /// An end rule saw the root succeed ([`SuccessTwice`], [`FirstSuccess`], [`Finished`]).
    Success,
    /// The root skipped the whole tree ([`Finished`]).
    Skipped,
    /// The root succeeded with the world's goal holding ([`GoalReached`]).
    Goal,
    /// The world came back to a state it was in before ([`Loops`]).
    Loop,
    /// The tick limit was reached first.
    Limit,
}

/// A rule that may end an episode after a tick. Tuples of rules check them in order,
/// the first that stops wins.
pub trait Ends<W: ?Sized> {
    /// A tree starts ticking in `world` (at the start of an episode, and again after the
    /// tree grew): forget what was seen.
    fn start(&mut self, world: &W) {
        let _ = world;
    }

    /// Tick `tick` returned `root`: whether the episode ends, and why.
    fn check(&mut self, tick: u32, root: Status, world: &W) -> Option<Stop>;
}

impl<W: ?Sized, E: Ends<W> + ?Sized> Ends<W> for &mut E {
    #[inline(always)]
    fn start(&mut self, world: &W) {
        (**self).start(world);
    }

    #[inline(always)]
    fn check(&mut self, tick: u32, root: Status, world: &W) -> Option<Stop> {
        (**self).check(tick, root, world)
    }
}

/// No rule: only the tick limit ends the episode.
impl<W: ?Sized> Ends<W> for () {
    #[inline(always)]
    fn check(&mut self, _: u32, _: Status, _: &W) -> Option<Stop> {
        None
    }
}

/// Maybe a rule: `None` never stops.
impl<W: ?Sized, E: Ends<W>> Ends<W> for Option<E> {
    #[inline(always)]
    fn start(&mut self, world: &W) {
        if let Some(e) = self {
            e.start(world);
        }
    }

    #[inline(always)]
    fn check(&mut self, tick: u32, root: Status, world: &W) -> Option<Stop> {
        self.as_mut().and_then(|e| e.check(tick, root, world))
    }
}

macro_rules! tuple_ends {
    ($($r:ident $i:tt),+) => {
        impl<W: ?Sized, $($r: Ends<W>),+> Ends<W> for ($($r,)+) {
            #[inline(always)]
            fn start(&mut self, world: &W) {
                $(self.$i.start(world);)+
            }

            #[inline(always)]
            fn check(&mut self, tick: u32, root: Status, world: &W) -> Option<Stop> {
                $(if let Some(stop) = self.$i.check(tick, root, world) {
                    return Some(stop);
                })+
                None
            }
        }
    };
}

tuple_ends!(A 0, B 1);
tuple_ends!(A 0, B 1, C 2);

/// The root failed on this many ticks in a row: 1 ends the episode at the first
/// Failure; 2 is a robot that ticks on after a failed tick and stops when the next one
/// fails too.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Failures {
    in_a_row: u32,
    seen: u32,
}

impl Failures {
    /// The first Failure ends the episode.
    #[must_use]
    pub const fn first() -> Self {
        Self::in_a_row(1)
    }

    /// `n` Failures in a row end the episode (at least 1).
    #[must_use]
    pub const fn in_a_row(n: u32) -> Self {
        Self { in_a_row: if n == 0 { 1 } else { n }, seen: 0 }
    }
}

impl<W: ?Sized> Ends<W> for Failures {
    fn start(&mut self, _: &W) {
        self.seen = 0;
    }

    #[inline]
    fn check(&mut self, _: u32, root: Status, _: &W) -> Option<Stop> {
        if root == Status::Failure {
            self.seen += 1;
            if self.seen >= self.in_a_row {
                return Some(Stop::Failure);
            }
        } else {
            self.seen = 0;
        }
        None
    }
}

/// The root succeeded on two ticks in a row (Styrud et al.: the world had one tick to
/// show that what the tree did holds). A Running or skipped tick in between starts over.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SuccessTwice {
    succeeded: bool,
}

impl<W: ?Sized> Ends<W> for SuccessTwice {
    fn start(&mut self, _: &W) {
        self.succeeded = false;
    }

    #[inline]
    fn check(&mut self, _: u32, root: Status, _: &W) -> Option<Stop> {
        match root {
            Status::Success if self.succeeded => return Some(Stop::Success),
            Status::Success => self.succeeded = true,
            _ => self.succeeded = false,
        }
        None
    }
}

/// The root's first Success ends the episode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FirstSuccess;

impl<W: ?Sized> Ends<W> for FirstSuccess {
    #[inline]
    fn check(&mut self, _: u32, root: Status, _: &W) -> Option<Stop> {
        (root == Status::Success).then_some(Stop::Success)
    }
}

/// The first tick on which the root returns anything but Running ends the episode: a
/// Success, a Failure, or a skip of the whole tree.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Finished;

impl<W: ?Sized> Ends<W> for Finished {
    #[inline]
    fn check(&mut self, _: u32, root: Status, _: &W) -> Option<Stop> {
        match root {
            Status::Running => None,
            Status::Success => Some(Stop::Success),
            Status::Failure => Some(Stop::Failure),
            Status::Skipped => Some(Stop::Skipped),
        }
    }
}

/// A world that knows its goal.
pub trait Goal {
    /// Whether every goal condition holds now.
    fn goal_reached(&self) -> bool;
}

/// The root succeeded *and* the world's goal holds. A Success with the goal false (an
/// action undid a condition checked earlier in the same tick) does not end the episode:
/// the next tick starts a new activation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GoalReached;

impl<W: Goal + ?Sized> Ends<W> for GoalReached {
    #[inline]
    fn check(&mut self, _: u32, root: Status, world: &W) -> Option<Stop> {
        (root == Status::Success && world.goal_reached()).then_some(Stop::Goal)
    }
}

/// A world whose progress can be counted and whose situation can be compared, for
/// [`Loops`].
pub trait Progress {
    /// What the world and the tree's running actions look like, compared for equality.
    type Key: Hash + Eq;

    /// A count that grows whenever something is done (the actions completed so far).
    fn progress(&self) -> usize;

    /// The situation now.
    fn key(&self) -> Self::Key;
}

/// The world came back to a situation it was in after something was done: a
/// deterministic tree in a deterministic world would repeat what it did since, forever.
/// Only for worlds that change by the tree alone.
#[derive(Clone, Debug)]
pub struct Loops<K> {
    seen: HashMap<K, usize>,
    done: usize,
    from: Option<usize>,
}

impl<K> Default for Loops<K> {
    fn default() -> Self {
        Self { seen: HashMap::new(), done: 0, from: None }
    }
}

impl<K> Loops<K> {
    /// After a [`Stop::Loop`]: the world's [`Progress::progress`] at the first visit of the
    /// situation; what was done from there on repeats.
    #[must_use]
    pub fn repeats_from(&self) -> Option<usize> {
        self.from
    }
}

impl<W: Progress + ?Sized> Ends<W> for Loops<W::Key> {
    fn start(&mut self, world: &W) {
        self.seen.clear();
        self.done = world.progress();
        self.from = None;
    }

    fn check(&mut self, _: u32, _: Status, world: &W) -> Option<Stop> {
        let done = world.progress();
        if done == self.done {
            return None;
        }
        self.done = done;
        let key = world.key();
        if let Some(&before) = self.seen.get(&key) {
            self.from = Some(before);
            return Some(Stop::Loop);
        }
        self.seen.insert(key, done);
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run<E: Ends<()>>(mut ends: E, statuses: &[Status]) -> Option<(u32, Stop)> {
        ends.start(&());
        (1..).zip(statuses).find_map(|(k, &s)| ends.check(k, s, &()).map(|stop| (k, stop)))
    }

    use Status::{Failure as F, Running as R, Skipped as K, Success as S};

    #[test]
    fn styrud_episodes_end_at_the_first_failure_or_the_second_success_in_a_row() {
        let ends = || (Failures::first(), SuccessTwice::default());
        assert_eq!(run(ends(), &[R, S, R, S, S]), Some((5, Stop::Success)));
        assert_eq!(run(ends(), &[S, K, S, R]), None);
        assert_eq!(run(ends(), &[S, F]), Some((2, Stop::Failure)));
    }

    #[test]
    fn failures_in_a_row_count_only_consecutive_ones() {
        assert_eq!(run(Failures::in_a_row(2), &[F, R, F, S, F, F]), Some((6, Stop::Failure)));
        assert_eq!(run(Failures::in_a_row(0), &[R, F]), Some((2, Stop::Failure)));
    }

    #[test]
    fn finished_names_what_the_root_did() {
        assert_eq!(run(Finished, &[R, K]), Some((2, Stop::Skipped)));
        assert_eq!(run(Finished, &[R, R, S]), Some((3, Stop::Success)));
        assert_eq!(run(FirstSuccess, &[F, S]), Some((2, Stop::Success)));
    }

    struct Counter {
        done: usize,
        at: u8,
        goal: bool,
    }

    impl Progress for Counter {
        type Key = u8;
        fn progress(&self) -> usize {
            self.done
        }
        fn key(&self) -> u8 {
            self.at
        }
    }

    impl Goal for Counter {
        fn goal_reached(&self) -> bool {
            self.goal
        }
    }

    #[test]
    fn a_world_back_where_it_was_loops() {
        let mut w = Counter { done: 0, at: 0, goal: false };
        let mut ends = (GoalReached, Loops::default());
        ends.start(&w);
        for (k, at) in [1u8, 2, 1].into_iter().enumerate() {
            w.done += 1;
            w.at = at;
            let stop = ends.check(k as u32 + 1, S, &w);
            assert_eq!(stop, (k == 2).then_some(Stop::Loop), "tick {k}");
        }
        assert_eq!(ends.1.repeats_from(), Some(1));
        // Nothing done: no new situation, however long.
        assert_eq!(ends.check(4, R, &w), None);
        w.goal = true;
        assert_eq!(ends.check(5, S, &w), Some(Stop::Goal));
        ends.start(&w);
        assert_eq!(ends.1.repeats_from(), None);
    }
}
