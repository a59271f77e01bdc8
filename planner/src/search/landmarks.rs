//! Landmarks and the landmark-count heuristic, as LAMA uses them to guide its
//! search alongside h_FF (Richter, Westphal, "The LAMA planner", JAIR 2010), in a
//! simpler form: fact landmarks only (no disjunctive ones), found by backchaining
//! from the goal through the relaxed problem.
//!
//! A literal is a *landmark* when every plan makes it true at some point. The goal's
//! literals are; and for a landmark `l` not true initially, every plan reaches `l`
//! first by an action that is applicable in the relaxed problem without `l`: the
//! literals all of those *possible first achievers* need are landmarks too, ordered
//! before `l`. The count of a state reached along a path is the landmarks not yet
//! *accepted* on it (true at some state of the path, after every landmark ordered
//! before them was accepted), plus the accepted ones that must be made true again: a
//! goal literal that is false now, or a landmark ordered before one not accepted yet
//! that is false now. Helpful here, as in Fast Downward's landmark heuristic: the
//! applicable actions that make true a landmark the count counts.
//!
//! Derived atoms (`:derived`) are left out: not landmarks, and not preconditions in the
//! relaxed problem (relaxing further only finds fewer landmarks, never a false one).

use std::time::Instant;

use crate::ground::{ActionId, Grounding, Lit};
use crate::state::State;

/// Most pre-condition visits landmark generation may make (the relaxed reachability
/// it runs per landmark costs one per precondition of every operator).
const WORK: u64 = 50_000_000;

/// The landmarks of a problem with their orderings.
#[derive(Debug)]
pub struct Landmarks {
    /// The landmarks, as literal indices.
    lits: Vec<u32>,
    /// Per landmark: the landmarks ordered before it.
    before: Vec<Vec<u32>>,
    /// Per literal index: its landmark, if it is one.
    of_lit: Vec<u32>,
    /// Whether each landmark is a goal literal.
    goal: Vec<bool>,
}

const NONE: u32 = u32::MAX;

/// One relaxed operator: its preconditions and effects as literal indices.
struct Op {
    pre: Vec<u32>,
    eff: Vec<u32>,
}

fn ops_of(g: &Grounding) -> Vec<Op> {
    let mut ops = Vec::new();
    let basic = |l: &&Lit| !g.is_derived(l.atom);
    for a in g.actions() {
        ops.push(Op {
            pre: a.pre.iter().filter(basic).map(|l| l.index() as u32).collect(),
            eff: a.must_effects().map(|l| l.index() as u32).collect(),
        });
        for c in &a.cond {
            let add = c.add.iter().map(|&atom| Lit { atom, positive: true });
            let del = c.del.iter().map(|&atom| Lit { atom, positive: false });
            ops.push(Op {
                pre: a.pre.iter().chain(c.when.iter()).filter(basic).map(|l| l.index() as u32).collect(),
                eff: add.chain(del).map(|l| l.index() as u32).collect(),
            });
        }
    }
    ops
}

impl Landmarks {
    /// The landmarks of `g` from its initial state; `None` when there are none beyond
    /// what holds initially, or the deadline passed while they were being found.
    #[must_use]
    pub fn new(g: &Grounding, deadline: Option<Instant>) -> Option<Self> {
        let lits = g.atom_count() * 2;
        let ops = ops_of(g);
        let mut consumers: Vec<Vec<u32>> = vec![Vec::new(); lits];
        for (k, op) in ops.iter().enumerate() {
            for &p in &op.pre {
                consumers[p as usize].push(k as u32);
            }
        }
        let init: Vec<bool> =
            (0..lits).map(|i| Lit { atom: (i / 2) as u32, positive: i % 2 == 1 }.holds(g.init())).collect();
        let mut out = Self { lits: Vec::new(), before: Vec::new(), of_lit: vec![NONE; lits], goal: Vec::new() };
        for l in g.goal().iter().filter(|l| !g.is_derived(l.atom)) {
            out.add(l.index() as u32, true);
        }
        let mut reached = vec![false; lits];
        let mut unsat = vec![0u32; ops.len()];
        let mut queue: Vec<u32> = Vec::new();
        let mut work: u64 = 0;
        let mut k = 0;
        while k < out.lits.len() {
            let l = out.lits[k];
            if init[l as usize] {
                k += 1;
                continue;
            }
            if deadline.is_some_and(|d| Instant::now() >= d) || work > WORK {
                break;
            }
            // Relaxed reachability from the initial state without the operators that
            // make `l` true.
            reached.copy_from_slice(&init);
            queue.clear();
            queue.extend((0..lits as u32).filter(|&i| init[i as usize]));
            for (o, op) in ops.iter().enumerate() {
                unsat[o] = op.pre.len() as u32;
            }
            let fire = |o: usize, reached: &mut Vec<bool>, queue: &mut Vec<u32>| {
                if ops[o].eff.contains(&l) {
                    return;
                }
                for &e in &ops[o].eff {
                    if !reached[e as usize] {
                        reached[e as usize] = true;
                        queue.push(e);
                    }
                }
            };
            for (o, op) in ops.iter().enumerate() {
                if op.pre.is_empty() {
                    fire(o, &mut reached, &mut queue);
                }
            }
            while let Some(p) = queue.pop() {
                for &o in &consumers[p as usize] {
                    work += 1;
                    unsat[o as usize] -= 1;
                    if unsat[o as usize] == 0 {
                        fire(o as usize, &mut reached, &mut queue);
                    }
                }
            }
            // The possible first achievers, and the preconditions they all share.
            let mut shared: Option<Vec<u32>> = None;
            for op in &ops {
                if !op.eff.contains(&l) || !op.pre.iter().all(|&p| reached[p as usize]) {
                    continue;
                }
                work += op.pre.len() as u64 + 1;
                shared = Some(match shared {
                    None => op.pre.clone(),
                    Some(s) => s.into_iter().filter(|p| op.pre.contains(p)).collect(),
                });
            }
            for p in shared.unwrap_or_default() {
                let q = out.add(p, false);
                if q != k as u32 && !out.before[k].contains(&q) {
                    out.before[k].push(q);
                }
            }
            k += 1;
        }
        if deadline.is_some_and(|d| Instant::now() >= d) {
            return None;
        }
        (out.lits.iter().any(|&l| !init[l as usize])).then_some(out)
    }

    /// The landmark of literal `l`, added if new.
    fn add(&mut self, l: u32, goal: bool) -> u32 {
        match self.of_lit[l as usize] {
            NONE => {
                let id = self.lits.len() as u32;
                self.of_lit[l as usize] = id;
                self.lits.push(l);
                self.before.push(Vec::new());
                self.goal.push(goal);
                id
            }
            id => {
                self.goal[id as usize] |= goal;
                id
            }
        }
    }

    /// How many landmarks.
    #[must_use]
    pub fn len(&self) -> usize {
        self.lits.len()
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.lits.is_empty()
    }

    /// Words of one accepted set.
    #[must_use]
    pub fn words(&self) -> usize {
        self.lits.len().div_ceil(64)
    }

    fn holds(&self, k: usize, s: &State) -> bool {
        let l = self.lits[k];
        Lit { atom: l / 2, positive: l % 2 == 1 }.holds(s)
    }

    /// The landmarks accepted at the start: those true in `s` with nothing before them
    /// that is not.
    pub fn initial(&self, s: &State, out: &mut Vec<u64>) {
        let none = vec![0u64; self.words()];
        self.accept(&none, s, out);
    }

    /// The landmarks accepted in `s` reached from a state whose accepted set is
    /// `parent`: those accepted there, and those true in `s` whose predecessors were
    /// all accepted there or are true in `s`.
    pub fn accept(&self, parent: &[u64], s: &State, out: &mut Vec<u64>) {
        out.clear();
        out.extend_from_slice(parent);
        let is = |set: &[u64], k: usize| set.get(k / 64).is_some_and(|w| w >> (k % 64) & 1 == 1);
        for k in 0..self.lits.len() {
            if is(parent, k) || !self.holds(k, s) {
                continue;
            }
            if self.before[k].iter().all(|&p| is(parent, p as usize) || self.holds(p as usize, s))
                && let Some(w) = out.get_mut(k / 64)
            {
                *w |= 1 << (k % 64);
            }
        }
    }

    /// The landmark count of `s` with `accepted` (see the module docs), and the
    /// helpful actions applicable in `s` into `helpful`.
    pub fn count(&self, g: &Grounding, accepted: &[u64], s: &State, helpful: &mut Vec<ActionId>) -> u32 {
        helpful.clear();
        let is = |k: usize| accepted.get(k / 64).is_some_and(|w| w >> (k % 64) & 1 == 1);
        // The landmarks still to make true: not accepted, or accepted and needed again.
        let mut future = vec![false; self.lits.len()];
        for k in 0..self.lits.len() {
            if is(k) {
                future[k] |= self.goal[k] && !self.holds(k, s);
                continue;
            }
            future[k] = true;
            for &p in &self.before[k] {
                if is(p as usize) && !self.holds(p as usize, s) {
                    future[p as usize] = true;
                }
            }
        }
        let mut h = 0u32;
        for k in (0..self.lits.len()).filter(|&k| future[k]) {
            h += 1;
            let l = self.lits[k];
            for &a in g.achievers(Lit { atom: l / 2, positive: l % 2 == 1 }) {
                if !helpful.contains(&a) && g.action(a).is_some_and(|x| x.applicable(s)) {
                    helpful.push(a);
                }
            }
        }
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domains;

    /// The applicable achiever of `atom` in `s`, applied to `s`.
    fn step(g: &Grounding, s: &mut State, atom: crate::ground::AtomId) -> ActionId {
        let a =
            *g.achievers(Lit { atom, positive: true }).iter().find(|&&a| g.action(a).unwrap().applicable(s)).unwrap();
        g.action(a).unwrap().apply(s);
        a
    }

    #[test]
    fn the_achiever_of_a_goal_undone_after_it_was_accepted_is_helpful() {
        // Goal: b1 on b2, b0 on b1. Stack b1 on b2, then pick b1 up again.
        let g = domains::blocks_world(3).unwrap();
        let lm = Landmarks::new(&g, None).unwrap();
        let on12 = g.atom_by_name("on", &["b1", "b2"]).unwrap();
        let holding1 = g.atom_by_name("holding", &["b1"]).unwrap();
        let mut s = g.init().clone();
        let (mut accepted, mut next) = (Vec::new(), Vec::new());
        lm.initial(&s, &mut accepted);
        let mut stack = 0;
        for (k, atom) in [holding1, on12, holding1].into_iter().enumerate() {
            let a = step(&g, &mut s, atom);
            if k == 1 {
                stack = a;
            }
            lm.accept(&accepted, &s, &mut next);
            std::mem::swap(&mut accepted, &mut next);
        }
        assert!(!g.goal_holds(&s));
        let mut helpful = Vec::new();
        let h = lm.count(&g, &accepted, &s, &mut helpful);
        assert!(h > 0);
        assert!(helpful.contains(&stack), "{helpful:?}");
    }
}
