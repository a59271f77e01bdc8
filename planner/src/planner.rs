//! Algorithm 1 of seed 000: the [`Planner`] that grows a tree by backchaining, used
//! offline ([`plan`]) and online ([`Planner::on_failure`]).

use std::fmt;
use std::sync::Arc;

use bt_core::{Catalog, Node, NodeState, Status};

use crate::PlanError;
use crate::algorithm::{self, Move};
use crate::ground::{ActionId, Grounding, Lit};
use crate::refine::Refinement;
use crate::state::State;
use crate::strips::{self, StripsWorld};
use crate::tree::{Flat, Kind, PlanNode, PlanTree};

/// Planner settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Options {
    /// How free template parameters are bound.
    pub refinement: Refinement,
    /// Offline: most ticks of the symbolic world between two expansions before giving
    /// up (the tree may oscillate).
    pub max_ticks: u32,
    /// Most expansions.
    pub max_expansions: usize,
    /// Offline: keep a copy of the tree after every expansion ([`Plan::steps`]).
    pub record_steps: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self { refinement: Refinement::Cheapest, max_ticks: 10_000, max_expansions: 10_000, record_steps: false }
    }
}

/// A conflict met while placing a new subtree, and how IncreasePriority answered it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ConflictStep {
    /// The new subtree's precondition that was undone.
    pub precondition: String,
    /// The action executed before it that undoes it.
    pub by: String,
    /// What IncreasePriority did about it.
    pub moved: Move,
}

/// What one expansion did, for a caller to narrate.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Expansion {
    /// The failed condition that was expanded.
    pub condition: String,
    /// The achieving actions of its atomic BT, in order.
    pub actions: Vec<String>,
    /// Failed conditions passed over before it because no action achieves them.
    pub unachievable: Vec<String>,
    /// Conflicts met and the moves that resolved them, in order.
    pub conflicts: Vec<ConflictStep>,
    /// Nodes in the tree afterwards.
    pub nodes: usize,
}

impl fmt::Display for Expansion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "expanded `{}` with {}", self.condition, self.actions.join(", "))?;
        for c in &self.conflicts {
            let how = match c.moved {
                Move::Left => "moved the new subtree one place left",
                Move::Up => "moved the new subtree up a level",
            };
            write!(f, "; conflict: `{}` undoes its precondition `{}`, {how}", c.by, c.precondition)?;
        }
        write!(f, " ({} nodes)", self.nodes)
    }
}

/// The backchaining planner: the tree, which conditions were expanded, and the
/// grounded problem. Offline planning ([`plan`]) drives it against the symbolic world;
/// a running system drives it through [`Planner::on_failure`].
#[derive(Clone, Debug)]
pub struct Planner {
    g: Arc<Grounding>,
    tree: PlanTree,
    expanded: Vec<bool>,
    flat: Flat,
    options: Options,
    expansions: usize,
}

impl Planner {
    /// The initial tree of Algorithm 1: the goal conditions in a Sequence.
    ///
    /// # Errors
    /// [`PlanError::NoLeaf`] when a goal condition has no leaf.
    pub fn new(g: Arc<Grounding>, options: Options) -> Result<Self, PlanError> {
        let tree = PlanTree::from_goal(g.goal());
        let flat = tree.flatten(&g)?;
        Ok(Self { g, tree, expanded: Vec::new(), flat, options, expansions: 0 })
    }

    /// The current tree, as bt-core nodes.
    #[must_use]
    pub fn nodes(&self) -> &[Node] {
        &self.flat.nodes
    }

    /// The grounded problem.
    #[must_use]
    pub fn grounding(&self) -> &Arc<Grounding> {
        &self.g
    }

    /// Expansions made so far.
    #[must_use]
    pub fn expansions(&self) -> usize {
        self.expansions
    }

    /// The literal a bt-core condition node checks (an inverted condition counts once,
    /// at the Inverter), if it is one.
    #[must_use]
    pub fn condition_at(&self, node: usize) -> Option<Lit> {
        let &n = self.flat.of.get(node)?;
        match self.tree.kind(n) {
            Kind::Condition(l) if self.flat.top.get(n as usize) == Some(&(node as u32)) => Some(l),
            _ => None,
        }
    }

    fn mark(&mut self, n: PlanNode) {
        if self.expanded.len() <= n as usize {
            self.expanded.resize(n as usize + 1, false);
        }
        self.expanded[n as usize] = true;
    }

    /// Lines 9-12 of Algorithm 1, for a tree that just returned Failure: reads the
    /// failed conditions from `states` (the executor's node states after that tick,
    /// `Executor::states()`, for the tree [`Planner::nodes`] returned), expands the
    /// first one breadth-first that was not expanded before, and resolves conflicts.
    /// Everything built before is kept. `belief` is the world state as the planner's
    /// model sees it, used to refine free parameters. Afterwards tick the new
    /// [`Planner::nodes`] with a fresh executor.
    ///
    /// # Errors
    /// [`PlanError::NoAchiever`] / [`PlanError::NothingToExpand`] when nothing can be
    /// expanded, [`PlanError::Unresolvable`], [`PlanError::TooManyExpansions`],
    /// [`PlanError::TreeTooLarge`].
    pub fn on_failure(&mut self, states: &[NodeState], belief: &State) -> Result<Expansion, PlanError> {
        if self.expansions >= self.options.max_expansions {
            return Err(PlanError::TooManyExpansions(self.expansions));
        }
        let candidates = algorithm::conditions_to_expand(&self.tree, &self.flat, states, &self.expanded);
        let mut unachievable = Vec::new();
        let mut chosen = None;
        for c in candidates {
            let Kind::Condition(lit) = self.tree.kind(c) else { continue };
            self.mark(c);
            match algorithm::expand(&mut self.tree, &self.g, c, belief, self.options.refinement) {
                Some((sub, actions)) => {
                    chosen = Some((lit, sub, actions));
                    break;
                }
                None => unachievable.push(self.g.lit_name(lit)),
            }
        }
        let Some((lit, sub, actions)) = chosen else {
            if let Some(first) = unachievable.into_iter().next() {
                return Err(PlanError::NoAchiever { condition: first });
            }
            let failed: Vec<String> = (0..self.flat.nodes.len())
                .filter(|&i| states.get(i).map(NodeState::status) == Some(bt_core::NodeStatus::Failure))
                .filter_map(|i| self.condition_at(i))
                .map(|l| self.g.lit_name(l))
                .collect();
            return Err(PlanError::NothingToExpand {
                failed: if failed.is_empty() { "none".into() } else { failed.join(", ") },
            });
        };
        self.expansions += 1;
        let conflicts = self.resolve(sub)?;
        self.flat = self.tree.flatten(&self.g)?;
        Ok(Expansion {
            condition: self.g.lit_name(lit),
            actions: actions.iter().map(|&a| self.g.action_name(a)).collect(),
            unachievable,
            conflicts,
            nodes: self.flat.nodes.len(),
        })
    }

    /// Lines 11-12: while the new subtree conflicts, IncreasePriority.
    fn resolve(&mut self, sub: PlanNode) -> Result<Vec<ConflictStep>, PlanError> {
        let mut steps = Vec::new();
        let mut guarded = false;
        let limit = self.tree.capacity() * 2 + 2;
        while let Some(c) = algorithm::conflict(&self.tree, &self.g, sub) {
            let text = |g: &Grounding, c: algorithm::Conflict| (g.lit_name(c.precondition), g.action_name(c.by));
            if steps.len() > limit {
                let (p, by) = text(&self.g, c);
                return Err(PlanError::Unresolvable(format!("`{by}` undoes `{p}` wherever the subtree goes")));
            }
            if !guarded {
                if let Some(guard) = algorithm::leave_guard(&mut self.tree, sub) {
                    self.mark(guard);
                }
                guarded = true;
            }
            let Some(moved) = algorithm::increase_priority(&mut self.tree, sub) else {
                let (p, by) = text(&self.g, c);
                return Err(PlanError::Unresolvable(format!(
                    "`{by}` undoes `{p}`, and the new subtree is already leftmost in the top Sequence"
                )));
            };
            let (precondition, by) = text(&self.g, c);
            steps.push(ConflictStep { precondition, by, moved });
        }
        Ok(steps)
    }

    /// The ground action of a bt-core action node, if it is one.
    #[must_use]
    pub fn action_at(&self, node: usize) -> Option<ActionId> {
        let &n = self.flat.of.get(node)?;
        match self.tree.kind(n) {
            Kind::Action(a) => Some(a),
            _ => None,
        }
    }
}

/// A planned tree with its name table and what planning did.
#[derive(Clone, Debug)]
pub struct Plan<C> {
    /// The tree, as bt-core nodes in pre-order.
    pub nodes: Vec<Node>,
    /// The behavior set the tree is built for.
    pub catalog: Arc<C>,
    /// Every expansion, in order.
    pub expansions: Vec<Expansion>,
    /// With [`Options::record_steps`]: the tree before any expansion, then after each.
    pub steps: Vec<Vec<Node>>,
    /// Ticks of the symbolic world spent planning.
    pub planning_ticks: u32,
    /// Ticks the final tree takes from the initial state to the goal in the symbolic
    /// world, or `None` if it does not reach it there.
    pub goal_ticks: Option<u32>,
    /// The planner, to continue online from this tree.
    pub planner: Planner,
}

/// Offline mode: ticks the tree against the symbolic STRIPS world of `g`, expanding
/// the failed condition each time it fails, until it reaches the goal there; then
/// checks the final tree from the initial state.
///
/// # Errors
/// [`PlanError::NoAchiever`] (the condition no action achieves),
/// [`PlanError::Unresolvable`] (the conflict that could not be resolved),
/// [`PlanError::NoProgress`], and the errors of [`Planner::on_failure`].
pub fn plan<C: Catalog>(g: Arc<Grounding>, catalog: Arc<C>, options: Options) -> Result<Plan<C>, PlanError> {
    let mut planner = Planner::new(g.clone(), options)?;
    let mut world = StripsWorld::new(g.clone());
    let mut states = Vec::new();
    let mut expansions = Vec::new();
    let mut steps = Vec::new();
    let mut planning_ticks = 0;
    if options.record_steps {
        steps.push(planner.nodes().to_vec());
    }
    loop {
        let out =
            strips::run(planner.nodes(), catalog.as_ref(), &mut world, options.max_ticks, |_, _| {}, &mut states)?;
        planning_ticks += out.ticks;
        match out.status {
            Status::Success => break,
            Status::Running => return Err(PlanError::NoProgress { ticks: options.max_ticks }),
            Status::Failure => {
                let belief = world.state().clone();
                expansions.push(planner.on_failure(&states, &belief)?);
                if options.record_steps {
                    steps.push(planner.nodes().to_vec());
                }
            }
        }
    }
    let mut fresh = StripsWorld::new(g);
    let check = strips::run(planner.nodes(), catalog.as_ref(), &mut fresh, options.max_ticks, |_, _| {}, &mut states)?;
    let goal_ticks = (check.status == Status::Success).then_some(check.ticks);
    Ok(Plan { nodes: planner.nodes().to_vec(), catalog, expansions, steps, planning_ticks, goal_ticks, planner })
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
/// and goes on with the new tree from the world as it is. `script(tick, world)` runs
/// before every tick (tick numbers continue across expansions), for external agents.
///
/// # Errors
/// Those of [`Planner::on_failure`] and [`strips::run`].
pub fn run_blended<C: Catalog + ?Sized>(
    planner: &mut Planner,
    catalog: &C,
    world: &mut StripsWorld,
    max_ticks: u32,
    mut script: impl FnMut(u32, &mut StripsWorld),
) -> Result<Blended, PlanError> {
    let mut states = Vec::new();
    let mut ticks = 0;
    let mut expansions = Vec::new();
    loop {
        let base = ticks;
        let out =
            strips::run(planner.nodes(), catalog, world, max_ticks - ticks, |t, w| script(base + t, w), &mut states)?;
        ticks += out.ticks;
        if out.status != Status::Failure || ticks >= max_ticks {
            return Ok(Blended { status: out.status, ticks, expansions });
        }
        let belief = world.state().clone();
        expansions.push((ticks, planner.on_failure(&states, &belief)?));
    }
}
