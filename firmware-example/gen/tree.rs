//! The tree the firmware runs, made into image bytes on the host by `build.rs`: the
//! planner's own output.
//!
//! `planner` (Colledanchise et al. 2019, Algorithm 1) plans the cube/sphere problem in which the sphere
//! already blocks the path to the goal (`planner/domains/cube-sphere/problem-blocked.pddl`):
//! Fig. 3(a)-(e), then `path-free(goal)` expanded with `clear-path(sphere, goal)` and
//! moved left and up by `IncreasePriority` to run before the cube is picked (the
//! arrangement of Fig. 4), then `near(sphere)`. Planned from the initial state, the hand
//! is empty whenever that tree checks `hand-empty`. The firmware's plant also puts the
//! cube in the hand while the path is blocked (its `help` event), as in Example 2, so the
//! tree is then expanded at run time from that state (`planner::expand_at`, Algorithm 1
//! lines 9-12): `hand-empty` gets its atomic BT, with `drop(cube)`. The result is the
//! tree at the end of Example 2, 37 nodes; `sim-host plan ... --expand-at 'holding(cube),
//! not hand-empty'` prints the same.
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

/// The state the tree is expanded at: the initial state of the blocked problem with the
/// cube in the hand.
const CUBE_IN_HAND: &str = "holding(cube), not hand-empty";

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
    let changes =
        planner::parse_changes(&grounding, CUBE_IN_HAND).map_err(|e| format!("the state `{CUBE_IN_HAND}`: {e}"))?;
    planner::expand_at(&mut plan.planner, catalog.as_ref(), &changes, 1000)
        .map_err(|e| format!("expanding the planned tree for the cube in the hand: {e}"))?;
    bt_formats::Image::new(plan.planner.nodes()).encode(catalog.fingerprint()).map_err(|e| format!("the image: {e}"))
}
