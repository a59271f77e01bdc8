//! State variables, and guided backchaining that does not pin them to the values a
//! plan happened to give them.
//!
//! A predicate is a *state variable* at argument `j` when, for each choice of its other
//! arguments, at most one of its atoms holds in every reachable state: the number of
//! free stacks (`stacks-avail ?n`, one atom in all), a truck's place (`at ?t ?l`, in its
//! second argument), its fuel level. [`StateVariables::of`] shows it from the problem: the
//! initial state has at most one such atom per choice, and every action that makes one
//! true makes another of the same choice false, which it needs (a sufficient test, the
//! simplest of the invariants planners such as Fast Downward find).
//!
//! Such a variable can make guided backchaining fail. The plan's steps pin it
//! (`start-order(o2, n2, n1)` with two stacks free), so where the tree meets another
//! value, a step's condition `stacks-avail(n2)` fails, and the plan's causal link for
//! it is whatever step last set it, unrelated to this one (another order shipped):
//! the tree chains orders together and, once that order is shipped, asks to start it
//! again. Openstacks, whose every step moves the counter, gets no backchained tree at
//! all, and its regression tree, which pins the counter in every rule, fails after
//! almost any order started out of turn. With [`Variables`], guided backchaining
//! instead:
//!
//! * gives a step its *siblings*: the groundings of the same action, with the same
//!   other arguments, that start from another value the plan's path visits, at most
//!   [`MAX_DISTURBANCES`] actions from the step's own (as many as an agent does in an
//!   episode), and differ in nothing else (static facts aside). The preconditions they share are checked
//!   once, then a Fallback of `Sequence(value?, step)` rows, one per value
//!   ([`crate::algorithm::expand_shared`]): Problem 1 of Colledanchise et al. 2019, its third point,
//!   several actions achieving a condition so that where one cannot run another can;
//! * ends that Fallback with the actions that set the plan's value and change nothing
//!   but state variables (open a stack), for where the variable holds none of them;
//! * expands a failed value with such an action where one exists (else as Algorithm 1
//!   would), never through the plan's causal link, and adds the sibling for the value
//!   the world is in where a step's row meets one it has no row for
//!   ([`Variables::sibling_for`]);
//! * leaves values out of the conflict test (a sibling row serves every value), and
//!   sees no conflict where the subtree's own condition holds by the time it is
//!   reached, or where the action that undoes a precondition makes that condition
//!   true (a second subtree for `started(o)` after the first started it).
//!
//! The planner tries this after plain guided backchaining fails, and keeps the plan's
//! regression tree instead where that copes better with disturbances ([`crate::plan`]).

use std::collections::{HashMap, HashSet};

use crate::ground::{ActionId, AtomId, GroundAction, Grounding, Lit};
use crate::guide::Trace;
use crate::model::{ObjectId, PredicateId};
use crate::regress::MAX_DISTURBANCES;
use crate::state::State;

/// The state variables of a problem ([`StateVariables::of`]).
#[derive(Clone, Debug, Default)]
pub struct StateVariables {
    /// `(predicate, argument)` pairs that are state variables.
    at: HashSet<(PredicateId, usize)>,
}

impl StateVariables {
    /// Finds the state variables of `g` (see the module docs).
    #[must_use]
    pub fn of(g: &Grounding) -> Self {
        let mut at: HashSet<(PredicateId, usize)> = HashSet::new();
        for atom in 0..g.atom_count() as AtomId {
            if !g.is_static(atom) {
                let a = g.atom(atom);
                at.extend((0..a.args.len()).map(|j| (a.predicate, j)));
            }
        }
        // The initial state: at most one atom per choice of the other arguments.
        let mut seen: HashSet<(PredicateId, usize, Vec<ObjectId>)> = HashSet::new();
        for atom in g.init().iter() {
            let a = g.atom(atom);
            for j in 0..a.args.len() {
                if at.contains(&(a.predicate, j)) && !seen.insert((a.predicate, j, others(&a.args, j))) {
                    at.remove(&(a.predicate, j));
                }
            }
        }
        // Every action that makes one true makes another of the same choice false, which
        // it needs; conditional effects are not looked into.
        for x in g.actions() {
            for &atom in x.cond.iter().flat_map(|c| c.add.iter()) {
                let a = g.atom(atom);
                for j in 0..a.args.len() {
                    at.remove(&(a.predicate, j));
                }
            }
            for &atom in &x.add {
                let a = g.atom(atom);
                for j in 0..a.args.len() {
                    if !at.contains(&(a.predicate, j)) {
                        continue;
                    }
                    let key = others(&a.args, j);
                    let same = |b: AtomId| {
                        let o = g.atom(b);
                        o.predicate == a.predicate && o.args.len() == a.args.len() && others(&o.args, j) == key
                    };
                    // (An action that adds a value it needs, `move(a, a)`, changes nothing.)
                    let frees = x.pre.contains(&Lit { atom, positive: true })
                        || x.del.iter().any(|&d| same(d) && x.pre.contains(&Lit { atom: d, positive: true }));
                    if !frees || x.add.iter().filter(|&&b| same(b)).count() != 1 {
                        at.remove(&(a.predicate, j));
                    }
                }
            }
        }
        Self { at }
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.at.is_empty()
    }

    /// The state variables as `predicate/argument` (argument counted from 1), sorted.
    #[must_use]
    pub fn names(&self, g: &Grounding) -> Vec<String> {
        let preds = &g.problem().domain.predicates;
        let mut v: Vec<String> = self
            .at
            .iter()
            .map(|&(p, j)| format!("{}/{}", preds.get(usize::from(p)).map_or("?", |x| x.name.as_str()), j + 1))
            .collect();
        v.sort();
        v
    }

    /// Whether `lit` gives a state variable a value (a positive atom of one).
    #[must_use]
    pub fn is_value(&self, g: &Grounding, lit: Lit) -> bool {
        lit.positive && {
            let a = g.atom(lit.atom);
            (0..a.args.len()).any(|j| self.at.contains(&(a.predicate, j)))
        }
    }

    /// Whether the action changes nothing but state variables (opens a stack, moves a
    /// truck), unconditionally.
    #[must_use]
    pub fn only_moves(&self, g: &Grounding, x: &GroundAction) -> bool {
        x.cond.is_empty() && x.may_effects().all(|l| self.is_value(g, l) || self.is_value(g, l.negated()))
    }

    /// Whether atoms `a` and `b` are two values of one state variable.
    fn values_of_one(&self, g: &Grounding, a: AtomId, b: AtomId) -> bool {
        let (x, y) = (g.atom(a), g.atom(b));
        if x.predicate != y.predicate || x.args.len() != y.args.len() {
            return false;
        }
        let mut differ = (0..x.args.len()).filter(|&i| x.args.get(i) != y.args.get(i));
        match (differ.next(), differ.next()) {
            (Some(j), None) => self.at.contains(&(x.predicate, j)),
            _ => false,
        }
    }

    /// How the literals of `from` that `to` lacks become those of `to` that `from`
    /// lacks, each a value of a state variable turned into another of the same
    /// variable; `None` where they differ otherwise.
    fn pairing(&self, g: &Grounding, from: &[Lit], to: &[Lit]) -> Option<Vec<(Lit, Lit)>> {
        let only_from = from.iter().copied().filter(|l| !to.contains(l));
        let mut only_to: Vec<Lit> = to.iter().copied().filter(|l| !from.contains(l)).collect();
        let mut out = Vec::new();
        for l in only_from {
            let i = only_to.iter().position(|m| l.positive && m.positive && self.values_of_one(g, l.atom, m.atom))?;
            out.push((l, only_to.swap_remove(i)));
        }
        only_to.is_empty().then_some(out)
    }

    /// The siblings of action `a` for `lit`: achievers of `lit` of the same template
    /// whose preconditions and effects differ from `a`'s only in values of state
    /// variables, each value it needs that `a` does not passing `start`. Each comes
    /// with its preconditions in the order of `pre` (`a`'s, in the order chosen for
    /// it) with `a`'s values turned into its own, then any others it has.
    #[must_use]
    pub fn siblings(
        &self,
        g: &Grounding,
        a: ActionId,
        lit: Lit,
        pre: &[Lit],
        start: &dyn Fn(AtomId) -> bool,
    ) -> Vec<(ActionId, Vec<Lit>)> {
        let Some(x) = g.action(a).filter(|x| x.cond.is_empty()) else { return Vec::new() };
        let atoms = |v: &[AtomId]| v.iter().map(|&atom| Lit { atom, positive: true }).collect::<Vec<_>>();
        let mut out = Vec::new();
        for &b in g.achievers(lit) {
            let Some(y) = g.action(b) else { continue };
            if b == a || y.template != x.template || !y.cond.is_empty() {
                continue;
            }
            let Some(map) = self.pairing(g, &x.pre, &y.pre) else { continue };
            if map.iter().any(|&(_, to)| !start(to.atom))
                || self.pairing(g, &atoms(&x.add), &atoms(&y.add)).is_none()
                || self.pairing(g, &atoms(&x.del), &atoms(&y.del)).is_none()
            {
                continue;
            }
            let mut p: Vec<Lit> = pre.iter().map(|&l| map.iter().find(|m| m.0 == l).map_or(l, |m| m.1)).collect();
            for &l in &y.pre {
                if !p.contains(&l) {
                    p.push(l);
                }
            }
            out.push((b, p));
        }
        out
    }
}

/// The arguments but the `j`th.
fn others(args: &[ObjectId], j: usize) -> Vec<ObjectId> {
    args.iter().enumerate().filter(|&(i, _)| i != j).map(|(_, &o)| o).collect()
}

/// One achiever as guided backchaining places it: the action, its preconditions in the
/// order to check them, and the plan step it stands for.
pub type Choice = (ActionId, Vec<Lit>, usize);

/// A plan's state variables and the values its path visits, for guided backchaining
/// (see the module docs).
#[derive(Clone, Debug)]
pub struct Variables {
    of: StateVariables,
    /// Every atom that holds in some state of the plan's path.
    visited: State,
    /// For each value of a state variable, the values of the same variable one action
    /// turns it into, or that turn into it.
    moves: HashMap<AtomId, Vec<AtomId>>,
}

impl Variables {
    /// The state variables of `g` and the values `trace` visits; `None` where the
    /// problem has none.
    #[must_use]
    pub fn new(g: &Grounding, trace: &Trace) -> Option<Self> {
        let of = StateVariables::of(g);
        if of.is_empty() {
            return None;
        }
        let mut visited = State::new(g.atom_count());
        for s in (0..=trace.plan().len()).filter_map(|i| trace.state(i)) {
            for atom in s.iter() {
                visited.set(atom, true);
            }
        }
        let mut moves: HashMap<AtomId, Vec<AtomId>> = HashMap::new();
        for x in g.actions() {
            for &d in x.del.iter().filter(|&&d| x.pre.contains(&Lit { atom: d, positive: true })) {
                for &b in x.add.iter().filter(|&&b| of.values_of_one(g, d, b)) {
                    for (u, v) in [(d, b), (b, d)] {
                        let next = moves.entry(u).or_default();
                        if !next.contains(&v) {
                            next.push(v);
                        }
                    }
                }
            }
        }
        Some(Self { of, visited, moves })
    }

    /// Whether value `to` is at most [`MAX_DISTURBANCES`] actions from value `from` (the
    /// same variable): where the plan's step needs `from`, the world an agent disturbed
    /// that often can be at `to`, and no farther.
    fn near(&self, from: AtomId, to: AtomId) -> bool {
        let mut layer = vec![from];
        let mut seen = vec![from];
        for _ in 0..MAX_DISTURBANCES {
            if seen.contains(&to) {
                return true;
            }
            let mut next = Vec::new();
            for u in &layer {
                for &v in self.moves.get(u).map_or(&[][..], Vec::as_slice) {
                    if !seen.contains(&v) {
                        seen.push(v);
                        next.push(v);
                    }
                }
            }
            layer = next;
        }
        seen.contains(&to)
    }

    /// The state variables.
    #[must_use]
    pub fn state_variables(&self) -> &StateVariables {
        &self.of
    }

    /// Whether `lit` gives a state variable a value.
    #[must_use]
    pub fn is_value(&self, g: &Grounding, lit: Lit) -> bool {
        self.of.is_value(g, lit)
    }

    /// How to expand `lit` given the plan's choice `first`, in `belief`: a value by an
    /// action that only moves state variables instead (one that runs in `belief` first,
    /// then the cheapest; none: `lit` is not expanded); then that action with its
    /// siblings from values the plan visits near the step's own ([`MAX_DISTURBANCES`]
    /// actions at most) or `belief` holds, and, where it has
    /// siblings, the actions that set its values from such values.
    #[must_use]
    pub fn choices(&self, g: &Grounding, lit: Lit, first: Choice, belief: &State) -> Vec<Choice> {
        // Values the plan visits, near one the step needs: an agent's few acts move the
        // world only that far from the plan's values (a sibling for every value the plan
        // visits made openstacks' tree about twice as large).
        let values: Vec<AtomId> = first.1.iter().filter(|&&p| self.is_value(g, p)).map(|p| p.atom).collect();
        let start = |atom: AtomId| {
            belief.holds(atom) || (self.visited.holds(atom) && values.iter().any(|&v| self.near(v, atom)))
        };
        let mut first = first;
        if self.is_value(g, lit) {
            let best = g
                .achievers(lit)
                .iter()
                .filter_map(|&a| {
                    g.action(a).filter(|x| self.of.only_moves(g, x)).map(|x| (!x.applicable(belief), x.cost, a))
                })
                .min();
            let Some(x) = best.and_then(|(_, _, a)| g.action(a).map(|x| (a, x))) else { return Vec::new() };
            first = (x.0, x.1.pre.clone(), first.2);
        }
        let mut out: Vec<Choice> =
            self.of.siblings(g, first.0, lit, &first.1, &start).into_iter().map(|(b, pre)| (b, pre, first.2)).collect();
        if !out.is_empty() {
            let mut setters: Vec<Choice> = Vec::new();
            for &p in &first.1 {
                if !self.is_value(g, p) || out.iter().all(|o| o.1.contains(&p)) {
                    continue;
                }
                for &a in g.achievers(p) {
                    let Some(x) = g.action(a) else { continue };
                    let from_visited = x.pre.iter().all(|q| !self.is_value(g, *q) || start(q.atom));
                    if self.of.only_moves(g, x) && from_visited && !setters.iter().any(|s| s.0 == a) {
                        setters.push((a, x.pre.clone(), first.2));
                    }
                }
            }
            out.extend(setters);
        }
        out.insert(0, first);
        out
    }

    /// For a failed value `lit` in the row `Sequence(own?.., a)` of a Fallback of
    /// siblings that has no row for the values `belief` holds: the sibling of `a` that
    /// runs in `belief` and is not among `have`, with the conditions its row checks
    /// (`own` with `a`'s values turned into its own, and what else it needs that `a`
    /// does not).
    #[must_use]
    pub fn sibling_for(
        &self,
        g: &Grounding,
        lit: Lit,
        a: ActionId,
        own: &[Lit],
        have: &[ActionId],
        belief: &State,
    ) -> Option<(ActionId, Vec<Lit>)> {
        if !self.is_value(g, lit) {
            return None;
        }
        let x = g.action(a)?;
        // What the step is for: an effect that is no value of a state variable.
        let purpose = x.must_effects().find(|&l| !self.is_value(g, l) && !self.is_value(g, l.negated()))?;
        let (b, pre) = self
            .of
            .siblings(g, a, purpose, own, &|atom| belief.holds(atom))
            .into_iter()
            .find(|(b, _)| !have.contains(b) && g.action(*b).is_some_and(|y| y.applicable(belief)))?;
        Some((b, pre.into_iter().filter(|l| !x.pre.contains(l) || own.contains(l)).collect()))
    }
}
