//! The planning model of seed 000: typed objects, predicates, action templates with
//! positive and negative pre- and postconditions (Table I of the paper), and problems
//! with an initial state and goal conditions.
//!
//! Built in Rust with [`DomainBuilder`] and [`ProblemBuilder`], or read from PDDL with
//! [`crate::pddl`]; both check the same rules and report a [`ModelError`].
//!
//! Names are case-insensitive, as in PDDL: they are stored in lower case.

pub(crate) mod builder;
mod error;

pub use builder::{ActionBuilder, DomainBuilder, ProblemBuilder};
pub use error::ModelError;

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

/// A declared type.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TypeDef {
    /// Its name.
    pub name: String,
    /// Its parent type (`None` only for `object`).
    pub parent: Option<TypeId>,
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

/// An action template: typed parameters, preconditions and postconditions (effects),
/// each a list of literals in the order written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ActionTemplate {
    /// Its name.
    pub name: String,
    /// Its parameters.
    pub params: Vec<Param>,
    /// Preconditions over parameter indices.
    pub pre: Vec<Literal<u8>>,
    /// Postconditions over parameter indices: positive literals are added, negative
    /// ones deleted (an atom both added and deleted ends up true, as in PDDL).
    pub effects: Vec<Literal<u8>>,
}

/// Types, predicates and action templates, in declaration order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Domain {
    /// Its name.
    pub name: String,
    /// Types; `types[0]` is `object`.
    pub types: Vec<TypeDef>,
    /// Predicates, in declaration order (their bt-core behavior ids).
    pub predicates: Vec<Predicate>,
    /// Action templates, in declaration order (behavior ids after the predicates).
    pub actions: Vec<ActionTemplate>,
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
    /// Objects, in declaration order (their index is a leaf argument).
    pub objects: Vec<Object>,
    /// Atoms true in the initial state; every other atom is false.
    pub init: Vec<Atom<ObjectId>>,
    /// Goal conditions, in order.
    pub goal: Vec<Literal<ObjectId>>,
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

    /// True when `ty` is `of` or descends from it.
    #[must_use]
    pub fn is_subtype(&self, mut ty: TypeId, of: TypeId) -> bool {
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

    /// The predicates no action changes: their truth is fixed by the initial state.
    #[must_use]
    pub fn static_predicates(&self) -> Vec<bool> {
        let mut fixed = vec![true; self.predicates.len()];
        for a in &self.actions {
            for e in &a.effects {
                if let Some(f) = fixed.get_mut(usize::from(e.atom.predicate)) {
                    *f = false;
                }
            }
        }
        fixed
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
