//! Delete-relaxation heuristics over literals: h_add and h_FF with helpful actions.
//!
//! The relaxation works on literals, not atoms: `p` and `not p` are separate facts, a
//! delete effect achieves `not p`, and a state makes true every literal that holds in
//! it. Negative preconditions and goals are then estimated like positive ones. Each
//! ground action is one relaxed operator, and each of its conditional effects one
//! more (with the effect's condition added to the preconditions).
//!
//! The rules of derived predicates are relaxed operators too, costing nothing;
//! negated derived atoms (in preconditions, rule bodies and goals) are left out of the
//! relaxation, as they cannot be achieved by any one operator.
//!
//! h_add propagates costs with a priority queue (Dijkstra over the AND/OR graph of
//! operators and literals), each action costing 1; h_FF extracts a relaxed plan by
//! following best supporters back from the goal and counts its actions. The
//! relaxed plan's actions whose preconditions hold in the state are the *helpful
//! actions*.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::ground::{ActionId, Grounding, Lit};
use crate::state::State;

/// Unreachable in the relaxation.
pub const INFINITE: u32 = u32::MAX;

/// The relaxed operators in compressed rows, and the scratch space of an evaluation.
#[derive(Debug)]
pub struct Relaxation {
    /// Per operator: the range of its preconditions in `pre`.
    op_pre: Vec<(u32, u32)>,
    /// Per operator: the range of its effects in `eff`.
    op_eff: Vec<(u32, u32)>,
    /// Per operator: the ground action it comes from ([`NONE`] for a rule).
    op_action: Vec<ActionId>,
    pre: Vec<u32>,
    eff: Vec<u32>,
    /// Per literal: the range of the operators that need it in `consumers`.
    lit_consumers: Vec<(u32, u32)>,
    consumers: Vec<u32>,
    /// Operators without preconditions.
    free: Vec<u32>,
    /// [`Relaxation::size`].
    full_size: u64,
    goal: Vec<u32>,
    is_goal: Vec<bool>,
    // Scratch, reused by every evaluation.
    cost: Vec<u32>,
    supporter: Vec<u32>,
    unsat: Vec<u32>,
    op_cost: Vec<u32>,
    marked: Vec<bool>,
    marked_list: Vec<u32>,
    heap: BinaryHeap<Reverse<(u32, u32)>>,
}

const NONE: u32 = u32::MAX;

/// Relaxed operators in compressed rows, as [`Relaxation`] keeps them.
struct Rows {
    op_pre: Vec<(u32, u32)>,
    op_eff: Vec<(u32, u32)>,
    op_action: Vec<ActionId>,
    pre: Vec<u32>,
    eff: Vec<u32>,
}

impl Rows {
    /// Keeps only what can matter to the goal, as Fast Downward's translator does
    /// (backward relevance): a literal is relevant when it is a goal or a
    /// precondition of a relevant operator, an operator when one of its effects is
    /// relevant. The rest never changes the cost of a goal literal nor its best
    /// supporters (the order in which relevant operators fire is kept), so h_add,
    /// h_FF and the helpful actions are the same, for less work per evaluation: a
    /// delete effect no negative precondition or goal needs, an atom only the plan's
    /// bookkeeping writes (trucks: `delivered` at times no goal names).
    fn keep_relevant(&mut self, goal: &[u32], lits: usize) {
        // Per literal: the operators with it among their effects.
        let mut producers: Vec<Vec<u32>> = vec![Vec::new(); lits];
        for (op, &(s, e)) in self.op_eff.iter().enumerate() {
            for &l in self.eff.get(s as usize..e as usize).unwrap_or(&[]) {
                if let Some(p) = producers.get_mut(l as usize) {
                    p.push(op as u32);
                }
            }
        }
        let mut relevant = vec![false; lits];
        let mut used = vec![false; self.op_pre.len()];
        let mut stack: Vec<u32> = Vec::new();
        for &l in goal {
            if let Some(r) = relevant.get_mut(l as usize).filter(|r| !**r) {
                *r = true;
                stack.push(l);
            }
        }
        while let Some(l) = stack.pop() {
            for &op in producers.get(l as usize).map_or(&[][..], Vec::as_slice) {
                let Some(u) = used.get_mut(op as usize).filter(|u| !**u) else { continue };
                *u = true;
                let (s, e) = self.op_pre.get(op as usize).copied().unwrap_or((0, 0));
                for &p in self.pre.get(s as usize..e as usize).unwrap_or(&[]) {
                    if let Some(r) = relevant.get_mut(p as usize).filter(|r| !**r) {
                        *r = true;
                        stack.push(p);
                    }
                }
            }
        }
        let mut kept =
            Rows { op_pre: Vec::new(), op_eff: Vec::new(), op_action: Vec::new(), pre: Vec::new(), eff: Vec::new() };
        for (op, &keep) in used.iter().enumerate() {
            let (Some(&(ps, pe)), Some(&(es, ee)), Some(&action)) =
                (self.op_pre.get(op), self.op_eff.get(op), self.op_action.get(op))
            else {
                continue;
            };
            if !keep {
                continue;
            }
            let s = kept.pre.len() as u32;
            kept.pre.extend_from_slice(self.pre.get(ps as usize..pe as usize).unwrap_or(&[]));
            kept.op_pre.push((s, kept.pre.len() as u32));
            let s = kept.eff.len() as u32;
            let effects = self.eff.get(es as usize..ee as usize).unwrap_or(&[]);
            kept.eff.extend(effects.iter().copied().filter(|&l| relevant.get(l as usize).copied().unwrap_or(false)));
            kept.op_eff.push((s, kept.eff.len() as u32));
            kept.op_action.push(action);
        }
        *self = kept;
    }
}

impl Relaxation {
    /// The relaxed operators of `g`, for its goal.
    #[must_use]
    pub fn new(g: &Grounding) -> Self {
        Self::build(g, true)
    }

    /// The relaxed operators of `g`, those irrelevant to the goal left out or not.
    fn build(g: &Grounding, relevant_only: bool) -> Self {
        let lits = g.atom_count() * 2;
        let mut op_pre = Vec::new();
        let mut op_eff = Vec::new();
        let mut op_action = Vec::new();
        let mut pre: Vec<u32> = Vec::new();
        let mut eff: Vec<u32> = Vec::new();
        let kept = |l: &Lit| l.positive || !g.is_derived(l.atom);
        let mut push = |p: &mut dyn Iterator<Item = Lit>, e: &mut dyn Iterator<Item = Lit>, action: ActionId| {
            let s = pre.len() as u32;
            pre.extend(p.filter(kept).map(|l| l.index() as u32));
            op_pre.push((s, pre.len() as u32));
            let s = eff.len() as u32;
            eff.extend(e.map(|l| l.index() as u32));
            op_eff.push((s, eff.len() as u32));
            op_action.push(action);
        };
        for (i, a) in g.actions().iter().enumerate() {
            push(&mut a.pre.iter().copied(), &mut a.must_effects(), i as ActionId);
            for c in &a.cond {
                let add = c.add.iter().map(|&atom| Lit { atom, positive: true });
                let del = c.del.iter().map(|&atom| Lit { atom, positive: false });
                push(&mut a.pre.iter().chain(c.when.iter()).copied(), &mut add.chain(del), i as ActionId);
            }
        }
        for r in g.rules() {
            push(&mut r.body.iter().copied(), &mut std::iter::once(Lit { atom: r.head, positive: true }), NONE);
        }
        let full_size = (op_pre.len() + pre.len() + eff.len() + lits) as u64;
        let goal: Vec<u32> = g.goal().iter().filter(|l| kept(l)).map(|l| l.index() as u32).collect();
        let mut ops = Rows { op_pre, op_eff, op_action, pre, eff };
        if relevant_only {
            ops.keep_relevant(&goal, lits);
        }
        let Rows { op_pre, op_eff, op_action, pre, eff } = ops;
        let nops = op_pre.len();
        let mut counts = vec![0u32; lits + 1];
        for &p in &pre {
            counts[p as usize + 1] += 1;
        }
        for i in 0..lits {
            counts[i + 1] += counts[i];
        }
        let mut fill = counts.clone();
        let mut consumers = vec![0u32; pre.len()];
        let mut free = Vec::new();
        for (op, &(s, e)) in op_pre.iter().enumerate() {
            if s == e {
                free.push(op as u32);
            }
            for &p in &pre[s as usize..e as usize] {
                consumers[fill[p as usize] as usize] = op as u32;
                fill[p as usize] += 1;
            }
        }
        let lit_consumers = (0..lits).map(|i| (counts[i], counts[i + 1])).collect();
        Self {
            op_pre,
            op_eff,
            op_action,
            pre,
            eff,
            lit_consumers,
            consumers,
            free,
            full_size,
            goal,
            is_goal: {
                let mut v = vec![false; lits];
                for l in g.goal().iter().filter(|l| kept(l)) {
                    if let Some(x) = v.get_mut(l.index()) {
                        *x = true;
                    }
                }
                v
            },
            cost: vec![INFINITE; lits],
            supporter: vec![NONE; lits],
            unsat: vec![0; nops],
            op_cost: vec![0; nops],
            marked: vec![false; nops],
            marked_list: Vec::new(),
            heap: BinaryHeap::new(),
        }
    }

    /// The entries of the relaxation before the operators and effects irrelevant to the
    /// goal are left out: operators, their preconditions and effects, and literals (a
    /// measure of the grounding's size that does not depend on the machine, used for
    /// search budgets; an evaluation visits at most this many).
    #[must_use]
    pub fn size(&self) -> u64 {
        self.full_size
    }

    /// The entries an evaluation visits at most: [`Relaxation::size`] without what is
    /// irrelevant to the goal.
    #[must_use]
    pub fn relevant_size(&self) -> u64 {
        (self.op_pre.len() + self.pre.len() + self.eff.len() + self.cost.len()) as u64
    }

    /// Runs h_add's propagation from `state` until every goal literal has its final
    /// cost (or nothing more can be reached). Returns h_add.
    fn propagate(&mut self, state: &State) -> u32 {
        self.cost.fill(INFINITE);
        self.supporter.fill(NONE);
        self.heap.clear();
        for (op, &(s, e)) in self.op_pre.iter().enumerate() {
            self.unsat[op] = e - s;
            self.op_cost[op] = 0;
        }
        let atoms = self.cost.len() / 2;
        for atom in 0..atoms {
            let l = Lit { atom: atom as u32, positive: state.holds(atom as u32) }.index();
            self.cost[l] = 0;
        }
        for i in 0..self.free.len() {
            let op = self.free[i];
            self.fire(op, 0);
        }
        // Literals true in the state cost nothing: settle them without the queue.
        for atom in 0..atoms {
            let l = Lit { atom: atom as u32, positive: state.holds(atom as u32) }.index() as u32;
            self.settle(l, 0);
        }
        let mut goals_left = self.goal.iter().filter(|&&g| self.cost[g as usize] != 0).count();
        while goals_left > 0 {
            let Some(Reverse((c, l))) = self.heap.pop() else { break };
            if c > self.cost[l as usize] {
                continue;
            }
            if self.is_goal[l as usize] {
                goals_left = goals_left.saturating_sub(1);
            }
            self.settle(l, c);
        }
        let mut h: u32 = 0;
        for &g in &self.goal {
            let c = self.cost[g as usize];
            if c == INFINITE {
                return INFINITE;
            }
            h = h.saturating_add(c);
        }
        h
    }

    /// Literal `l` has its final cost `c`: its consumers count it.
    fn settle(&mut self, l: u32, c: u32) {
        let (s, e) = self.lit_consumers[l as usize];
        for k in s..e {
            let op = self.consumers[k as usize];
            self.op_cost[op as usize] = self.op_cost[op as usize].saturating_add(c);
            self.unsat[op as usize] -= 1;
            if self.unsat[op as usize] == 0 {
                let oc = self.op_cost[op as usize];
                self.fire(op, oc);
            }
        }
    }

    /// An operator whose preconditions cost `pre_cost` in total reaches its effects
    /// at that cost plus one (plus nothing for a rule).
    fn fire(&mut self, op: u32, pre_cost: u32) {
        let c = pre_cost.saturating_add(u32::from(self.op_action[op as usize] != NONE));
        let (s, e) = self.op_eff[op as usize];
        for k in s..e {
            let l = self.eff[k as usize] as usize;
            if c < self.cost[l] {
                self.cost[l] = c;
                self.supporter[l] = op;
                self.heap.push(Reverse((c, l as u32)));
            }
        }
    }

    /// h_add of `state`.
    pub fn h_add(&mut self, state: &State) -> u32 {
        self.propagate(state)
    }

    /// h_FF of `state` (the number of operators of a relaxed plan), and the helpful
    /// actions (relaxed-plan actions applicable in `state`) into `helpful`.
    pub fn h_ff(&mut self, state: &State, helpful: &mut Vec<ActionId>) -> u32 {
        helpful.clear();
        if self.propagate(state) == INFINITE {
            return INFINITE;
        }
        for &op in &self.marked_list {
            self.marked[op as usize] = false;
        }
        self.marked_list.clear();
        let mut stack: Vec<u32> = self.goal.clone();
        while let Some(l) = stack.pop() {
            if self.cost[l as usize] == 0 {
                continue;
            }
            let op = self.supporter[l as usize];
            if op == NONE || self.marked[op as usize] {
                continue;
            }
            self.marked[op as usize] = true;
            self.marked_list.push(op);
            let (s, e) = self.op_pre[op as usize];
            let mut applicable = true;
            for k in s..e {
                let p = self.pre[k as usize];
                if self.cost[p as usize] != 0 {
                    applicable = false;
                    stack.push(p);
                }
            }
            let a = self.op_action[op as usize];
            if applicable && a != NONE && !helpful.contains(&a) {
                helpful.push(a);
            }
        }
        self.marked_list.iter().filter(|&&op| self.op_action[op as usize] != NONE).count() as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domains;
    use crate::pddl::{parse_domain, parse_problem};

    /// A delivery with a negative precondition, a conditional effect and a log no goal
    /// reads (as trucks' `delivered` at every time).
    const DOMAIN: &str = "(define (domain d) (:requirements :adl)
        (:predicates (at ?x) (held) (logged ?x) (lit) (dark))
        (:action pick :parameters (?x) :precondition (and (at ?x) (not (held)))
            :effect (and (held) (not (at ?x)) (logged ?x) (when (lit) (dark))))
        (:action drop :parameters (?x) :precondition (held)
            :effect (and (not (held)) (at ?x) (logged ?x)))
        (:action switch :parameters () :precondition (not (dark)) :effect (lit)))";
    const PROBLEM: &str = "(define (problem p) (:domain d) (:objects a b c)
        (:init (at a)) (:goal (and (at c) (not (dark)))))";

    fn delivery() -> Grounding {
        let d = parse_domain("d.pddl", DOMAIN).unwrap();
        Grounding::new(&parse_problem("p.pddl", PROBLEM, &d).unwrap()).unwrap()
    }

    #[test]
    fn an_evaluation_leaves_out_what_the_goal_does_not_need() {
        for g in [delivery(), domains::blocks_world(5).unwrap()] {
            let h = Relaxation::new(&g);
            assert!(h.relevant_size() < h.size(), "{} of {}", h.relevant_size(), h.size());
            assert_eq!(h.size(), Relaxation::build(&g, false).relevant_size());
        }
        // Nothing reads `logged` nor `(not (at ?x))`: no effect writes them.
        let g = delivery();
        let h = Relaxation::new(&g);
        let logged = g.atom_by_name("logged", &["a"]).unwrap();
        let not_at = Lit { atom: g.atom_by_name("at", &["a"]).unwrap(), positive: false };
        assert!(!h.eff.contains(&(Lit { atom: logged, positive: true }.index() as u32)));
        assert!(!h.eff.contains(&(not_at.index() as u32)));
        // `held` is a precondition of `drop`, which reaches the goal `(at c)`.
        assert!(h.eff.contains(&(Lit { atom: g.atom_by_name("held", &[]).unwrap(), positive: true }.index() as u32)));
    }

    #[test]
    fn h_ff_and_helpful_actions_are_those_of_the_whole_relaxation() {
        for g in [delivery(), domains::blocks_world(5).unwrap(), domains::cellphone().unwrap()] {
            let mut pruned = Relaxation::new(&g);
            let mut whole = Relaxation::build(&g, false);
            let (mut a, mut b) = (Vec::new(), Vec::new());
            let mut s = g.init().clone();
            let mut seed: u64 = 7;
            for _ in 0..300 {
                assert_eq!(pruned.h_add(&s), whole.h_add(&s));
                assert_eq!(pruned.h_ff(&s, &mut a), whole.h_ff(&s, &mut b));
                assert_eq!(a, b);
                let applicable: Vec<&crate::ground::GroundAction> =
                    g.actions().iter().filter(|x| x.applicable(&s)).collect();
                if applicable.is_empty() {
                    s = g.init().clone();
                    continue;
                }
                seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                g.apply(applicable[(seed >> 33) as usize % applicable.len()], &mut s);
            }
        }
    }
}
