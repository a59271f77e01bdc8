//! The tree the firmware runs, made into image bytes on the host by `build.rs`: the
//! planner's own output.
//!
//! `planner` (seed 000, Algorithm 1) plans the cube/sphere problem in which the sphere
//! already blocks the path to the goal (`planner/domains/cube-sphere/problem-blocked.pddl`).
//! Offline, it grows Fig. 3(a)-(e) and then expands `path-free(goal)` with
//! `clear-path(sphere, goal)`; that subtree needs `hand-empty` while `pick(cube)` undoes
//! it, so `IncreasePriority` moves it up a level and left, to run before the cube is
//! picked: the arrangement of Fig. 4.
//!
//! ```text
//! Fallback
//!   at(cube, goal)?
//!   Sequence
//!     Fallback [path-free(goal)?, Sequence [Fallback [near(sphere)?, ... move-to(sphere)!],
//!                                           Fallback [hand-empty?, ... drop(cube)!],
//!                                           clear-path(sphere, goal)!]]
//!     Fallback [holding(cube)?, Sequence [... move-to(cube)!, hand-empty?, pick(cube)!]]
//!     Fallback [near(goal)?, Sequence [path-free(goal)?, move-to(goal)!]]
//!     place(cube, goal)!
//! ```
//!
//! The catalog the planner derives from the PDDL file must equal the firmware's constant
//! one (`src/catalog.rs`): `image()` checks the fingerprints, so a drift between the
//! contract and the firmware stops the build with a message instead of an image the
//! controller would refuse.

use std::sync::Arc;

use bt_core::Catalog as _;

use crate::catalog::FINGERPRINT;

/// The PDDL files the tree is planned from, relative to the firmware folder (for
/// `rerun-if-changed`).
pub const SOURCES: [&str; 2] =
    ["../planner/domains/cube-sphere/domain.pddl", "../planner/domains/cube-sphere/problem-blocked.pddl"];

/// The image of the planner's tree for the cube/sphere behavior set.
///
/// # Errors
/// What went wrong, in words.
pub fn image() -> Result<Vec<u8>, String> {
    let grounding =
        Arc::new(planner::domains::cube_sphere_blocked().map_err(|e| format!("loading the cube/sphere domain: {e}"))?);
    let catalog = Arc::new(planner::PddlCatalog::new(grounding.problem()));
    if catalog.fingerprint() != FINGERPRINT {
        return Err(format!(
            "the planner's cube/sphere catalog ({:#018x}) differs from src/catalog.rs ({FINGERPRINT:#018x}): \
             the firmware no longer follows planner/domains/cube-sphere/domain.pddl",
            catalog.fingerprint()
        ));
    }
    let mut plan = planner::plan(grounding.clone(), catalog.clone(), planner::Options::default())
        .map_err(|e| format!("planning the cube/sphere problem: {e}"))?;
    // Planned from the initial state, the hand is empty whenever the tree checks
    // `hand-empty`, so Algorithm 1 never expands it. The firmware's plant puts the cube in
    // the hand (its `help` event) while the sphere blocks the path: expand as the planner
    // does at run time when the tree fails in that state (Algorithm 1, lines 9-12), which
    // gives `hand-empty` its atomic BT with `drop(cube)`: the tree of Fig. 4.
    let mut world = planner::strips::StripsWorld::new(grounding);
    if !(world.set_named("hand-empty", &[], false) && world.set_named("holding", &["cube"], true)) {
        return Err("the cube/sphere domain has no hand-empty or holding(cube)".into());
    }
    let mut states = Vec::new();
    let outcome = planner::strips::run_with(
        plan.planner.nodes(),
        plan.planner.values(),
        catalog.as_ref(),
        &mut world,
        1000,
        |_, _| {},
        &mut states,
    )
    .map_err(|e| format!("ticking the planned tree: {e}"))?;
    if outcome.status != bt_core::Status::Failure {
        return Err("the planned tree does not fail with the cube in the hand and the path blocked".into());
    }
    let belief = world.state().clone();
    plan.planner
        .on_failure(&states, &belief)
        .map_err(|e| format!("expanding the planned tree for the cube in the hand: {e}"))?;
    planner::output::to_image(plan.planner.nodes(), catalog.as_ref()).map_err(|e| format!("encoding the image: {e}"))
}
