//! PDDL input: STRIPS with `:typing` and `:negative-preconditions`, domain and problem
//! files.
//!
//! A small reader of our own (no PDDL crate reports positions the way we need): a
//! tokenizer that builds the parenthesised structure without recursion and refuses
//! nesting deeper than [`MAX_DEPTH`], then an interpretation into the
//! [`model`](crate::model) with the same checks as the Rust builders. Every error names
//! the file, line and column and what was expected; no input makes it panic.
//!
//! Supported: `(:requirements :strips :typing :negative-preconditions)`, `(:types ...)`
//! with parents in any order, `(:predicates ...)`, `(:action ... :parameters
//! :precondition :effect)` with conjunctions of literals, and problems with `(:domain)`,
//! `(:objects)`, `(:init)` and `(:goal)`. Everything else (constants, equality,
//! quantifiers, conditional effects, numbers, ...) is refused by name.
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

pub use sexp::MAX_DEPTH;

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
    #[error("unsupported requirement `{0}` (supported: :strips :typing :negative-preconditions)")]
    UnsupportedRequirement(String),
    /// A construct outside STRIPS with typing and negative preconditions.
    #[error("`{0}` is not supported: this reader takes STRIPS with :typing and :negative-preconditions")]
    Unsupported(String),
    /// A negative precondition or goal without the requirement.
    #[error("negative conditions need `:negative-preconditions` in the domain's :requirements")]
    NegativeNeedsRequirement,
    /// Types used without the requirement.
    #[error("types need `:typing` in the domain's :requirements")]
    TypingNeedsRequirement,
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

/// Reads a domain file; `file` names it in errors.
///
/// # Errors
/// The first fault, as a [`PddlError`].
pub fn parse_domain(file: &str, text: &str) -> Result<Domain, PddlError> {
    let at = |(pos, kind)| PddlError { file: file.to_string(), pos, kind: Box::new(kind) };
    let sexp = sexp::read(text).map_err(at)?;
    read::domain(&sexp).map_err(at)
}

/// Reads a problem file over `domain`; `file` names it in errors.
///
/// # Errors
/// The first fault, as a [`PddlError`].
pub fn parse_problem(file: &str, text: &str, domain: &Domain) -> Result<Problem, PddlError> {
    let at = |(pos, kind)| PddlError { file: file.to_string(), pos, kind: Box::new(kind) };
    let sexp = sexp::read(text).map_err(at)?;
    read::problem(&sexp, domain).map_err(at)
}
