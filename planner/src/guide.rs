//! A plan found by search, as guidance for backchaining: which action achieves a
//! condition, and in which order to place conditions.
//!
//! The plan `a1 .. an` passes through the states `s0 .. sn`. A condition that some
//! action needs (the goal counts as step `n + 1`) has a *causal link*: the step from
//! which it holds without a break until it is needed (step 0 when it holds from the
//! initial state on). Guided backchaining expands a condition with the action of its
//! link, with that action's preconditions in the order their own links come in the
//! plan (earliest first), and places the goal conditions the same way. The tree keeps
//! the shape of Algorithm 1 — condition, Fallback, Sequence of preconditions and
//! action — and its reactivity; only the choices come from the plan.

use crate::ground::{ActionId, Grounding, Lit};
use crate::state::State;

/// A plan and the states it passes through.
#[derive(Clone, Debug)]
pub struct Trace {
    plan: Vec<ActionId>,
    states: Vec<State>,
}

impl Trace {
    /// The trace of `plan` from the initial state, or `None` when an action is not
    /// applicable where the plan uses it.
    #[must_use]
    pub fn new(g: &Grounding, plan: &[ActionId]) -> Option<Self> {
        Self::from_state(g, g.init(), plan)
    }

    /// The trace of `plan` from `start`, or `None` when an action is not applicable
    /// where the plan uses it.
    #[must_use]
    pub fn from_state(g: &Grounding, start: &State, plan: &[ActionId]) -> Option<Self> {
        let mut states = Vec::with_capacity(plan.len() + 1);
        let mut s = start.clone();
        states.push(s.clone());
        for &a in plan {
            let x = g.action(a)?;
            if !x.applicable(&s) {
                return None;
            }
            g.apply(x, &mut s);
            states.push(s.clone());
        }
        Some(Self { plan: plan.to_vec(), states })
    }

    /// The plan.
    #[must_use]
    pub fn plan(&self) -> &[ActionId] {
        &self.plan
    }

    /// The step of the goal: `n + 1`.
    #[must_use]
    pub fn goal_step(&self) -> usize {
        self.plan.len() + 1
    }

    /// State `s_i` (`s_0` is the initial state).
    #[must_use]
    pub fn state(&self, i: usize) -> Option<&State> {
        self.states.get(i)
    }

    /// The step from which `lit` holds without a break until step `k` needs it (in
    /// `s_{k-1}`): 0 when it holds from the initial state on. When `lit` does not
    /// hold where step `k` would need it, the last step before `k` that made it true.
    #[must_use]
    pub fn since(&self, lit: Lit, k: usize) -> Option<usize> {
        let k = k.min(self.goal_step());
        let mut t = k.checked_sub(1)?;
        if !lit.holds(self.states.get(t)?) {
            return (1..k).rev().find(|&j| lit.holds(&self.states[j]) && !lit.holds(&self.states[j - 1]));
        }
        while t > 0 && lit.holds(&self.states[t - 1]) {
            t -= 1;
        }
        Some(t)
    }

    /// The action of `lit`'s causal link for step `k` and its step, unless `lit`
    /// holds from the initial state on.
    #[must_use]
    pub fn achiever(&self, lit: Lit, k: usize) -> Option<(usize, ActionId)> {
        let j = self.since(lit, k)?;
        let a = *self.plan.get(j.checked_sub(1)?)?;
        Some((j, a))
    }

    /// The action of `lit`'s causal link for step `k` ([`Trace::achiever`]), with the
    /// conditions it needs there (its preconditions and those of the effect that makes
    /// `lit` true) in the order of their own causal links, and its step: how guided
    /// backchaining expands `lit`. `None` where `lit` holds from the initial state on,
    /// or where that action needs `lit` itself.
    #[must_use]
    pub fn causal_step(&self, g: &Grounding, lit: Lit, k: usize) -> Option<(ActionId, Vec<Lit>, usize)> {
        let (j, a) = self.achiever(lit, k)?;
        let action = g.action(a)?;
        let mut pre = action.pre.clone();
        for &w in action.achieving_condition(lit)? {
            if !pre.contains(&w) {
                pre.push(w);
            }
        }
        if pre.contains(&lit) {
            return None;
        }
        Some((a, self.ordered(&pre, j), j))
    }

    /// `lits` in the order of their causal links for step `k` (earliest first; ties,
    /// and literals without a link, keep their order).
    #[must_use]
    pub fn ordered(&self, lits: &[Lit], k: usize) -> Vec<Lit> {
        let mut v: Vec<(usize, usize, Lit)> =
            lits.iter().enumerate().map(|(i, &l)| (self.since(l, k).unwrap_or(0), i, l)).collect();
        v.sort_unstable();
        v.into_iter().map(|x| x.2).collect()
    }
}
