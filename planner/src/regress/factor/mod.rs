//! The nesting of a regression tree's rules that makes the tree small while it ticks
//! exactly as the rules side by side do.
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
//! [`Nesting`] finds the cheapest nesting of *maximal* runs by a dynamic programme:
//!
//! - A run is checked with *all* the conditions its rules share (what it leaves to
//!   the rules, each of them checks again), so a rule's condition is known inside the
//!   run `[a, b]` exactly when the run of neighbours having it spans `[a, b]`, which
//!   precomputed run bounds answer at once.
//! - The runs looked at are those that could take in neither neighbouring rule
//!   without losing a shared condition: from each rule they end where one of its
//!   conditions stops being shared, so there are at most as many as it has
//!   conditions. A run cut short where another run begins can be cheaper still, so
//!   the nesting is the cheaper of this one and the halves' ([`halves`], which split
//!   the rules at the middle, then each half at its middle).
//!
//! The work is bounded: on more than [`CHUNK`] rules, or where the programme would
//! take more than [`WORK`] steps, the rules are split at the halves first and each
//! half nested so; runs nested more than [`NEST`] deep (bt-core's depth limit) are
//! split at the halves too.

use std::collections::HashMap;

use foldhash::fast::FixedState;

use super::Rule;
use crate::ground::{ActionId, Grounding, Lit};
use crate::tree::{Kind, PlanNode, PlanTree};

/// The most runs nested in one another (each is a Sequence and a Fallback: two
/// levels). With the root, a rule's Sequence, an Inverter and a condition, the halves
/// above [`CHUNK`] rules of 65,535 (18 levels) and below the deepest run (14), a tree
/// stays within bt-core's [`crate::tree::DEPTH`] levels (84 of 128).
const NEST: usize = 24;

/// The most steps (a rule or a run looked at) the programme takes on one set of
/// rules, about 20 ms: the closure over disturbances counts the tree's nodes after
/// every addition.
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
    nest(t, parent, rules, &[], Some((condition, action)));
}

/// Appends `rules` to the Fallback `parent`, whose ancestors checked `known`: nested
/// by [`Nesting`] where `costs` are given, that is cheaper than by [`halves`] and takes
/// at most [`WORK`] steps (tried on at most [`CHUNK`] rules), else split at the halves,
/// each half nested likewise.
fn nest(t: &mut PlanTree, parent: PlanNode, rules: &[&Rule], known: &[Lit], costs: Option<Costs<'_>>) {
    if rules.len() <= 2 {
        for r in rules {
            let when: Vec<Lit> = r.when.iter().copied().filter(|l| !known.contains(l)).collect();
            t.push_step(parent, &when, r.action);
        }
        return;
    }
    if let Some(costs) = costs
        && rules.len() <= CHUNK
        && nest_runs(t, parent, rules, known, costs)
    {
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
    nest(t, parent, rules, known, None);
}

#[cfg(test)]
mod tests;
