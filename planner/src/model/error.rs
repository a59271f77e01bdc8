//! What can be wrong with a domain or a problem, wherever it came from.

/// A domain or problem that breaks a rule of the model. PDDL input wraps it with the
/// file, line and column ([`crate::pddl::PddlError`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// A type that was not declared.
    #[error("undefined type `{name}`")]
    UnknownType {
        /// The name used.
        name: String,
    },
    /// A type declared twice, or a parent chain that loops.
    #[error("type `{name}` declared twice or in a cycle")]
    DuplicateType {
        /// The name.
        name: String,
    },
    /// A predicate that was not declared.
    #[error("unknown predicate `{name}` (declared: {declared})")]
    UnknownPredicate {
        /// The name used.
        name: String,
        /// The declared predicates, comma separated.
        declared: String,
    },
    /// A predicate declared twice.
    #[error("predicate `{name}` declared twice")]
    DuplicatePredicate {
        /// The name.
        name: String,
    },
    /// An action template declared twice.
    #[error("action `{name}` declared twice")]
    DuplicateAction {
        /// The name.
        name: String,
    },
    /// A parameter name used twice in one list.
    #[error("parameter `?{name}` declared twice")]
    DuplicateParameter {
        /// The name.
        name: String,
    },
    /// An object declared twice.
    #[error("object `{name}` declared twice")]
    DuplicateObject {
        /// The name.
        name: String,
    },
    /// A predicate applied to the wrong number of arguments.
    #[error("`{predicate}` takes {}, given {found}", crate::wording::count(*.expected, "argument"))]
    WrongArity {
        /// The predicate.
        predicate: String,
        /// Its parameter count.
        expected: usize,
        /// Arguments given.
        found: usize,
    },
    /// A `?variable` that is not a parameter of the action.
    #[error("`?{name}` is not a parameter of action `{action}`")]
    UnknownParameter {
        /// The variable.
        name: String,
        /// The action.
        action: String,
    },
    /// An object that the problem does not declare.
    #[error("undeclared object `{name}`")]
    UnknownObject {
        /// The name used.
        name: String,
    },
    /// An argument whose type does not fit the predicate's parameter.
    #[error("argument {position} of `{predicate}` must be a `{expected}`, `{argument}` is a `{found}`")]
    TypeMismatch {
        /// The predicate.
        predicate: String,
        /// 1-based argument position.
        position: usize,
        /// The argument (object or `?parameter`).
        argument: String,
        /// The type the predicate wants.
        expected: String,
        /// The argument's type.
        found: String,
    },
    /// An action without postconditions: it could never achieve anything.
    #[error("action `{action}` has no effects")]
    NoEffects {
        /// The action.
        action: String,
    },
    /// A problem with no goal conditions.
    #[error("the goal is empty")]
    EmptyGoal,
    /// An initial-state atom written negated: the initial state lists true atoms only.
    #[error("the initial state lists true atoms only; `(not ...)` is not allowed there")]
    NegativeInit,
    /// A problem for another domain.
    #[error("the problem is for domain `{problem}`, the domain given is `{domain}`")]
    DomainMismatch {
        /// What the problem names.
        problem: String,
        /// The domain's name.
        domain: String,
    },
    /// A name that is not a PDDL name (letters, digits, `-` and `_`, starting with a
    /// letter or digit; a `?` only at the start of a variable).
    #[error("`{name}` is not a valid name (letters, digits, `-`, `_`, starting with a letter or digit)")]
    BadName {
        /// The name.
        name: String,
    },
    /// A word PDDL reserves (`and`, `not`, `forall`, ...) used as a name.
    #[error("`{name}` is a reserved word of PDDL and cannot name {what}")]
    ReservedName {
        /// The name.
        name: String,
        /// What it was to name.
        what: &'static str,
    },
    /// A function that was not declared in `:functions`.
    #[error("unknown function `{name}`")]
    UnknownFunction {
        /// The name used.
        name: String,
    },
    /// A function declared twice, or two values for one function term.
    #[error("function `{name}` declared or valued twice")]
    DuplicateFunction {
        /// The name.
        name: String,
    },
    /// An argument whose type cannot be the parameter's (the types share no object).
    #[error("`{argument}` is a `{found}`, which can never be a `{expected}` ({what})")]
    Incompatible {
        /// The argument.
        argument: String,
        /// Its type.
        found: String,
        /// The type wanted.
        expected: String,
        /// Where: the function or equality.
        what: String,
    },
    /// More variables in one action than the model numbers (255).
    #[error("action `{action}` has more than 255 parameters and quantified variables")]
    TooManyVariables {
        /// The action.
        action: String,
    },
    /// Too many declarations for 16-bit ids.
    #[error("too many {what} (at most {max})")]
    TooMany {
        /// What.
        what: &'static str,
        /// The limit.
        max: usize,
    },
    /// An action that changes a derived predicate: derived atoms follow from the
    /// rules alone.
    #[error("action `{action}` changes `{predicate}`, a derived predicate (only its `:derived` rules make it true)")]
    DerivedChanged {
        /// The action.
        action: String,
        /// The derived predicate.
        predicate: String,
    },
    /// Derived predicates that depend on their own negation: the rules cannot be
    /// stratified.
    #[error(
        "the rules of derived predicate `{predicate}` depend on its own negation (through `{through}`): \
         derived predicates must be stratifiable"
    )]
    NotStratifiable {
        /// The derived predicate whose rule closes the cycle.
        predicate: String,
        /// The derived predicate negated on the cycle.
        through: String,
    },
}
