//! Choosing groundings for the atomic BT — the paper's action refinement (Section
//! V-D.1): a template such as `Place(c, p)` becomes one grounded action.
//!
//! A template whose parameters are all fixed by the condition being achieved has one
//! grounding, used as is. A template with *free* parameters (e.g. `unstack(?x, b)` for
//! `clear(b)`) has one grounding per choice of them; the paper's refinement picks one
//! valid choice. [`Refinement::Cheapest`] (the default) picks, per template, the
//! grounding whose preconditions are cheapest to reach from the current state by the
//! additive delete-relaxation estimate (h_add), the first in object order on ties;
//! [`Refinement::All`] keeps every grounding (larger trees, every alternative present).

use crate::ground::{ActionId, Grounding, Lit};
use crate::state::State;

/// How free template parameters are bound when a condition is expanded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Refinement {
    /// One grounding per achieving template: the cheapest from the current state.
    #[default]
    Cheapest,
    /// Every grounding of every achieving template.
    All,
}

const INF: u32 = u32::MAX;

/// Additive delete-relaxed cost of each literal (index [`Lit::index`]) from `state`:
/// 0 for literals that hold, else the cheapest achieving action's 1 + the sum of its
/// preconditions' costs; `u32::MAX` when unreachable.
#[must_use]
pub fn h_add(g: &Grounding, state: &State) -> Vec<u32> {
    let n = g.atom_count();
    let mut cost = vec![INF; n * 2];
    for atom in 0..n as u32 {
        let holds = state.holds(atom);
        cost[Lit { atom, positive: holds }.index()] = 0;
    }
    loop {
        let mut changed = false;
        for a in g.actions() {
            let mut c: u32 = 1;
            for p in &a.pre {
                let pc = cost[p.index()];
                if pc == INF {
                    c = INF;
                    break;
                }
                c = c.saturating_add(pc);
            }
            if c == INF {
                continue;
            }
            for &atom in &a.add {
                let slot = &mut cost[Lit { atom, positive: true }.index()];
                if c < *slot {
                    *slot = c;
                    changed = true;
                }
            }
            for &atom in &a.del {
                let slot = &mut cost[Lit { atom, positive: false }.index()];
                if c < *slot {
                    *slot = c;
                    changed = true;
                }
            }
        }
        if !changed {
            return cost;
        }
    }
}

/// The achieving actions of `lit` to put in its atomic BT, in domain order (template
/// order, then grounding order). Groundings that need `lit` itself are never used.
#[must_use]
pub fn achieving_actions(g: &Grounding, lit: Lit, state: &State, how: Refinement) -> Vec<ActionId> {
    let usable: Vec<ActionId> =
        g.achievers(lit).iter().copied().filter(|&a| g.action(a).is_some_and(|x| !x.pre.contains(&lit))).collect();
    if how == Refinement::All {
        return usable;
    }
    let mut out = Vec::new();
    let mut cost: Option<Vec<u32>> = None;
    let mut i = 0;
    while i < usable.len() {
        let template = g.action(usable[i]).map(|a| a.template);
        let mut j = i + 1;
        while j < usable.len() && g.action(usable[j]).map(|a| a.template) == template {
            j += 1;
        }
        if j - i == 1 {
            out.push(usable[i]);
        } else {
            let cost = cost.get_or_insert_with(|| h_add(g, state));
            let price = |a: ActionId| -> u64 {
                g.action(a).map_or(u64::MAX, |x| {
                    x.pre.iter().map(|p| u64::from(cost[p.index()])).fold(0u64, u64::saturating_add)
                })
            };
            // min_by_key keeps the first of equal keys.
            if let Some(best) = usable[i..j].iter().copied().min_by_key(|&a| price(a)) {
                out.push(best);
            }
        }
        i = j;
    }
    out
}
