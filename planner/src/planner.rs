//! Algorithm 1 of Colledanchise et al. 2019: the [`Planner`] that grows a tree by backchaining, used
//! offline ([`crate::plan`]) and online ([`Planner::on_failure`]).

use std::fmt;
use std::sync::Arc;

use bt_core::{Node, NodeState, NodeStatus};

use crate::PlanError;
use crate::algorithm::{self, Move};
use crate::ground::{ActionId, Grounding, Lit};
use crate::guide::Trace;
use crate::options::Options;
use crate::state::State;
use crate::tree::{Flat, Kind, PlanNode, PlanTree};
use crate::variables::{Choice, Variables};

/// What [`Planner::backtrack`] did.
enum Backtrack {
    /// Added an achieving action to the Fallback of a condition.
    Alternative(Lit, PlanNode, ActionId),
    /// Expanded a condition that stood alone.
    Expanded(Lit, PlanNode, Vec<ActionId>),
}

/// Most achieving actions one Fallback gets when alternatives are added to it
/// ([`Planner::on_failure`] when every failed condition was expanded before).
pub const MAX_ALTERNATIVES: usize = 8;

/// A conflict met while placing a new subtree, and how IncreasePriority answered it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ConflictStep {
    /// The new subtree's precondition that was undone.
    pub precondition: String,
    /// The action that undoes it.
    pub by: String,
    /// Whether that action is in the new subtree (it undoes a condition established
    /// before the subtree), rather than executed before it.
    pub by_new_subtree: bool,
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
    /// Whether this added another achieving action to a condition expanded before
    /// (all its alternatives had failed), instead of expanding a new condition.
    pub added_alternative: bool,
}

impl fmt::Display for Expansion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.added_alternative {
            write!(f, "added {} as another way to achieve `{}`", self.actions.join(", "), self.condition)?;
        } else {
            write!(f, "expanded `{}` with {}", self.condition, self.actions.join(", "))?;
        }
        for c in &self.conflicts {
            let how = match c.moved {
                Move::Left => "moved the new subtree one place left",
                Move::Up => "moved the new subtree up a level",
            };
            if c.by_new_subtree {
                write!(f, "; conflict: its `{}` undoes `{}`, established before it, {how}", c.by, c.precondition)?;
            } else {
                write!(f, "; conflict: `{}` undoes its precondition `{}`, {how}", c.by, c.precondition)?;
            }
        }
        write!(f, " ({})", crate::wording::count(self.nodes, "node"))
    }
}

/// The backchaining planner: the tree, which conditions were expanded, and the
/// grounded problem. Offline planning ([`crate::plan`]) drives it against the
/// symbolic world; a running system drives it through [`Planner::on_failure`].
///
/// With a [`Trace`] (a plan found by search), expansions are *guided*: a condition
/// is expanded with the action of its causal link in the plan, and preconditions and
/// goal conditions are placed in the order the plan achieves them ([`crate::guide`]).
#[derive(Clone, Debug)]
pub struct Planner {
    g: Arc<Grounding>,
    tree: PlanTree,
    expanded: Vec<bool>,
    flat: Flat,
    options: Options,
    expansions: usize,
    guide: Option<Arc<Trace>>,
    /// Per planner node, the plan step that needs its condition (guided only).
    steps: Vec<u32>,
    /// How often each literal was expanded again as a lone condition.
    again: std::collections::HashMap<Lit, u8>,
    /// Guided only: the plan's state variables, which its steps do not pin
    /// ([`Planner::with_state_variables`]).
    variables: Option<Arc<Variables>>,
}

impl Planner {
    /// The initial tree of Algorithm 1: the goal conditions in a Sequence.
    ///
    /// # Errors
    /// [`PlanError::NoLeaf`] when a goal condition has no leaf.
    pub fn new(g: Arc<Grounding>, options: Options) -> Result<Self, PlanError> {
        let tree =
            if options.goal_sequence { PlanTree::goal_sequence(g.goal()) } else { PlanTree::from_goal(g.goal()) };
        Self::from_tree(g, tree, options)
    }

    /// The initial tree guided by `trace`: the goal conditions in the order the plan
    /// achieves them.
    ///
    /// # Errors
    /// As [`Planner::new`].
    pub fn guided(g: Arc<Grounding>, trace: Arc<Trace>, options: Options) -> Result<Self, PlanError> {
        let goal = trace.ordered(g.goal(), trace.goal_step());
        let tree = if options.goal_sequence { PlanTree::goal_sequence(&goal) } else { PlanTree::from_goal(&goal) };
        let mut p = Self::from_tree(g, tree, options)?;
        p.steps = vec![trace.goal_step() as u32; p.tree.capacity()];
        p.guide = Some(trace);
        Ok(p)
    }

    /// A planner that goes on from `tree`.
    ///
    /// # Errors
    /// As [`Planner::new`].
    pub fn from_tree(g: Arc<Grounding>, tree: PlanTree, options: Options) -> Result<Self, PlanError> {
        let flat = tree.flatten(&g)?;
        Ok(Self {
            g,
            tree,
            expanded: Vec::new(),
            flat,
            options,
            expansions: 0,
            guide: None,
            steps: Vec::new(),
            again: std::collections::HashMap::new(),
            variables: None,
        })
    }

    /// The planner's tree.
    #[must_use]
    pub fn tree(&self) -> &PlanTree {
        &self.tree
    }

    /// The current tree, as bt-core nodes.
    #[must_use]
    pub fn nodes(&self) -> &[Node] {
        &self.flat.nodes
    }

    /// The current tree's value table (see [`Flat::values`]).
    #[must_use]
    pub fn values(&self) -> &[u16] {
        &self.flat.values
    }

    /// The grounded problem.
    #[must_use]
    pub fn grounding(&self) -> &Arc<Grounding> {
        &self.g
    }

    /// The settings it plans with.
    #[must_use]
    pub fn options(&self) -> &Options {
        &self.options
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

    /// Marks condition node `n` as expanded.
    pub(crate) fn mark(&mut self, n: PlanNode) {
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
        let statuses: Vec<NodeStatus> = states.iter().map(NodeState::status).collect();
        self.on_reported_failure(&statuses, belief)
    }

    /// [`Planner::on_failure`] from each node's status after the failed tick, as a
    /// controller ticking the tree elsewhere reports them (bt-link's status stream): all
    /// Algorithm 1 reads of a tick.
    ///
    /// # Errors
    /// As [`Planner::on_failure`].
    pub fn on_reported_failure(&mut self, states: &[NodeStatus], belief: &State) -> Result<Expansion, PlanError> {
        if self.expansions >= self.options.max_expansions {
            return Err(PlanError::TooManyExpansions(self.expansions));
        }
        let candidates = algorithm::conditions_to_expand(&self.tree, &self.flat, states, &self.expanded);
        let mut unachievable = Vec::new();
        let mut chosen = None;
        for c in candidates {
            let Kind::Condition(lit) = self.tree.kind(c) else { continue };
            self.mark(c);
            if let Some(action) = self.add_sibling(c, lit, belief) {
                // The new row differs from the others of its Fallback only in values of
                // state variables, which never conflict: nothing moves.
                self.expansions += 1;
                self.flat = self.tree.flatten(&self.g)?;
                return Ok(Expansion {
                    condition: self.g.lit_name(lit),
                    actions: vec![self.g.action_name(action)],
                    unachievable,
                    conflicts: Vec::new(),
                    nodes: self.flat.nodes.len(),
                    added_alternative: true,
                });
            }
            match self.expand_at(c, lit, belief) {
                Some((sub, actions)) => {
                    chosen = Some((lit, sub, actions));
                    break;
                }
                None => unachievable.push(self.g.lit_name(lit)),
            }
        }
        if chosen.is_none() && unachievable.is_empty() {
            match self.backtrack(states, belief) {
                Some(Backtrack::Alternative(lit, fallback, action)) => {
                    self.expansions += 1;
                    let conflicts = self.resolve(fallback)?;
                    self.flat = self.tree.flatten(&self.g)?;
                    return Ok(Expansion {
                        condition: self.g.lit_name(lit),
                        actions: vec![self.g.action_name(action)],
                        unachievable,
                        conflicts,
                        nodes: self.flat.nodes.len(),
                        added_alternative: true,
                    });
                }
                Some(Backtrack::Expanded(lit, sub, actions)) => chosen = Some((lit, sub, actions)),
                None => {}
            }
        }
        let Some((lit, sub, actions)) = chosen else {
            if let Some(first) = unachievable.into_iter().next() {
                return Err(PlanError::NoAchiever { condition: first });
            }
            let failed: Vec<String> = (0..self.flat.nodes.len())
                .filter(|&i| states.get(i) == Some(&NodeStatus::Failure))
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
            added_alternative: false,
        })
    }

    /// When every failed condition was expanded before, the first of them
    /// (breadth-first) that can still be helped: a condition whose Fallback failed
    /// gets one more achieving action, the cheapest from `belief` by h_add among those
    /// its Fallback does not have yet (a grounding chosen before may lead nowhere in
    /// the situation the tree meets now), at most [`MAX_ALTERNATIVES`] per Fallback; a
    /// condition standing alone (the guard IncreasePriority leaves behind) is expanded
    /// in place.
    fn backtrack(&mut self, states: &[NodeStatus], belief: &State) -> Option<Backtrack> {
        let mut failed: Vec<(u16, usize, PlanNode)> = Vec::new();
        for (i, &n) in self.flat.of.iter().enumerate() {
            let failed_here = states.get(i) == Some(&NodeStatus::Failure);
            if !failed_here || self.flat.top.get(n as usize) != Some(&(i as u32)) {
                continue;
            }
            if !matches!(self.tree.kind(n), Kind::Condition(_))
                || !self.expanded.get(n as usize).copied().unwrap_or(false)
            {
                continue;
            }
            failed.push((self.flat.depth[i], i, n));
        }
        failed.sort_unstable();
        let mut cost: Option<Vec<u32>> = None;
        for (_, _, n) in failed {
            let Kind::Condition(lit) = self.tree.kind(n) else { continue };
            let Some(fb) = self.tree.parent(n) else { continue };
            let in_fallback = self.tree.kind(fb) == Kind::Fallback && self.tree.children(fb).first() == Some(&n);
            if !in_fallback {
                let count = self.again.entry(lit).or_insert(0);
                if *count >= 2 {
                    continue;
                }
                *count += 1;
                if let Some((sub, actions)) = self.expand_at(n, lit, belief) {
                    return Some(Backtrack::Expanded(lit, sub, actions));
                }
                continue;
            }
            let have: Vec<ActionId> = self.tree.children(fb).iter().filter_map(|&c| self.tree.row_action(c)).collect();
            if have.len() >= MAX_ALTERNATIVES {
                continue;
            }
            let cost = cost.get_or_insert_with(|| crate::refine::h_add(&self.g, belief));
            let price = |a: ActionId| -> u64 {
                self.g.action(a).map_or(u64::MAX, |x| {
                    let extra = x.achieving_condition(lit).unwrap_or(&[]);
                    x.pre.iter().chain(extra).map(|p| u64::from(cost[p.index()])).fold(0, u64::saturating_add)
                })
            };
            let best = self
                .g
                .achievers(lit)
                .iter()
                .copied()
                .filter(|a| !have.contains(a))
                .filter(|&a| self.g.action(a).is_some_and(|x| !x.pre.contains(&lit)))
                .map(|a| (price(a), a))
                .filter(|&(p, _)| p < u64::from(u32::MAX))
                .min();
            let Some((_, action)) = best else { continue };
            let x = self.g.action(action)?;
            let mut pre = x.pre.clone();
            for &w in x.achieving_condition(lit).unwrap_or(&[]) {
                if !pre.contains(&w) {
                    pre.push(w);
                }
            }
            self.push_alternative(fb, n, action, &pre);
            return Some(Backtrack::Alternative(lit, fb, action));
        }
        None
    }

    /// The plan's choice for expanding condition node `c` (`lit`): the action of its
    /// causal link and its preconditions in plan order, with the step they belong to.
    fn guided_choice(&self, c: PlanNode, lit: Lit) -> Option<(ActionId, Vec<Lit>, usize)> {
        let trace = self.guide.as_ref()?;
        let k = self.steps.get(c as usize).map_or(trace.goal_step(), |&s| s as usize);
        trace.causal_step(&self.g, lit, k)
    }

    /// Expands condition node `c` (`lit`): with the plan's choices when guided (and its
    /// siblings over state variables, [`Variables::choices`]), else as Algorithm 1 does.
    /// Returns the new subtree and the actions used, or `None` when nothing achieves it.
    fn expand_at(&mut self, c: PlanNode, lit: Lit, belief: &State) -> Option<(PlanNode, Vec<ActionId>)> {
        let mut guided: Vec<Choice> = self.guided_choice(c, lit).into_iter().collect();
        if let Some(v) = &self.variables
            && let Some(first) = guided.pop()
        {
            // Empty for a value that no action sets without doing more: expanded as
            // Algorithm 1 would.
            guided = v.choices(&self.g, lit, first, belief);
        }
        let (sub, actions) = match guided.len() {
            0 => algorithm::expand(&mut self.tree, &self.g, c, belief, self.options.refinement)?,
            1 => algorithm::expand_with(&mut self.tree, c, lit, &guided),
            _ => algorithm::expand_shared(&mut self.tree, &self.g, c, &guided),
        };
        self.set_steps(sub, c, guided.first());
        Some((sub, actions))
    }

    /// With state variables, where the failed value `lit` (node `c`) stands in a row of
    /// siblings and none of them starts from the values `belief` holds: adds the one
    /// that does to their Fallback ([`Variables::sibling_for`]). Returns its action.
    fn add_sibling(&mut self, c: PlanNode, lit: Lit, belief: &State) -> Option<ActionId> {
        let v = self.variables.clone()?;
        let row = self.tree.parent(c)?;
        let fb = self.tree.parent(row)?;
        if self.tree.kind(row) != Kind::Sequence || self.tree.kind(fb) != Kind::Fallback {
            return None;
        }
        let a = self.tree.row_action(row)?;
        let own: Vec<Lit> = self
            .tree
            .children(row)
            .iter()
            .filter_map(|&k| match self.tree.kind(k) {
                Kind::Condition(l) => Some(l),
                _ => None,
            })
            .collect();
        let have: Vec<ActionId> = self.tree.children(fb).iter().filter_map(|&r| self.tree.row_action(r)).collect();
        let (b, pre) = v.sibling_for(&self.g, lit, a, &own, &have, belief)?;
        self.push_alternative(fb, c, b, &pre);
        Some(b)
    }

    /// Appends `Sequence(pre?.., action)` to the Fallback `fb` as one more alternative,
    /// its conditions standing for the plan step of node `at` (guided only).
    fn push_alternative(&mut self, fb: PlanNode, at: PlanNode, action: ActionId, pre: &[Lit]) {
        self.tree.push_step(fb, pre, action);
        if let Some(trace) = &self.guide {
            let step = self.steps.get(at as usize).copied().unwrap_or(trace.goal_step() as u32);
            self.steps.resize(self.tree.capacity(), step);
        }
    }

    /// Guided backchaining that does not pin the plan's state variables to the values
    /// its steps give them ([`crate::variables`]). Returns `false`, and changes
    /// nothing, where the planner is not guided or the problem has none.
    pub fn with_state_variables(&mut self) -> bool {
        let Some(v) = self.guide.as_ref().and_then(|t| Variables::new(&self.g, t)) else { return false };
        self.variables = Some(Arc::new(v));
        true
    }

    /// The state variables it does not pin ([`Planner::with_state_variables`]), as
    /// `predicate/argument`.
    #[must_use]
    pub fn state_variable_names(&self) -> Vec<String> {
        self.variables.as_ref().map_or_else(Vec::new, |v| v.state_variables().names(&self.g))
    }

    /// Records the plan step of the new subtree's conditions.
    fn set_steps(&mut self, sub: PlanNode, expanded: PlanNode, guided: Option<&Choice>) {
        let Some(trace) = &self.guide else { return };
        let outer = self.steps.get(expanded as usize).copied().unwrap_or(trace.goal_step() as u32);
        let inner = guided.map_or(outer, |g| g.2 as u32);
        if self.steps.len() < self.tree.capacity() {
            self.steps.resize(self.tree.capacity(), trace.goal_step() as u32);
        }
        for n in self.tree.preorder(sub) {
            self.steps[n as usize] = if n == expanded { outer } else { inner };
        }
    }

    /// Lines 11-12: while the new subtree conflicts, IncreasePriority.
    fn resolve(&mut self, sub: PlanNode) -> Result<Vec<ConflictStep>, PlanError> {
        let mut steps = Vec::new();
        let mut guarded = false;
        let limit = self.tree.capacity() * 2 + 2;
        let variables = self.variables.clone();
        let of = variables.as_ref().map(|v| v.state_variables());
        while let Some(c) = algorithm::conflict_with(&self.tree, &self.g, sub, of) {
            let text = |g: &Grounding, c: algorithm::Conflict| (g.lit_name(c.precondition), g.action_name(c.by));
            if steps.len() > limit {
                let (p, by) = text(&self.g, c);
                return Err(PlanError::Unresolvable(format!("`{by}` undoes `{p}` wherever the subtree goes")));
            }
            if !guarded {
                if let Some(guard) = algorithm::leave_guard(&mut self.tree, sub) {
                    self.mark(guard);
                    if let Some(&step) = self.steps.get(sub as usize) {
                        self.steps.resize(self.tree.capacity(), step);
                    }
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
            steps.push(ConflictStep { precondition, by, moved, by_new_subtree: c.by_new_subtree });
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
