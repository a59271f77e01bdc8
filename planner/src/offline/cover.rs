//! Covering checks: a condition a guided backchained tree only checks gets the plan's
//! step that made it true.

use std::sync::Arc;

use bt_core::Catalog;

use super::{Plan, finish};
use crate::ground::Grounding;
use crate::guide::Trace;
use crate::options::Options;
use crate::planner::Planner;
use crate::tree::PlanTree;

/// Conditions of `tree` whose failure fails the whole tree: the root, the children
/// of such a Sequence, and the last child of such a Fallback (pre-order).
fn root_failing(tree: &PlanTree) -> Vec<crate::tree::PlanNode> {
    use crate::tree::Kind;
    let mut out = Vec::new();
    let mut stack = vec![tree.root()];
    while let Some(n) = stack.pop() {
        match tree.kind(n) {
            Kind::Condition(_) => out.push(n),
            Kind::Action(_) => {}
            Kind::Sequence => stack.extend(tree.children(n).iter().rev()),
            Kind::Fallback => stack.extend(tree.children(n).last()),
        }
    }
    out
}

/// Gives each condition that a guided backchained tree only checks, and whose failure
/// fails the whole tree, the plan's step that made it true ([`Trace::causal_step`] for
/// the goal's step): `c?`
/// becomes `Fallback(c?, Sequence(pre?.., a))`. Such checks are conditions the plan
/// made true on the way to another (a plane maintained by the visit planned for
/// another plane at the same airport), which guided backchaining never expands
/// because they never fail there; where a disturbance undoes one, or achieves the
/// condition the step was planned for in another way (the other plane maintained on
/// another day), the tree failed. The new branches act only where the tree failed
/// before, so its undisturbed run stays the same (checked). Returns the plan with the
/// new tree and [`Plan::covered`] set, or as it was when nothing was covered.
pub(super) fn cover_checks<C: Catalog>(p: Plan<C>, g: &Arc<Grounding>, options: Options) -> Plan<C> {
    use crate::tree::Kind;
    let Some(trace) = Trace::new(g, &p.executed) else { return p };
    let mut tree = p.planner.tree().clone();
    let mut covered = 0;
    for n in root_failing(&tree) {
        let Kind::Condition(l) = tree.kind(n) else { continue };
        let Some((a, pre, _)) = trace.causal_step(g, l, trace.goal_step()) else { continue };
        let fb = tree.add(Kind::Fallback);
        tree.replace(n, fb);
        tree.push_child(fb, n);
        tree.push_step(fb, &pre, a);
        covered += 1;
    }
    if covered == 0 {
        return p;
    }
    let Ok(planner) = Planner::from_tree(g.clone(), tree, options) else { return p };
    match finish(
        planner,
        g.clone(),
        p.catalog.clone(),
        options,
        p.method,
        p.expansions.clone(),
        p.steps.clone(),
        p.planning_ticks,
    ) {
        Ok(mut q) if q.executed == p.executed => {
            q.gave_up = p.gave_up;
            q.closed = p.closed;
            q.covered = covered;
            q.variables = p.variables;
            q.first = p.first;
            q
        }
        _ => p,
    }
}
