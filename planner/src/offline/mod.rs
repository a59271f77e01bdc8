//! Offline planning: Algorithm 1 against the symbolic world, each run of the tree
//! from the initial state, judged on the goal state; guided by heuristic search when
//! Algorithm 1 cannot finish; and a final check that the tree reaches the goal.

use std::sync::Arc;
use std::time::Instant;

use bt_core::{Catalog, Node};

use crate::PlanError;
use crate::ground::{ActionId, Grounding};
use crate::guide::Trace;
use crate::options::{Method, Options};
use crate::planner::{Expansion, Planner};
use crate::search::SearchOptions;
use crate::strips::{self, StripsWorld, Verdict};

mod behind;
mod closed;
mod closure_time;
mod cover;
pub(crate) mod fit;
mod pace;
mod portfolio;
mod select;
use closed::{CHOICE_SEED, better_under_disturbances, close_backchained, regression};
use closure_time::closure_deadline;
use cover::cover_checks;
use pace::Pace;

/// Where offline runs start ([`PlanError::GoalNotReached`]).
const INITIAL: &str = "the initial state";

/// Which method made a tree.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Made {
    /// Algorithm 1 of Colledanchise et al. 2019.
    Algorithm1,
    /// Algorithm 1 with its choices (achieving actions, order of goal conditions and
    /// preconditions) taken from a plan of greedy best-first search with h_FF.
    SearchGuided,
    /// The regression tree of a plan of greedy best-first search with h_FF
    /// ([`crate::regress`]).
    Regression,
}

impl Made {
    /// A short name: `algorithm-1`, `search-guided`, `regression`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Algorithm1 => "algorithm-1",
            Self::SearchGuided => "search-guided",
            Self::Regression => "regression",
        }
    }

    /// What it is, in a sentence.
    #[must_use]
    pub fn describe(self) -> &'static str {
        match self {
            Self::Algorithm1 => "Algorithm 1 of Colledanchise et al. 2019 (backchaining by ticking the tree)",
            Self::SearchGuided => {
                "Algorithm 1 guided by a plan of heuristic search (achievers and order from the plan)"
            }
            Self::Regression => "the regression tree of a plan of heuristic search",
        }
    }
}

/// A planned tree with its name table and what planning did.
#[derive(Debug)]
pub struct Plan<C> {
    /// The value table of the tree's leaves with more than `bt_core::MAX_ARGS`
    /// arguments (empty when it has none); images carry it in their values section.
    pub values: Vec<u16>,
    /// The tree, as bt-core nodes in pre-order.
    pub nodes: Vec<Node>,
    /// The behavior set the tree is built for.
    pub catalog: Arc<C>,
    /// Every expansion of the method that made the tree, in order.
    pub expansions: Vec<Expansion>,
    /// With [`Options::record_steps`]: the tree before any expansion, then after each.
    pub steps: Vec<Vec<Node>>,
    /// Ticks of the symbolic world spent planning.
    pub planning_ticks: u32,
    /// Ticks the final tree takes from the initial state to the goal in the symbolic
    /// world (always `Some`: a tree that does not reach the goal is an error).
    pub goal_ticks: Option<u32>,
    /// The planner, to continue online from this tree.
    pub planner: Planner,
    /// The method that made the tree.
    pub method: Made,
    /// The actions the tree executes from the initial state, undisturbed.
    pub executed: Vec<ActionId>,
    /// The methods tried before and why each was given up, in order (empty when
    /// Algorithm 1 made the tree).
    pub gave_up: Vec<GaveUp>,
    /// For a regression tree, how it was closed over disturbances
    /// ([`crate::regress::close`]).
    pub closed: Option<crate::regress::Closed>,
    /// Conditions a guided tree only checked that were given the plan's step that
    /// made them true, so that a disturbance undoing one does not fail the tree (0 for
    /// the other methods).
    pub covered: usize,
    /// The state variables that guided backchaining did not pin to the values of the
    /// plan's steps, as `predicate/argument` ([`crate::variables`]; empty where it
    /// pinned them, or another method made the tree).
    pub variables: Vec<String>,
    /// Its size, and whether the closure over disturbances was cut to fit
    /// [`Options::fit`].
    pub fit: fit::Fitted,
    /// When the first tree that reaches the goal was ready: this tree, or the one it
    /// was made from before its closure over disturbances (the time a planner that
    /// only plans would have its plan; the closure's time comes after).
    pub first: Instant,
}

impl<C> Clone for Plan<C> {
    fn clone(&self) -> Self {
        Self {
            values: self.values.clone(),
            nodes: self.nodes.clone(),
            catalog: self.catalog.clone(),
            expansions: self.expansions.clone(),
            steps: self.steps.clone(),
            planning_ticks: self.planning_ticks,
            goal_ticks: self.goal_ticks,
            planner: self.planner.clone(),
            method: self.method,
            executed: self.executed.clone(),
            gave_up: self.gave_up.clone(),
            closed: self.closed,
            covered: self.covered,
            variables: self.variables.clone(),
            fit: self.fit,
            first: self.first,
        }
    }
}

/// A method that did not make the tree, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GaveUp {
    /// The method.
    pub method: Made,
    /// Its error (for an oscillation, with the tree and the repeating actions).
    pub error: PlanError,
}

/// Offline mode (see [`Method`]): makes a tree, then checks that it reaches the goal
/// from the initial state in the symbolic world of `g`.
///
/// Algorithm 1 ticks the tree against the symbolic world from the initial state,
/// expanding the failed condition each time it fails, until it reaches the goal:
/// the root returns Success with every goal condition true.
///
/// With [`Method::Auto`], Algorithm 1 gives up past [`Options::algorithm1_nodes`] and
/// guided backchaining past four times the plan's regression tree, and the search for
/// the plan runs on threads of its own meanwhile ([`Options::parallel`]); neither
/// changes the tree, only the time to it. A tree that does not fit [`Options::fit`]
/// has its closure over disturbances cut until it does ([`Plan::fit`]); one that does
/// not fit even without it gives way to the next method, and the smallest is returned
/// where none fits (unless the fit is strict): a regression tree then with rules back
/// by one action from the states one act of an agent leads to where it fails
/// ([`crate::regress::close_one_act`], at most an eighth more nodes).
///
/// With [`Options::deadline`], guided backchaining gets half the time left, and gives
/// way to the next method sooner where its progress along the plan says it would not
/// be done in that time ([`PlanError::Behind`]); the closure over disturbances gets as
/// long as the first tree took (at least 0.6 s, at most half the time left), so that the closed
/// tree comes at most about twice as late as the first; without one it stops only at
/// its budget of states, plans and nodes, and the tree does not depend on the
/// machine's speed.
///
/// Guided backchaining with state variables not pinned ([`crate::variables`]) is tried
/// only where plain guided backchaining fails. Where its tree's closure over
/// disturbances does not cover every disturbed state it looked at, the plan's
/// regression tree is made too, and kept instead if it reaches the goal in more of 20
/// seeded disturbed episodes (in visitall, with the robot's place not pinned, the tree
/// reached the goal in 6 of the benchmark's 20, the regression tree in 20; in
/// openstacks-sat11, the stack count not pinned, 18 against 6).
///
/// # Errors
/// [`PlanError::GoalNotReached`] with the tree when the final tree does not reach the
/// goal (never returned as a plan), and with [`Method::Algorithm1`] when Algorithm 1
/// stops with a tree that fails and that it cannot expand further (no achieving
/// action, nothing left to expand, an unresolvable conflict) or that runs without
/// reaching the goal; [`PlanError::Oscillates`] with the tree and the repeating
/// actions; [`PlanError::NoPlan`] and [`PlanError::Timeout`] from
/// search; [`PlanError::TooBig`] when a strict [`Options::fit`] cannot be met.
pub fn plan<C: Catalog>(g: Arc<Grounding>, catalog: Arc<C>, options: Options) -> Result<Plan<C>, PlanError> {
    let started = Instant::now();
    let mut gave_up = Vec::new();
    // The smallest tree made so far that does not fit `options.fit`: kept unless a later
    // method's tree fits.
    let mut too_big: Option<Plan<C>> = None;
    let mut searching = None;
    if options.method != Method::Search {
        let mut a1 = options;
        let mut budget = None;
        if options.method == Method::Auto {
            if let Some(d) = options.deadline {
                // Algorithm 1 gets a quarter of the time left; search and guided
                // backchaining the rest.
                let now = Instant::now();
                a1.deadline = Some(now + d.saturating_duration_since(now) / 4);
            }
            budget = Some(options.algorithm1_nodes);
            if options.parallel {
                searching = portfolio::Searching::start(&g, search_options(options));
            }
        }
        let made = algorithm1(g.clone(), catalog.clone(), a1, budget).and_then(|p| {
            if options.close_backchained {
                let until = closure_deadline(options, started, p.first);
                fit::within(options, |n| close_backchained(p.clone(), &g, Options { close_nodes: n, ..options }, until))
            } else {
                measured(p, options)
            }
        });
        match made {
            Ok(p) if p.fit.fits => return Ok(p),
            Ok(p) if options.method == Method::Algorithm1 => return fitted_or_error(p, options),
            Ok(p) => {
                gave_up.push(GaveUp { method: Made::Algorithm1, error: fit::too_big(p.fit.size, options.fit) });
                keep_smaller(&mut too_big, p);
            }
            Err(e) if options.method == Method::Algorithm1 || !recoverable(&e) => return Err(e),
            Err(error) => gave_up.push(GaveUp { method: Made::Algorithm1, error }),
        }
    }
    let found = match searching {
        Some(s) => s.join()?,
        None => portfolio::search_plan(&g, &search_options(options))?,
    };
    let trace = Arc::new(
        Trace::new(&g, &found.plan).ok_or_else(|| PlanError::NoPlan("search returned an invalid plan".into()))?,
    );
    // Guided backchaining gives up where its tree outgrows four times the plan's
    // regression tree (the last resort, made in no time), and at least Algorithm 1's
    // budget: a plan that guides it well makes a tree of about that size.
    let regression_nodes = crate::regress::tree(&g, &trace).flatten(&g).map_or(0, |f| f.nodes.len());
    let guided_budget = options.algorithm1_nodes.max(4 * regression_nodes);
    let guided = Planner::guided(g.clone(), trace.clone(), options)?;
    let budget = Some(guided_budget);
    let (timed, pace) = paced(options, found.plan.len());
    let made =
        run_algorithm1(guided, g.clone(), catalog.clone(), timed, Made::SearchGuided, budget, pace).and_then(|p| {
            let p = cover_checks(p, &g, options);
            let until = closure_deadline(options, started, p.first);
            fit::within(options, |n| close_backchained(p.clone(), &g, Options { close_nodes: n, ..options }, until))
        });
    match made {
        Ok(mut p) if p.fit.fits => {
            p.gave_up = gave_up;
            return Ok(p);
        }
        Ok(p) => {
            gave_up.push(GaveUp { method: Made::SearchGuided, error: fit::too_big(p.fit.size, options.fit) });
            keep_smaller(&mut too_big, p);
        }
        Err(e) if !recoverable(&e) => return Err(e),
        Err(error) => gave_up.push(GaveUp { method: Made::SearchGuided, error }),
    }
    let mut guided = Planner::guided(g.clone(), trace.clone(), options)?;
    if guided.with_state_variables() {
        let variables = guided.state_variable_names();
        let (timed, pace) = paced(options, found.plan.len());
        match run_algorithm1(guided, g.clone(), catalog.clone(), timed, Made::SearchGuided, budget, pace) {
            Ok(mut p) => {
                p.variables = variables;
                let p = cover_checks(p, &g, options);
                // The regression tree below, if made, shares this closure's time.
                let until = closure_deadline(options, started, p.first);
                let mut p = fit::within(options, |n| {
                    close_backchained(p.clone(), &g, Options { close_nodes: n, ..options }, until)
                })?;
                if !p.fit.fits {
                    // Said apart from plain guided backchaining's reason, which is
                    // another tree's.
                    let what = fit::too_big(p.fit.size, options.fit);
                    let what = format!("with {} not pinned, {what}", p.variables.join(", "));
                    gave_up.push(GaveUp { method: Made::SearchGuided, error: PlanError::TooBig { what } });
                }
                if p.closed.is_some_and(|c| !c.complete) || !p.fit.fits || p.fit.cut.is_some() {
                    // Its closure did not cover every disturbed state it looked at (or was cut
                    // or left out to fit): the
                    // plan's regression tree instead where that copes better.
                    let r = regression(g.clone(), catalog.clone(), options, &trace, until)?;
                    if (r.fit.fits && !p.fit.fits)
                        || (r.fit.fits == p.fit.fits && better_under_disturbances(&r, &p, &g)?)
                    {
                        p = r;
                    }
                }
                if p.fit.fits {
                    p.gave_up = gave_up;
                    return Ok(p);
                }
                keep_smaller(&mut too_big, p);
            }
            Err(e) if !recoverable(&e) => return Err(e),
            // Not reported apart: it is guided backchaining's second try.
            Err(_) => {}
        }
    }
    // The regression tree is made in no time: it is the first tree from here.
    let until = closure_deadline(options, started, Instant::now());
    let mut p = regression(g, catalog, options, &trace, until)?;
    if !p.fit.fits {
        keep_smaller(&mut too_big, p);
        p = too_big.take().ok_or_else(|| PlanError::NoPlan("no tree was kept".into()))?;
    }
    p.gave_up = gave_up;
    fitted_or_error(p, options)
}

/// How the plan that guides the tree is searched for.
fn search_options(options: Options) -> SearchOptions {
    SearchOptions {
        deadline: options.deadline,
        lazy: options.deferred,
        landmarks: options.landmarks,
        ..SearchOptions::default()
    }
}

/// `p`, measured against `options.fit` with nothing cut.
fn measured<C: Catalog>(mut p: Plan<C>, options: Options) -> Result<Plan<C>, PlanError> {
    let size = fit::size_of(&p.nodes, &p.values)?;
    p.fit = fit::Fitted { size, fits: options.fit.admits(size), ..fit::Fitted::default() };
    Ok(p)
}

/// `p` where it fits or the fit is not strict, else [`PlanError::TooBig`].
fn fitted_or_error<C: Catalog>(p: Plan<C>, options: Options) -> Result<Plan<C>, PlanError> {
    if p.fit.fits || !options.fit.strict { Ok(p) } else { Err(fit::too_big(p.fit.size, options.fit)) }
}

/// Keeps the smaller image of `kept` and `p`.
fn keep_smaller<C: Catalog>(kept: &mut Option<Plan<C>>, p: Plan<C>) {
    if kept.as_ref().is_none_or(|k| p.fit.size.bytes < k.fit.size.bytes) {
        *kept = Some(p);
    }
}

/// [`Plan::variables`] in a line: `state variables not pinned: stacks-avail/1 (each
/// step also has its groundings from the other values the plan visits up to three
/// actions from its own)`.
#[must_use]
pub fn variables_line(variables: &[String]) -> String {
    format!(
        "state variables not pinned: {} (each step also has its groundings from the other values the plan visits up to three actions from its own)",
        variables.join(", ")
    )
}

/// [`Plan::covered`] in a line: `checks covered: 124 conditions the tree only
/// checked redo the plan's step that made them true, where they are false`.
#[must_use]
pub fn covered_line(covered: usize) -> String {
    format!(
        "checks covered: {} the tree only checked {} the plan's step that made {} true, where {} false",
        crate::wording::count(covered, "condition"),
        if covered == 1 { "redoes" } else { "redo" },
        if covered == 1 { "it" } else { "them" },
        if covered == 1 { "it is" } else { "they are" },
    )
}

/// Errors after which another method may still make a tree.
fn recoverable(e: &PlanError) -> bool {
    !matches!(
        e,
        PlanError::TooManyValues { .. } | PlanError::NoLeaf { .. } | PlanError::InvalidTree(_) | PlanError::Tick(_)
    )
}

/// Algorithm 1 from the goal, giving up past `budget` nodes ([`run_algorithm1`]).
fn algorithm1<C: Catalog>(
    g: Arc<Grounding>,
    catalog: Arc<C>,
    options: Options,
    budget: Option<usize>,
) -> Result<Plan<C>, PlanError> {
    let planner = Planner::new(g.clone(), options)?;
    run_algorithm1(planner, g, catalog, options, Made::Algorithm1, budget, None)
}

/// The options and [`Pace`] of guided backchaining for a plan of `steps` actions: with
/// a deadline, half the time left and no longer than its progress promises; without
/// one, as `options` (its tree then does not depend on the machine's speed).
fn paced(options: Options, steps: usize) -> (Options, Option<Pace>) {
    match options.deadline {
        Some(d) => {
            let pace = Pace::new(steps, d);
            (Options { deadline: Some(pace.until()), ..options }, Some(pace))
        }
        None => (options, None),
    }
}

/// The loop of Algorithm 1: run the tree from the initial state; on Failure expand;
/// give up ([`PlanError::OverBudget`]) when the tree has grown past `budget` nodes, and
/// ([`PlanError::Behind`]) when it falls behind `pace`.
#[allow(clippy::too_many_arguments)]
fn run_algorithm1<C: Catalog>(
    mut planner: Planner,
    g: Arc<Grounding>,
    catalog: Arc<C>,
    options: Options,
    made: Made,
    budget: Option<usize>,
    mut pace: Option<Pace>,
) -> Result<Plan<C>, PlanError> {
    let mut world = StripsWorld::new(g.clone());
    let mut states = Vec::new();
    let mut expansions = Vec::new();
    let mut steps = Vec::new();
    let mut planning_ticks: u32 = 0;
    if options.record_steps {
        steps.push(planner.nodes().to_vec());
    }
    loop {
        if let Some(d) = options.deadline
            && Instant::now() >= d
        {
            return Err(PlanError::Timeout { stage: "expanding the tree" });
        }
        world.reset();
        let verdict = strips::run_to_goal(
            (planner.nodes(), planner.values()),
            catalog.as_ref(),
            &mut world,
            options.max_ticks,
            strips::Ends::DETERMINISTIC,
            (),
            &mut states,
        )?;
        match verdict {
            Verdict::Reached { ticks } => {
                planning_ticks = planning_ticks.saturating_add(ticks);
                break;
            }
            Verdict::Failed { ticks } => {
                planning_ticks = planning_ticks.saturating_add(ticks);
                if let Some(pace) = &mut pace {
                    pace.check(world.executed().len())?;
                }
                let belief = world.state().clone();
                match planner.on_failure(&states, &belief) {
                    Ok(e) => expansions.push(e),
                    Err(e) => return Err(crate::run_time::stuck(e, &planner, INITIAL)),
                }
                let nodes = planner.nodes().len();
                if let Some(budget) = budget.filter(|&b| nodes > b) {
                    return Err(PlanError::OverBudget { nodes, budget });
                }
                if options.record_steps {
                    steps.push(planner.nodes().to_vec());
                }
            }
            Verdict::Oscillates { actions } => {
                return Err(PlanError::Oscillates {
                    actions: actions.iter().map(|&a| g.action_name(a)).collect(),
                    nodes: planner.nodes().to_vec(),
                    values: planner.values().to_vec(),
                });
            }
            Verdict::OutOfTicks { ticks } => {
                return Err(crate::run_time::stuck(PlanError::NoProgress { ticks }, &planner, INITIAL));
            }
        }
    }
    finish(planner, g, catalog, options, made, expansions, steps, planning_ticks)
}

/// The final check: the tree, run from the initial state, reaches the goal.
#[allow(clippy::too_many_arguments)]
fn finish<C: Catalog>(
    planner: Planner,
    g: Arc<Grounding>,
    catalog: Arc<C>,
    options: Options,
    method: Made,
    expansions: Vec<Expansion>,
    steps: Vec<Vec<Node>>,
    planning_ticks: u32,
) -> Result<Plan<C>, PlanError> {
    let mut fresh = StripsWorld::new(g.clone());
    let mut states = Vec::new();
    let verdict = strips::run_to_goal(
        (planner.nodes(), planner.values()),
        catalog.as_ref(),
        &mut fresh,
        options.max_ticks,
        strips::Ends::DETERMINISTIC,
        (),
        &mut states,
    )?;
    let nodes = planner.nodes().to_vec();
    let values = planner.values().to_vec();
    let ticks = match verdict {
        Verdict::Reached { ticks } => ticks,
        Verdict::Failed { ticks } => {
            return Err(PlanError::GoalNotReached {
                from: INITIAL,
                why: format!("the root fails at tick {ticks}"),
                nodes,
                values,
            });
        }
        Verdict::Oscillates { actions } => {
            let names: Vec<String> = actions.iter().map(|&a| g.action_name(a)).collect();
            return Err(PlanError::GoalNotReached {
                from: INITIAL,
                why: format!("it oscillates, repeating {}", names.join(", ")),
                nodes,
                values,
            });
        }
        Verdict::OutOfTicks { ticks } => {
            return Err(PlanError::GoalNotReached {
                from: INITIAL,
                why: format!("not reached within {ticks} ticks"),
                nodes,
                values,
            });
        }
    };
    let executed = fresh.executed().to_vec();
    Ok(Plan {
        nodes,
        values,
        catalog,
        expansions,
        steps,
        planning_ticks,
        goal_ticks: Some(ticks),
        planner,
        method,
        executed,
        gave_up: Vec::new(),
        closed: None,
        covered: 0,
        variables: Vec::new(),
        fit: fit::Fitted::default(),
        first: Instant::now(),
    })
}

#[cfg(test)]
mod tests;
