//! Grounding — the paper's action refinement over a finite set of typed objects.
//!
//! Every predicate is instantiated over the objects of its parameter types, giving
//! dense atom ids, and every action template over the objects of its parameters.
//! Predicates that no action changes are *static*: a grounding whose static
//! preconditions are false in the initial state can never run and is pruned, and
//! static preconditions that are true are left out of the grounded action (and so out
//! of every tree). Each grounding keeps its non-static preconditions in the order
//! written, its add and delete lists, and is indexed by the literals it achieves.
//!
//! A grounding also knows the bt-core leaves of its atoms and actions: by default the
//! PDDL contract (behavior ids are the predicates in declaration order, then the
//! actions; leaf arguments are object indices), or a custom [`Vocabulary`] (the brick
//! tasks), in which case actions and conditions without a leaf are dropped.

use std::collections::HashMap;

use bt_core::{Leaf, MAX_ARGS};

use crate::PlanError;
use crate::model::{Atom, ObjectId, PredicateId, Problem, TemplateId, TypeId};
use crate::state::State;

/// Index of a ground atom.
pub type AtomId = u32;
/// Index of a ground action in [`Grounding::actions`].
pub type ActionId = u32;

const NONE: u32 = u32::MAX;
/// Most atoms, and most candidate groundings of one template.
pub const MAX_GROUND: u64 = 1 << 24;

/// A ground literal: an atom that must hold (`positive`) or must not.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Lit {
    /// The atom.
    pub atom: AtomId,
    /// True for the atom, false for its negation.
    pub positive: bool,
}

impl Lit {
    /// The literal's index among all literals: `2 * atom + positive`.
    #[must_use]
    pub fn index(self) -> usize {
        self.atom as usize * 2 + usize::from(self.positive)
    }

    /// The opposite literal.
    #[must_use]
    pub fn negated(self) -> Self {
        Self { atom: self.atom, positive: !self.positive }
    }
}

/// A grounded action.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GroundAction {
    /// Its template.
    pub template: TemplateId,
    /// The objects bound to the template's parameters.
    pub args: Vec<ObjectId>,
    /// Non-static preconditions, in the order written.
    pub pre: Vec<Lit>,
    /// Atoms it makes true.
    pub add: Vec<AtomId>,
    /// Atoms it makes false (never also in `add`).
    pub del: Vec<AtomId>,
}

impl GroundAction {
    /// Whether its preconditions hold in `state`.
    #[must_use]
    pub fn applicable(&self, state: &State) -> bool {
        self.pre.iter().all(|l| state.holds(l.atom) == l.positive)
    }

    /// Applies its effects to `state`.
    pub fn apply(&self, state: &mut State) {
        for &d in &self.del {
            state.set(d, false);
        }
        for &a in &self.add {
            state.set(a, true);
        }
    }

    /// Whether it makes `lit` true.
    #[must_use]
    pub fn achieves(&self, lit: Lit) -> bool {
        if lit.positive { self.add.contains(&lit.atom) } else { self.del.contains(&lit.atom) }
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

/// One parameter dimension of the dense atom or action space.
#[derive(Clone, Debug)]
struct Dim {
    ty: TypeId,
    count: u32,
    stride: u32,
}

/// A problem grounded into atoms and actions, with their bt-core leaves.
#[derive(Clone, Debug)]
pub struct Grounding {
    problem: Problem,
    statics: Vec<bool>,
    /// Per type: position of each object among the objects of that type, or NONE.
    type_pos: Vec<Vec<u32>>,
    type_objects: Vec<Vec<ObjectId>>,
    pred_base: Vec<u32>,
    pred_dims: Vec<Vec<Dim>>,
    atoms: u32,
    init: State,
    actions: Vec<GroundAction>,
    /// Dense index of (template, args) → ActionId or NONE.
    template_base: Vec<u32>,
    template_dims: Vec<Vec<Dim>>,
    dense_action: Vec<u32>,
    /// Per literal index: the actions achieving it, in template then grounding order.
    achievers: Vec<Vec<ActionId>>,
    goal: Vec<Lit>,
    leaves: Leaves,
}

fn dims(
    problem: &Problem,
    types: impl Iterator<Item = TypeId>,
    type_objects: &[Vec<ObjectId>],
) -> Result<(Vec<Dim>, u64), PlanError> {
    let mut dims: Vec<Dim> = types
        .map(|ty| Dim { ty, count: type_objects.get(usize::from(ty)).map_or(0, |v| v.len() as u32), stride: 1 })
        .collect();
    let mut size: u64 = 1;
    for d in dims.iter_mut().rev() {
        d.stride = size.min(u64::from(u32::MAX)) as u32;
        size = size.saturating_mul(u64::from(d.count));
        if size > MAX_GROUND {
            return Err(PlanError::TooLarge {
                what: "groundings of one predicate or action",
                count: size,
                limit: MAX_GROUND,
            });
        }
    }
    let _ = problem;
    Ok((dims, size))
}

impl Grounding {
    /// Grounds `problem` with the PDDL leaf contract.
    ///
    /// # Errors
    /// [`PlanError::TooManyArgs`] for a predicate or action with more than
    /// `bt_core::MAX_ARGS` parameters; [`PlanError::TooLarge`].
    pub fn new(problem: &Problem) -> Result<Self, PlanError> {
        let d = &problem.domain;
        let arities = d.predicates.iter().map(|p| (&p.name, p.params.len()));
        for (name, arity) in arities.chain(d.actions.iter().map(|a| (&a.name, a.params.len()))) {
            if arity > MAX_ARGS {
                return Err(PlanError::TooManyArgs { name: name.clone(), arity, max: MAX_ARGS });
            }
        }
        Self::build(problem, Leaves::Pddl)
    }

    /// Grounds `problem` with the leaves of `vocabulary`; actions without a leaf, or
    /// with a precondition without one, are left out.
    ///
    /// # Errors
    /// [`PlanError::TooLarge`].
    pub fn with_vocabulary(problem: &Problem, vocabulary: &dyn Vocabulary) -> Result<Self, PlanError> {
        let mut g = Self::build(problem, Leaves::Pddl)?;
        let mut atom_leaf = HashMap::new();
        let mut by_leaf: HashMap<Leaf, Target> = HashMap::new();
        for atom in 0..g.atoms {
            if let Some(leaf) = vocabulary.condition(problem, &g.atom(atom)) {
                atom_leaf.insert(atom, leaf);
                by_leaf.insert(leaf, Target::Condition(atom));
            }
        }
        let mut keep = Vec::new();
        let mut action_leaf = Vec::new();
        for a in std::mem::take(&mut g.actions) {
            let Some(leaf) = vocabulary.action(problem, a.template, &a.args) else { continue };
            if a.pre.iter().any(|l| !atom_leaf.contains_key(&l.atom)) {
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
        g.leaves = Leaves::Table { atom_leaf, action_leaf, by_leaf };
        g.index();
        Ok(g)
    }

    fn build(problem: &Problem, leaves: Leaves) -> Result<Self, PlanError> {
        let d = &problem.domain;
        let nt = d.types.len();
        let mut type_objects = vec![Vec::new(); nt];
        let mut type_pos = vec![vec![NONE; problem.objects.len()]; nt];
        for (o, obj) in problem.objects.iter().enumerate() {
            for ty in 0..nt {
                let ty = ty as TypeId;
                if d.is_subtype(obj.ty, ty) {
                    let list: &mut Vec<ObjectId> = &mut type_objects[usize::from(ty)];
                    type_pos[usize::from(ty)][o] = list.len() as u32;
                    list.push(o as ObjectId);
                }
            }
        }
        let mut pred_base = Vec::with_capacity(d.predicates.len());
        let mut pred_dims = Vec::with_capacity(d.predicates.len());
        let mut atoms: u64 = 0;
        for p in &d.predicates {
            let (dm, size) = dims(problem, p.params.iter().map(|p| p.ty), &type_objects)?;
            pred_base.push(atoms as u32);
            pred_dims.push(dm);
            atoms += size;
            if atoms > MAX_GROUND {
                return Err(PlanError::TooLarge { what: "ground atoms", count: atoms, limit: MAX_GROUND });
            }
        }
        let mut g = Self {
            problem: problem.clone(),
            statics: d.static_predicates(),
            type_pos,
            type_objects,
            pred_base,
            pred_dims,
            atoms: atoms as u32,
            init: State::new(atoms as usize),
            actions: Vec::new(),
            template_base: Vec::new(),
            template_dims: Vec::new(),
            dense_action: Vec::new(),
            achievers: Vec::new(),
            goal: Vec::new(),
            leaves,
        };
        for a in &problem.init {
            if let Some(id) = g.atom_id(a.predicate, &a.args) {
                g.init.set(id, true);
            }
        }
        g.goal = problem
            .goal
            .iter()
            .filter_map(|l| g.atom_id(l.atom.predicate, &l.atom.args).map(|atom| Lit { atom, positive: l.positive }))
            .collect();
        g.ground_actions()?;
        g.index();
        Ok(g)
    }

    fn ground_actions(&mut self) -> Result<(), PlanError> {
        let d = self.problem.domain.clone();
        let mut dense_len: u64 = 0;
        for (t, tpl) in d.actions.iter().enumerate() {
            let (dm, size) = dims(&self.problem, tpl.params.iter().map(|p| p.ty), &self.type_objects)?;
            self.template_base.push(dense_len as u32);
            dense_len += size;
            if dense_len > MAX_GROUND {
                return Err(PlanError::TooLarge {
                    what: "candidate ground actions",
                    count: dense_len,
                    limit: MAX_GROUND,
                });
            }
            let mut args = vec![0 as ObjectId; tpl.params.len()];
            'combos: for combo in 0..size {
                for (i, dim) in dm.iter().enumerate() {
                    let pos = (combo / u64::from(dim.stride)) % u64::from(dim.count.max(1));
                    args[i] = self.type_objects[usize::from(dim.ty)][pos as usize];
                }
                let ground = |l: &crate::model::Literal<u8>| -> Option<Lit> {
                    let objs: Vec<ObjectId> = l.atom.args.iter().map(|&p| args[usize::from(p)]).collect();
                    self.atom_id(l.atom.predicate, &objs).map(|atom| Lit { atom, positive: l.positive })
                };
                let mut pre = Vec::new();
                for l in &tpl.pre {
                    let Some(g) = ground(l) else {
                        self.dense_action.push(NONE);
                        continue 'combos;
                    };
                    if self.statics[usize::from(l.atom.predicate)] {
                        if self.init.holds(g.atom) != g.positive {
                            self.dense_action.push(NONE);
                            continue 'combos;
                        }
                    } else if !pre.contains(&g) {
                        pre.push(g);
                    }
                }
                let mut add = Vec::new();
                let mut del = Vec::new();
                for l in &tpl.effects {
                    let Some(g) = ground(l) else { continue };
                    let list = if g.positive { &mut add } else { &mut del };
                    if !list.contains(&g.atom) {
                        list.push(g.atom);
                    }
                }
                del.retain(|a| !add.contains(a));
                self.dense_action.push(self.actions.len() as u32);
                self.actions.push(GroundAction { template: t as TemplateId, args: args.clone(), pre, add, del });
            }
            self.template_dims.push(dm);
        }
        Ok(())
    }

    /// Rebuilds the achiever index and the dense action table after `actions` changed.
    fn index(&mut self) {
        self.achievers = vec![Vec::new(); self.atoms as usize * 2];
        for (i, a) in self.actions.iter().enumerate() {
            for &atom in &a.add {
                self.achievers[Lit { atom, positive: true }.index()].push(i as ActionId);
            }
            for &atom in &a.del {
                self.achievers[Lit { atom, positive: false }.index()].push(i as ActionId);
            }
        }
        if matches!(self.leaves, Leaves::Table { .. }) {
            self.dense_action.clear();
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
        self.atoms as usize
    }

    /// The ground actions that survived pruning.
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

    /// Whether the atom's predicate is static (no action changes it).
    #[must_use]
    pub fn is_static(&self, atom: AtomId) -> bool {
        self.atom_predicate(atom).is_some_and(|p| self.statics.get(usize::from(p)).copied().unwrap_or(false))
    }

    /// The actions that make `lit` true, in template then grounding order.
    #[must_use]
    pub fn achievers(&self, lit: Lit) -> &[ActionId] {
        self.achievers.get(lit.index()).map_or(&[], Vec::as_slice)
    }

    /// The id of `predicate(args)`, if the arguments fit the parameter types.
    #[must_use]
    pub fn atom_id(&self, predicate: PredicateId, args: &[ObjectId]) -> Option<AtomId> {
        let dims = self.pred_dims.get(usize::from(predicate))?;
        if dims.len() != args.len() {
            return None;
        }
        let mut id = *self.pred_base.get(usize::from(predicate))?;
        for (d, &o) in dims.iter().zip(args) {
            let pos = *self.type_pos.get(usize::from(d.ty))?.get(usize::from(o))?;
            if pos == NONE {
                return None;
            }
            id += pos * d.stride;
        }
        Some(id)
    }

    /// The atom `name(objects...)` by names.
    #[must_use]
    pub fn atom_by_name(&self, predicate: &str, objects: &[&str]) -> Option<AtomId> {
        let p = self.problem.domain.predicate(predicate)?;
        let args: Option<Vec<ObjectId>> = objects.iter().map(|o| self.problem.object(o)).collect();
        self.atom_id(p, &args?)
    }

    fn atom_predicate(&self, atom: AtomId) -> Option<PredicateId> {
        if atom >= self.atoms {
            return None;
        }
        // Predicates without groundings share their base with the next one; the last
        // predicate whose base is at most `atom` is the one it belongs to.
        let p = self.pred_base.partition_point(|&b| b <= atom).checked_sub(1)?;
        Some(p as PredicateId)
    }

    /// The predicate and objects of an atom.
    #[must_use]
    pub fn atom(&self, atom: AtomId) -> Atom<ObjectId> {
        let Some(p) = self.atom_predicate(atom) else {
            return Atom { predicate: 0, args: Vec::new() };
        };
        let rem = atom - self.pred_base[usize::from(p)];
        let args = self.pred_dims[usize::from(p)]
            .iter()
            .map(|d| self.type_objects[usize::from(d.ty)][((rem / d.stride) % d.count.max(1)) as usize])
            .collect();
        Atom { predicate: p, args }
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

    /// The condition leaf of an atom.
    #[must_use]
    pub fn condition_leaf(&self, atom: AtomId) -> Option<Leaf> {
        match &self.leaves {
            Leaves::Pddl => {
                let a = self.atom(atom);
                Leaf::with_args(a.predicate, &a.args).ok()
            }
            Leaves::Table { atom_leaf, .. } => atom_leaf.get(&atom).copied(),
        }
    }

    /// The action leaf of a ground action.
    #[must_use]
    pub fn action_leaf(&self, id: ActionId) -> Option<Leaf> {
        match &self.leaves {
            Leaves::Pddl => {
                let a = self.action(id)?;
                let behavior = (self.problem.domain.predicates.len() as u16).checked_add(a.template)?;
                Leaf::with_args(behavior, &a.args).ok()
            }
            Leaves::Table { action_leaf, .. } => action_leaf.get(id as usize).copied(),
        }
    }

    /// The atom a condition leaf checks.
    #[must_use]
    pub fn leaf_atom(&self, leaf: &Leaf) -> Option<AtomId> {
        match &self.leaves {
            Leaves::Pddl => self.atom_id(leaf.behavior(), leaf.args()),
            Leaves::Table { by_leaf, .. } => match by_leaf.get(leaf)? {
                Target::Condition(a) => Some(*a),
                Target::Actions(_) => None,
            },
        }
    }

    /// The ground actions an action leaf may stand for: one under the PDDL contract;
    /// under a vocabulary, every grounding named by that leaf (e.g. `place at P!` for
    /// each brick), of which a world runs the first applicable one.
    pub fn leaf_actions(&self, leaf: &Leaf, out: &mut Vec<ActionId>) {
        out.clear();
        match &self.leaves {
            Leaves::Pddl => {
                let Some(t) = leaf.behavior().checked_sub(self.problem.domain.predicates.len() as u16) else { return };
                let (Some(dims), Some(&base)) =
                    (self.template_dims.get(usize::from(t)), self.template_base.get(usize::from(t)))
                else {
                    return;
                };
                if dims.len() != leaf.argc() {
                    return;
                }
                let mut idx = base;
                for (d, &o) in dims.iter().zip(leaf.args()) {
                    let Some(&pos) = self.type_pos.get(usize::from(d.ty)).and_then(|v| v.get(usize::from(o))) else {
                        return;
                    };
                    if pos == NONE {
                        return;
                    }
                    idx += pos * d.stride;
                }
                if let Some(&a) = self.dense_action.get(idx as usize)
                    && a != NONE
                {
                    out.push(a);
                }
            }
            Leaves::Table { by_leaf, .. } => {
                if let Some(Target::Actions(v)) = by_leaf.get(leaf) {
                    out.extend_from_slice(v);
                }
            }
        }
    }
}
