//! Grounding — the paper's action refinement over a finite set of typed objects.
//!
//! Grounding is by reachability: starting from the initial state, an action template
//! is instantiated only with objects that make its preconditions reachable in the
//! delete relaxation, and an atom exists only if the initial state has it or a
//! reachable action makes it true (or the goal names it). Memory and time follow the
//! reachable part of the problem, not the product of the object counts; [`Limits`]
//! bounds both, and the error says which limit was hit.
//!
//! Predicates that no action changes are *static*: static preconditions are checked
//! while grounding and left out of the ground actions (and so out of every tree).
//! Each ground action keeps its other preconditions in the order written, its add and
//! delete lists, its conditional effects and its cost.
//!
//! ADL is compiled away: a precondition with `or`, `imply`, `forall` or `exists` is
//! expanded over the objects and brought into disjunctive normal form, after static
//! atoms are replaced by their truth; each alternative becomes a ground action of its
//! own (same template, same arguments, same leaf). `when` effects become conditional
//! effects of the ground action. A formula with more alternatives than
//! [`Limits::alternatives`] is refused, naming the action.
//!
//! A grounding also knows the bt-core leaves of its atoms and actions: by default the
//! PDDL contract (behavior ids are the predicates in declaration order, then the
//! actions; leaf arguments are object indices), or a custom [`Vocabulary`] (the brick
//! tasks), in which case actions and conditions without a leaf are dropped.

mod action;
mod build;
mod derive;
mod formula;
mod reach;
mod tables;

use std::collections::HashMap;
use std::time::Instant;

use bt_core::Leaf;

pub use action::{ActionId, AtomId, CondEffect, GroundAction, Lit};
pub use derive::Rule;

use crate::PlanError;
use crate::model::{Atom, ObjectId, PredicateId, Problem, TemplateId};
use crate::state::State;
use foldhash::fast::FixedState;
use tables::with_key;

/// Bounds on grounding, so that a large problem is refused instead of exhausting
/// memory or time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Most ground atoms.
    pub atoms: usize,
    /// Most ground actions.
    pub actions: usize,
    /// Most alternatives one ADL formula may expand to.
    pub alternatives: usize,
    /// Give up at this instant.
    pub deadline: Option<Instant>,
}

impl Default for Limits {
    fn default() -> Self {
        Self { atoms: 1 << 23, actions: 1 << 22, alternatives: 256, deadline: None }
    }
}

/// Names a problem's atoms and actions as bt-core leaves, for behavior sets that do
/// not follow the PDDL contract (e.g. the brick tasks of [`crate::duplo`]).
pub trait Vocabulary {
    /// The condition leaf of an atom, if the behavior set has one.
    fn condition(&self, problem: &Problem, atom: &Atom<ObjectId>) -> Option<Leaf>;
    /// The action leaf of a grounding of `template`, if the behavior set has one.
    fn action(&self, problem: &Problem, template: TemplateId, args: &[ObjectId]) -> Option<Leaf>;
}

/// What a leaf stands for under a custom vocabulary.
#[derive(Clone, Debug)]
enum Target {
    Condition(AtomId),
    Actions(Vec<ActionId>),
}

#[derive(Clone, Debug)]
enum Leaves {
    /// The PDDL contract: computed, no tables.
    Pddl,
    /// A custom vocabulary: tables both ways.
    Table { atom_leaf: HashMap<AtomId, Leaf>, action_leaf: Vec<Leaf>, by_leaf: HashMap<Leaf, Target> },
}

/// A problem grounded into atoms and actions, with their bt-core leaves.
#[derive(Clone, Debug)]
pub struct Grounding {
    problem: Problem,
    statics: Vec<bool>,
    /// Per atom, its key `[predicate, args...]`; atoms are sorted by key.
    keys: Vec<Box<[u16]>>,
    atom_index: HashMap<Box<[u16]>, AtomId, FixedState>,
    init: State,
    actions: Vec<GroundAction>,
    /// `[template, args...]` → the ground actions of that leaf.
    action_index: HashMap<Box<[u16]>, Vec<ActionId>, FixedState>,
    /// Per literal index: the actions achieving it, in template then grounding order.
    achievers: Vec<Vec<ActionId>>,
    goal: Vec<Lit>,
    leaves: Leaves,
    unit_cost: bool,
    /// The ground rules of derived predicates.
    rules: derive::Rules,
}

impl Grounding {
    /// Grounds `problem` with the PDDL leaf contract and the default [`Limits`].
    ///
    /// # Errors
    /// [`PlanError::TooLarge`], [`PlanError::Unbounded`], [`PlanError::TooComplex`],
    /// [`PlanError::MissingCost`], [`PlanError::ContradictoryGoal`],
    /// [`PlanError::Unsolvable`] (a goal atom no action reaches).
    pub fn new(problem: &Problem) -> Result<Self, PlanError> {
        Self::with_limits(problem, &Limits::default())
    }

    /// Grounds `problem` within `limits`.
    ///
    /// # Errors
    /// As [`Grounding::new`], and [`PlanError::Timeout`] past the deadline.
    pub fn with_limits(problem: &Problem, limits: &Limits) -> Result<Self, PlanError> {
        build::build(problem, limits)
    }

    /// Grounds `problem` with the leaves of `vocabulary`; actions without a leaf, or
    /// with a precondition without one, are left out.
    ///
    /// # Errors
    /// As [`Grounding::new`].
    pub fn with_vocabulary(problem: &Problem, vocabulary: &dyn Vocabulary) -> Result<Self, PlanError> {
        let mut g = Self::new(problem)?;
        let mut atom_leaf = HashMap::new();
        let mut by_leaf: HashMap<Leaf, Target> = HashMap::new();
        for atom in 0..g.keys.len() as AtomId {
            if let Some(leaf) = vocabulary.condition(problem, &g.atom(atom)) {
                atom_leaf.insert(atom, leaf);
                by_leaf.insert(leaf, Target::Condition(atom));
            }
        }
        let mut keep = Vec::new();
        let mut action_leaf = Vec::new();
        for a in std::mem::take(&mut g.actions) {
            let Some(leaf) = vocabulary.action(problem, a.template, &a.args) else { continue };
            let conds = a.pre.iter().chain(a.cond.iter().flat_map(|c| c.when.iter()));
            if conds.clone().any(|l| !atom_leaf.contains_key(&l.atom)) {
                continue;
            }
            let id = keep.len() as ActionId;
            match by_leaf.entry(leaf).or_insert_with(|| Target::Actions(Vec::new())) {
                Target::Actions(v) => v.push(id),
                Target::Condition(_) => continue,
            }
            action_leaf.push(leaf);
            keep.push(a);
        }
        g.actions = keep;
        g.action_index.clear();
        g.leaves = Leaves::Table { atom_leaf, action_leaf, by_leaf };
        g.index();
        Ok(g)
    }

    /// Rebuilds the achiever index after `actions` changed.
    fn index(&mut self) {
        self.achievers = vec![Vec::new(); self.keys.len() * 2];
        for (i, a) in self.actions.iter().enumerate() {
            let mut lits: Vec<Lit> = a.may_effects().collect();
            lits.sort_unstable();
            lits.dedup();
            for l in lits {
                if let Some(v) = self.achievers.get_mut(l.index()) {
                    v.push(i as ActionId);
                }
            }
        }
    }

    /// The problem.
    #[must_use]
    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    /// Number of ground atoms (ids run from 0).
    #[must_use]
    pub fn atom_count(&self) -> usize {
        self.keys.len()
    }

    /// The ground actions.
    #[must_use]
    pub fn actions(&self) -> &[GroundAction] {
        &self.actions
    }

    /// Ground action `id`.
    #[must_use]
    pub fn action(&self, id: ActionId) -> Option<&GroundAction> {
        self.actions.get(id as usize)
    }

    /// The initial state.
    #[must_use]
    pub fn init(&self) -> &State {
        &self.init
    }

    /// The goal conditions, in order.
    #[must_use]
    pub fn goal(&self) -> &[Lit] {
        &self.goal
    }

    /// Whether every goal condition holds in `state`.
    #[must_use]
    pub fn goal_holds(&self, state: &State) -> bool {
        self.goal.iter().all(|l| l.holds(state))
    }

    /// Whether plan cost is the number of actions (no action costs, or no metric).
    #[must_use]
    pub fn unit_cost(&self) -> bool {
        self.unit_cost
    }

    /// The cost of a sequence of actions.
    #[must_use]
    pub fn cost_of(&self, plan: &[ActionId]) -> u64 {
        plan.iter().map(|&a| self.action(a).map_or(0, |x| u64::from(x.cost))).sum()
    }

    /// Whether the atom's predicate is static (no action changes it).
    #[must_use]
    pub fn is_static(&self, atom: AtomId) -> bool {
        self.atom_predicate(atom).is_some_and(|p| self.is_static_predicate(p))
    }

    /// Whether no action changes the predicate's atoms.
    #[must_use]
    pub fn is_static_predicate(&self, predicate: PredicateId) -> bool {
        self.statics.get(usize::from(predicate)).copied().unwrap_or(false)
    }

    /// The actions that make `lit` true (unconditionally or under a condition), in
    /// template then grounding order.
    #[must_use]
    pub fn achievers(&self, lit: Lit) -> &[ActionId] {
        self.achievers.get(lit.index()).map_or(&[], Vec::as_slice)
    }

    /// The id of `predicate(args)`, if that atom exists (in the initial state, made
    /// true by some reachable action, or named by the goal).
    #[must_use]
    pub fn atom_id(&self, predicate: PredicateId, args: &[ObjectId]) -> Option<AtomId> {
        with_key(predicate, args, |key| self.atom_index.get(key).copied())
    }

    /// The atom `name(objects...)` by names.
    #[must_use]
    pub fn atom_by_name(&self, predicate: &str, objects: &[&str]) -> Option<AtomId> {
        let p = self.problem.domain.predicate(predicate)?;
        let args: Option<Vec<ObjectId>> = objects.iter().map(|o| self.problem.object(o)).collect();
        self.atom_id(p, &args?)
    }

    fn atom_predicate(&self, atom: AtomId) -> Option<PredicateId> {
        self.keys.get(atom as usize).and_then(|k| k.first().copied())
    }

    /// The predicate and objects of an atom.
    #[must_use]
    pub fn atom(&self, atom: AtomId) -> Atom<ObjectId> {
        match self.keys.get(atom as usize) {
            Some(k) => Atom { predicate: k[0], args: k[1..].to_vec() },
            None => Atom { predicate: 0, args: Vec::new() },
        }
    }

    /// The objects of an atom, without copying.
    #[must_use]
    pub fn atom_args(&self, atom: AtomId) -> &[ObjectId] {
        self.keys.get(atom as usize).map_or(&[], |k| &k[1..])
    }

    /// `name(obj, ...)` of an atom.
    #[must_use]
    pub fn atom_name(&self, atom: AtomId) -> String {
        self.problem.atom_name(&self.atom(atom))
    }

    /// `name(obj, ...)` of a literal, with `not ` for negative ones.
    #[must_use]
    pub fn lit_name(&self, lit: Lit) -> String {
        let n = self.atom_name(lit.atom);
        if lit.positive { n } else { format!("not {n}") }
    }

    /// `name(obj, ...)` of a ground action.
    #[must_use]
    pub fn action_name(&self, id: ActionId) -> String {
        let Some(a) = self.action(id) else { return "?".into() };
        let name = self.problem.domain.actions.get(usize::from(a.template)).map_or("?", |t| t.name.as_str());
        self.problem.call_name(name, &a.args)
    }

    /// `(name obj ...)` of a ground action, as plan files write it.
    #[must_use]
    pub fn action_pddl(&self, id: ActionId) -> String {
        let Some(a) = self.action(id) else { return "()".into() };
        let mut s = String::from("(");
        s.push_str(self.problem.domain.actions.get(usize::from(a.template)).map_or("?", |t| t.name.as_str()));
        for &o in &a.args {
            s.push(' ');
            s.push_str(self.problem.objects.get(usize::from(o)).map_or("?", |x| x.name.as_str()));
        }
        s.push(')');
        s
    }

    /// The behavior id and argument values of an atom's condition leaf under the PDDL
    /// contract (`None` under a custom vocabulary).
    #[must_use]
    pub fn condition_call(&self, atom: AtomId) -> Option<(u16, &[u16])> {
        match &self.leaves {
            Leaves::Pddl => self.keys.get(atom as usize).map(|k| (k[0], &k[1..])),
            Leaves::Table { .. } => None,
        }
    }

    /// The behavior id and argument values of a ground action's leaf under the PDDL
    /// contract (`None` under a custom vocabulary).
    #[must_use]
    pub fn action_call(&self, id: ActionId) -> Option<(u16, &[u16])> {
        match &self.leaves {
            Leaves::Pddl => {
                let a = self.action(id)?;
                let behavior = (self.problem.domain.predicates.len() as u16).checked_add(a.template)?;
                Some((behavior, &a.args))
            }
            Leaves::Table { .. } => None,
        }
    }

    /// The condition leaf of an atom (`None` when it has more arguments than a leaf
    /// carries inline, or none under the vocabulary).
    #[must_use]
    pub fn condition_leaf(&self, atom: AtomId) -> Option<Leaf> {
        match &self.leaves {
            Leaves::Pddl => {
                let (b, args) = self.condition_call(atom)?;
                Leaf::with_args(b, args).ok()
            }
            Leaves::Table { atom_leaf, .. } => atom_leaf.get(&atom).copied(),
        }
    }

    /// The action leaf of a ground action.
    #[must_use]
    pub fn action_leaf(&self, id: ActionId) -> Option<Leaf> {
        match &self.leaves {
            Leaves::Pddl => {
                let (b, args) = self.action_call(id)?;
                Leaf::with_args(b, args).ok()
            }
            Leaves::Table { action_leaf, .. } => action_leaf.get(id as usize).copied(),
        }
    }

    /// The atom a condition leaf checks, given its argument values.
    #[must_use]
    pub fn leaf_atom_of(&self, leaf: &Leaf, args: &[u16]) -> Option<AtomId> {
        match &self.leaves {
            Leaves::Pddl => self.atom_id(leaf.behavior(), args),
            Leaves::Table { by_leaf, .. } => match by_leaf.get(leaf)? {
                Target::Condition(a) => Some(*a),
                Target::Actions(_) => None,
            },
        }
    }

    /// The atom a condition leaf checks.
    #[must_use]
    pub fn leaf_atom(&self, leaf: &Leaf) -> Option<AtomId> {
        self.leaf_atom_of(leaf, leaf.args())
    }

    /// The ground actions an action leaf with these argument values may stand for:
    /// under the PDDL contract the alternatives of one grounding (one for a STRIPS
    /// action); under a vocabulary every grounding named by that leaf (e.g. `place at
    /// P!` for each brick). A world runs the first applicable one.
    pub fn leaf_actions_of(&self, leaf: &Leaf, args: &[u16], out: &mut Vec<ActionId>) {
        out.clear();
        match &self.leaves {
            Leaves::Pddl => {
                let Some(t) = leaf.behavior().checked_sub(self.problem.domain.predicates.len() as u16) else { return };
                if let Some(v) = with_key(t, args, |key| self.action_index.get(key)) {
                    out.extend_from_slice(v);
                }
            }
            Leaves::Table { by_leaf, .. } => {
                if let Some(Target::Actions(v)) = by_leaf.get(leaf) {
                    out.extend_from_slice(v);
                }
            }
        }
    }

    /// [`Grounding::leaf_actions_of`] with the leaf's inline arguments.
    pub fn leaf_actions(&self, leaf: &Leaf, out: &mut Vec<ActionId>) {
        self.leaf_actions_of(leaf, leaf.args(), out);
    }
}
