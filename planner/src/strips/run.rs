//! The planner's runs of a tree in the STRIPS world, on the [`worlds`] runner: until the
//! root finishes ([`run`]), or until the goal holds ([`run_to_goal`]).

use bt_core::{Catalog, NodeState, Status, Tree};
use worlds::end::{Failures, Finished, GoalReached, Loops};
use worlds::{Agent, Clock, Runner, Settings, Stop};

use super::StripsWorld;
use crate::PlanError;
use crate::ground::ActionId;
use crate::tree::DEPTH;

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// The root's last status (Running when the tick budget ran out).
    pub status: Status,
    /// Ticks made.
    pub ticks: u32,
}

/// The planner's runs: tick `k` (from 1) at `now` = `k` ms; the world does not move on
/// after the last tick (agents act before ticks); what still runs at the end is halted.
fn settings(max_ticks: u32) -> Settings {
    Settings {
        limit: max_ticks,
        clock: Clock { ms_per_tick: 1, first: 1 },
        moves_on_at_limit: false,
        moves_on_at_stop: false,
        halt_at_limit: true,
    }
}

fn validate<'a, C: Catalog + ?Sized>(
    nodes: &'a [bt_core::Node],
    values: &'a [u16],
    catalog: &C,
) -> Result<Tree<'a, DEPTH>, PlanError> {
    Tree::validate_with(nodes, values, catalog).map_err(|e| PlanError::InvalidTree(e.to_string()))
}

/// Ticks `nodes` (with their value table, for leaves with more than
/// [`bt_core::MAX_ARGS`] arguments) in `world` until the root returns Success or
/// Failure, or `max_ticks` ticks; `agents` act before every tick
/// ([`worlds::agent::BeforeTicks`] for a script, `()` for none). `states` receives the
/// node states after the last tick.
///
/// # Errors
/// [`PlanError::InvalidTree`] when the tree does not validate within the planner's
/// depth, [`PlanError::Tick`] when a behavior breaks the rules.
pub fn run<C: Catalog + ?Sized>(
    tree: (&[bt_core::Node], &[u16]),
    catalog: &C,
    world: &mut StripsWorld,
    max_ticks: u32,
    agents: impl Agent<StripsWorld>,
    states: &mut Vec<NodeState>,
) -> Result<Outcome, PlanError> {
    let out = episode(tree, catalog, world, max_ticks, &mut Finished, agents, states)?;
    Ok(Outcome { status: out.root, ticks: out.ticks })
}

/// One episode of the tree in `world` on the [`worlds`] runner, as the planner runs them
/// ([`settings`]), until `ends` or the tick limit stop it.
fn episode<C: Catalog + ?Sized>(
    (nodes, values): (&[bt_core::Node], &[u16]),
    catalog: &C,
    world: &mut StripsWorld,
    max_ticks: u32,
    ends: &mut impl worlds::Ends<StripsWorld>,
    mut agents: impl Agent<StripsWorld>,
    states: &mut Vec<NodeState>,
) -> Result<worlds::Outcome, PlanError> {
    let tree = validate(nodes, values, catalog)?;
    let mut runner = Runner::new(settings(max_ticks)).with_states(std::mem::take(states));
    let out = runner.run(tree, world, ends, &mut agents, &mut ());
    // One state per node, after the last tick.
    *states = runner.into_states();
    states.resize(nodes.len(), NodeState::IDLE);
    states.truncate(nodes.len());
    Ok(out?)
}

/// How an episode judged on the goal state ended ([`run_to_goal`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The root returned Success with every goal condition true, after `ticks` ticks.
    Reached {
        /// Ticks made.
        ticks: u32,
    },
    /// The root returned Failure.
    Failed {
        /// Ticks made.
        ticks: u32,
    },
    /// The world came back to a state it was in before, with the same actions
    /// running, without reaching the goal: ticking on repeats `actions` forever.
    Oscillates {
        /// The actions completed between the two visits of that state, in order.
        actions: Vec<ActionId>,
    },
    /// The tick budget ran out (the root kept returning Running, or Success with the
    /// goal false).
    OutOfTicks {
        /// The budget.
        ticks: u32,
    },
}

impl Verdict {
    /// Whether the goal was reached.
    #[must_use]
    pub fn reached(&self) -> bool {
        matches!(self, Self::Reached { .. })
    }
}

/// What ends a run of [`run_to_goal`] besides the goal and the tick budget.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ends {
    /// Stop as soon as the world returns to a state it was in after an action
    /// completed, with the same actions running (the tree and the world are
    /// deterministic, so it would loop); `false` when the world changes at random.
    pub on_loop: bool,
    /// Root Failures in a row that end the run: 1, the first; 2, a robot that ticks on
    /// after a failed tick and stops when the next one fails too.
    pub failures: u32,
}

impl Ends {
    /// A deterministic run: it ends at the first Failure or loop.
    pub const DETERMINISTIC: Self = Self { on_loop: true, failures: 1 };
    /// A run whose world changes at random: it ends at the first Failure.
    pub const RANDOM: Self = Self { on_loop: false, failures: 1 };
}

/// Ticks `nodes` (with their value table) in `world` until the goal is reached: the
/// root returns Success *and* every goal condition holds in the world. A Success with a
/// goal condition false (an action undid a condition checked earlier in the same tick)
/// is not the end: the next tick starts a new activation. `ends` says what else ends
/// it (a Failure, a loop). `agents` act before every tick. `states` receives the node
/// states after the last tick.
///
/// # Errors
/// As [`run`].
pub fn run_to_goal<C: Catalog + ?Sized>(
    (nodes, values): (&[bt_core::Node], &[u16]),
    catalog: &C,
    world: &mut StripsWorld,
    max_ticks: u32,
    ends: Ends,
    agents: impl Agent<StripsWorld>,
    states: &mut Vec<NodeState>,
) -> Result<Verdict, PlanError> {
    let mut loops = ends.on_loop.then(Loops::default);
    let mut rules = (Failures::in_a_row(ends.failures), GoalReached, &mut loops);
    let out = episode((nodes, values), catalog, world, max_ticks, &mut rules, agents, states)?;
    Ok(match out.stop {
        Stop::Goal => Verdict::Reached { ticks: out.ticks },
        Stop::Failure => Verdict::Failed { ticks: out.ticks },
        Stop::Loop => {
            let from = loops.as_ref().and_then(Loops::repeats_from).unwrap_or(0);
            Verdict::Oscillates { actions: world.executed().get(from..).unwrap_or(&[]).to_vec() }
        }
        Stop::Success | Stop::Skipped | Stop::Limit => Verdict::OutOfTicks { ticks: max_ticks },
    })
}
