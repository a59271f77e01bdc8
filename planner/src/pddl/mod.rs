//! PDDL input: domain and problem files of classical planning — STRIPS with typing,
//! negative preconditions, equality, constants, `either` types, action costs and the
//! ADL constructs (`or`, `imply`, `forall`, `exists`, `when`).
//!
//! A small reader of our own (no PDDL crate reports positions the way we need): a
//! tokenizer that builds the parenthesised structure without recursion and refuses
//! nesting deeper than [`MAX_DEPTH`], then an interpretation into the
//! [`model`](crate::model) with the same checks as the Rust builders. Every error names
//! the file, line and column and what was expected; no input makes it panic.
//!
//! Conditions are read into negation normal form (`not` pushed down to the literals);
//! grounding compiles the ADL constructs away ([`crate::ground`]). Action costs are
//! `(increase (total-cost) N)` or `(increase (total-cost) (f args...))` with static
//! functions valued in the problem's `:init`, and `(:metric minimize (total-cost))`.
//!
//! Derived predicates (`:derived (p ?x - t) CONDITION)`, the same conditions as
//! preconditions) are read as rules of the domain ([`crate::model::Domain::axioms`]);
//! an action that changes a derived predicate, or rules that depend on their own
//! negation (not stratifiable), are refused with the position of the action or rule.
//!
//! Refused, each by name with its position: numeric fluents other than action costs,
//! durative actions, timed initial literals, preferences and constraints.
//!
//! Accepted with a [`PddlWarning`], as other planners read them: a construct used
//! without its `:requirements` entry, a parameter repeated in a predicate declaration,
//! and an old `(:length ...)` section in a problem. A UTF-8 byte-order mark, any line
//! ending, `(aircraft?a)` without a space and names that start with a digit are simply
//! read.
//!
//! ```
//! let domain = planner::pddl::parse_domain("d.pddl", "(define (domain d) (:predicates (p)) \
//!     (:action a :parameters () :precondition () :effect (p)))")?;
//! let problem = planner::pddl::parse_problem("p.pddl", "(define (problem q) (:domain d) \
//!     (:init) (:goal (p)))", &domain)?;
//! assert_eq!(problem.goal.len(), 1);
//! let err = planner::pddl::parse_problem("p.pddl", "(define (problem q) (:domain d)\n(:goal (q)))", &domain)
//!     .unwrap_err();
//! assert_eq!(err.to_string(), "p.pddl:2:9: unknown predicate `q` (declared: p)");
//! # Ok::<(), planner::pddl::PddlError>(())
//! ```

mod read;
mod sexp;

pub use sexp::{MAX_BEHAVIORS, MAX_DEPTH, MAX_OBJECTS};

use crate::model::{Domain, ModelError, Problem};

/// A 1-based line and column (in characters).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Pos {
    /// Line, from 1.
    pub line: usize,
    /// Column, from 1.
    pub column: usize,
}

/// A PDDL file that could not be read, and where.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{file}:{}:{}: {kind}", pos.line, pos.column)]
pub struct PddlError {
    /// The file, as the caller named it.
    pub file: String,
    /// Where.
    pub pos: Pos,
    /// What.
    pub kind: Box<ErrorKind>,
}

/// What is wrong in a PDDL file.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ErrorKind {
    /// A `(` never closed.
    #[error("unbalanced parentheses: this `(` is never closed")]
    Unclosed,
    /// A `)` with nothing open.
    #[error("unbalanced parentheses: `)` closes nothing")]
    UnexpectedClose,
    /// Text after the closing `)` of `define`.
    #[error("text after the end of the definition")]
    Trailing,
    /// Nesting over [`MAX_DEPTH`].
    #[error("lists nested deeper than {limit} levels")]
    TooDeep {
        /// The limit.
        limit: usize,
    },
    /// A control character.
    #[error("invalid character {0:?}")]
    BadCharacter(char),
    /// Something else than what the grammar wants here.
    #[error("expected {expected}, found {found}")]
    Expected {
        /// What the grammar wants.
        expected: String,
        /// What is there.
        found: String,
    },
    /// A requirement this reader does not implement.
    #[error("unsupported requirement `{0}` (this reader takes classical STRIPS and ADL with action costs)")]
    UnsupportedRequirement(String),
    /// A construct outside classical STRIPS and ADL with action costs.
    #[error("`{0}` is not supported (this reader takes classical STRIPS and ADL with action costs)")]
    Unsupported(String),
    /// More declarations than ids exist for.
    #[error("more than {limit} {what}")]
    TooMany {
        /// What is counted.
        what: &'static str,
        /// The limit.
        limit: usize,
    },
    /// A number that is not a non-negative integer where one is needed.
    #[error("`{0}` is not a cost this reader takes (a whole number from 0 to 4294967295)")]
    BadNumber(String),
    /// A section or key given twice.
    #[error("`{0}` given twice")]
    Duplicate(String),
    /// A section that must be there is missing.
    #[error("missing `{0}`")]
    Missing(String),
    /// A rule of the model.
    #[error("{0}")]
    Model(ModelError),
}

/// Something a file does that other planners accept but that is not quite PDDL.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{file}:{}:{}: warning: {message}", pos.line, pos.column)]
pub struct PddlWarning {
    /// The file.
    pub file: String,
    /// Where.
    pub pos: Pos,
    /// What.
    pub message: String,
}

/// Reads a domain file; `file` names it in errors. Warnings are dropped; see
/// [`read_domain`].
///
/// # Errors
/// The first fault, as a [`PddlError`].
pub fn parse_domain(file: &str, text: &str) -> Result<Domain, PddlError> {
    read_domain(file, text).map(|(d, _)| d)
}

/// Reads a problem file over `domain`; `file` names it in errors. Warnings are
/// dropped; see [`read_problem`].
///
/// # Errors
/// The first fault, as a [`PddlError`].
pub fn parse_problem(file: &str, text: &str, domain: &Domain) -> Result<Problem, PddlError> {
    read_problem(file, text, domain).map(|(p, _)| p)
}

fn warnings(file: &str, list: Vec<(Pos, String)>) -> Vec<PddlWarning> {
    list.into_iter().map(|(pos, message)| PddlWarning { file: file.to_string(), pos, message }).collect()
}

/// Reads a domain file, with the warnings it gave.
///
/// # Errors
/// The first fault, as a [`PddlError`].
pub fn read_domain(file: &str, text: &str) -> Result<(Domain, Vec<PddlWarning>), PddlError> {
    let at = |(pos, kind)| PddlError { file: file.to_string(), pos, kind: Box::new(kind) };
    let sexp = sexp::read(text).map_err(at)?;
    let mut w = Vec::new();
    let d = read::domain(&sexp, &mut w).map_err(at)?;
    Ok((d, warnings(file, w)))
}

/// Reads a problem file over `domain`, with the warnings it gave.
///
/// # Errors
/// The first fault, as a [`PddlError`].
pub fn read_problem(file: &str, text: &str, domain: &Domain) -> Result<(Problem, Vec<PddlWarning>), PddlError> {
    let at = |(pos, kind)| PddlError { file: file.to_string(), pos, kind: Box::new(kind) };
    let sexp = sexp::read(text).map_err(at)?;
    let mut w = Vec::new();
    let p = read::problem(&sexp, domain, &mut w).map_err(at)?;
    Ok((p, warnings(file, w)))
}
