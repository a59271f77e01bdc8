//! Ways back from a state a disturbance led to, to a state where one of the tree's
//! rules holds: a short path ([`repair`]), the rest of a plan already added
//! ([`Policy::resume`]), a search on the rules' unmet conditions ([`Policy::rejoin`]),
//! or a new plan to the goal ([`way_back`] chooses).

use std::collections::{HashMap, HashSet};
use std::time::Instant;

use super::close::Budget;
use super::{Closed, Policy, Rule, successor};
use crate::PlanError;
use crate::ground::{ActionId, AtomId, Grounding};
use crate::guide::Trace;
use crate::search::{self, SearchOptions};
use crate::state::State;

/// Most states [`Policy::rejoin`] stores.
const REJOIN_STATES: usize = 5_000;

impl Policy {
    /// A way back to the rules from `t` that follows the end of one of the plans
    /// added, and the rule it leads to: where a disturbance did a step out of turn (a
    /// product made, an order started) that no action undoes, the plan's rest without
    /// that step often still reaches the goal, found with no search, and soon meets
    /// the plan's own states. A step that cannot be done is left out where what it
    /// adds holds (done out of turn, or no longer needed), else done after the first of
    /// the actions `own` that makes it possible again (an order the agent started took
    /// the stack the plan opened for another: one more opened), else left out.
    /// `distance` is how far from the goal the tree was before the disturbance: the
    /// first plan and the eight latest are tried from that far before their end (and
    /// up to two steps earlier, the latest start whose rest reaches the goal); the way
    /// is cut at the first state where a rule holds (or the goal), and the shortest way
    /// to the goal kept. A few runs along each plan: no search.
    #[must_use]
    pub fn resume(&self, g: &Grounding, t: &State, distance: u32, own: &[ActionId]) -> Option<(Vec<ActionId>, Rule)> {
        let n = self.plans.len();
        let recent = n.saturating_sub(RESUME_PLANS).max(1);
        let mut best: Option<Vec<ActionId>> = None;
        for plan in self.plans.iter().take(1).chain(self.plans.iter().skip(recent)) {
            let Some(at) = plan.len().checked_sub(distance as usize) else { continue };
            for start in (at.saturating_sub(RESUME_BACK)..=at).rev() {
                let mut s = t.clone();
                let mut done = Vec::new();
                for &a in &plan[start..] {
                    if g.goal_holds(&s) {
                        break;
                    }
                    let Some(x) = g.action(a) else { continue };
                    if !x.applicable(&s) {
                        // Done out of turn (what it adds holds), or one action of the
                        // tree's away: a stack opened for an order another one took.
                        if x.add.iter().all(|&atom| s.holds(atom)) {
                            continue;
                        }
                        let Some((b, after)) =
                            own.iter().find_map(|&b| successor(g, b, &s).filter(|u| x.applicable(u)).map(|u| (b, u)))
                        else {
                            continue;
                        };
                        s = after;
                        done.push(b);
                    }
                    g.apply(x, &mut s);
                    done.push(a);
                }
                if g.goal_holds(&s) {
                    if best.as_ref().is_none_or(|b| done.len() < b.len()) {
                        best = Some(done);
                    }
                    break;
                }
            }
        }
        let steps = best?;
        let trace = Trace::from_state(g, t, &steps)?;
        for i in 1..steps.len() {
            if let Some(r) = trace.state(i).and_then(|s| self.first(s)) {
                return Some((steps[..i].to_vec(), r.clone()));
            }
        }
        Some((steps, Rule::goal(g)))
    }

    /// A path from `t` to a state where a rule (or the goal) holds, and the first rule
    /// that holds there: best-first search on the conditions of the nearest rule that
    /// do not hold plus the actions taken (one action weighs as one condition; ties: the
    /// rule nearer the goal), leaving out the rules that need a fact false in `t` that no
    /// action makes true; with the actions `own` first, then with any. `None` when
    /// neither finds one within 5,000 stored states or by `deadline`. Where a
    /// disturbance did a step of a long plan out of turn, the plan's own later steps
    /// lead back to its rules long before the goal: a new plan to the goal would add a
    /// rule for every one of its steps.
    #[must_use]
    pub fn rejoin(
        &self,
        g: &Grounding,
        t: &State,
        own: &[ActionId],
        deadline: Option<Instant>,
    ) -> Option<(Vec<ActionId>, Rule)> {
        let goal = Rule::goal(g);
        // A rule with a condition that is false in `t` and that no action makes true
        // (a product made, a day gone) is out of reach: left out of the score. Derived
        // atoms have no achievers but follow the basic ones.
        let within =
            |r: &&Rule| r.when.iter().all(|&l| l.holds(t) || g.is_derived(l.atom) || !g.achievers(l).is_empty());
        let near: Vec<&Rule> = std::iter::once(&goal).chain(self.rules.iter()).filter(within).collect();
        let mut nearest = Nearest::new(&near, t);
        // The tree's own actions first, as in `repair`.
        let mut allowed = vec![false; g.actions().len()];
        for &a in own {
            if let Some(x) = allowed.get_mut(a as usize) {
                *x = true;
            }
        }
        // One action costs as much as one unmet condition.
        let plan = search::best_first_to(g, t, Some(&allowed), 1 << 32, REJOIN_STATES, deadline, |s| nearest.score(s))
            .or_else(|| search::best_first_to(g, t, None, 1 << 32, REJOIN_STATES, deadline, |s| nearest.score(s)))?;
        let end = Trace::from_state(g, t, &plan)?.state(plan.len())?.clone();
        let rule = if g.goal_holds(&end) { goal } else { self.first(&end)?.clone() };
        Some((plan, rule))
    }
}

/// The score [`Policy::rejoin`] searches by: for a state, the fewest conditions of one
/// of `rules` that do not hold there, and that rule's distance, as `unmet << 32 |
/// distance` (0 where one holds). The searched states differ from the start `t` in a
/// few atoms, and a rule's count changes only through those: the counts in `t` are
/// taken once, and a state's score is found from the atoms where it differs from `t`
/// (each with the rules that name it) and, for the rules none of those atoms touches,
/// the best of them in `t`. The same score as counting every rule's conditions, in a
/// fraction of the time where the tree has hundreds of rules.
struct Nearest<'r> {
    rules: Vec<&'r Rule>,
    /// Unmet conditions of each rule in `t`.
    base: Vec<u32>,
    /// The rules by `(base, distance)`, best first.
    by_score: Vec<u32>,
    /// For each atom a rule names: the rules, and whether they need it true.
    naming: HashMap<AtomId, Vec<(u32, bool)>>,
    t: State,
    /// Change of each rule's count in the state scored, for the rules in `touched`.
    delta: Vec<i32>,
    touched: Vec<u32>,
    /// Which rules are in `touched` (`mark[r] == stamp`).
    mark: Vec<u32>,
    stamp: u32,
}

impl<'r> Nearest<'r> {
    fn new(rules: &[&'r Rule], t: &State) -> Self {
        let mut naming: HashMap<AtomId, Vec<(u32, bool)>> = HashMap::new();
        let mut base = Vec::with_capacity(rules.len());
        for (k, r) in rules.iter().enumerate() {
            base.push(r.when.iter().filter(|l| !l.holds(t)).count() as u32);
            for l in &r.when {
                naming.entry(l.atom).or_default().push((k as u32, l.positive));
            }
        }
        let key = |k: u32| {
            let k = k as usize;
            (u64::from(base.get(k).copied().unwrap_or(u32::MAX)) << 32)
                | u64::from(rules.get(k).map_or(0, |r| r.distance))
        };
        let mut by_score: Vec<u32> = (0..rules.len() as u32).collect();
        by_score.sort_by_key(|&k| key(k));
        Self {
            rules: rules.to_vec(),
            base,
            by_score,
            naming,
            t: t.clone(),
            delta: vec![0; rules.len()],
            touched: Vec::new(),
            mark: vec![0; rules.len()],
            stamp: 0,
        }
    }

    fn score(&mut self, s: &State) -> u64 {
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.mark.fill(0);
            self.stamp = 1;
        }
        self.touched.clear();
        for (i, (&a, &b)) in s.words().iter().zip(self.t.words()).enumerate() {
            let mut diff = a ^ b;
            while diff != 0 {
                let atom = (i as u32) * 64 + diff.trailing_zeros();
                diff &= diff - 1;
                let now = s.holds(atom);
                for &(r, positive) in self.naming.get(&atom).map_or(&[][..], Vec::as_slice) {
                    let k = r as usize;
                    if let (Some(m), Some(d)) = (self.mark.get_mut(k), self.delta.get_mut(k)) {
                        if *m != self.stamp {
                            *m = self.stamp;
                            *d = 0;
                            self.touched.push(r);
                        }
                        // The literal holds now where it did not in `t`, or the other way.
                        *d += if positive == now { -1 } else { 1 };
                    }
                }
            }
        }
        let key = |k: usize, unmet: i64| -> u64 {
            (u64::try_from(unmet).unwrap_or(0) << 32) | u64::from(self.rules.get(k).map_or(0, |r| r.distance))
        };
        let mut best = u64::MAX;
        for &r in &self.touched {
            let k = r as usize;
            let unmet =
                i64::from(self.base.get(k).copied().unwrap_or(0)) + i64::from(self.delta.get(k).copied().unwrap_or(0));
            best = best.min(key(k, unmet));
        }
        if let Some(&r) = self.by_score.iter().find(|&&r| self.mark.get(r as usize) != Some(&self.stamp)) {
            let k = r as usize;
            best = best.min(key(k, i64::from(self.base.get(k).copied().unwrap_or(0))));
        }
        if best >> 32 == 0 { 0 } else { best }
    }
}

/// A way back: its actions, and the rule it leads to.
pub(super) type Way = (Vec<ActionId>, Rule);

/// The ways back for `t`, the state a disturbance led to from `s`, that need no new
/// plan: a short way back to the rules, else a longer way back or the rest of a plan
/// that is no farther from the goal than the tree was before the disturbance
/// (`Ok`); else (`Err`) the cheapest of those found, to weigh against a new plan.
fn near(
    g: &Grounding,
    policy: &Policy,
    s: &State,
    t: &State,
    own: &[ActionId],
    deadline: Option<Instant>,
) -> Result<Way, Option<Way>> {
    if let Some(way) = repair(g, policy, t, own) {
        return Ok(way);
    }
    let before = policy.first(s).map(|r| r.distance);
    let no_farther = |way: &Option<Way>| {
        way.as_ref().zip(before).is_some_and(|((p, r), d)| p.len() + r.distance as usize <= d as usize)
    };
    // The rest of a plan first: a few runs along it, where the search below stores up
    // to thousands of states, scoring each against every rule.
    let resumed = before.and_then(|d| policy.resume(g, t, d, own));
    if no_farther(&resumed) {
        return resumed.ok_or(None);
    }
    let rejoined = policy.rejoin(g, t, own, deadline);
    if no_farther(&rejoined) {
        return rejoined.ok_or(None);
    }
    Err(cheaper(own, resumed, rejoined))
}

/// The cheaper of two ways, where a way costs its length to the goal plus one for every
/// action it brings that the tree (`own`) does not have yet; `a` on a tie.
fn cheaper(own: &[ActionId], a: Option<Way>, b: Option<Way>) -> Option<Way> {
    let cost = |(steps, r): &Way| steps.len() + r.distance as usize + novel(steps, own);
    match (a, b) {
        (Some(a), Some(b)) => Some(if cost(&b) < cost(&a) { b } else { a }),
        (a, b) => a.or(b),
    }
}

/// A way back for `t` that needs no new plan ([`near`]), or else the cheapest way back
/// the look found all the same (one that leads farther from the goal than the tree
/// was), if any: [`close`] serves the states that have one before those that need a
/// new plan to the goal, whose rules take many more nodes and whose search takes many
/// times longer.
///
/// [`close`]: super::close()
pub(super) fn near_way_back(
    g: &Grounding,
    policy: &Policy,
    s: &State,
    t: &State,
    own: &[ActionId],
    budget: &Budget,
) -> Result<Way, Option<Way>> {
    near(g, policy, s, t, own, search_deadline(budget.deadline, Instant::now(), false))
}

/// A way back for `t`, the state a disturbance led to from `s`: one that needs no new
/// plan ([`near`]); else the cheapest of those and a new plan (see the module docs).
/// `own` is the tree's actions. `None` when there is none (counted in `done` as a dead
/// end, or as given up when the search ran out of time).
pub(super) fn way_back(
    g: &Grounding,
    policy: &Policy,
    s: &State,
    t: &State,
    own: &[ActionId],
    budget: &Budget,
    done: &mut Closed,
) -> Option<Way> {
    let deadline = search_deadline(budget.deadline, Instant::now(), false);
    let known = match near(g, policy, s, t, own, deadline) {
        Ok(way) => return Some(way),
        Err(known) => known,
    };
    // Both `None` without a closure deadline, else both `Some`.
    let deadline =
        if known.is_some() { search_deadline(budget.deadline, Instant::now(), true).min(deadline) } else { deadline };
    let options = SearchOptions { deadline, ..SearchOptions::default() };
    match search::gbfs_from(g, t, &options) {
        // On a tie the plan: rules regressed from the goal hold in more states than
        // those from another rule.
        Ok(found) => cheaper(own, Some((found.plan, Rule::goal(g))), known),
        Err(PlanError::NoPlan(_)) if known.is_none() => {
            done.dead_ends += 1;
            None
        }
        // One hard state does not end the closure: the others may be easy.
        Err(_) => {
            if known.is_none() {
                done.given_up += 1;
            }
            known
        }
    }
}

/// How many distinct actions of `steps` are not in `own`.
fn novel(steps: &[ActionId], own: &[ActionId]) -> usize {
    let mut new: Vec<ActionId> = steps.iter().copied().filter(|a| !own.contains(a)).collect();
    new.sort_unstable();
    new.dedup();
    new.len()
}

/// The deadline, from `now`, of one search of [`close`] that must stop by `closure`
/// (the closure's deadline): an eighth of the closure's time left (at least
/// [`MIN_SEARCH`]), so that a state from which a plan is hard to find, or to prove
/// absent, does not use up the time of all the others. Where a way back is `known`
/// already, the search can only find a cheaper one, while the states not yet looked at
/// may have none: it gets [`KNOWN_SHARE`] of that. (In ged a way back from a cut
/// started out of turn is found at once, and a new plan to the goal is seldom found
/// within a search's eighth: with the whole eighth, the closure of d-11-6 looks at 27 to
/// 40 of the 69 states it looks at without a deadline, with a quarter of it all 69.)
fn search_deadline(closure: Option<Instant>, now: Instant, known: bool) -> Option<Instant> {
    let share = if known { KNOWN_SHARE } else { 1 };
    closure.map(|d| d.min(now + (d.saturating_duration_since(now) / (8 * share)).max(MIN_SEARCH / share)))
}

/// The least time one search of [`close`] gets (within the closure's deadline).
const MIN_SEARCH: std::time::Duration = std::time::Duration::from_millis(100);
/// The share of [`search_deadline`]'s time a search gets where a way back is known.
const KNOWN_SHARE: u32 = 4;

/// How many of the latest plans [`Policy::resume`] tries besides the first.
const RESUME_PLANS: usize = 8;
/// How many steps before the tree's place in a plan [`Policy::resume`] also starts.
const RESUME_BACK: usize = 2;

/// Deepest path [`repair`] looks for.
const REPAIR_DEPTH: usize = 2;
/// Most states [`repair`] looks at.
const REPAIR_STATES: usize = 4_000;

/// The shortest path (at most [`REPAIR_DEPTH`] actions) from `t` to a state where a
/// rule holds, and that rule (for the goal, its conditions at distance 0): with the
/// tree's own actions if they can (a tree with fewer distinct actions gives an external
/// agent fewer to do), else with any; breadth first, actions in a fixed order, so the
/// result is deterministic.
fn repair(g: &Grounding, policy: &Policy, t: &State, own: &[ActionId]) -> Option<(Vec<ActionId>, Rule)> {
    repair_with(g, policy, t, own).or_else(|| {
        let all: Vec<ActionId> = (0..g.actions().len() as ActionId).collect();
        repair_with(g, policy, t, &all)
    })
}

fn repair_with(g: &Grounding, policy: &Policy, t: &State, actions: &[ActionId]) -> Option<(Vec<ActionId>, Rule)> {
    let mut layer: Vec<(State, Vec<ActionId>)> = vec![(t.clone(), Vec::new())];
    let mut seen: HashSet<State> = HashSet::new();
    seen.insert(t.clone());
    for _ in 0..REPAIR_DEPTH {
        let mut next = Vec::new();
        for (s, path) in &layer {
            for &id in actions {
                let Some(u) = successor(g, id, s) else { continue };
                if !seen.insert(u.clone()) {
                    continue;
                }
                let mut p = path.clone();
                p.push(id);
                if g.goal_holds(&u) {
                    return Some((p, Rule::goal(g)));
                }
                if let Some(r) = policy.first(&u) {
                    return Some((p, r.clone()));
                }
                if seen.len() >= REPAIR_STATES {
                    return None;
                }
                next.push((u, p));
            }
        }
        layer = next;
    }
    None
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;

    #[test]
    fn a_search_that_can_only_improve_on_a_known_way_back_gets_a_quarter_of_the_time() {
        use std::time::Duration;
        let now = Instant::now();
        let at = |ms: u64| now + Duration::from_millis(ms);
        // Without a closure deadline, no search deadline.
        assert_eq!(search_deadline(None, now, false), None);
        assert_eq!(search_deadline(None, now, true), None);
        // 8 s left: an eighth, or a quarter of that where a way back is known.
        assert_eq!(search_deadline(Some(at(8_000)), now, false), Some(at(1_000)));
        assert_eq!(search_deadline(Some(at(8_000)), now, true), Some(at(250)));
        // 400 ms left: the least time, or a quarter of it.
        assert_eq!(search_deadline(Some(at(400)), now, false), Some(at(100)));
        assert_eq!(search_deadline(Some(at(400)), now, true), Some(at(25)));
        // Never past the closure's deadline.
        assert_eq!(search_deadline(Some(at(10)), now, false), Some(at(10)));
        assert_eq!(search_deadline(Some(now), now, true), Some(now));
    }

    /// The score counted the plain way: every rule's unmet conditions.
    fn counted(rules: &[&Rule], s: &State) -> u64 {
        let best = rules
            .iter()
            .map(|r| ((r.when.iter().filter(|l| !l.holds(s)).count() as u64) << 32) | u64::from(r.distance))
            .min()
            .unwrap_or(u64::MAX);
        if best >> 32 == 0 { 0 } else { best }
    }

    /// [`Nearest`] scores every state of a walk away from its start as counting every
    /// rule's conditions does.
    #[test]
    fn the_nearest_rule_is_found_from_the_atoms_that_changed() {
        let g = crate::domains::blocks_world(6).unwrap();
        let found = search::gbfs(&g, &SearchOptions::default()).unwrap();
        let policy = Policy::of_trace(&g, &Trace::new(&g, &found.plan).unwrap());
        let goal = Rule::goal(&g);
        let rules: Vec<&Rule> = std::iter::once(&goal).chain(policy.rules()).collect();
        assert!(rules.len() > 10, "{}", rules.len());
        // Start halfway along the plan, then walk: each step the k-th applicable action.
        let t = Trace::new(&g, &found.plan).unwrap().state(found.plan.len() / 2).unwrap().clone();
        let mut nearest = Nearest::new(&rules, &t);
        let mut s = t.clone();
        let mut scores = std::collections::BTreeSet::new();
        for step in 0..300_usize {
            let got = nearest.score(&s);
            assert_eq!(got, counted(&rules, &s), "step {step}");
            scores.insert(got);
            let applicable: Vec<ActionId> =
                (0..g.actions().len() as ActionId).filter(|&a| g.action(a).unwrap().applicable(&s)).collect();
            let a = applicable[(step * 7 + 3) % applicable.len()];
            s = successor(&g, a, &s).unwrap();
        }
        assert!(scores.len() > 3, "the walk met too few scores: {scores:?}");
    }
}
