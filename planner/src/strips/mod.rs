//! The symbolic STRIPS world: a [`BehaviorSet`] over a set of true ground atoms.
//!
//! A condition leaf succeeds when its atom holds. An action leaf runs its ground
//! action: on the tick it starts it returns Failure if its preconditions do not hold
//! (or it was sabotaged), else Running; on the next tick its effects are applied and it
//! returns Success. A halted action has no effect. Under a custom vocabulary a leaf may
//! name several groundings (`place at P!` for whichever brick is held): the first
//! applicable one runs.
//!
//! External agents act through [`StripsWorld::set`] (and the by-name variants) between
//! ticks; [`run`] calls a script hook before every tick for that.
//!
//! ```
//! use std::sync::Arc;
//! use planner::{domains, strips::StripsWorld};
//! let g = Arc::new(domains::cube_sphere()?);
//! let mut world = StripsWorld::new(g.clone());
//! assert!(world.holds_named("hand-empty", &[]));
//! world.set_named("path-free", &["goal"], false);
//! assert!(!world.holds_named("path-free", &["goal"]));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::sync::Arc;

use bt_core::{BehaviorSet, Catalog, Context, Executor, Leaf, NodeId, NodeState, Status, Tree};

use crate::PlanError;
use crate::ground::{ActionId, AtomId, Grounding};
use crate::state::State;
use crate::tree::DEPTH;

/// The symbolic world of a grounded problem.
#[derive(Clone, Debug)]
pub struct StripsWorld {
    g: Arc<Grounding>,
    state: State,
    running: Vec<(NodeId, ActionId)>,
    sabotaged: Vec<bool>,
    starts: Vec<u32>,
    done: Vec<u32>,
    executed: Vec<ActionId>,
    scratch: Vec<ActionId>,
    checked: bool,
}

impl StripsWorld {
    /// The world in the problem's initial state.
    #[must_use]
    pub fn new(g: Arc<Grounding>) -> Self {
        let n = g.actions().len();
        Self {
            state: g.init().clone(),
            g,
            running: Vec::new(),
            sabotaged: vec![false; n],
            starts: vec![0; n],
            done: vec![0; n],
            executed: Vec::new(),
            scratch: Vec::new(),
            checked: false,
        }
    }

    /// The grounding it runs.
    #[must_use]
    pub fn grounding(&self) -> &Arc<Grounding> {
        &self.g
    }

    /// The atoms that hold.
    #[must_use]
    pub fn state(&self) -> &State {
        &self.state
    }

    /// Whether `atom` holds.
    #[must_use]
    pub fn holds(&self, atom: AtomId) -> bool {
        self.state.holds(atom)
    }

    /// Whether `predicate(objects)` holds (false for unknown names).
    #[must_use]
    pub fn holds_named(&self, predicate: &str, objects: &[&str]) -> bool {
        self.g.atom_by_name(predicate, objects).is_some_and(|a| self.state.holds(a))
    }

    /// An external change of the whole state (the actions running go on).
    pub fn set_state(&mut self, state: State) {
        self.state = state;
    }

    /// An external change: makes `atom` true or false.
    pub fn set(&mut self, atom: AtomId, value: bool) {
        self.state.set(atom, value);
    }

    /// An external change by names; returns false (and changes nothing) for unknown names.
    pub fn set_named(&mut self, predicate: &str, objects: &[&str], value: bool) -> bool {
        match self.g.atom_by_name(predicate, objects) {
            Some(a) => {
                self.state.set(a, value);
                true
            }
            None => false,
        }
    }

    /// Makes ground action `action` fail whenever it starts (an external condition the
    /// model does not know, e.g. a jammed door), or work again. Note that a reactive
    /// Fallback retries a failing alternative every tick, preempting the ones after it:
    /// an external condition the tree can check is better modelled as a precondition.
    pub fn sabotage(&mut self, action: ActionId, on: bool) {
        if let Some(s) = self.sabotaged.get_mut(action as usize) {
            *s = on;
        }
    }

    /// How often `action` started (returned Running on its first tick).
    #[must_use]
    pub fn starts(&self, action: ActionId) -> u32 {
        self.starts.get(action as usize).copied().unwrap_or(0)
    }

    /// How often `action` completed (its effects applied).
    #[must_use]
    pub fn completions(&self, action: ActionId) -> u32 {
        self.done.get(action as usize).copied().unwrap_or(0)
    }

    /// With `true`, an action whose preconditions an external change made false while
    /// it ran fails when it would complete, without effects (the change interrupted
    /// it); by default it completes as started.
    pub fn set_checked_completion(&mut self, on: bool) {
        self.checked = on;
    }

    /// The actions completed so far, in order (the plan the tree executed).
    #[must_use]
    pub fn executed(&self) -> &[ActionId] {
        &self.executed
    }

    /// The actions running now, with the nodes that run them, sorted by node.
    #[must_use]
    pub fn running(&self) -> Vec<(NodeId, ActionId)> {
        let mut r = self.running.clone();
        r.sort_unstable();
        r
    }

    /// Back to the initial state, nothing running, counters cleared.
    pub fn reset(&mut self) {
        self.state = self.g.init().clone();
        self.running.clear();
        self.starts.fill(0);
        self.done.fill(0);
        self.executed.clear();
    }

    /// Whether every goal condition holds.
    #[must_use]
    pub fn goal_reached(&self) -> bool {
        self.g.goal_holds(&self.state)
    }
}

impl BehaviorSet for StripsWorld {
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        match self.g.leaf_atom_of(leaf, ctx.args(leaf)) {
            Some(a) if self.state.holds(a) => Status::Success,
            _ => Status::Failure,
        }
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        if !ctx.starting
            && let Some(i) = self.running.iter().position(|r| r.0 == ctx.node)
        {
            let (_, a) = self.running.swap_remove(i);
            if let Some(ga) = self.g.action(a) {
                if self.checked && !ga.applicable(&self.state) {
                    return Status::Failure;
                }
                ga.apply(&mut self.state);
            }
            if let Some(d) = self.done.get_mut(a as usize) {
                *d += 1;
            }
            self.executed.push(a);
            return Status::Success;
        }
        let mut candidates = std::mem::take(&mut self.scratch);
        self.g.leaf_actions_of(leaf, ctx.args(leaf), &mut candidates);
        let chosen = candidates.iter().copied().find(|&a| {
            !self.sabotaged.get(a as usize).copied().unwrap_or(false)
                && self.g.action(a).is_some_and(|ga| ga.applicable(&self.state))
        });
        self.scratch = candidates;
        match chosen {
            Some(a) => {
                self.running.retain(|r| r.0 != ctx.node);
                self.running.push((ctx.node, a));
                if let Some(s) = self.starts.get_mut(a as usize) {
                    *s += 1;
                }
                Status::Running
            }
            None => Status::Failure,
        }
    }

    fn halt(&mut self, _: &Leaf, node: NodeId) {
        self.running.retain(|r| r.0 != node);
    }
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// The root's last status (Running when the tick budget ran out).
    pub status: Status,
    /// Ticks made.
    pub ticks: u32,
}

/// Ticks `nodes` in `world` until the root returns Success or Failure, or `max_ticks`
/// ticks; `script(tick, world)` runs before every tick (tick numbers start at 1), for
/// external agents. `states` receives the node states after the last tick.
///
/// # Errors
/// [`PlanError::TreeTooLarge`] when the tree does not validate within the planner's
/// depth, [`PlanError::Tick`] when a behavior breaks the rules.
pub fn run<C: Catalog + ?Sized>(
    nodes: &[bt_core::Node],
    catalog: &C,
    world: &mut StripsWorld,
    max_ticks: u32,
    script: impl FnMut(u32, &mut StripsWorld),
    states: &mut Vec<NodeState>,
) -> Result<Outcome, PlanError> {
    run_with(nodes, &[], catalog, world, max_ticks, script, states)
}

/// [`run`] for a tree with a value table (leaves with more than
/// [`bt_core::MAX_ARGS`] arguments).
///
/// # Errors
/// As [`run`].
pub fn run_with<C: Catalog + ?Sized>(
    nodes: &[bt_core::Node],
    values: &[u16],
    catalog: &C,
    world: &mut StripsWorld,
    max_ticks: u32,
    mut script: impl FnMut(u32, &mut StripsWorld),
    states: &mut Vec<NodeState>,
) -> Result<Outcome, PlanError> {
    let tree: Tree<'_, DEPTH> =
        Tree::validate_with(nodes, values, catalog).map_err(|e| PlanError::InvalidTree(e.to_string()))?;
    states.clear();
    states.resize(nodes.len(), NodeState::IDLE);
    let mut exec = Executor::new(tree, states).map_err(|_| PlanError::InvalidTree("state storage too small".into()))?;
    let mut status = Status::Running;
    let mut ticks = 0;
    while ticks < max_ticks {
        ticks += 1;
        script(ticks, world);
        status = exec.tick(world, ticks)?;
        if status != Status::Running {
            break;
        }
    }
    if status == Status::Running {
        exec.halt_all(world);
    }
    Ok(Outcome { status, ticks })
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

/// Ticks `nodes` (with their value table) in `world` until the goal is reached: the root returns Success *and*
/// every goal condition holds in the world. A Success with a goal condition false
/// (an action undid a condition checked earlier in the same tick) is not the end: the
/// next tick starts a new activation. `ends` says what else ends it (a Failure, a
/// loop). `script(tick, world)` runs before every tick. `states` receives the node
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
    mut script: impl FnMut(u32, &mut StripsWorld),
    states: &mut Vec<NodeState>,
) -> Result<Verdict, PlanError> {
    let tree: Tree<'_, DEPTH> =
        Tree::validate_with(nodes, values, catalog).map_err(|e| PlanError::InvalidTree(e.to_string()))?;
    states.clear();
    states.resize(nodes.len(), NodeState::IDLE);
    let mut exec = Executor::new(tree, states).map_err(|_| PlanError::InvalidTree("state storage too small".into()))?;
    let mut seen: std::collections::HashMap<(State, Vec<(NodeId, ActionId)>), usize> = std::collections::HashMap::new();
    let mut completed = world.executed.len();
    let mut ticks = 0;
    let mut failures = 0;
    while ticks < max_ticks {
        ticks += 1;
        script(ticks, world);
        let status = exec.tick(world, ticks)?;
        failures = if status == Status::Failure { failures + 1 } else { 0 };
        match status {
            Status::Failure if failures >= ends.failures.max(1) => return Ok(Verdict::Failed { ticks }),
            Status::Success if world.goal_reached() => return Ok(Verdict::Reached { ticks }),
            _ => {}
        }
        if ends.on_loop && world.executed.len() != completed {
            completed = world.executed.len();
            let key = (world.state.clone(), world.running());
            if let Some(&before) = seen.get(&key) {
                let actions = world.executed[before..].to_vec();
                exec.halt_all(world);
                return Ok(Verdict::Oscillates { actions });
            }
            seen.insert(key, completed);
        }
    }
    exec.halt_all(world);
    Ok(Verdict::OutOfTicks { ticks })
}
