//! Learning on any PDDL problem the planner reads: GP's leaves are the problem's
//! grounded conditions and actions, episodes run in the symbolic STRIPS world, the
//! planner's tree is the baseline, and external agents may disturb every episode.
//!
//! # Leaves
//!
//! GP draws argument-less leaves ([`gp::Alphabet`]), so each grounded literal and each
//! ground action is one leaf of a [`FlatCatalog`]: the conditions are the literals that
//! some ground action needs, that a conditional effect's `when` asks for, or that the
//! goal asks for (`holding(cube)`, and `not hand-empty` for a negative one), then every
//! ground action (`move-to(goal)`). Trees are converted both ways to the PDDL leaf
//! contract (predicate or action id with object arguments; a negative condition is an
//! `Inverter` over the condition), which is what images, XML and ASCII output use.
//!
//! # Episodes
//!
//! Episodes run on the one runner of [`worlds`], in the planner's STRIPS world
//! ([`planner::strips::StripsWorld`]): a condition leaf holds when its literal does; an
//! action leaf fails if its preconditions do not hold when it starts, else returns
//! Running, and on its next tick applies its effects (conditional ones included) and
//! succeeds; a halted action has no effect. An episode ticks the tree from the initial
//! state until the root fails, succeeds on two ticks in a row, or the tick limit is
//! reached (a timeout).
//!
//! With disturbances, external agents act before ticks as in the IPC benchmark
//! ([`planner::strips::disturb`]: with chance `rate` per tick, at most three times an
//! episode, they undo the robot's last completed action or do one of the tree's actions
//! for it). The agents of episode `k` draw from a generator seeded by the disturbance
//! seed and `k`, so a tree always meets the same `episodes` disturbed episodes and its
//! fitness is a function of the tree.
//!
//! # Fitness
//!
//! In the spirit of Styrud et al.'s Eq. (1), with goal literals in place of brick distances:
//!
//! ```text
//! F = - G U - λ L - κ T - ϕ F - τ O
//! ```
//!
//! U: goal literals that do not hold at the end of the episode (G = 100 each); L: nodes
//! of the tree as GP counts them, a negative condition one node (λ = 0.1); T: ticks
//! the episode ran (κ = 0.1: a node must save a tick to pay for itself); F: 1 if the
//! root returned Failure (ϕ = 50); O: 1 if the episode hit the tick limit (τ = 10).
//! With disturbances the fitness is the mean over the episodes, summed in episode
//! order.

use std::collections::BTreeSet;
use std::sync::Arc;

use anyhow::{Context as _, anyhow, bail};
use bt_core::{BehaviorInfo, Catalog, Leaf, LeafKind, Node, NodeKind};
use planner::ground::{ActionId, Grounding, Lit};
use planner::{Options, PddlCatalog};

use crate::text::count_as;

/// Most levels a tree may have in an episode: as many as the planner makes.
pub const DEPTH: usize = planner::tree::DEPTH;

/// Argument-less leaves named after grounded literals and actions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FlatCatalog {
    leaves: Vec<(String, LeafKind)>,
}

impl Catalog for FlatCatalog {
    fn len(&self) -> usize {
        self.leaves.len()
    }

    fn info(&self, id: bt_core::BehaviorId) -> Option<BehaviorInfo<'_>> {
        self.leaves.get(usize::from(id)).map(|(name, kind)| BehaviorInfo { name, kind: *kind, arity: 0 })
    }
}

/// What a leaf of the [`FlatCatalog`] stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Letter {
    /// A literal to check.
    Condition(Lit),
    /// A ground action to run.
    Action(ActionId),
}

/// The constants of the fitness (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StripsFitnessParams {
    /// G: cost of each goal literal that does not hold at the end.
    pub unmet_goal: f64,
    /// λ: cost per node.
    pub length: f64,
    /// κ: cost per tick.
    pub tick: f64,
    /// ϕ: cost of ending in Failure.
    pub failure: f64,
    /// τ: cost of ending by timeout.
    pub timeout: f64,
}

impl Default for StripsFitnessParams {
    fn default() -> Self {
        Self { unmet_goal: 100.0, length: 0.1, tick: 0.1, failure: 50.0, timeout: 10.0 }
    }
}

/// External agents that disturb every episode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disturbance {
    /// Chance per tick that an agent acts, in `[0, 1]`.
    pub rate: f64,
    /// Seed of the episodes' agents.
    pub seed: u64,
    /// How many disturbed episodes score a tree.
    pub episodes: u32,
}

impl Disturbance {
    /// The agents' model: the IPC benchmark's, with this rate and seed.
    #[must_use]
    pub fn model(&self) -> planner::strips::disturb::Disturbance {
        planner::strips::disturb::Disturbance {
            rate: self.rate,
            seed: self.seed,
            ..planner::strips::disturb::Disturbance::default()
        }
    }
}

/// A PDDL problem ready to learn on: grounded, with its leaves and the planner's tree.
#[derive(Debug)]
pub struct StripsProblem {
    /// The domain file's text, as read (copied into run folders).
    pub domain_text: String,
    /// The problem file's text, as read.
    pub problem_text: String,
    g: Arc<Grounding>,
    pddl: PddlCatalog,
    catalog: FlatCatalog,
    letters: Vec<Letter>,
    planner_tree: Vec<Node>,
    planner_ticks: Option<u32>,
    planner_fit: planner::Fitted,
}

impl StripsProblem {
    /// Reads, grounds and plans a problem; `domain_file` and `problem_file` name the
    /// texts in errors. With `goal_sequence` the planner keeps the goal Sequence at the
    /// root for a single goal ([`planner::Options::goal_sequence`]).
    ///
    /// # Errors
    /// PDDL errors (file:line:column), grounding and planning errors, a problem with
    /// more leaves than 16-bit ids name, or names GP's token notation cannot carry.
    pub fn new(
        domain_file: &str,
        domain_text: String,
        problem_file: &str,
        problem_text: String,
        goal_sequence: bool,
        bound: gp::Bound,
    ) -> anyhow::Result<Self> {
        let domain = planner::pddl::parse_domain(domain_file, &domain_text)?;
        let problem = planner::pddl::parse_problem(problem_file, &problem_text, &domain)?;
        let g = Arc::new(Grounding::new(&problem).with_context(|| format!("grounding {problem_file}"))?);
        let pddl = PddlCatalog::new(&problem);
        // A bound replaces the planner's default 16 KiB: its closure over disturbances
        // is cut to fit. Not strict: a tree too big even without it is kept, for the
        // variants without a baseline; the others refuse it by name.
        let fit = match (bound.bytes, bound.nodes) {
            (None, None) => planner::Fit::DEFAULT,
            (b, n) => planner::Fit { bytes: b.unwrap_or(usize::MAX), nodes: n.unwrap_or(usize::MAX), strict: false },
        };
        let options = Options { goal_sequence, fit, ..Options::default() };
        let plan = planner::plan(g.clone(), Arc::new(pddl.clone()), options)
            .with_context(|| format!("planning {problem_file} (the baseline)"))?;

        let mut conditions: BTreeSet<Lit> = g.goal().iter().copied().collect();
        for a in g.actions() {
            conditions.extend(a.pre.iter().copied());
            conditions.extend(a.cond.iter().flat_map(|c| c.when.iter().copied()));
        }
        let mut letters: Vec<Letter> = conditions.into_iter().map(Letter::Condition).collect();
        letters.extend((0..g.actions().len() as ActionId).map(Letter::Action));
        if letters.len() > usize::from(u16::MAX) {
            bail!(
                "{problem_file}: {}; learning handles at most 65535",
                count_as(letters.len(), "grounded condition or action", "grounded conditions and actions")
            );
        }
        let leaves: Vec<(String, LeafKind)> = letters
            .iter()
            .map(|&l| match l {
                Letter::Condition(lit) => (g.lit_name(lit), LeafKind::Condition),
                Letter::Action(a) => (g.action_name(a), LeafKind::Action),
            })
            .collect();
        if let Some((name, _)) = leaves.iter().find(|(n, _)| n.contains(['?', '!'])) {
            bail!(
                "{problem_file}: `{name}` contains `?` or `!`, which the token notation of learned trees cannot carry"
            );
        }
        let mut p = Self {
            domain_text,
            problem_text,
            g,
            pddl,
            catalog: FlatCatalog { leaves },
            letters,
            planner_tree: Vec::new(),
            planner_ticks: plan.goal_ticks,
            planner_fit: plan.fit,
        };
        p.planner_tree = p.from_pddl(&plan.nodes).context("the planner's tree")?;
        Ok(p)
    }

    /// The problem's name, from its `(define (problem NAME))`.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.g.problem().name
    }

    /// The domain's name.
    #[must_use]
    pub fn domain_name(&self) -> &str {
        &self.g.problem().domain.name
    }

    /// GP's leaves.
    #[must_use]
    pub fn catalog(&self) -> &FlatCatalog {
        &self.catalog
    }

    /// The behavior set of the PDDL leaf contract (images, XML).
    #[must_use]
    pub fn pddl_catalog(&self) -> &PddlCatalog {
        &self.pddl
    }

    /// The grounded problem.
    #[must_use]
    pub fn grounding(&self) -> &Arc<Grounding> {
        &self.g
    }

    /// What leaf `id` of the [`FlatCatalog`] stands for.
    #[must_use]
    pub fn letter(&self, id: bt_core::BehaviorId) -> Option<Letter> {
        self.letters.get(usize::from(id)).copied()
    }

    /// The planner's tree in GP's leaves (the baseline).
    #[must_use]
    pub fn planner_tree(&self) -> &[Node] {
        &self.planner_tree
    }

    /// The size of a tree in GP's leaves as `learn` writes it: in the PDDL leaf
    /// contract, its image without the names section.
    #[must_use]
    pub fn size(&self, tree: &[Node]) -> Option<gp::Size> {
        gp::image_size(&self.to_pddl(tree).ok()?)
    }

    /// The planner's tree's size, and whether its closure over disturbances was cut to
    /// fit the bound.
    #[must_use]
    pub fn planner_fit(&self) -> planner::Fitted {
        self.planner_fit
    }

    /// Ticks the planner's tree takes to the goal in the undisturbed world, if it
    /// reaches it.
    #[must_use]
    pub fn planner_ticks(&self) -> Option<u32> {
        self.planner_ticks
    }

    /// The default tick limit of an episode: room for the planner's tree three times
    /// over and 30 ticks more (200 if the planner's tree does not reach the goal).
    #[must_use]
    pub fn default_tick_limit(&self) -> u32 {
        self.planner_ticks.map_or(200, |t| t.saturating_mul(3).saturating_add(30))
    }

    /// A tree in GP's leaves as a tree of the PDDL leaf contract: a negative condition
    /// becomes an Inverter over the condition.
    ///
    /// # Errors
    /// A leaf GP's catalog does not have, or a node kind GP does not use.
    pub fn to_pddl(&self, flat: &[Node]) -> anyhow::Result<Vec<Node>> {
        // Sizes grow by one per negative condition inside a subtree: rebuild them.
        let extra: Vec<u16> = flat
            .iter()
            .map(|n| match n.kind() {
                NodeKind::Condition(l) => match self.letter(l.behavior()) {
                    Some(Letter::Condition(lit)) => u16::from(!lit.positive),
                    _ => 0,
                },
                _ => 0,
            })
            .collect();
        let mut out = Vec::with_capacity(flat.len() + extra.iter().map(|&e| usize::from(e)).sum::<usize>());
        for (i, n) in flat.iter().enumerate() {
            let end = i + usize::from(n.size());
            let grown: usize = extra
                .get(i..end)
                .ok_or_else(|| anyhow!("node {i}: malformed tree"))?
                .iter()
                .map(|&e| usize::from(e))
                .sum();
            let size = u16::try_from(usize::from(n.size()) + grown).map_err(|_| anyhow!("tree too large"))?;
            match n.kind() {
                NodeKind::Sequence | NodeKind::Fallback => out.push(Node::new(*n.kind(), size)),
                NodeKind::Condition(l) => {
                    let Some(Letter::Condition(lit)) = self.letter(l.behavior()) else {
                        bail!("node {i}: behavior {} is not a condition of this problem", l.behavior());
                    };
                    let leaf = self
                        .g
                        .condition_leaf(lit.atom)
                        .ok_or_else(|| anyhow!("node {i}: `{}` has no leaf", self.g.lit_name(lit)))?;
                    if !lit.positive {
                        out.push(Node::new(NodeKind::Inverter, 2));
                    }
                    out.push(Node::new(NodeKind::Condition(leaf), 1));
                }
                NodeKind::Action(l) => {
                    let Some(Letter::Action(a)) = self.letter(l.behavior()) else {
                        bail!("node {i}: behavior {} is not an action of this problem", l.behavior());
                    };
                    let leaf = self
                        .g
                        .action_leaf(a)
                        .ok_or_else(|| anyhow!("node {i}: `{}` has no leaf", self.g.action_name(a)))?;
                    out.push(Node::new(NodeKind::Action(leaf), 1));
                }
                other => bail!("node {i}: a {}; learned trees have only Sequence, Fallback and leaves", other.name()),
            }
        }
        Ok(out)
    }

    /// A tree of the PDDL leaf contract (as the planner makes it) in GP's leaves.
    ///
    /// # Errors
    /// Node kinds other than reactive Sequence, Fallback, leaves and an Inverter over a
    /// condition; leaves that are not grounded conditions or actions of the problem.
    pub fn from_pddl(&self, nodes: &[Node]) -> anyhow::Result<Vec<Node>> {
        // Inverters are dropped (their condition becomes a negative one): `kept[i]`
        // counts the nodes kept before node i, to rebuild subtree sizes.
        let inverter = |n: &Node| matches!(n.kind(), NodeKind::Inverter);
        let mut kept = Vec::with_capacity(nodes.len() + 1);
        kept.push(0usize);
        for n in nodes {
            kept.push(kept.last().copied().unwrap_or(0) + usize::from(!inverter(n)));
        }
        let mut flat = Vec::with_capacity(nodes.len());
        for (i, n) in nodes.iter().enumerate() {
            let end = i + usize::from(n.size());
            if end > nodes.len() || n.size() == 0 {
                bail!("node {i}: malformed tree");
            }
            let size = u16::try_from(kept[end] - kept[i]).map_err(|_| anyhow!("tree too large"))?;
            let kind = match n.kind() {
                NodeKind::Inverter => {
                    if n.size() != 2 || !nodes.get(i + 1).is_some_and(|c| matches!(c.kind(), NodeKind::Condition(_))) {
                        bail!("node {i}: an Inverter over something other than a condition");
                    }
                    continue;
                }
                NodeKind::Sequence | NodeKind::Fallback => *n.kind(),
                NodeKind::Condition(leaf) => {
                    let atom = self.g.leaf_atom(leaf).ok_or_else(|| anyhow!("node {i}: unknown condition"))?;
                    let negated = i > 0 && nodes.get(i - 1).is_some_and(inverter);
                    let lit = Lit { atom, positive: !negated };
                    let id = self.letter_of(Letter::Condition(lit)).ok_or_else(|| {
                        anyhow!(
                            "node {i}: `{}` is not a precondition, effect condition or goal of this problem",
                            self.g.lit_name(lit)
                        )
                    })?;
                    NodeKind::Condition(Leaf::new(id))
                }
                NodeKind::Action(leaf) => {
                    let mut candidates = Vec::new();
                    self.g.leaf_actions(leaf, &mut candidates);
                    let &[a] = candidates.as_slice() else { bail!("node {i}: unknown action") };
                    let id = self.letter_of(Letter::Action(a)).ok_or_else(|| anyhow!("node {i}: unknown action"))?;
                    NodeKind::Action(Leaf::new(id))
                }
                other => bail!("node {i}: a {}; learning uses only Sequence, Fallback and leaves", other.name()),
            };
            flat.push(Node::new(kind, size));
        }
        Ok(flat)
    }

    fn letter_of(&self, letter: Letter) -> Option<u16> {
        self.letters.iter().position(|&l| l == letter).and_then(|i| u16::try_from(i).ok())
    }
}

mod episode;

pub use episode::{StripsEnd, StripsEpisode, StripsFitness, StripsRunner};
