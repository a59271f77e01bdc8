//! The planning model of Colledanchise et al. 2019: typed objects, predicates, action templates with
//! pre- and postconditions (Table I of the paper), and problems with an initial state
//! and goal conditions.
//!
//! Conditions are formulas in negation normal form ([`Condition`]): literals,
//! equalities, conjunctions, and the ADL constructs PDDL domains use (`or`, `forall`,
//! `exists`); effects are literals, possibly under `forall` and `when` ([`Effect`]);
//! actions may have a cost (`increase (total-cost) ...`). Grounding
//! ([`crate::ground`]) compiles the ADL constructs away.
//!
//! Built in Rust with [`DomainBuilder`] and [`ProblemBuilder`], or read from PDDL with
//! [`crate::pddl`]; both check the same rules and report a [`ModelError`].
//!
//! Names are case-insensitive, as in PDDL: they are stored in lower case.

pub(crate) mod builder;
mod derived;
mod error;
mod formula;

pub use builder::{ActionBuilder, DomainBuilder, ProblemBuilder};
pub use error::ModelError;
pub use formula::{Condition, CostTerm, Effect, FunctionValue, Term, Var};

/// Index of a type in [`Domain::types`]; type 0 is `object`, the root of every type.
pub type TypeId = u16;
/// Index of a predicate in [`Domain::predicates`].
pub type PredicateId = u16;
/// Index of an action template in [`Domain::actions`].
pub type TemplateId = u16;
/// Index of an object in [`Problem::objects`] — a leaf argument in a bt-core tree.
pub type ObjectId = u16;

/// The root type every other type descends from.
pub const OBJECT: TypeId = 0;

/// Index of a function (`:functions`) in [`Domain::functions`].
pub type FunctionId = u16;

/// A declared type, or a union `(either a b)` made for a parameter.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TypeDef {
    /// Its name (`(either a b)` for a union).
    pub name: String,
    /// Its parent type (`None` for `object` and for unions).
    pub parent: Option<TypeId>,
    /// For a union: the types it joins (an object of any of them belongs to it).
    pub either: Vec<TypeId>,
}

/// A typed parameter of a predicate or an action template.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Param {
    /// Its name, without the leading `?`.
    pub name: String,
    /// Its type.
    pub ty: TypeId,
}

/// A predicate: a condition over typed arguments.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Predicate {
    /// Its name.
    pub name: String,
    /// Its parameters.
    pub params: Vec<Param>,
}

/// A predicate applied to arguments: parameter indices (`u8`) in templates, objects
/// ([`ObjectId`]) in problems.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Atom<T> {
    /// The predicate.
    pub predicate: PredicateId,
    /// Its arguments.
    pub args: Vec<T>,
}

/// An atom or its negation.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Literal<T> {
    /// False for `(not ...)`.
    pub positive: bool,
    /// The atom.
    pub atom: Atom<T>,
}

/// An action template: typed parameters, a precondition and postconditions (effects).
///
/// Variables ([`Term::Var`]) number the parameters first (`0..params.len()`), then the
/// variables of quantifiers (`forall`, `exists`) in the order they appear.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ActionTemplate {
    /// Its name.
    pub name: String,
    /// Its parameters.
    pub params: Vec<Param>,
    /// Every variable: the parameters, then the quantified ones; `vars[i]` is the type
    /// of variable `i`.
    pub vars: Vec<TypeId>,
    /// The precondition: a conjunction of its parts, in the order written.
    pub pre: Vec<Condition>,
    /// Postconditions: positive literals are added, negative ones deleted (an atom both
    /// added and deleted ends up true, as in PDDL).
    pub effects: Vec<Effect>,
    /// What one execution costs (`increase (total-cost) ...`); empty for cost 1.
    pub cost: Vec<CostTerm>,
}

/// A function of `:functions`: `total-cost`, or a static one giving action costs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Function {
    /// Its name.
    pub name: String,
    /// Its parameters.
    pub params: Vec<Param>,
}

/// Types, constants, predicates, functions and action templates, in declaration order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Domain {
    /// Its name.
    pub name: String,
    /// Types; `types[0]` is `object`.
    pub types: Vec<TypeDef>,
    /// Constants (`:constants`): objects every problem has, before its own.
    pub constants: Vec<Object>,
    /// Predicates, in declaration order (their bt-core behavior ids).
    pub predicates: Vec<Predicate>,
    /// Functions (`:functions`), used only for action costs.
    pub functions: Vec<Function>,
    /// Action templates, in declaration order (behavior ids after the predicates).
    pub actions: Vec<ActionTemplate>,
    /// The rules of derived predicates (`:derived`), in declaration order: each is a
    /// template named after its predicate, with the predicate's parameters, the rule's
    /// body as precondition and one effect, the head. No action changes a derived
    /// predicate; its atoms hold exactly when some rule derives them ([`crate::ground::Grounding::close`]).
    pub axioms: Vec<ActionTemplate>,
    /// The requirements the domain file declares (`:strips`, `:typing`, ...), lower
    /// case; a problem's constructs are checked against them and its own.
    pub requirements: Vec<String>,
}

/// A typed object of a problem.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Object {
    /// Its name.
    pub name: String,
    /// Its type.
    pub ty: TypeId,
}

/// A problem: its domain, objects, the atoms true initially and the goal conditions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Problem {
    /// Its name.
    pub name: String,
    /// The domain it is posed in.
    pub domain: Domain,
    /// Objects: the domain's constants, then the problem's own, in declaration order
    /// (their index is a leaf argument).
    pub objects: Vec<Object>,
    /// Atoms true in the initial state; every other atom is false.
    pub init: Vec<Atom<ObjectId>>,
    /// Values of the cost functions in the initial state (`(= (f a b) 3)`).
    pub functions: Vec<FunctionValue>,
    /// The goal: a conjunction of its parts, in order.
    pub goal: Vec<Condition>,
    /// Whether the problem asks to minimize `total-cost` (`:metric`); plan cost is then
    /// the sum of action costs, else the number of actions.
    pub metric: bool,
}

impl Domain {
    /// The predicate with this name.
    #[must_use]
    pub fn predicate(&self, name: &str) -> Option<PredicateId> {
        let name = name.to_ascii_lowercase();
        self.predicates.iter().position(|p| p.name == name).and_then(|i| PredicateId::try_from(i).ok())
    }

    /// The action template with this name.
    #[must_use]
    pub fn action(&self, name: &str) -> Option<TemplateId> {
        let name = name.to_ascii_lowercase();
        self.actions.iter().position(|a| a.name == name).and_then(|i| TemplateId::try_from(i).ok())
    }

    /// The type with this name.
    #[must_use]
    pub fn type_id(&self, name: &str) -> Option<TypeId> {
        let name = name.to_ascii_lowercase();
        self.types.iter().position(|t| t.name == name).and_then(|i| TypeId::try_from(i).ok())
    }

    /// True when every object of type `ty` is of type `of`: `ty` is `of` or descends
    /// from it (for unions: every member of `ty` does, or `ty` is a subtype of a member
    /// of `of`).
    #[must_use]
    pub fn is_subtype(&self, ty: TypeId, of: TypeId) -> bool {
        if let Some(t) = self.types.get(usize::from(ty))
            && !t.either.is_empty()
        {
            return t.either.iter().all(|&m| self.is_plain_subtype(m, of) || self.in_union(m, of));
        }
        self.is_plain_subtype(ty, of) || self.in_union(ty, of)
    }

    /// Whether `ty` (not a union) descends from a member of the union `of`.
    fn in_union(&self, ty: TypeId, of: TypeId) -> bool {
        self.types.get(usize::from(of)).is_some_and(|u| u.either.iter().any(|&m| self.is_plain_subtype(ty, m)))
    }

    /// Whether some object can be of both types (neither rules the other out).
    #[must_use]
    pub fn overlaps(&self, a: TypeId, b: TypeId) -> bool {
        let members = |t: TypeId| -> Vec<TypeId> {
            match self.types.get(usize::from(t)) {
                Some(d) if !d.either.is_empty() => d.either.clone(),
                _ => vec![t],
            }
        };
        members(a)
            .iter()
            .any(|&x| members(b).iter().any(|&y| self.is_plain_subtype(x, y) || self.is_plain_subtype(y, x)))
    }

    /// Whether an object whose declared type is `ty` (never a union) is of type `of`.
    #[must_use]
    pub fn object_is(&self, ty: TypeId, of: TypeId) -> bool {
        self.is_plain_subtype(ty, of) || self.in_union(ty, of)
    }

    /// True when `ty` is `of` or descends from it along parents.
    fn is_plain_subtype(&self, mut ty: TypeId, of: TypeId) -> bool {
        // Parents form a forest rooted at `object` (no cycles: the builder checks), so
        // this walk ends; the bound is a second guard.
        for _ in 0..=self.types.len() {
            if ty == of {
                return true;
            }
            match self.types.get(usize::from(ty)).and_then(|t| t.parent) {
                Some(p) => ty = p,
                None => return false,
            }
        }
        false
    }

    /// The predicates no action changes and no rule derives: their truth is fixed by
    /// the initial state.
    #[must_use]
    pub fn static_predicates(&self) -> Vec<bool> {
        let mut fixed = vec![true; self.predicates.len()];
        for a in self.actions.iter().chain(&self.axioms) {
            for e in &a.effects {
                if let Some(f) = fixed.get_mut(usize::from(e.literal.atom.predicate)) {
                    *f = false;
                }
            }
        }
        fixed
    }

    /// Whether any action has a cost other than 1.
    #[must_use]
    pub fn has_costs(&self) -> bool {
        self.actions.iter().any(|a| !a.cost.is_empty())
    }
}

impl Problem {
    /// The object with this name.
    #[must_use]
    pub fn object(&self, name: &str) -> Option<ObjectId> {
        let name = name.to_ascii_lowercase();
        self.objects.iter().position(|o| o.name == name).and_then(|i| ObjectId::try_from(i).ok())
    }

    /// `name(arg, ...)` of a ground atom, with object names.
    #[must_use]
    pub fn atom_name(&self, atom: &Atom<ObjectId>) -> String {
        let name = self.domain.predicates.get(usize::from(atom.predicate)).map_or("?", |p| p.name.as_str());
        self.call_name(name, &atom.args)
    }

    /// `name(arg, ...)` with object names (`name` alone without arguments).
    #[must_use]
    pub fn call_name(&self, name: &str, args: &[ObjectId]) -> String {
        if args.is_empty() {
            return name.to_string();
        }
        let args: Vec<&str> =
            args.iter().map(|&o| self.objects.get(usize::from(o)).map_or("?", |o| o.name.as_str())).collect();
        format!("{name}({})", args.join(", "))
    }
}
