//! Closing a tree over disturbances: a plan's regression tree, closed and cut to fit,
//! and a backchained tree closed where [`Options::close_backchained`] or guided
//! backchaining asks for it.

use std::sync::Arc;
use std::time::Instant;

use bt_core::Catalog;

use super::behind::Behind;
use super::closure_time::close_budget;
use super::{Made, Plan, finish, select};
use crate::PlanError;
use crate::ground::Grounding;
use crate::guide::Trace;
use crate::options::Options;
use crate::planner::Planner;
use crate::regress::Stop;

/// Seed of the disturbed episodes [`better_under_disturbances`] runs (not the
/// benchmark's: the planner must not choose on the episodes it is measured by).
pub(super) const CHOICE_SEED: u64 = 0x5EED_C401;

/// Whether tree `a` reaches the goal in more of 20 seeded disturbed episodes than `b`
/// (agents as in [`crate::coverage::disturbed`], with their own seed
/// [`CHOICE_SEED`]); on a tie, `b` is kept.
pub(super) fn better_under_disturbances<C: Catalog>(
    a: &Plan<C>,
    b: &Plan<C>,
    g: &Arc<Grounding>,
) -> Result<bool, PlanError> {
    Ok(select::reached(a, g)? > select::reached(b, g)?)
}

/// The regression tree of the plan, closed over disturbances and cut to fit
/// [`Options::fit`] by the disturbed episodes its rules save per byte
/// ([`select::closed_to_fit`]).
pub(super) fn regression<C: Catalog>(
    g: Arc<Grounding>,
    catalog: Arc<C>,
    options: Options,
    trace: &Trace,
    until: Option<Instant>,
) -> Result<Plan<C>, PlanError> {
    let plain = crate::regress::Policy::of_trace(&g, trace);
    let make = |policy: &crate::regress::Policy, closed| policy_plan(&g, &catalog, options, policy, closed);
    select::closed_to_fit(options, &g, &plain, until, &make)
}

/// The tree of `policy`'s rules, checked to reach the goal, with its closure report.
fn policy_plan<C: Catalog>(
    g: &Arc<Grounding>,
    catalog: &Arc<C>,
    options: Options,
    policy: &crate::regress::Policy,
    closed: Option<crate::regress::Closed>,
) -> Result<Plan<C>, PlanError> {
    let planner = Planner::from_tree(g.clone(), policy.tree(g), options)?;
    let mut p = finish(planner, g.clone(), catalog.clone(), options, Made::Regression, Vec::new(), Vec::new(), 0)?;
    p.closed = closed;
    Ok(p)
}

/// [`regression`] with its closure made again with fewer nodes until the tree fits
/// ([`super::fit::within`]): what [`select::closed_to_fit`] is measured against.
#[cfg(test)]
pub(super) fn regression_by_budgets<C: Catalog>(
    g: Arc<Grounding>,
    catalog: Arc<C>,
    options: Options,
    trace: &Trace,
    until: Option<Instant>,
) -> Result<Plan<C>, PlanError> {
    let plain = crate::regress::Policy::of_trace(&g, trace);
    super::fit::within(options, |nodes| {
        let mut policy = plain.clone();
        let budget = close_budget(Options { close_nodes: nodes, ..options }, until);
        let closed = if nodes == 0 { None } else { Some(crate::regress::close(&g, &mut policy, &budget)?) };
        policy_plan(&g, &catalog, options, &policy, closed)
    })
}

/// Closes a tree of guided backchaining over disturbances, and one of Algorithm 1 with
/// [`Options::close_backchained`] ([`crate::regress::close_with`]): where a disturbance
/// leads to a state from which the tree does not reach the goal, rules go in front of
/// it and undo rules behind it (`Fallback(goal?, rules..., tree, undo rules...)`: the
/// rules of the tree's own plan, and those of the ways back from such states). A tree
/// that reaches the goal alone from every state looked at stays exactly as it was, and
/// so does one whose closure reached its node budget or left out a way back that was
/// too long. A closure cut short by its time or its states ([`Stop::out_of_work`])
/// keeps the rules it found, unless the tree alone reaches the goal in more of the
/// planner's own seeded disturbed episodes ([`better_under_disturbances`]).
pub(super) fn close_backchained<C: Catalog>(
    p: Plan<C>,
    g: &Arc<Grounding>,
    options: Options,
    until: Option<Instant>,
) -> Result<Plan<C>, PlanError> {
    close_backchained_within(p, g, options, &close_budget(options, until))
}

/// [`close_backchained`] within `budget`.
pub(super) fn close_backchained_within<C: Catalog>(
    p: Plan<C>,
    g: &Arc<Grounding>,
    options: Options,
    budget: &crate::regress::Budget,
) -> Result<Plan<C>, PlanError> {
    if !(options.close_backchained || p.method == Made::SearchGuided) || options.close_nodes == 0 {
        return Ok(p);
    }
    let base = p.planner.tree().clone();
    let max_ticks = crate::coverage::episode_ticks(p.goal_ticks.unwrap_or(0));
    let mut behind = Behind::new(g.clone(), p.catalog.as_ref(), &base, max_ticks);
    // The rules of the tree's own plan first: a rule added for a disturbed state then
    // takes over on the tree's path only where it is nearer the goal, so the tree's
    // undisturbed plan never gets longer.
    let mut policy = Trace::new(g, &p.executed)
        .map_or_else(crate::regress::Policy::empty, |t| crate::regress::Policy::of_trace(g, &t));
    let mut closed = crate::regress::close_with(g, &mut policy, &mut behind, budget)?;
    // Cut short by its time or states, the closure keeps the rules found so far where
    // they do at least as well as the tree alone (checked below).
    let partial = !closed.complete && closed.too_long == 0 && closed.stopped.is_some_and(Stop::out_of_work);
    if (!closed.complete || closed.too_long > 0) && !partial {
        // Unlike a regression tree, which fails wherever no rule holds, a backchained
        // tree copes alone with many of the states disturbances lead to; rules for only
        // some of the others bring new actions that an agent can do out of turn
        // (maintenance: 12 of 20 disturbed episodes alone, 2 with 12 plans in front).
        closed.kept = true;
        return Ok(Plan { closed: Some(closed), ..p });
    }
    if closed.plans == 0 && closed.undo == 0 && !partial {
        // Nothing added, but the closure looked with the plan's rules in front: the
        // tree stays as it was only if it does as well alone.
        let mut none = crate::regress::Policy::empty();
        let alone = crate::regress::close_with(g, &mut none, &mut behind, budget)?;
        if alone.plans == 0 && alone.undo == 0 && alone.given_up == 0 && alone.too_long == 0 {
            return Ok(Plan { closed: Some(closed), ..p });
        }
        closed.own_rules = true;
    }
    let planner = Planner::from_tree(g.clone(), policy.tree_before(g, &base), options)?;
    let catalog = p.catalog.clone();
    match finish(
        planner,
        g.clone(),
        catalog,
        options,
        p.method,
        p.expansions.clone(),
        p.steps.clone(),
        p.planning_ticks,
    ) {
        Ok(q) if partial && better_under_disturbances(&p, &q, g)? => {
            // The rules of an unfinished closure did worse than the tree alone.
            closed.kept = true;
            Ok(Plan { closed: Some(closed), ..p })
        }
        Ok(mut q) => {
            q.gave_up = p.gave_up;
            q.closed = Some(closed);
            q.covered = p.covered;
            q.variables = p.variables;
            q.first = p.first;
            Ok(q)
        }
        // The rules are checked on every state they were made for; should the whole tree
        // still miss the goal from the initial state, the tree stays as it was.
        Err(_) => Ok(p),
    }
}
