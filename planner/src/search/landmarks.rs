//! Landmarks and the landmark-count heuristic, as LAMA uses them to guide its
//! search alongside h_FF (Richter, Westphal, "The LAMA planner", JAIR 2010), in a
//! simpler form: landmarks of one literal and small disjunctive ones, found by
//! backchaining from the goal through the relaxed problem.
//!
//! A literal is a *landmark* when every plan makes it true at some point. The goal's
//! literals are; and for a landmark `l` not true initially, every plan reaches `l`
//! first by an action that is applicable in the relaxed problem without `l`: the
//! literals all of those *possible first achievers* need are landmarks too, ordered
//! before `l` (greedy-necessary orderings: the only kind kept). So is a *disjunctive*
//! landmark, as in Fast Downward's `lm_rhw`: where every possible first achiever needs
//! a literal of one predicate and sign (a hand holding the shaker, left or right), one
//! of those literals holds before `l` is first reached; at most four, none true
//! initially, none sharing a literal with another landmark. A disjunctive landmark
//! holds where one of its literals does. The count of a state reached along a path is the landmarks not yet
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
    /// The landmarks, as literal indices: one, or for a disjunctive landmark the few
    /// of which every plan makes one true.
    lits: Vec<Vec<u32>>,
    /// Per landmark: the landmarks ordered before it.
    before: Vec<Vec<u32>>,
    /// Per literal index: the landmark of that literal alone, if it is one.
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
        let init: Vec<bool> = (0..lits as u32).map(|i| Lit::from_index(i).holds(g.init())).collect();
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
            let l = out.lits[k].clone();
            if l.iter().any(|&x| init[x as usize]) {
                k += 1;
                continue;
            }
            if deadline.is_some_and(|d| Instant::now() >= d) || work > WORK {
                break;
            }
            // Relaxed reachability from the initial state without the operators that
            // make (a literal of) `l` true.
            reached.copy_from_slice(&init);
            queue.clear();
            queue.extend((0..lits as u32).filter(|&i| init[i as usize]));
            for (o, op) in ops.iter().enumerate() {
                unsat[o] = op.pre.len() as u32;
            }
            let fire = |o: usize, reached: &mut Vec<bool>, queue: &mut Vec<u32>| {
                if ops[o].eff.iter().any(|e| l.contains(e)) {
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
            // The possible first achievers, the preconditions they all share, and the
            // disjunctions they all need one literal of.
            let first: Vec<&Op> = ops
                .iter()
                .filter(|op| op.eff.iter().any(|e| l.contains(e)) && op.pre.iter().all(|&p| reached[p as usize]))
                .collect();
            work += first.iter().map(|op| op.pre.len() as u64 + 1).sum::<u64>();
            let mut shared: Option<Vec<u32>> = None;
            for op in &first {
                shared = Some(match shared {
                    None => op.pre.clone(),
                    Some(s) => s.into_iter().filter(|p| op.pre.contains(p)).collect(),
                });
            }
            let shared = shared.unwrap_or_default();
            let mut found: Vec<u32> = shared.iter().map(|&p| out.add(p, false)).collect();
            for set in disjunctions(g, &first, &shared, &init) {
                if set.iter().all(|&x| out.of_lit[x as usize] == NONE && !l.contains(&x))
                    && let Some(q) = out.add_set(set)
                {
                    found.push(q);
                }
            }
            for q in found {
                if q != k as u32 && !out.before[k].contains(&q) {
                    out.before[k].push(q);
                }
            }
            k += 1;
        }
        if deadline.is_some_and(|d| Instant::now() >= d) {
            return None;
        }
        out.drop_overlapping();
        (out.lits.iter().any(|l| l.iter().all(|&x| !init[x as usize]))).then_some(out)
    }

    /// The landmark of literal `l`, added if new.
    fn add(&mut self, l: u32, goal: bool) -> u32 {
        match self.of_lit[l as usize] {
            NONE => {
                let id = self.push(vec![l], goal);
                self.of_lit[l as usize] = id;
                id
            }
            id => {
                self.goal[id as usize] |= goal;
                id
            }
        }
    }

    /// Drops the disjunctive landmarks with a literal that is a landmark alone (found
    /// after them): that one says more, and the disjunction, reached with it, would
    /// only count again what it counts.
    fn drop_overlapping(&mut self) {
        let keep: Vec<bool> =
            self.lits.iter().map(|l| l.len() == 1 || l.iter().all(|&x| self.of_lit[x as usize] == NONE)).collect();
        let mut id = vec![NONE; self.lits.len()];
        let mut n = 0;
        for (k, &kept) in keep.iter().enumerate() {
            if kept {
                id[k] = n;
                n += 1;
            }
        }
        let mut k = 0;
        self.lits.retain(|_| (keep[k], k += 1).0);
        k = 0;
        self.goal.retain(|_| (keep[k], k += 1).0);
        k = 0;
        self.before.retain(|_| (keep[k], k += 1).0);
        for before in &mut self.before {
            before.retain(|&p| id[p as usize] != NONE);
            for p in before.iter_mut() {
                *p = id[*p as usize];
            }
        }
        for x in &mut self.of_lit {
            if *x != NONE {
                *x = id[*x as usize];
            }
        }
    }

    /// The disjunctive landmark of the literals `set` (sorted), added if no landmark
    /// shares a literal with it; where some do, the one that holds all of `set`, if
    /// any (disjunctive landmarks never overlap: a state reaching one literal would
    /// count as reaching two landmarks).
    fn add_set(&mut self, set: Vec<u32>) -> Option<u32> {
        let overlapping: Vec<usize> =
            (0..self.lits.len()).filter(|&k| self.lits[k].iter().any(|x| set.contains(x))).collect();
        if overlapping.is_empty() {
            return Some(self.push(set, false));
        }
        overlapping.into_iter().find(|&k| set.iter().all(|x| self.lits[k].contains(x))).map(|k| k as u32)
    }

    fn push(&mut self, lits: Vec<u32>, goal: bool) -> u32 {
        let id = self.lits.len() as u32;
        self.lits.push(lits);
        self.before.push(Vec::new());
        self.goal.push(goal);
        id
    }

    /// How many landmarks.
    #[must_use]
    pub fn len(&self) -> usize {
        self.lits.len()
    }

    /// How many landmarks are disjunctive.
    #[must_use]
    pub fn disjunctive(&self) -> usize {
        self.lits.iter().filter(|l| l.len() > 1).count()
    }

    /// How many orderings (each landmark before another).
    #[must_use]
    pub fn orderings(&self) -> usize {
        self.before.iter().map(Vec::len).sum()
    }

    /// The landmark's literals, as `g` names them, joined by " | ".
    #[must_use]
    pub fn name(&self, g: &Grounding, k: usize) -> String {
        let names: Vec<String> =
            self.lits.get(k).map_or(&[][..], Vec::as_slice).iter().map(|&x| g.lit_name(Lit::from_index(x))).collect();
        names.join(" | ")
    }

    /// The landmarks ordered before landmark `k`.
    #[must_use]
    pub fn before(&self, k: usize) -> &[u32] {
        self.before.get(k).map_or(&[], Vec::as_slice)
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
        self.lits.get(k).is_some_and(|l| l.iter().any(|&x| Lit::from_index(x).holds(s)))
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
            for &x in &self.lits[k] {
                for &a in g.achievers(Lit::from_index(x)) {
                    if !helpful.contains(&a) && g.action(a).is_some_and(|y| y.applicable(s)) {
                        helpful.push(a);
                    }
                }
            }
        }
        h
    }
}

/// Most literals of a disjunctive landmark: larger disjunctions say little, and each
/// costs a test per state.
const MAX_DISJUNCTION: usize = 4;

/// Preconditions of one predicate and sign: (predicate, sign), literals.
type Group = ((crate::model::PredicateId, u32), Vec<u32>);

/// The disjunctive landmarks the possible first achievers `first` of a landmark need
/// (each sorted): per predicate and sign of which every achiever has a precondition
/// outside `shared`, those preconditions together, when they are few and none holds
/// initially (one of them must hold before the landmark's first achiever).
fn disjunctions(g: &Grounding, first: &[&Op], shared: &[u32], init: &[bool]) -> Vec<Vec<u32>> {
    let key = |x: u32| {
        let l = Lit::from_index(x);
        (g.atom(l.atom).predicate, u32::from(l.positive))
    };
    let mut sets: Option<Vec<Group>> = None;
    for op in first {
        let mut mine: Vec<Group> = Vec::new();
        for &p in op.pre.iter().filter(|p| !shared.contains(p)) {
            match mine.iter_mut().find(|(k, _)| *k == key(p)) {
                Some((_, v)) => v.push(p),
                None => mine.push((key(p), vec![p])),
            }
        }
        sets = Some(match sets {
            None => mine,
            Some(s) => s
                .into_iter()
                .filter_map(|(k, mut v)| {
                    let (_, more) = mine.iter().find(|(m, _)| *m == k)?;
                    for &p in more {
                        if !v.contains(&p) {
                            v.push(p);
                        }
                    }
                    Some((k, v))
                })
                .collect(),
        });
    }
    let mut out: Vec<Vec<u32>> = sets
        .unwrap_or_default()
        .into_iter()
        .map(|(_, mut v)| {
            v.sort_unstable();
            v
        })
        .filter(|v| v.len() > 1 && v.len() <= MAX_DISJUNCTION && v.iter().all(|&x| !init[x as usize]))
        .collect();
    out.sort_unstable();
    out
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

    /// A tool either hand may grasp, needed to finish; tidying needs it in the left.
    fn two_hands(goal: &str) -> Grounding {
        let domain = "(define (domain hands) (:requirements :strips :typing) (:types hand)
            (:constants left right - hand)
            (:predicates (free ?h - hand) (holding ?h - hand) (ontable) (done) (tidy))
            (:action grasp :parameters (?h - hand) :precondition (and (free ?h) (ontable))
                :effect (and (holding ?h) (not (free ?h)) (not (ontable))))
            (:action finish :parameters (?h - hand) :precondition (holding ?h) :effect (done))
            (:action tidy :parameters () :precondition (holding left) :effect (tidy)))";
        let problem =
            format!("(define (problem p) (:domain hands) (:init (free left) (free right) (ontable)) (:goal {goal}))");
        let d = crate::pddl::parse_domain("hands.pddl", domain).unwrap();
        let p = crate::pddl::parse_problem("p.pddl", &problem, &d).unwrap();
        Grounding::new(&p).unwrap()
    }

    #[test]
    fn grasping_with_either_hand_is_progress_of_the_count() {
        // No one hand is a landmark, but holding the tool in one of them is.
        let g = two_hands("(done)");
        let lm = Landmarks::new(&g, None).unwrap();
        assert_eq!((lm.len(), lm.disjunctive()), (3, 1), "done, the two hands, ontable");
        let (mut accepted, mut next, mut helpful) = (Vec::new(), Vec::new(), Vec::new());
        lm.initial(g.init(), &mut accepted);
        assert_eq!(lm.count(&g, &accepted, g.init(), &mut helpful), 2);
        assert_eq!(helpful.len(), 2, "either grasp");
        for hand in ["left", "right"] {
            let mut s = g.init().clone();
            step(&g, &mut s, g.atom_by_name("holding", &[hand]).unwrap());
            lm.accept(&accepted, &s, &mut next);
            assert_eq!(lm.count(&g, &next, &s, &mut helpful), 1, "{hand}");
            // Were the tool back on the table, it would be needed again for `done`.
            assert_eq!(lm.count(&g, &next, g.init(), &mut helpful), 2, "{hand}");
        }
    }

    #[test]
    fn a_disjunction_overlapping_a_landmark_found_later_is_dropped() {
        // Tidying makes holding the tool in the left hand a landmark of its own.
        let g = two_hands("(and (done) (tidy))");
        let lm = Landmarks::new(&g, None).unwrap();
        assert_eq!(lm.disjunctive(), 0);
        let names: Vec<String> = (0..lm.len()).map(|k| lm.name(&g, k)).collect();
        assert!(names.contains(&"holding(left)".to_string()), "{names:?}");
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
