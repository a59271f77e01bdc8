//! The nesting of a regression tree's rules that makes the tree smallest while it
//! ticks exactly as the rules side by side do.
//!
//! A contiguous run of rules that all have the conditions `I` (and whose ancestors
//! checked `K`) can become `Sequence(I - K?, Fallback(rules without I))`: ticked, it
//! does what the rules side by side do (where a condition of `I` is false none of them
//! holds, and the Fallback around it goes on to the next rule; where all hold, the
//! first of them that holds acts). The order of the rules never changes; only runs of
//! neighbours nest. What a nesting costs is what the image charges ([`Cost`]): for
//! each node its subtree size, its tag and its fields (a leaf's behavior and
//! arguments), each a varint; a negative condition is an Inverter over the
//! condition. The value table holds each extended leaf's arguments once however often
//! the leaf appears, so it does not change.
//!
//! [`Nesting`] finds the cheapest nesting by a dynamic programme over runs. Two facts
//! keep it small:
//!
//! - A run is best checked with *all* the conditions its rules share (what it leaves
//!   to the rules, each of them checks again), so the conditions a nested rule still
//!   checks are those not shared by the whole run around it: a rule's condition is
//!   known inside the run `[a, b]` exactly when the run of neighbours having it spans
//!   `[a, b]`, which precomputed run bounds answer at once.
//! - Only *maximal* runs need be looked at: a run that could take in its neighbour
//!   without losing a shared condition is never cheaper than the run that does (the
//!   neighbour, inside, checks fewer conditions). From each rule, the maximal runs end
//!   where one of its conditions stops being shared, so there are at most as many as
//!   it has conditions.
//!
//! The work is bounded ([`WORK`]); a closure of rules so large that the programme
//! would take longer, and runs nested more than [`NEST`] deep (bt-core's depth limit),
//! fall back to splitting at the halves ([`halves`]), whose depth grows with the
//! logarithm of the number of rules.

use std::collections::HashMap;

use foldhash::fast::FixedState;

use super::Rule;
use crate::ground::{ActionId, Grounding, Lit};
use crate::tree::{Kind, PlanNode, PlanTree};

/// The most runs nested in one another (each is a Sequence and a Fallback: two
/// levels). With the root, a rule's Sequence, an Inverter and a condition, and the
/// halves' nesting below it for 65,535 rules, a tree stays within bt-core's
/// [`crate::tree::DEPTH`] levels.
const NEST: usize = 24;

/// The most steps (a rule or a run looked at) the programme takes before it leaves
/// the rules to [`halves`]: about 20 ms. The closure over disturbances counts the
/// tree's nodes after every addition.
const WORK: usize = 1_000_000;

/// The most rules the programme is tried on at once; more are split at the halves
/// first.
const CHUNK: usize = 128;

/// Bytes and nodes of part of a tree in the image; compared by bytes first.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
struct Cost {
    bytes: usize,
    nodes: usize,
}

impl std::ops::Add for Cost {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self { bytes: self.bytes + o.bytes, nodes: self.nodes + o.nodes }
    }
}

impl std::ops::Sub for Cost {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self { bytes: self.bytes - o.bytes, nodes: self.nodes - o.nodes }
    }
}

impl Cost {
    const MAX: Self = Self { bytes: usize::MAX / 2, nodes: usize::MAX / 2 };

    /// A Sequence or Fallback over `children`: its subtree size, a varint, and its tag.
    fn control(children: Self) -> Self {
        let nodes = children.nodes + 1;
        Self { bytes: children.bytes + 1 + varint_len(nodes), nodes }
    }
}

/// Bytes of `v` as a LEB128 varint, as the image writes sizes, ids and arguments.
fn varint_len(v: usize) -> usize {
    match v {
        0..0x80 => 1,
        0x80..0x4000 => 2,
        _ => 3,
    }
}

/// A leaf's cost in the image (bt-core's wire format, `bt_core::image`): size and
/// tag, the behavior, then the list of its arguments, or of the start and length of
/// its arguments in the value table where there are more than fit a node (the start
/// taken as two bytes).
fn leaf(call: Option<(u16, &[u16])>) -> Cost {
    let bytes = match call {
        Some((b, args)) if args.len() <= bt_core::MAX_ARGS => {
            3 + varint_len(usize::from(b)) + args.iter().map(|&a| varint_len(usize::from(a))).sum::<usize>()
        }
        Some((b, args)) => 5 + varint_len(usize::from(b)) + varint_len(args.len()),
        // A leaf of a behavior table: a behavior and an argument or two.
        None => 5,
    };
    Cost { bytes, nodes: 1 }
}

/// A condition's cost: a negative one is an Inverter over it.
fn condition(g: &Grounding, l: Lit) -> Cost {
    let c = leaf(g.condition_call(l.atom));
    if l.positive { c } else { c + Cost { bytes: 2, nodes: 1 } }
}

/// Appends `rules` to the Fallback `parent` (whose ancestors checked nothing), nested
/// the cheapest way (see the module docs).
pub(super) fn push(g: &Grounding, t: &mut PlanTree, parent: PlanNode, rules: &[&Rule]) {
    push_with(t, parent, rules, &|l| condition(g, l), &|a| leaf(g.action_call(a)));
}

/// [`push`] with the cost of each condition and action given.
fn push_with(
    t: &mut PlanTree,
    parent: PlanNode,
    rules: &[&Rule],
    condition: &dyn Fn(Lit) -> Cost,
    action: &dyn Fn(ActionId) -> Cost,
) {
    nest(t, parent, rules, &[], (condition, action));
}

/// Appends `rules` to the Fallback `parent`, whose ancestors checked `known`: nested
/// by [`Nesting`] where that is cheaper than by [`halves`] and takes at most
/// [`WORK`] steps (tried on at most [`CHUNK`] rules), else split at the halves as
/// [`halves`] does, each half nested likewise.
fn nest(t: &mut PlanTree, parent: PlanNode, rules: &[&Rule], known: &[Lit], costs: Costs<'_>) {
    if rules.len() <= 2 {
        for r in rules {
            let when: Vec<Lit> = r.when.iter().copied().filter(|l| !known.contains(l)).collect();
            t.push_step(parent, &when, r.action);
        }
        return;
    }
    if rules.len() <= CHUNK && nest_runs(t, parent, rules, known, costs) {
        return;
    }
    for (half, shared) in split(rules, known) {
        if shared.is_empty() {
            nest(t, parent, half, known, costs);
        } else {
            let fb = push_shared(t, parent, &shared);
            let inner: Vec<Lit> = known.iter().chain(&shared).copied().collect();
            nest(t, fb, half, &inner, costs);
        }
    }
}

/// [`nest`] by [`Nesting`], or by [`halves`] where that is cheaper; false (and
/// nothing appended) where the programme would take more than [`WORK`] steps.
fn nest_runs(t: &mut PlanTree, parent: PlanNode, rules: &[&Rule], known: &[Lit], costs: Costs<'_>) -> bool {
    let (condition, action) = costs;
    let own: Vec<Rule> = rules
        .iter()
        .map(|r| Rule { when: r.when.iter().copied().filter(|l| !known.contains(l)).collect(), ..(*r).clone() })
        .collect();
    let own: Vec<&Rule> = own.iter().collect();
    let top = (0, own.len() - 1, true);
    let mut runs = Nesting::new(&own, condition, action);
    let best = runs.cost(top);
    if runs.work > WORK {
        return false;
    }
    let mut by_halves = PlanTree::with_root(Kind::Fallback);
    let root = by_halves.root();
    halves(&mut by_halves, root, &own, &[]);
    if best < children_cost(&by_halves, root, condition, action) {
        runs.build(t, parent, top, 0);
    } else {
        for &c in by_halves.children(root) {
            t.graft_from(parent, &by_halves, c);
        }
    }
    true
}

/// The cost of each condition and of each action.
type Costs<'c> = (&'c dyn Fn(Lit) -> Cost, &'c dyn Fn(ActionId) -> Cost);

/// The halves of `rules` (more than two), each with the conditions its rules share
/// that `known` lacks, where checking them once saves more than the Sequence and the
/// Fallback around them cost (else none).
fn split<'r, 's>(rules: &'s [&'r Rule], known: &[Lit]) -> [(&'s [&'r Rule], Vec<Lit>); 2] {
    let (a, b) = rules.split_at(rules.len() / 2);
    [a, b].map(|half| {
        let shared: Vec<Lit> = half[0]
            .when
            .iter()
            .copied()
            .filter(|l| !known.contains(l) && half[1..].iter().all(|r| r.when.binary_search(l).is_ok()))
            .collect();
        // The Sequence and the Fallback cost two nodes; sharing saves the shared
        // conditions once per rule but the first.
        if (half.len() - 1) * shared.len() <= 2 { (half, Vec::new()) } else { (half, shared) }
    })
}

/// Appends `Sequence(shared?, Fallback)` to `parent`; returns the Fallback.
fn push_shared(t: &mut PlanTree, parent: PlanNode, shared: &[Lit]) -> PlanNode {
    let seq = t.add(Kind::Sequence);
    for &l in shared {
        let c = t.add(Kind::Condition(l));
        t.push_child(seq, c);
    }
    let fb = t.add(Kind::Fallback);
    t.push_child(seq, fb);
    t.push_child(parent, seq);
    fb
}

/// The cost of `parent`'s children in `t`.
fn children_cost(
    t: &PlanTree,
    parent: PlanNode,
    condition: &dyn Fn(Lit) -> Cost,
    action: &dyn Fn(ActionId) -> Cost,
) -> Cost {
    // Children before parents: a node's own children are summed before it.
    let order = t.preorder(parent);
    let mut cost = vec![Cost::default(); t.capacity()];
    for &n in order.iter().rev() {
        cost[n as usize] = match t.kind(n) {
            Kind::Condition(l) => condition(l),
            Kind::Action(a) => action(a),
            Kind::Sequence | Kind::Fallback => {
                Cost::control(t.children(n).iter().fold(Cost::default(), |s, &c| s + cost[c as usize]))
            }
        };
    }
    t.children(parent).iter().fold(Cost::default(), |s, &c| s + cost[c as usize])
}

/// One way to cover the front of a run: a rule alone, or the run `start..=end`.
#[derive(Clone, Copy)]
enum Piece {
    Rule(usize),
    Run { start: usize, end: usize },
}

/// The dynamic programme over the runs of `rules`.
struct Nesting<'a> {
    rules: &'a [&'a Rule],
    /// For each rule, for each of its conditions: the index past the run of rules from
    /// this one on that have it, and the first index of that run.
    bounds: Vec<Vec<(u32, u32)>>,
    /// For each rule, the cost of each of its conditions, and of its action.
    costs: Vec<(Vec<Cost>, Cost)>,
    /// For each rule, by the distinct ends of its conditions' runs, the farthest first:
    /// the end, the cost of the conditions whose run reaches it, and whether one of
    /// them starts at this rule.
    ends: Vec<Vec<(u32, Cost, bool)>>,
    /// Cheapest cost of the rules of a run, nested inside it (what checks their shared
    /// conditions not counted), by the run's first and last index.
    memo: HashMap<(u32, u32), Cost, FixedState>,
    /// Steps taken; past [`WORK`] the programme stops (while `bounded`).
    work: usize,
    bounded: bool,
}

impl<'a> Nesting<'a> {
    fn new(rules: &'a [&'a Rule], condition: &dyn Fn(Lit) -> Cost, action: &dyn Fn(ActionId) -> Cost) -> Self {
        let n = rules.len();
        let mut of: HashMap<Lit, Cost, FixedState> = HashMap::default();
        let costs: Vec<(Vec<Cost>, Cost)> = rules
            .iter()
            .map(|r| {
                let when = r.when.iter().map(|&l| *of.entry(l).or_insert_with(|| condition(l))).collect();
                (when, action(r.action))
            })
            .collect();
        let mut bounds: Vec<Vec<(u32, u32)>> = rules.iter().map(|r| vec![(0, 0); r.when.len()]).collect();
        // Literal -> (last index it was seen at, the bound there), walking each way.
        let mut seen: HashMap<Lit, (usize, u32), FixedState> = HashMap::default();
        for i in (0..n).rev() {
            for (j, &l) in rules[i].when.iter().enumerate() {
                let end = match seen.get(&l) {
                    Some(&(at, end)) if at == i + 1 => end,
                    _ => (i + 1) as u32,
                };
                seen.insert(l, (i, end));
                bounds[i][j].0 = end;
            }
        }
        seen.clear();
        for i in 0..n {
            for (j, &l) in rules[i].when.iter().enumerate() {
                let start = match seen.get(&l) {
                    Some(&(at, start)) if at + 1 == i => start,
                    _ => i as u32,
                };
                seen.insert(l, (i, start));
                bounds[i][j].1 = start;
            }
        }
        let ends = (0..n)
            .map(|i| {
                let mut by: Vec<(u32, Cost, bool)> = bounds[i]
                    .iter()
                    .zip(&costs[i].0)
                    .map(|(&(end, start), &c)| (end, c, start as usize == i))
                    .collect();
                by.sort_unstable_by_key(|e| std::cmp::Reverse(e.0));
                let mut out: Vec<(u32, Cost, bool)> = Vec::new();
                let (mut sum, mut left) = (Cost::default(), false);
                for (end, c, starts) in by {
                    sum = sum + c;
                    left |= starts;
                    match out.last_mut() {
                        Some(last) if last.0 == end => *last = (end, sum, left),
                        _ => out.push((end, sum, left)),
                    }
                }
                out
            })
            .collect();
        Self { rules, bounds, costs, ends, memo: HashMap::default(), work: 0, bounded: true }
    }

    /// Whether rule `i`'s `j`th condition was checked by the run `a..=b` around it (the
    /// whole list, `top`, checks nothing): its run of neighbours spans `a..=b`.
    fn known(&self, i: usize, j: usize, (a, b, top): (usize, usize, bool)) -> bool {
        let (end, start) = self.bounds[i][j];
        !top && start as usize <= a && end as usize > b
    }

    /// The cost of the conditions `run` checked, which every rule in it has.
    fn checked(&self, (a, b, top): (usize, usize, bool)) -> Cost {
        if top {
            return Cost::default();
        }
        let (when, _) = &self.costs[a];
        (0..when.len()).filter(|&j| self.bounds[a][j].0 as usize > b).fold(Cost::default(), |s, j| s + when[j])
    }

    /// Rule `i` alone inside a run that checked conditions costing `known`: its
    /// Sequence, other conditions and action, or the action alone.
    fn single(&self, i: usize, known: Cost) -> Cost {
        let (when, action) = &self.costs[i];
        let all = when.iter().fold(Cost::default(), |s, &c| s + c);
        if all.nodes == known.nodes { *action } else { Cost::control(all - known + *action) }
    }

    /// The maximal runs inside `run` that start at rule `c` (at least two rules, with
    /// a condition `run` did not check, whose cost `known` it did): `(end, the cost of
    /// its new conditions)`, the longest first.
    fn runs_from(&self, c: usize, run: (usize, usize, bool), known: Cost, out: &mut Vec<(usize, Cost)>) {
        let (a, b, _) = run;
        out.clear();
        let ends = &self.ends[c];
        // The conditions whose run reaches past `b` make the run to `b`.
        let past = ends.partition_point(|e| e.0 as usize > b);
        let mut runs = ends[past..].iter().map(|&(end, sum, left)| (end as usize - 1, sum, left));
        let to_b = past.checked_sub(1).map(|k| (b, ends[k].1, ends[k].2));
        for (end, sum, left) in to_b.into_iter().chain(&mut runs) {
            if end < c + 1 {
                break;
            }
            // A run that could start earlier without losing a shared condition is
            // never cheaper than the one that does.
            if sum.nodes > known.nodes && (left || c == a) {
                out.push((end, sum - known));
            }
        }
    }

    /// The cheapest cost of the rules of `run` inside it, with the pieces that give
    /// it when `pieces` is asked for (the last piece of each prefix).
    fn solve(&mut self, run: (usize, usize, bool), mut pieces: Option<&mut Vec<Piece>>) -> Cost {
        let (a, b, _) = run;
        let len = b - a + 1;
        let known = self.checked(run);
        let mut best = vec![Cost::MAX; len + 1];
        best[0] = Cost::default();
        if let Some(p) = pieces.as_deref_mut() {
            p.clear();
            p.resize(len + 1, Piece::Rule(a));
        }
        let mut runs = Vec::new();
        for c in a..=b {
            let here = best[c - a];
            let one = here + self.single(c, known);
            if one < best[c - a + 1] {
                best[c - a + 1] = one;
                if let Some(p) = pieces.as_deref_mut() {
                    p[c - a + 1] = Piece::Rule(c);
                }
            }
            self.runs_from(c, run, known, &mut runs);
            self.work += 1 + runs.len();
            if self.bounded && self.work > WORK {
                return best[len];
            }
            for &(end, shared) in &runs {
                let cost = here + Cost::control(shared + Cost::control(self.cost((c, end, false))));
                if cost < best[end - a + 1] {
                    best[end - a + 1] = cost;
                    if let Some(p) = pieces.as_deref_mut() {
                        p[end - a + 1] = Piece::Run { start: c, end };
                    }
                }
            }
        }
        best[len]
    }

    /// [`Nesting::solve`] for `run`, remembered.
    fn cost(&mut self, run: (usize, usize, bool)) -> Cost {
        let (a, b, top) = run;
        if top {
            return self.solve(run, None);
        }
        if let Some(&c) = self.memo.get(&(a as u32, b as u32)) {
            return c;
        }
        let c = self.solve(run, None);
        self.memo.insert((a as u32, b as u32), c);
        c
    }

    /// Appends the rules of `run`, nested the cheapest way, to `parent`, `depth` runs
    /// deep.
    fn build(&mut self, t: &mut PlanTree, parent: PlanNode, run: (usize, usize, bool), depth: usize) {
        // Building looks again at the runs chosen only, each remembered.
        self.bounded = false;
        let (a, b, _) = run;
        let mut pieces = Vec::new();
        self.solve(run, Some(&mut pieces));
        let mut chosen = Vec::new();
        let mut at = b - a + 1;
        while at > 0 {
            let p = pieces[at];
            chosen.push(p);
            at = match p {
                Piece::Rule(i) => i - a,
                Piece::Run { start, .. } => start - a,
            };
        }
        for p in chosen.into_iter().rev() {
            match p {
                Piece::Rule(i) => {
                    let when = self.unchecked(i, run);
                    t.push_step(parent, &when, self.rules[i].action);
                }
                Piece::Run { start, end } => {
                    let inner = (start, end, false);
                    let when = self.rules[start].when.iter().enumerate();
                    let shared: Vec<Lit> = when
                        .filter(|&(j, _)| !self.known(start, j, run) && self.known(start, j, inner))
                        .map(|(_, &l)| l)
                        .collect();
                    let fb = push_shared(t, parent, &shared);
                    if depth + 1 >= NEST {
                        let known: Vec<Lit> = (0..self.rules[start].when.len())
                            .filter(|&j| self.known(start, j, inner))
                            .map(|j| self.rules[start].when[j])
                            .collect();
                        halves(t, fb, &self.rules[start..=end], &known);
                    } else {
                        self.build(t, fb, inner, depth + 1);
                    }
                }
            }
        }
    }

    /// Rule `i`'s conditions that `run` did not check.
    fn unchecked(&self, i: usize, run: (usize, usize, bool)) -> Vec<Lit> {
        let when = &self.rules[i].when;
        (0..when.len()).filter(|&j| !self.known(i, j, run)).map(|j| when[j]).collect()
    }
}

/// Appends `rules` to the Fallback `parent`, whose ancestors have checked `known`,
/// nested by halves: a half whose rules share conditions becomes `Sequence(shared?,
/// Fallback(its rules without them))`, then its halves likewise. The nesting is about
/// twice the logarithm of the number of rules deep; the cheapest nesting ([`push`])
/// falls back to it.
pub(super) fn halves(t: &mut PlanTree, parent: PlanNode, rules: &[&Rule], known: &[Lit]) {
    if rules.len() <= 2 {
        for r in rules {
            let when: Vec<Lit> = r.when.iter().copied().filter(|l| !known.contains(l)).collect();
            t.push_step(parent, &when, r.action);
        }
        return;
    }
    for (half, shared) in split(rules, known) {
        if shared.is_empty() {
            halves(t, parent, half, known);
        } else {
            let fb = push_shared(t, parent, &shared);
            let inner: Vec<Lit> = known.iter().chain(&shared).copied().collect();
            halves(t, fb, half, &inner);
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::panic, clippy::indexing_slicing)]

    use std::path::Path;

    use proptest::prelude::*;

    use super::{Cost, halves, push_with};
    use crate::ground::{ActionId, Grounding, Lit};
    use crate::guide::Trace;
    use crate::pddl::{parse_domain, parse_problem};
    use crate::regress::{Budget, Policy, Rule, close};
    use crate::state::State;
    use crate::tree::{Kind, PlanNode, PlanTree};

    /// What a reactive tree of Sequences, Fallbacks, conditions and actions returns in
    /// a state: an action ticked stands for Running.
    #[derive(Debug, PartialEq, Eq)]
    enum Tick {
        Success,
        Failure,
        Act(ActionId),
    }

    fn tick(t: &PlanTree, n: PlanNode, s: &State) -> Tick {
        match t.kind(n) {
            Kind::Condition(l) if l.holds(s) => Tick::Success,
            Kind::Condition(_) => Tick::Failure,
            Kind::Action(a) => Tick::Act(a),
            Kind::Sequence => {
                t.children(n).iter().map(|&c| tick(t, c, s)).find(|r| *r != Tick::Success).unwrap_or(Tick::Success)
            }
            Kind::Fallback => {
                t.children(n).iter().map(|&c| tick(t, c, s)).find(|r| *r != Tick::Failure).unwrap_or(Tick::Failure)
            }
        }
    }

    /// What the rules side by side do: the first that holds acts.
    fn flat(rules: &[Rule], s: &State) -> Tick {
        rules.iter().find(|r| r.holds(s)).map_or(Tick::Failure, |r| Tick::Act(r.action))
    }

    fn condition(l: Lit) -> Cost {
        if l.positive { Cost { bytes: 3, nodes: 1 } } else { Cost { bytes: 5, nodes: 2 } }
    }

    fn action(_: ActionId) -> Cost {
        Cost { bytes: 4, nodes: 1 }
    }

    /// The cost of `t`'s nodes under `condition` and `action`.
    fn cost_of(t: &PlanTree, n: PlanNode) -> Cost {
        match t.kind(n) {
            Kind::Condition(l) => condition(l),
            Kind::Action(a) => action(a),
            _ => Cost::control(t.children(n).iter().fold(Cost::default(), |s, &c| s + cost_of(t, c))),
        }
    }

    /// Rules as a plan's regression makes them: each differs from the one before in a
    /// few literals.
    fn rules() -> impl Strategy<Value = Vec<Rule>> {
        let step = (prop::collection::vec(0..10u32, 0..3), prop::collection::vec((0..10u32, any::<bool>()), 0..3));
        (prop::collection::vec((0..10u32, any::<bool>()), 1..6), prop::collection::vec(step, 0..50)).prop_map(
            |(first, steps)| {
                let mut when: Vec<Lit> = Vec::new();
                let put = |when: &mut Vec<Lit>, (atom, positive): (u32, bool)| {
                    when.retain(|l| l.atom != atom);
                    when.push(Lit { atom, positive });
                };
                for l in first {
                    put(&mut when, l);
                }
                let mut out = Vec::new();
                for (k, (drop, add)) in std::iter::once((Vec::new(), Vec::new())).chain(steps).enumerate() {
                    when.retain(|l| !drop.contains(&l.atom));
                    for l in add {
                        put(&mut when, l);
                    }
                    let mut sorted = when.clone();
                    sorted.sort_unstable();
                    out.push(Rule { when: sorted, action: k as ActionId, distance: k as u32 + 1, group: 0 });
                }
                out
            },
        )
    }

    proptest! {
        /// The nesting ticks exactly as the rules side by side do, in every state of
        /// their atoms, and is never larger than the halves'.
        #[test]
        fn the_cheapest_nesting_ticks_as_the_rules_side_by_side(rules in rules()) {
            let refs: Vec<&Rule> = rules.iter().collect();
            let mut nested = PlanTree::with_root(Kind::Fallback);
            let root = nested.root();
            push_with(&mut nested, root, &refs, &condition, &action);
            let mut by_halves = PlanTree::with_root(Kind::Fallback);
            halves(&mut by_halves, root, &refs, &[]);
            for bits in 0..1u32 << 10 {
                let mut s = State::new(10);
                for atom in 0..10 {
                    s.set(atom, bits & (1 << atom) != 0);
                }
                prop_assert_eq!(tick(&nested, root, &s), flat(&rules, &s), "state {:010b}", bits);
            }
            prop_assert!(cost_of(&nested, root) <= cost_of(&by_halves, root));
        }
    }

    /// The IPC fixtures' regression trees, closed over disturbances: each ticks as its
    /// rules side by side do (from states where a rule holds), and its image is no
    /// larger than the one the halves make.
    #[test]
    fn fixture_trees_tick_as_their_rules_and_are_no_larger_than_halves() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ipc");
        let mut looked = 0;
        let mut dirs: Vec<_> = std::fs::read_dir(&root).unwrap().map(|e| e.unwrap().path()).collect();
        dirs.sort();
        for dir in dirs.iter().filter(|d| d.join("domain.pddl").exists()) {
            let d = std::fs::read_to_string(dir.join("domain.pddl")).unwrap();
            let mut files: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
            files.sort();
            for file in
                files.iter().filter(|f| f.extension().is_some_and(|e| e == "pddl") && !f.ends_with("domain.pddl"))
            {
                let p = std::fs::read_to_string(file).unwrap();
                let name = file.display().to_string();
                let problem = parse_domain("domain.pddl", &d).and_then(|d| parse_problem(&name, &p, &d)).unwrap();
                let g = Grounding::new(&problem).unwrap();
                let plan = crate::search::gbfs(&g, &crate::search::SearchOptions::default()).unwrap().plan;
                let mut policy = Policy::of_trace(&g, &Trace::new(&g, &plan).unwrap());
                close(&g, &mut policy, &Budget { nodes: 2_000, ..Budget::default() }).unwrap();
                let tree = policy.tree(&g);
                let mut by_halves = PlanTree::with_root(Kind::Fallback);
                let top = by_halves.root();
                by_halves.graft(top, &PlanTree::from_goal(g.goal()));
                let all: Vec<&Rule> = policy.rules().iter().chain(policy.undo_rules()).collect();
                halves(&mut by_halves, top, &all, &[]);
                let bytes = |t: &PlanTree| {
                    let f = t.flatten(&g).unwrap();
                    crate::offline::fit::size_of(&f.nodes, &f.values).unwrap().bytes
                };
                assert!(bytes(&tree) <= bytes(&by_halves), "{name}: {} > {}", bytes(&tree), bytes(&by_halves));
                // States where each rule holds, the others' atoms as the initial state has them.
                let goal = |s: &State| g.goal_holds(s);
                for r in &all {
                    let mut s = g.init().clone();
                    for l in &r.when {
                        s.set(l.atom, l.positive);
                    }
                    let want = if goal(&s) { Tick::Success } else { flat(policy.rules(), &s) };
                    let want = if want == Tick::Failure { flat(policy.undo_rules(), &s) } else { want };
                    assert_eq!(tick(&tree, tree.root(), &s), want, "{name}");
                    looked += 1;
                }
            }
        }
        assert!(looked > 100, "{looked} states looked at");
    }
}
