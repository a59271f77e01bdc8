//! Expansion at run time from a given state: Example 2 of Colledanchise et al. 2019 on a planned tree.
//!
//! Offline planning ([`crate::plan`]) runs the tree from the problem's initial state,
//! so it expands only the conditions that fail on the way from there. In Example 2 the
//! tree of Fig. 3(e) meets a state planning never saw: the robot carries the cube when
//! the sphere blocks the path. The tree fails; Algorithm 1 expands the failed
//! condition at run time (lines 9-12) and IncreasePriority moves the new subtree until
//! it is conflict-free: that tree is Fig. 4. The robot goes on acting, and each later
//! failure (at the sphere, the cube still in the hand) is expanded the same way.
//! [`expand_at`] does this in the symbolic world from a state given as changes of the
//! initial one ([`parse_changes`]), and checks the tree it ends with from both states.
//!
//! ```
//! use std::sync::Arc;
//! use planner::{Options, PddlCatalog, domains, expand_at, parse_changes, plan};
//!
//! let g = Arc::new(domains::cube_sphere()?);
//! let c = Arc::new(PddlCatalog::new(g.problem()));
//! let mut p = plan(g.clone(), c.clone(), Options::default())?; // Fig. 3(e), 19 nodes
//! let carrying = parse_changes(&g, "holding(cube), not hand-empty, not path-free(goal)")?;
//! let at = expand_at(&mut p.planner, c.as_ref(), &carrying, 1000)?;
//! let expanded: Vec<&str> = at.expansions.iter().map(|e| e.condition.as_str()).collect();
//! assert_eq!(expanded, ["path-free(goal)", "near(sphere)", "hand-empty"]);
//! assert_eq!(at.expansions[0].nodes, 25); // Fig. 4
//! assert_eq!(p.planner.nodes().len(), 37);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::sync::Arc;

use bt_core::{Catalog, LoadError, NodeState, Status, Tree};
use worlds::end::{Failures, Finished, GoalReached, Loops};
use worlds::{Agent, Clock, RunError, RunErrorKind, Runner, Settings, Stop, Trees};

use crate::Options;
use crate::PlanError;
use crate::ground::{ActionId, AtomId, Grounding};
use crate::planner::{Expansion, Planner};
use crate::state::State;
use crate::strips::{self, StripsWorld, Verdict};
use crate::tree::{Kind, PlanNode, PlanTree};

/// Where [`expand_at`]'s runs start ([`PlanError::GoalNotReached`]).
const GIVEN: &str = "the state given";

/// A fact of a state description that [`parse_changes`] refused, and where.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("column {column}: {message}")]
pub struct ChangeError {
    /// 1-based column (in characters) of the fact in the text.
    pub column: usize,
    /// What is wrong with it.
    pub message: String,
}

/// One change of the world: a ground atom made true or false.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Change {
    /// The atom.
    pub atom: AtomId,
    /// Its new value.
    pub value: bool,
}

/// Reads changes of the initial state in the notation the planner prints conditions
/// in: facts separated by commas, each `predicate(object, ...)` (or `predicate` for no
/// arguments), made false with a leading `not`. Example: `holding(cube), not
/// hand-empty`. Names are case-insensitive, as in PDDL.
///
/// # Errors
/// A [`ChangeError`] naming the column: an empty fact, an unknown predicate or object,
/// the wrong number of arguments, a static fact (no action changes it, so the planner
/// leaves it out of its trees), a fact that can never hold in this problem, or a fact
/// changed twice.
pub fn parse_changes(g: &Grounding, text: &str) -> Result<Vec<Change>, ChangeError> {
    let mut out: Vec<(Change, usize)> = Vec::new();
    for (column, item) in split_top(text) {
        let err = |message: String| ChangeError { column, message };
        let negated = item.get(..3).is_some_and(|w| w.eq_ignore_ascii_case("not"))
            && item[3..].chars().next().is_none_or(char::is_whitespace);
        let (value, fact, column) = match item.get(3..).filter(|_| negated) {
            Some(rest) => {
                let trimmed = rest.trim_start();
                (false, trimmed, column + item.chars().count() - trimmed.chars().count())
            }
            None => (true, item, column),
        };
        let err_at = |message: String| ChangeError { column, message };
        if fact.is_empty() {
            return Err(err("an empty fact (write `predicate(object, ...)`, or `not predicate(...)`)".into()));
        }
        let (name, args) = match fact.find('(') {
            Some(open) => {
                let Some(inner) = fact[open + 1..].strip_suffix(')') else {
                    return Err(err_at(format!("`{fact}`: no `)` at the end")));
                };
                let args: Vec<&str> = inner.split(',').map(str::trim).filter(|a| !a.is_empty()).collect();
                (fact[..open].trim(), args)
            }
            None => (fact, Vec::new()),
        };
        let domain = &g.problem().domain;
        let Some(p) = domain.predicate(name) else {
            let known: Vec<&str> = domain.predicates.iter().map(|p| p.name.as_str()).collect();
            return Err(err_at(format!("unknown predicate `{name}` (declared: {})", known.join(", "))));
        };
        let arity = domain.predicates.get(usize::from(p)).map_or(0, |d| d.params.len());
        if args.len() != arity {
            return Err(err_at(format!(
                "`{name}` takes {}, not {}",
                crate::wording::count(arity, "argument"),
                args.len()
            )));
        }
        if let Some(bad) = args.iter().find(|a| g.problem().object(a).is_none()) {
            return Err(err_at(format!("unknown object `{bad}`")));
        }
        let shown = if args.is_empty() { name.to_string() } else { format!("{name}({})", args.join(", ")) };
        if g.is_static_predicate(p) {
            return Err(err_at(format!(
                "`{shown}` is static (no action changes it), so the planner's trees never check it; \
                 change it in the problem's :init instead"
            )));
        }
        let Some(atom) = g.atom_by_name(name, &args) else {
            if value {
                return Err(err_at(format!(
                    "`{shown}` never holds in this problem: it is not in :init and no action makes it true"
                )));
            }
            // False in every reachable state already: nothing to change.
            continue;
        };
        if let Some((_, before)) = out.iter().find(|(c, _)| c.atom == atom) {
            return Err(err_at(format!("`{shown}` is changed twice (also at column {before})")));
        }
        out.push((Change { atom, value }, column));
    }
    Ok(out.into_iter().map(|(c, _)| c).collect())
}

/// The items of a comma-separated list whose items may hold commas inside
/// parentheses, trimmed, with the 1-based column each starts at.
fn split_top(text: &str) -> Vec<(usize, &str)> {
    let mut ranges = Vec::new();
    let mut depth = 0usize;
    let mut start = 0;
    for (i, ch) in text.char_indices() {
        match ch {
            '(' => depth += 1,
            ')' => depth = depth.saturating_sub(1),
            ',' if depth == 0 => {
                ranges.push((start, i));
                start = i + 1;
            }
            _ => {}
        }
    }
    ranges.push((start, text.len()));
    ranges
        .into_iter()
        .map(|(from, to)| {
            let raw = &text[from..to];
            let lead = raw.len() - raw.trim_start().len();
            (text[..from + lead].chars().count() + 1, raw.trim())
        })
        .collect()
}

/// The initial state of `g` with `changes` applied.
#[must_use]
pub fn state_with(g: &Grounding, changes: &[Change]) -> State {
    let mut s = g.init().clone();
    for c in changes {
        s.set(c.atom, c.value);
    }
    s
}

/// What [`expand_at`] did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AtRunTime {
    /// The expansions made at run time, in order.
    pub expansions: Vec<Expansion>,
    /// With [`crate::Options::record_steps`]: the tree after each of them.
    pub steps: Vec<Vec<bt_core::Node>>,
    /// Ticks of the run from the state given, expansions included.
    pub ticks: u32,
    /// Ticks the final tree takes to the goal from the state given, run afresh.
    pub goal_ticks_given: u32,
    /// Ticks the final tree takes to the goal from the problem's initial state.
    pub goal_ticks_initial: u32,
}

/// What the planner believes about a world: the state its expansions start from.
pub trait Belief {
    /// Each ground atom of `g`, as the world has it now.
    fn belief(&mut self, g: &Grounding) -> State;
}

impl Belief for StripsWorld {
    fn belief(&mut self, _: &Grounding) -> State {
        self.state().clone()
    }
}

/// The planner's tree as the tree of an episode that grows at run time
/// ([`worlds::Runner::run_growing`]): whenever the root fails, Algorithm 1 expands it in
/// place ([`Planner::on_failure`], lines 9-12, with the world's [`Belief`]), and the
/// episode goes on with the grown tree from the world as it is.
#[derive(Debug)]
pub struct Expanding<'a, C: ?Sized> {
    /// The planner that grows the tree.
    pub planner: &'a mut Planner,
    catalog: &'a C,
    until: u32,
    /// The expansions made, with the tick of the failure that caused each.
    pub expansions: Vec<(u32, Expansion)>,
    /// With [`crate::Options::record_steps`]: the tree after each expansion.
    pub steps: Vec<Vec<bt_core::Node>>,
}

impl<'a, C: Catalog + ?Sized> Expanding<'a, C> {
    /// The planner's tree, validated against `catalog`, expanded at every root Failure.
    pub fn new(planner: &'a mut Planner, catalog: &'a C) -> Self {
        Self { planner, catalog, until: u32::MAX, expansions: Vec::new(), steps: Vec::new() }
    }

    /// Expands only at Failures before tick `tick`; a later one ends the episode.
    #[must_use]
    pub fn until(mut self, tick: u32) -> Self {
        self.until = tick;
        self
    }
}

impl<W: Belief + ?Sized, C: Catalog + ?Sized> Trees<W> for Expanding<'_, C> {
    type Growth = Expansion;
    type Error = PlanError;

    fn tree<const D: usize>(&self) -> Result<Tree<'_, D>, LoadError> {
        Tree::validate_with(self.planner.nodes(), self.planner.values(), self.catalog)
    }

    fn grow(&mut self, tick: u32, states: &[NodeState], world: &mut W) -> Result<Option<Expansion>, PlanError> {
        if tick >= self.until {
            return Ok(None);
        }
        let belief = world.belief(self.planner.grounding());
        let e = self.planner.on_failure(states, &belief)?;
        self.expansions.push((tick, e.clone()));
        if self.planner.options().record_steps {
            self.steps.push(self.planner.nodes().to_vec());
        }
        Ok(Some(e))
    }
}

impl Planner {
    /// A planner that goes on from a bt-core tree of the kinds it grows
    /// ([`PlanTree::from_nodes`]), such as one it made before or one a controller runs:
    /// each condition that heads a Fallback counts as expanded (it has its achievers),
    /// the others will be expanded when they fail.
    ///
    /// # Errors
    /// As [`PlanTree::from_nodes`], and [`PlanError::InvalidTree`] when the tree made
    /// from it does not flatten back to the same nodes.
    pub fn from_nodes(
        g: Arc<Grounding>,
        nodes: &[bt_core::Node],
        values: &[u16],
        options: Options,
    ) -> Result<Self, PlanError> {
        let tree = PlanTree::from_nodes(&g, nodes, values)?;
        let heads: Vec<PlanNode> = tree
            .preorder(tree.root())
            .into_iter()
            .filter(|&n| matches!(tree.kind(n), Kind::Condition(_)))
            .filter(|&n| {
                tree.parent(n).is_some_and(|f| tree.kind(f) == Kind::Fallback && tree.children(f).first() == Some(&n))
            })
            .collect();
        let mut p = Self::from_tree(g, tree, options)?;
        if p.nodes() != nodes {
            return Err(PlanError::InvalidTree("it does not read back as the same tree under this problem".into()));
        }
        for n in heads {
            p.mark(n);
        }
        Ok(p)
    }
}

/// The planner's settings of a run in the symbolic world (as [`strips::run`]'s).
fn symbolic(limit: u32) -> Settings {
    Settings {
        limit,
        clock: Clock { ms_per_tick: 1, first: 1 },
        moves_on_at_limit: false,
        moves_on_at_stop: false,
        halt_at_limit: true,
    }
}

/// A [`RunError`] of the symbolic world as the planner's error.
fn plan_error(e: RunError<PlanError>) -> PlanError {
    match e.kind {
        RunErrorKind::Invalid(e) => PlanError::InvalidTree(e.to_string()),
        RunErrorKind::Tick(e) => PlanError::Tick(e),
        RunErrorKind::Grow(e) => e,
    }
}

/// How a blended run ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Blended {
    /// The root's last status (Running when the tick budget ran out).
    pub status: Status,
    /// Ticks made, in total.
    pub ticks: u32,
    /// The expansions made on the way, with the tick of the failure that caused each.
    pub expansions: Vec<(u32, Expansion)>,
}

/// Blended planning and acting (Section V, Example 2) in the symbolic world: ticks the
/// planner's tree in `world`; whenever the root returns Failure, asks the planner to
/// expand the tree in place ([`Planner::on_failure`], with the world's state as belief)
/// and goes on with the new tree from the world as it is, until the root succeeds or
/// the tick budget runs out (a Failure on its last tick is not expanded). `agents` act
/// before every tick (tick numbers continue across expansions).
///
/// # Errors
/// Those of [`Planner::on_failure`] and [`strips::run`].
pub fn run_blended<C: Catalog + ?Sized>(
    planner: &mut Planner,
    catalog: &C,
    world: &mut StripsWorld,
    max_ticks: u32,
    mut agents: impl Agent<StripsWorld>,
) -> Result<Blended, PlanError> {
    let mut trees = Expanding::new(planner, catalog).until(max_ticks);
    let out = Runner::new(symbolic(max_ticks))
        .run_growing::<{ crate::DEPTH }, _, _, _, _, _>(&mut trees, world, &mut Finished, &mut agents, &mut ())
        .map_err(plan_error)?;
    Ok(Blended { status: out.root, ticks: out.ticks, expansions: trees.expansions })
}

/// Runs the planner's tree in the symbolic world from the initial state with
/// `changes` applied, as a robot would at run time (Example 2 of Colledanchise et al. 2019): whenever
/// the root fails, expands the tree in place ([`Planner::on_failure`], Algorithm 1
/// lines 9-12, with the world's state as belief) and goes on from the world as it is,
/// until the goal is reached (the root succeeds with every goal condition true).
/// Then runs the final tree afresh from that state and from the initial state: it
/// must reach the goal from both.
///
/// # Errors
/// [`PlanError::GoalNotReached`] with the tree when the run stops short of the goal
/// (an expansion that cannot be made, an oscillation, `max_ticks` spent) or the final
/// tree does not reach the goal from one of the two states; the errors of
/// [`strips::run_to_goal`] and those of [`Planner::on_failure`] that are not about the
/// tree (its size).
pub fn expand_at<C: Catalog + ?Sized>(
    planner: &mut Planner,
    catalog: &C,
    changes: &[Change],
    max_ticks: u32,
) -> Result<AtRunTime, PlanError> {
    let g = planner.grounding().clone();
    let start = state_with(&g, changes);
    let mut world = StripsWorld::new(g.clone());
    world.set_state(start.clone());
    let mut loops = Loops::default();
    let mut trees = Expanding::new(planner, catalog);
    let mut ends = (Failures::first(), GoalReached, &mut loops);
    let out = Runner::new(symbolic(max_ticks)).run_growing::<{ crate::DEPTH }, _, _, _, _, _>(
        &mut trees,
        &mut world,
        &mut ends,
        &mut (),
        &mut (),
    );
    let Expanding { expansions, steps, .. } = trees;
    let out = out.map_err(|e| match e.kind {
        RunErrorKind::Grow(e) => stuck(e, planner, GIVEN),
        kind => plan_error(RunError { tick: e.tick, kind }),
    })?;
    match out.stop {
        Stop::Goal => {}
        Stop::Loop => {
            let actions = world.executed().get(loops.repeats_from().unwrap_or(0)..).unwrap_or(&[]);
            return Err(oscillates(&g, actions, planner, GIVEN));
        }
        _ => return Err(stuck(PlanError::NoProgress { ticks: max_ticks }, planner, GIVEN)),
    }
    let ticks = out.ticks;
    let expansions = expansions.into_iter().map(|(_, e)| e).collect();
    let goal_ticks_given = afresh(planner, catalog, Some(start), max_ticks, GIVEN)?;
    let goal_ticks_initial = afresh(planner, catalog, None, max_ticks, "the initial state")?;
    Ok(AtRunTime { expansions, steps, ticks, goal_ticks_given, goal_ticks_initial })
}

/// Ticks to the goal of the planner's tree from `start` (the initial state if `None`).
fn afresh<C: Catalog + ?Sized>(
    planner: &Planner,
    catalog: &C,
    start: Option<State>,
    max_ticks: u32,
    from: &'static str,
) -> Result<u32, PlanError> {
    let g = planner.grounding().clone();
    let mut world = StripsWorld::new(g.clone());
    if let Some(s) = start {
        world.set_state(s);
    }
    let tree = (planner.nodes(), planner.values());
    match strips::run_to_goal(tree, catalog, &mut world, max_ticks, strips::Ends::DETERMINISTIC, (), &mut Vec::new())? {
        Verdict::Reached { ticks } => Ok(ticks),
        Verdict::Failed { ticks } => Err(not_reached(planner, from, format!("the root fails at tick {ticks}"))),
        Verdict::Oscillates { actions } => Err(oscillates(&g, &actions, planner, from)),
        Verdict::OutOfTicks { ticks } => Err(not_reached(planner, from, format!("not reached within {ticks} ticks"))),
    }
}

fn not_reached(planner: &Planner, from: &'static str, why: String) -> PlanError {
    PlanError::GoalNotReached { from, why, nodes: planner.nodes().to_vec(), values: planner.values().to_vec() }
}

fn oscillates(g: &Grounding, actions: &[ActionId], planner: &Planner, from: &'static str) -> PlanError {
    let names: Vec<String> = actions.iter().map(|&a| g.action_name(a)).collect();
    not_reached(planner, from, format!("it oscillates, repeating {}", names.join(", ")))
}

/// An error of Algorithm 1 that leaves a tree failing (or running) without reaching
/// the goal — no achieving action, nothing left to expand, an unresolvable conflict,
/// no progress — as [`PlanError::GoalNotReached`] with that tree, for the caller to
/// show; other errors as they are.
pub(crate) fn stuck(e: PlanError, planner: &Planner, from: &'static str) -> PlanError {
    match e {
        PlanError::NoAchiever { .. }
        | PlanError::NothingToExpand { .. }
        | PlanError::Unresolvable(_)
        | PlanError::NoProgress { .. } => not_reached(planner, from, e.to_string()),
        e => e,
    }
}
