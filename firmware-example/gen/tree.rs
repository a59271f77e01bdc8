//! The tree the firmware runs, made into image bytes on the host by `build.rs`.
//!
//! This file is the one place to change when the planner's output replaces the
//! hand-built tree: `image()` must return image bytes for the behavior set of
//! `src/catalog.rs` (the loader refuses anything else), however they are made. If it
//! reads files (say the planner's `planner/domains/cube-sphere/*.pddl`), add them to
//! the `rerun-if-changed` list in `build.rs` so that the image follows them.

use bt_core::image::max_image_len;
use bt_core::{BuildError, Builder, Node, encode};

use crate::catalog::{
    AT, CLEAR_PATH, CUBE, DROP, FINGERPRINT, GOAL, HAND_EMPTY, HOLDING, MOVE_TO, NEAR, OBSTACLE, PATH_FREE, PICK,
    PLACE, SPHERE,
};

/// Node capacity of the builder here; the firmware's own capacity is
/// `firmware_example::MAX_NODES`.
const CAPACITY: usize = 64;
/// Deepest nesting the builder accepts.
const DEPTH: usize = 16;

/// Seed 000, Fig. 3(e) — the reactive plan of Example 1 — after Example 2's expansion
/// and conflict resolution (Fig. 4).
///
/// Example 2: the sphere blocks the path while the robot carries the cube, so
/// `path-free(goal)` (the precondition of `move-to(goal)`) fails and is expanded with
/// the atomic BT of `clear-path(sphere, goal)`, whose preconditions are expanded in turn
/// (`near(sphere)` by `move-to(sphere)`, `hand-empty` by `drop(cube)`). The new subtree
/// needs `hand-empty` while the main branch's effect is `holding(cube)`: a conflict, so
/// `IncreasePriority` moves it leftward and up until it runs before the whole
/// Fig. 3(e) subtree, as the first child of the root sequence of goal conditions. Where
/// it was, `move-to(goal)` is left alone in its sequence. Preconditions appear in the
/// domain's declaration order (`clear-path`: obstacle, near, hand-empty).
///
/// ```text
/// Sequence
///   Fallback                                  path to the goal is free, or make it so
///     path-free(goal)?
///     Sequence
///       obstacle(sphere)?
///       Fallback [near(sphere)?, Sequence [path-free(sphere)?, move-to(sphere)!]]
///       Fallback [hand-empty?, Sequence [holding(cube)?, drop(cube)!]]
///       clear-path(sphere, goal)!
///   Fallback                                  Fig. 3(e)
///     at(cube, goal)?
///     Sequence
///       Fallback [holding(cube)?,
///                 Sequence [Fallback [near(cube)?, Sequence [path-free(cube)?, move-to(cube)!]],
///                           hand-empty?, pick(cube)!]]
///       Fallback [near(goal)?, Sequence [move-to(goal)!]]
///       place(cube, goal)!
/// ```
///
/// # Errors
/// A [`BuildError`] if `storage` is too small.
pub fn build(storage: &mut [Node]) -> Result<&[Node], BuildError> {
    let mut b = Builder::<DEPTH>::new(storage);
    b.sequence()?;
    {
        // Example 2: keep the path to the goal free (moved here by IncreasePriority).
        b.fallback()?.condition(PATH_FREE, &[GOAL])?;
        {
            b.sequence()?.condition(OBSTACLE, &[SPHERE])?;
            b.fallback()?.condition(NEAR, &[SPHERE])?;
            b.sequence()?.condition(PATH_FREE, &[SPHERE])?.action(MOVE_TO, &[SPHERE])?.end()?;
            b.end()?;
            b.fallback()?.condition(HAND_EMPTY, &[])?;
            b.sequence()?.condition(HOLDING, &[CUBE])?.action(DROP, &[CUBE])?.end()?;
            b.end()?;
            b.action(CLEAR_PATH, &[SPHERE, GOAL])?;
            b.end()?;
        }
        b.end()?;
        // Example 1, Fig. 3(e): the cube onto the goal.
        b.fallback()?.condition(AT, &[CUBE, GOAL])?;
        {
            b.sequence()?;
            b.fallback()?.condition(HOLDING, &[CUBE])?;
            {
                b.sequence()?;
                b.fallback()?.condition(NEAR, &[CUBE])?;
                b.sequence()?.condition(PATH_FREE, &[CUBE])?.action(MOVE_TO, &[CUBE])?.end()?;
                b.end()?;
                b.condition(HAND_EMPTY, &[])?.action(PICK, &[CUBE])?;
                b.end()?;
            }
            b.end()?;
            b.fallback()?.condition(NEAR, &[GOAL])?;
            b.sequence()?.action(MOVE_TO, &[GOAL])?.end()?;
            b.end()?;
            b.action(PLACE, &[CUBE, GOAL])?;
            b.end()?;
        }
        b.end()?;
    }
    b.end()?;
    b.finish()
}

/// The image of [`build`]'s tree for the cube/sphere behavior set.
///
/// # Errors
/// What went wrong, in words.
pub fn image() -> Result<Vec<u8>, String> {
    let mut storage = [Node::EMPTY; CAPACITY];
    let nodes = build(&mut storage).map_err(|e| format!("building the tree: {e}"))?;
    let mut out = vec![0u8; max_image_len(nodes.len())];
    let len = encode(nodes, FINGERPRINT, &mut out).map_err(|e| format!("encoding the image: {e}"))?;
    out.truncate(len);
    Ok(out)
}
