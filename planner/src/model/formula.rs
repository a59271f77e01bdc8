//! Formulas of action templates and goals: terms, conditions in negation normal form,
//! effects and costs.

use super::{FunctionId, Literal, ObjectId, TypeId};

/// An argument of an atom in a template or a goal: a variable or an object.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Term {
    /// Variable `i` of the action (its parameters first, then quantified variables),
    /// or of the goal's quantifiers.
    Var(u8),
    /// An object: a domain constant in templates, any object in goals.
    Object(ObjectId),
}

/// A quantified variable: its index and type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Var {
    /// Its index ([`Term::Var`]).
    pub index: u8,
    /// Its type.
    pub ty: TypeId,
}

/// A condition in negation normal form: negation only on literals and equalities.
///
/// The reader and the builders keep nesting bounded (PDDL lists nest at most
/// [`crate::pddl::MAX_DEPTH`] levels), so code that walks a condition recursively
/// stays within a small stack.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Condition {
    /// An atom or its negation.
    Literal(Literal<Term>),
    /// `(= a b)`, or `(not (= a b))` when `positive` is false.
    Equal {
        /// False for the inequality.
        positive: bool,
        /// Left term.
        left: Term,
        /// Right term.
        right: Term,
    },
    /// All of them (`(and)` is true).
    And(Vec<Condition>),
    /// One of them (`(or)` is false).
    Or(Vec<Condition>),
    /// The body holds for every object of the variables' types.
    Forall(Vec<Var>, Box<Condition>),
    /// The body holds for some object of the variables' types.
    Exists(Vec<Var>, Box<Condition>),
}

impl Condition {
    /// The literal, if this is one.
    #[must_use]
    pub fn as_literal(&self) -> Option<&Literal<Term>> {
        match self {
            Self::Literal(l) => Some(l),
            _ => None,
        }
    }

    /// Whether this condition is a plain conjunction of literals (STRIPS).
    #[must_use]
    pub fn is_strips(&self) -> bool {
        match self {
            Self::Literal(_) => true,
            Self::And(parts) => parts.iter().all(Self::is_strips),
            _ => false,
        }
    }

    /// Calls `f` on every literal inside, in the order written.
    pub fn for_each_literal(&self, f: &mut impl FnMut(&Literal<Term>)) {
        let mut stack = vec![self];
        while let Some(c) = stack.pop() {
            match c {
                Self::Literal(l) => f(l),
                Self::Equal { .. } => {}
                Self::And(v) | Self::Or(v) => stack.extend(v.iter().rev()),
                Self::Forall(_, b) | Self::Exists(_, b) => stack.push(b),
            }
        }
    }
}

/// One postcondition: `literal`, for every binding of `forall` under which every
/// condition of `when` holds (in the state before the action).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Effect {
    /// Universally quantified variables (empty for a plain effect).
    pub forall: Vec<Var>,
    /// The effect's condition, a conjunction (empty: unconditional).
    pub when: Vec<Condition>,
    /// The literal made true.
    pub literal: Literal<Term>,
}

/// One part of an action's cost: a number, or a function's value for the arguments.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum CostTerm {
    /// A constant.
    Constant(u32),
    /// `(f args...)`, valued in the problem's `:init`.
    Function {
        /// The function.
        function: FunctionId,
        /// Its arguments.
        args: Vec<Term>,
    },
}

/// `(= (f args...) value)` in a problem's `:init`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct FunctionValue {
    /// The function.
    pub function: FunctionId,
    /// Its arguments.
    pub args: Vec<ObjectId>,
    /// Its value.
    pub value: u32,
}
