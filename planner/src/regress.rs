//! The last resort for a plan that guided backchaining could not turn into a tree
//! that reaches the goal: a tree built by regressing the goal through the plan.
//!
//! With `C_n` the goal and `C_{i-1}` what must hold before step `i` for the rest of
//! the plan to reach the goal (`C_i` without what action `a_i` achieves, plus its
//! preconditions and the conditions of the conditional effects it relies on), the
//! tree is
//!
//! ```text
//! Fallback( C_n?,  Sequence(C_{n-1}?, a_n),  ...,  Sequence(C_0?, a_1) )
//! ```
//!
//! Ticked, it does the step after the latest `C_i` that holds: from the initial state
//! it executes the plan; when an external change undoes a step it goes back, when one
//! does a step for it it skips ahead (the reactivity of Problem 1 in seed 000, for
//! the states the plan passes through). It is flat: its depth does not grow with the
//! plan's length.

use crate::ground::{Grounding, Lit};
use crate::guide::Trace;
use crate::tree::{Kind, PlanTree};

fn add(set: &mut Vec<Lit>, l: Lit) {
    if !set.contains(&l) {
        set.push(l);
    }
}

/// The regressed conditions `C_0 .. C_n` of a trace.
#[must_use]
pub fn conditions(g: &Grounding, trace: &Trace) -> Vec<Vec<Lit>> {
    let n = trace.plan().len();
    let mut out = vec![Vec::new(); n + 1];
    let mut c: Vec<Lit> = g.goal().to_vec();
    out[n].clone_from(&c);
    for i in (1..=n).rev() {
        let Some(a) = g.action(trace.plan()[i - 1]) else { continue };
        let Some(before) = trace.state(i - 1) else { continue };
        let mut prev: Vec<Lit> = Vec::new();
        for &l in &c {
            if a.must_effects().any(|e| e == l) {
                continue;
            }
            // A conditional effect that made `l` true here: keep its condition.
            if let Some(cond) = a.cond.iter().find(|k| {
                k.when.iter().all(|w| w.holds(before))
                    && if l.positive { k.add.contains(&l.atom) } else { k.del.contains(&l.atom) }
            }) {
                for &w in &cond.when {
                    add(&mut prev, w);
                }
                continue;
            }
            add(&mut prev, l);
            // A conditional effect that would undo `l` did not fire: keep it so.
            for k in &a.cond {
                let undoes = if l.positive { k.del.contains(&l.atom) } else { k.add.contains(&l.atom) };
                if undoes && let Some(off) = k.when.iter().find(|w| !w.holds(before)) {
                    add(&mut prev, off.negated());
                }
            }
        }
        for &p in &a.pre {
            add(&mut prev, p);
        }
        out[i - 1].clone_from(&prev);
        c = prev;
    }
    out
}

/// The regression tree of a trace (see the module docs).
#[must_use]
pub fn tree(g: &Grounding, trace: &Trace) -> PlanTree {
    let cs = conditions(g, trace);
    let mut t = PlanTree::with_root(Kind::Fallback);
    let root = t.root();
    let goal = if let [single] = g.goal() {
        t.add(Kind::Condition(*single))
    } else {
        let s = t.add(Kind::Sequence);
        for &l in g.goal() {
            let c = t.add(Kind::Condition(l));
            t.push_child(s, c);
        }
        s
    };
    t.push_child(root, goal);
    let mut rows: Vec<(Vec<Lit>, u32)> = Vec::new();
    for i in (1..=trace.plan().len()).rev() {
        let a = trace.plan()[i - 1];
        let mut pre = cs[i - 1].clone();
        pre.sort_unstable();
        if rows.iter().any(|r| r.0 == pre && r.1 == a) {
            continue;
        }
        rows.push((pre, a));
        let act = t.add(Kind::Action(a));
        if cs[i - 1].is_empty() {
            t.push_child(root, act);
            continue;
        }
        let seq = t.add(Kind::Sequence);
        for &l in &cs[i - 1] {
            let c = t.add(Kind::Condition(l));
            t.push_child(seq, c);
        }
        t.push_child(seq, act);
        t.push_child(root, seq);
    }
    t
}
