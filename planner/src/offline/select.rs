//! A regression tree's closure over disturbances cut to fit by the disturbed episodes
//! its rules save per byte ([`closed_to_fit`]).
//!
//! The closure adds its rules in groups (a way back from one disturbed state, or one
//! undo rule), the states one disturbance from the tree's path first. Cutting it by
//! that order keeps the groups for the nearest states, which are not always the ones
//! an agent's disturbances lead to: a long way back for a state no episode reaches can
//! take the room of a short one many episodes need. So the closure (within the first
//! node budget of [`super::fit::within`]) is run in the planner's own seeded disturbed
//! episodes, and each episode that reaches the
//! goal names the groups it acted on (a *unit*: all of them, since a way back leads
//! into the rules of another). Units are kept greedily by episodes per byte not yet
//! kept, then the other groups in the closure's order, as many as fit. That tree is
//! kept where it reaches the goal in more of those episodes than the closure's groups
//! kept in its own order, as many as fit. Either way the closure is made once.

use std::sync::Arc;
use std::time::Instant;

use bt_core::Catalog;

use super::closure_time::close_budget;
use super::fit::{self, Fitted};
use super::{CHOICE_SEED, Plan};
use crate::PlanError;
use crate::ground::Grounding;
use crate::options::Options;
use crate::regress::{Closed, Policy};

/// The tree of `policy` with its closure report (the offline planner's check that it
/// reaches the goal from the initial state included).
pub(super) type Make<'a, C> = dyn Fn(&Policy, Option<Closed>) -> Result<Plan<C>, PlanError> + 'a;

/// `plain` (a regression tree's rules) closed over disturbances within `until` and
/// the first node budget of [`fit::within`], as that would (the same tree wherever it
/// fits); where it does not fit, cut to fit [`Options::fit`] by the disturbed episodes
/// its groups of rules save per byte, or by the closure's own order where that keeps as
/// many of the planner's own episodes (see the module docs); without any closure where
/// not one group fits. Where the tree does not fit even without a closure (and the fit
/// is not strict), it gets only the small closure of return rules ([`one_act`]).
///
/// # Errors
/// From `make` and the closure.
pub(super) fn closed_to_fit<C: Catalog>(
    options: Options,
    g: &Arc<Grounding>,
    plain: &Policy,
    until: Option<Instant>,
    make: &Make<'_, C>,
) -> Result<Plan<C>, PlanError> {
    let measure = |p: Plan<C>| -> Result<Plan<C>, PlanError> {
        let size = fit::size_of(&p.nodes, &p.values)?;
        Ok(Plan { fit: Fitted { size, fits: options.fit.admits(size), ..Fitted::default() }, ..p })
    };
    let bare = measure(make(plain, None)?)?;
    if options.close_nodes == 0 || !bare.fit.fits {
        let bare = Plan { fit: Fitted { cut: (options.close_nodes > 0).then_some(0), ..bare.fit }, ..bare };
        if options.close_nodes == 0 || options.fit.strict {
            return Ok(bare);
        }
        return one_act(g, plain, bare, (options.close_nodes, until), make, &measure);
    }
    // The closure counts the nodes of its rules nested by halves ([`Policy::nodes`]),
    // more than the tree it hands over has: the budget is in those nodes.
    let tree = plain.tree(g);
    let counted = plain.nodes(g) as f64 / tree.preorder(tree.root()).len().max(1) as f64;
    let budget = fit::first_budget(options, bare.fit.size, counted.max(1.0));
    let mut policy = plain.clone();
    let closed =
        crate::regress::close(g, &mut policy, &close_budget(Options { close_nodes: budget, ..options }, until))?;
    let mut whole = measure(make(&policy, Some(closed))?)?;
    whole.first = whole.first.min(bare.first);
    if whole.fit.fits {
        // Cut only where the closure stopped short of the states it would look at.
        let cut = (budget < options.close_nodes && !closed.complete).then_some(budget);
        return Ok(Plan { fit: Fitted { cut, ..whole.fit }, ..whole });
    }
    let depth: Vec<u32> = (1..policy.group_count()).collect();
    let mut chosen = largest_fitting(&policy, &depth, closed, make, &measure)?;
    let order = by_episodes(&policy, g, &whole)?;
    if order != depth {
        let other = largest_fitting(&policy, &order, closed, make, &measure)?;
        if reached(&other, g)? > reached(&chosen, g)? {
            chosen = Plan { fit: Fitted { by_episodes: true, ..other.fit }, ..other };
        }
    }
    if chosen.fit.ways.is_none_or(|w| w.0 == 0) {
        return Ok(Plan { fit: Fitted { cut: Some(0), ..bare.fit }, ..bare });
    }
    chosen.first = bare.first;
    Ok(chosen)
}

/// `bare`, the tree of `plain` that does not fit even without a closure, with the
/// rules back by one action of [`crate::regress::close_one_act`], where it adds any:
/// no closure over three acts fits, and this one is small (a return rule has the
/// conditions of one action, where a way back's rules carry all those of the rule it
/// leads to). They may add an eighth ([`crate::regress::ONE_ACT_SHARE`]) of the
/// closure's node budget `close_nodes`, or of the tree's nodes where it has more,
/// within the closure's states and its time (`until`).
fn one_act<C: Catalog>(
    g: &Arc<Grounding>,
    plain: &Policy,
    bare: Plan<C>,
    (close_nodes, until): (usize, Option<Instant>),
    make: &Make<'_, C>,
    measure: &dyn Fn(Plan<C>) -> Result<Plan<C>, PlanError>,
) -> Result<Plan<C>, PlanError> {
    let mut policy = plain.clone();
    let nodes = bare.fit.size.nodes.max(close_nodes) / crate::regress::ONE_ACT_SHARE;
    let budget = crate::regress::Budget { nodes, deadline: until, ..crate::regress::Budget::default() };
    let done = crate::regress::close_one_act(g, &mut policy, &budget);
    if done.rules == 0 {
        return Ok(bare);
    }
    let closed = Closed {
        states: done.failing,
        undo: done.rules,
        complete: !done.budget_reached,
        stopped: done.budget_reached.then_some(crate::regress::Stop::Nodes),
        one_act: true,
        ..Closed::default()
    };
    let p = measure(make(&policy, Some(closed))?)?;
    Ok(Plan { first: bare.first, ..p })
}

/// The tree of `policy` with group 0 and as many of `order`'s groups, from its start,
/// as fit (found by bisection; a prefix whose tree misses the goal counts as not
/// fitting), with [`Fitted::cut`] and [`Fitted::ways`] set.
fn largest_fitting<C: Catalog>(
    policy: &Policy,
    order: &[u32],
    closed: Closed,
    make: &Make<'_, C>,
    measure: &dyn Fn(Plan<C>) -> Result<Plan<C>, PlanError>,
) -> Result<Plan<C>, PlanError> {
    let mut rank = vec![usize::MAX; policy.group_count() as usize];
    for (k, &grp) in order.iter().enumerate() {
        if let Some(r) = rank.get_mut(grp as usize) {
            *r = k;
        }
    }
    let with = |k: usize| -> Result<Option<Plan<C>>, PlanError> {
        let only = policy.only(|grp| grp == 0 || rank.get(grp as usize).is_some_and(|&r| r < k));
        match make(&only, Some(closed)) {
            Ok(p) => {
                let p = measure(p)?;
                Ok(p.fit.fits.then_some(p))
            }
            Err(PlanError::GoalNotReached { .. }) => Ok(None),
            Err(e) => Err(e),
        }
    };
    let (mut lo, mut hi) = (0, order.len());
    let mut best = None;
    while lo < hi {
        let mid = lo + (hi - lo).div_ceil(2);
        match with(mid)? {
            Some(p) => {
                best = Some((mid, p));
                lo = mid;
            }
            None => hi = mid - 1,
        }
    }
    let (k, p) = match best.filter(|(k, _)| *k == lo) {
        Some(b) => b,
        None => (lo, with(lo)?.ok_or_else(|| PlanError::NoPlan("the plain regression tree no longer fits".into()))?),
    };
    let total = u32::try_from(order.len()).unwrap_or(u32::MAX);
    let kept = u32::try_from(k).unwrap_or(u32::MAX);
    let fit = Fitted { cut: Some(p.fit.size.nodes), ways: Some((kept, total)), ..p.fit };
    Ok(Plan { fit, ..p })
}

/// The closure's groups (all but group 0) in the order [`closed_to_fit`] keeps them:
/// the units of the episodes of `whole` that reach the goal, greedily by episodes per
/// estimated node not yet kept ([`Policy::group_nodes`]; ties: the unit of the
/// earliest episode), then the other groups in the closure's order.
fn by_episodes<C: Catalog>(policy: &Policy, g: &Arc<Grounding>, whole: &Plan<C>) -> Result<Vec<u32>, PlanError> {
    let runs = episodes(whole, g)?;
    // Each unit (its groups, sorted) with the episodes it saves.
    let mut units: Vec<(Vec<u32>, usize)> = Vec::new();
    for (ok, changes) in runs {
        if !ok {
            continue;
        }
        let mut unit: Vec<u32> = Vec::new();
        for (_, after) in &changes {
            unit.extend(policy.groups_on_path(g, after).into_iter().filter(|&grp| grp != 0));
        }
        unit.sort_unstable();
        unit.dedup();
        if unit.is_empty() {
            continue;
        }
        match units.iter_mut().find(|u| u.0 == unit) {
            Some(u) => u.1 += 1,
            None => units.push((unit, 1)),
        }
    }
    let nodes = policy.group_nodes();
    let mut order: Vec<u32> = Vec::new();
    loop {
        let cost = |u: &[u32]| -> usize {
            u.iter().filter(|g| !order.contains(g)).map(|&g| nodes.get(g as usize).copied().unwrap_or(0)).sum()
        };
        // Episodes per node, compared as fractions: a/b > c/d when a*d > c*b.
        let mut best: Option<(usize, usize, usize)> = None;
        for (k, (unit, saved)) in units.iter().enumerate() {
            let c = cost(unit).max(1);
            if unit.iter().all(|g| order.contains(g)) {
                continue;
            }
            if best.is_none_or(|(_, s, bc)| saved * bc > s * c) {
                best = Some((k, *saved, c));
            }
        }
        let Some((k, _, _)) = best else { break };
        let unit = units.remove(k).0;
        order.extend(unit.into_iter().filter(|g| !order.contains(g)).collect::<Vec<_>>());
    }
    let rest: Vec<u32> = (1..policy.group_count()).filter(|g| !order.contains(g)).collect();
    order.extend(rest);
    Ok(order)
}

/// The planner's own seeded disturbed episodes of `p` ([`CHOICE_SEED`]).
fn episodes<C: Catalog>(p: &Plan<C>, g: &Arc<Grounding>) -> Result<Vec<crate::coverage::Episode>, PlanError> {
    let settings = crate::coverage::Settings { seed: CHOICE_SEED, ..crate::coverage::Settings::default() };
    let ticks = p.goal_ticks.unwrap_or(0);
    crate::coverage::episodes((&p.nodes, &p.values), p.catalog.as_ref(), g, ticks, &settings)
}

/// How many of [`episodes`] of `p` reach the goal.
pub(super) fn reached<C: Catalog>(p: &Plan<C>, g: &Arc<Grounding>) -> Result<usize, PlanError> {
    Ok(episodes(p, g)?.iter().filter(|e| e.0).count())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

    use std::path::Path;
    use std::sync::Arc;

    use super::super::Plan;
    use super::super::closed::{regression, regression_by_budgets};
    use super::reached;
    use crate::ground::Grounding;
    use crate::guide::Trace;
    use crate::pddl::{parse_domain, parse_problem};
    use crate::{Fit, Options, PddlCatalog};

    fn fixture(domain: &str, problem: &str) -> (Arc<Grounding>, Arc<PddlCatalog>, Trace) {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ipc").join(domain);
        let d = std::fs::read_to_string(dir.join("domain.pddl")).unwrap();
        let p = std::fs::read_to_string(dir.join(problem)).unwrap();
        let problem = parse_domain("domain.pddl", &d).and_then(|d| parse_problem(problem, &p, &d)).unwrap();
        let g = Grounding::new(&problem).unwrap();
        let plan = crate::search::gbfs(&g, &crate::search::SearchOptions::default()).unwrap().plan;
        let trace = Trace::new(&g, &plan).unwrap();
        (Arc::new(g), Arc::new(PddlCatalog::new(&problem)), trace)
    }

    #[test]
    fn a_closure_cut_by_the_episodes_its_rules_save_keeps_more_than_one_cut_by_depth() {
        let (g, c, trace) = fixture("openstacks-sat08-adl", "p01.pddl");
        let unbounded = Options { fit: Fit::NONE, ..Options::default() };
        let whole = regression(g.clone(), c.clone(), unbounded, &trace, None).unwrap();
        let bare = Options { close_nodes: 0, ..Options::default() };
        let bare = regression(g.clone(), c.clone(), bare, &trace, None).unwrap();
        assert!(whole.fit.cut.is_none(), "{}", whole.fit);
        // The benchmark's seed, not the one the planner chooses by.
        let settings = crate::coverage::Settings::default();
        let benchmark = |p: &Plan<PddlCatalog>| {
            crate::coverage::disturbed(&p.nodes, &p.values, c.as_ref(), &g, p.goal_ticks.unwrap(), &settings)
                .unwrap()
                .reached
        };
        // Room for `tenths` of what the whole closure adds: the closure cut by node
        // budgets shrinking until it fits, and the one cut by its groups of rules.
        let cut = |tenths: usize| {
            let bytes = bare.fit.size.bytes + (whole.fit.size.bytes - bare.fit.size.bytes) * tenths / 10;
            let options = Options { fit: Fit { bytes, ..Options::default().fit }, ..Options::default() };
            let by_budgets = regression_by_budgets(g.clone(), c.clone(), options, &trace, None).unwrap();
            let by_groups = regression(g.clone(), c.clone(), options, &trace, None).unwrap();
            assert!(by_groups.fit.fits && by_groups.fit.ways.is_some(), "{}", by_groups.fit);
            (by_budgets, by_groups)
        };
        // One tenth: the closure's groups kept in its own order, as many as fit, save
        // more episodes than the node budgets that shrank until the tree fit.
        let (budgets, groups) = cut(1);
        assert!(!groups.fit.by_episodes, "{}", groups.fit);
        let (b, k, w) = (benchmark(&budgets), benchmark(&groups), benchmark(&whole));
        assert!(b < k && k <= w, "by budgets {b}, by groups {k}, whole closure {w} of {}", settings.episodes);
        // Four tenths: the groups that serve the planner's own episodes first reach the
        // goal in more of them (19 of 20) than the closure's own order.
        let (budgets, groups) = cut(4);
        assert!(groups.fit.by_episodes, "{}", groups.fit);
        let (b, k) = (reached(&budgets, &g).unwrap(), reached(&groups, &g).unwrap());
        assert!(b < k, "the planner's own episodes: by budgets {b}, by episodes {k}");
        assert!(benchmark(&budgets) <= benchmark(&groups));
    }

    #[test]
    fn a_tree_that_does_not_fit_gets_rules_back_by_one_action() {
        use crate::regress::one_act_star as star;
        let d = parse_domain("domain.pddl", star::DOMAIN).unwrap();
        let problem = parse_problem("star.pddl", star::STAR, &d).unwrap();
        let g = Arc::new(Grounding::new(&problem).unwrap());
        let c = Arc::new(PddlCatalog::new(&problem));
        let name = |n: &str| (0..g.actions().len()).map(|k| k as u32).find(|&a| g.action_name(a) == n).unwrap();
        let plan: Vec<u32> = ["move(x, a)", "move(a, x)", "move(x, b)", "move(b, x)", "move(x, c)"].map(name).to_vec();
        let trace = Trace::new(&g, &plan).unwrap();
        // Room for no tree at all: without a closure, as before, a disturbed episode
        // whose agent moves the robot to b or c before a is visited fails.
        let tiny = Options { fit: Fit { bytes: 16, ..Fit::DEFAULT }, ..Options::default() };
        let bare = regression(g.clone(), c.clone(), Options { close_nodes: 0, ..tiny }, &trace, None).unwrap();
        let back = regression(g.clone(), c.clone(), tiny, &trace, None).unwrap();
        assert!(!back.fit.fits && back.closed.is_some_and(|c| c.one_act && c.undo >= 2), "{:?}", back.closed);
        assert_eq!(back.executed, bare.executed);
        let settings = crate::coverage::Settings::default();
        let reached = |p: &Plan<PddlCatalog>| {
            crate::coverage::disturbed(&p.nodes, &p.values, c.as_ref(), &g, p.goal_ticks.unwrap(), &settings)
                .unwrap()
                .reached
        };
        let (b, k) = (reached(&bare), reached(&back));
        assert!(b < k && k == settings.episodes, "disturbed episodes reaching the goal: {b} bare, {k} with the rules");
        // A strict fit gets no closure: the tree is refused elsewhere.
        let strict = Options { fit: Fit { strict: true, ..tiny.fit }, ..tiny };
        let p = regression(g.clone(), c.clone(), strict, &trace, None).unwrap();
        assert!(p.closed.is_none());
    }
}
