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
///
/// Where the tree with every check covered does not fit [`Options::fit`] and the tree
/// without does, as many checks as fit are covered, in pre-order (found by bisection):
/// a guided tree that fits copes better than the regression tree that would replace it
/// (openstacks-sat11 p01, the stack count not pinned: 17,923 bytes with its 249 checks
/// covered, 14 of 20 disturbed episodes with none, 6 for the regression tree).
pub(super) fn cover_checks<C: Catalog>(p: Plan<C>, g: &Arc<Grounding>, options: Options) -> Plan<C> {
    let Some(trace) = Trace::new(g, &p.executed) else { return p };
    let checks = root_failing(p.planner.tree());
    let Some(all) = covered(&p, g, options, &trace, &checks) else { return p };
    if fits(&all, options) || !fits(&p, options) {
        return all;
    }
    // The tree with `lo` checks covered fits (`best`, none: `p`), with `hi` it does not.
    let (mut lo, mut hi) = (0, checks.len());
    let mut best = None;
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        match covered(&p, g, options, &trace, checks.get(..mid).unwrap_or_default()) {
            Some(q) if fits(&q, options) => {
                lo = mid;
                best = Some(q);
            }
            Some(_) => hi = mid,
            // The tree with these covers did not run as before: fewer.
            None => hi = mid,
        }
    }
    best.unwrap_or(p)
}

/// Whether `p`'s image is within [`Options::fit`].
fn fits<C>(p: &Plan<C>, options: Options) -> bool {
    super::fit::size_of(&p.nodes, &p.values).is_ok_and(|size| options.fit.admits(size))
}

/// `p` with the conditions `checks` of its tree covered ([`cover_checks`]), where that
/// runs as before; `None` where nothing was covered or the tree changed its run.
fn covered<C: Catalog>(
    p: &Plan<C>,
    g: &Arc<Grounding>,
    options: Options,
    trace: &Trace,
    checks: &[crate::tree::PlanNode],
) -> Option<Plan<C>> {
    use crate::tree::Kind;
    let mut tree = p.planner.tree().clone();
    let mut covered = 0;
    for &n in checks {
        let Kind::Condition(l) = tree.kind(n) else { continue };
        let Some((a, pre, _)) = trace.causal_step(g, l, trace.goal_step()) else { continue };
        let fb = tree.add(Kind::Fallback);
        tree.replace(n, fb);
        tree.push_child(fb, n);
        tree.push_step(fb, &pre, a);
        covered += 1;
    }
    if covered == 0 {
        return None;
    }
    let planner = Planner::from_tree(g.clone(), tree, options).ok()?;
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
            q.gave_up.clone_from(&p.gave_up);
            q.closed = p.closed;
            q.covered = covered;
            q.variables.clone_from(&p.variables);
            q.first = p.first;
            Some(q)
        }
        _ => None,
    }
}
