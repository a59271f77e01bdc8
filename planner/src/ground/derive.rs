//! Derived atoms: the ground rules of `:derived` predicates, and the one place that
//! closes a state under them ([`Grounding::close`]).
//!
//! A state is made by an action (or a disturbance, or the initial state) on its basic
//! atoms; its derived atoms are then recomputed from scratch, stratum by stratum: in a
//! stratum, every rule whose body holds fires until none is left to fire (negated
//! derived atoms in a body belong to lower strata, already final). Counting each rule's
//! unmet positive body literals of its own stratum makes this linear in the rules.

use super::{AtomId, Grounding, Lit};
use crate::state::State;

/// A ground rule: `head` holds when every literal of `body` holds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rule {
    /// The derived atom it makes true.
    pub head: AtomId,
    /// Its body (static literals left out, as for actions).
    pub body: Vec<Lit>,
}

/// The ground rules of a problem, ordered by stratum, with what closing needs.
#[derive(Clone, Debug, Default)]
pub(super) struct Rules {
    pub(super) rules: Vec<Rule>,
    /// Per stratum, the end of its rules in `rules`.
    strata: Vec<usize>,
    /// The derived atoms (made false before closing).
    derived: Vec<AtomId>,
    /// Per atom, the rules of the atom's stratum with it as a positive body literal.
    watchers: Vec<Vec<u32>>,
    /// Per rule, the number of its positive body literals of its own stratum.
    recursive: Vec<u32>,
    /// Per rule, its other body literals (basic, lower strata, negated): fixed while
    /// its stratum is closed.
    fixed: Vec<Box<[Lit]>>,
    /// Per derived atom (in `derived` order), its rules.
    by_head: Vec<Vec<u32>>,
    /// Per atom, its stratum (0 for basic atoms).
    stratum: Vec<u16>,
}

impl Rules {
    /// Rules with the stratum of each (from its head's predicate), over `atoms` atoms;
    /// `derived(atom)` tells derived atoms.
    pub(super) fn new(mut rules: Vec<(u16, Rule)>, atoms: usize, derived: impl Fn(AtomId) -> bool) -> Self {
        rules.sort_by_key(|r| r.0);
        let mut strata: Vec<usize> = Vec::new();
        let mut stratum_of = vec![u16::MAX; atoms];
        for (i, (s, r)) in rules.iter().enumerate() {
            if i > 0 && rules[i - 1].0 != *s {
                strata.push(i);
            }
            stratum_of[r.head as usize] = *s;
        }
        if !rules.is_empty() {
            strata.push(rules.len());
        }
        let mut watchers = vec![Vec::new(); atoms];
        let mut recursive = Vec::with_capacity(rules.len());
        let mut fixed = Vec::with_capacity(rules.len());
        for (i, (s, r)) in rules.iter().enumerate() {
            let (own, rest): (Vec<Lit>, Vec<Lit>) =
                r.body.iter().partition(|l| l.positive && stratum_of[l.atom as usize] == *s);
            for l in &own {
                watchers[l.atom as usize].push(i as u32);
            }
            recursive.push(own.len() as u32);
            fixed.push(rest.into_boxed_slice());
        }
        let derived: Vec<AtomId> = (0..atoms as AtomId).filter(|&a| derived(a)).collect();
        let mut by_head = vec![Vec::new(); derived.len()];
        for (i, (_, r)) in rules.iter().enumerate() {
            if let Ok(k) = derived.binary_search(&r.head) {
                by_head[k].push(i as u32);
            }
        }
        let stratum = stratum_of.iter().map(|&s| if s == u16::MAX { 0 } else { s }).collect();
        Self {
            rules: rules.into_iter().map(|r| r.1).collect(),
            strata,
            derived,
            watchers,
            recursive,
            fixed,
            by_head,
            stratum,
        }
    }

    /// Closes `state`; with `why`, records per atom the rule that derived it (in the
    /// order of derivation, so following them back never loops).
    fn close(&self, state: &mut State, mut why: Option<&mut Vec<u32>>) {
        for &d in &self.derived {
            state.set(d, false);
        }
        let mut unmet: Vec<u32> = Vec::new();
        let mut queue: Vec<AtomId> = Vec::new();
        let mut start = 0;
        for &end in &self.strata {
            unmet.clear();
            for (i, r) in self.rules[start..end].iter().enumerate() {
                // The literals fixed in this stratum: basic, lower strata, negated.
                let own = self.recursive[start + i];
                let fixed_ok = self.fixed[start + i].iter().all(|l| l.holds(state));
                unmet.push(if fixed_ok { own } else { u32::MAX });
                if fixed_ok && own == 0 && !state.holds(r.head) {
                    state.set(r.head, true);
                    queue.push(r.head);
                    if let Some(w) = why.as_deref_mut() {
                        w[r.head as usize] = (start + i) as u32;
                    }
                }
            }
            while let Some(a) = queue.pop() {
                for &w in &self.watchers[a as usize] {
                    let k = w as usize - start;
                    if unmet[k] == u32::MAX || unmet[k] == 0 {
                        continue;
                    }
                    unmet[k] -= 1;
                    let head = self.rules[w as usize].head;
                    if unmet[k] == 0 && !state.holds(head) {
                        state.set(head, true);
                        queue.push(head);
                        if let Some(why) = why.as_deref_mut() {
                            why[head as usize] = w;
                        }
                    }
                }
            }
            start = end;
        }
    }
}

impl Grounding {
    /// Makes the derived atoms of `state` what the rules derive from its basic atoms
    /// (nothing to do without `:derived` rules). Every state the planner makes goes
    /// through here: the initial state, each successor ([`Grounding::apply`]) and each
    /// disturbed state.
    pub fn close(&self, state: &mut State) {
        if !self.rules.rules.is_empty() {
            self.rules.close(state, None);
        }
    }

    /// `lits`, each holding in the closed `state`, with every derived literal replaced
    /// by basic literals that hold in `state` and imply it in every state (its
    /// *support*): for a derived atom, the bodies of the rules that derived it, back to
    /// basic atoms; for a negated one, a false literal of each of its rules (an
    /// unfounded set: none of them can fire). Regression through actions then stays
    /// over basic atoms, which actions change. A derived literal that does not hold in
    /// `state` is kept as it is.
    #[must_use]
    pub fn support(&self, state: &State, lits: &[Lit]) -> Vec<Lit> {
        let r = &self.rules;
        let mut out: Vec<Lit> = Vec::new();
        if !lits.iter().any(|l| self.is_derived(l.atom)) {
            out.extend_from_slice(lits);
            return out;
        }
        let mut why = vec![u32::MAX; self.atom_count()];
        let mut closed = state.clone();
        r.close(&mut closed, Some(&mut why));
        let mut seen: Vec<Lit> = Vec::new();
        let mut stack: Vec<Lit> = lits.iter().rev().copied().collect();
        while let Some(l) = stack.pop() {
            if !self.is_derived(l.atom) {
                if !out.contains(&l) {
                    out.push(l);
                }
                continue;
            }
            if seen.contains(&l) {
                continue;
            }
            seen.push(l);
            if !l.holds(&closed) {
                // Not this state's: kept as it is (checked as the world derives it).
                if !out.contains(&l) {
                    out.push(l);
                }
                continue;
            }
            if l.positive {
                if let Some(rule) = r.rules.get(why[l.atom as usize] as usize) {
                    stack.extend(rule.body.iter().rev());
                }
                continue;
            }
            let Ok(k) = r.derived.binary_search(&l.atom) else { continue };
            for &i in &r.by_head[k] {
                // A false literal of the rule: basic first, then lower strata, then its own.
                let false_lits = r.rules[i as usize].body.iter().filter(|b| !b.holds(&closed));
                if let Some(b) = false_lits.min_by_key(|b| r.stratum[b.atom as usize]) {
                    stack.push(b.negated());
                }
            }
        }
        out
    }

    /// Applies ground action `action` to `state` and closes it under the rules.
    pub fn apply(&self, action: &super::GroundAction, state: &mut State) {
        action.apply(state);
        self.close(state);
    }

    /// The ground rules of derived predicates, by stratum.
    #[must_use]
    pub fn rules(&self) -> &[Rule] {
        &self.rules.rules
    }

    /// Whether the atom is derived (its predicate has `:derived` rules).
    #[must_use]
    pub fn is_derived(&self, atom: AtomId) -> bool {
        self.rules.derived.binary_search(&atom).is_ok()
    }
}
