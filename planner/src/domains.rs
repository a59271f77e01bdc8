//! The domains shipped with the project (PDDL files under `planner/domains/`).
//!
//! * `cube-sphere` — Colledanchise et al. 2019, Fig. 1 and Examples 1-2 (a contract: worlds and
//!   firmware derive their behavior set from it). [`cube_sphere`] grounds Example 1's
//!   problem, [`cube_sphere_blocked`] the one where the sphere already blocks the path
//!   (planning it yields the Fig. 4 arrangement).
//! * `cellphone` — Colledanchise et al. 2019, Section VI: two arms, regrasps by hand-over.
//! * `blocks` — the blocks world, with [`blocks_world`] generating problems of n blocks.
//!
//! The four brick tasks of Styrud et al. are in [`crate::duplo`].

use crate::ground::Grounding;
use crate::model::{Domain, Problem};
use crate::{PlanError, pddl};

/// The cube/sphere domain (contract).
pub const CUBE_SPHERE_DOMAIN: &str = include_str!("../domains/cube-sphere/domain.pddl");
/// Example 1: move the cube onto the goal; the path is free at the start.
pub const CUBE_SPHERE_PROBLEM: &str = include_str!("../domains/cube-sphere/problem.pddl");
/// Example 2 offline: the sphere blocks the path to the goal from the start.
pub const CUBE_SPHERE_BLOCKED: &str = include_str!("../domains/cube-sphere/problem-blocked.pddl");
/// The cellphone assembly domain.
pub const CELLPHONE_DOMAIN: &str = include_str!("../domains/cellphone/domain.pddl");
/// The cellphone assembly problem.
pub const CELLPHONE_PROBLEM: &str = include_str!("../domains/cellphone/problem.pddl");
/// The blocks world domain.
pub const BLOCKS_DOMAIN: &str = include_str!("../domains/blocks/domain.pddl");

/// Any failure to read or ground a built-in domain (a bug: tests read them all).
#[derive(Debug, thiserror::Error)]
pub enum BuiltinError {
    /// The PDDL did not parse.
    #[error(transparent)]
    Pddl(#[from] Box<pddl::PddlError>),
    /// Grounding failed.
    #[error(transparent)]
    Plan(#[from] PlanError),
}

fn problem(domain: (&str, &str), problem: (&str, &str)) -> Result<Problem, BuiltinError> {
    let d = pddl::parse_domain(domain.0, domain.1).map_err(Box::new)?;
    Ok(pddl::parse_problem(problem.0, problem.1, &d).map_err(Box::new)?)
}

/// The cube/sphere domain.
///
/// # Errors
/// Never for the shipped file.
pub fn cube_sphere_domain() -> Result<Domain, BuiltinError> {
    Ok(pddl::parse_domain("cube-sphere/domain.pddl", CUBE_SPHERE_DOMAIN).map_err(Box::new)?)
}

/// Example 1 of Colledanchise et al. 2019, grounded.
///
/// # Errors
/// Never for the shipped files.
pub fn cube_sphere() -> Result<Grounding, BuiltinError> {
    let p =
        problem(("cube-sphere/domain.pddl", CUBE_SPHERE_DOMAIN), ("cube-sphere/problem.pddl", CUBE_SPHERE_PROBLEM))?;
    Ok(Grounding::new(&p)?)
}

/// Example 2 of Colledanchise et al. 2019 with the path blocked from the start, grounded.
///
/// # Errors
/// Never for the shipped files.
pub fn cube_sphere_blocked() -> Result<Grounding, BuiltinError> {
    let p = problem(
        ("cube-sphere/domain.pddl", CUBE_SPHERE_DOMAIN),
        ("cube-sphere/problem-blocked.pddl", CUBE_SPHERE_BLOCKED),
    )?;
    Ok(Grounding::new(&p)?)
}

/// The cellphone assembly of Colledanchise et al. 2019, Section VI, grounded.
///
/// # Errors
/// Never for the shipped files.
pub fn cellphone() -> Result<Grounding, BuiltinError> {
    let p = problem(("cellphone/domain.pddl", CELLPHONE_DOMAIN), ("cellphone/problem.pddl", CELLPHONE_PROBLEM))?;
    Ok(Grounding::new(&p)?)
}

/// The PDDL text of a blocks-world problem with `n` blocks `b0`..`b{n-1}`: all on the
/// table at the start; the goal is one tower with `b{n-1}` at the bottom and `b0` on
/// top, its conditions listed from the bottom up.
#[must_use]
pub fn blocks_world_pddl(n: usize) -> String {
    let names: Vec<String> = (0..n).map(|i| format!("b{i}")).collect();
    let mut s = format!(
        "(define (problem blocks-{n})\n  (:domain blocks)\n  (:objects {} - block)\n  (:init (hand-empty)",
        names.join(" ")
    );
    for b in &names {
        s.push_str(&format!(" (on-table {b}) (clear {b})"));
    }
    s.push_str(")\n  (:goal (and");
    for i in (0..n.saturating_sub(1)).rev() {
        s.push_str(&format!(" (on b{i} b{})", i + 1));
    }
    s.push_str(")))\n");
    s
}

/// A blocks-world problem of `n` blocks (see [`blocks_world_pddl`]), grounded.
///
/// # Errors
/// Never for `n >= 2`; [`BuiltinError`] otherwise (empty goal).
pub fn blocks_world(n: usize) -> Result<Grounding, BuiltinError> {
    let text = blocks_world_pddl(n);
    let p = problem(("blocks/domain.pddl", BLOCKS_DOMAIN), ("blocks-generated.pddl", &text))?;
    Ok(Grounding::new(&p)?)
}
