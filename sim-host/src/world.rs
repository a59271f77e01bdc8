//! What every brick world offers, symbolic or physics: a [`worlds::World`] whose
//! behavior ids index the task's [`Spec::behaviors`], with bricks at positions.
//!
//! An episode alternates ticking the tree and [`worlds::World::step`]: the tree ticks
//! the behaviors, then the world advances by one tick (0.1 s at 10 Hz).
//! [`crate::episode::Runner`] runs episodes under Styrud et al.'s rules over any
//! `BrickWorld`.

use planner::duplo::Spec;

/// Ticks in an episode of a physics world: 20 s at 10 Hz (Styrud et al., Section IV).
pub const PHYSICS_TICK_LIMIT: u32 = 200;

/// Ticks in an episode of the fast symbolic world (the reference's limit).
pub const SYMBOLIC_TICK_LIMIT: u32 = 30;

/// "Actions will return Failure if not completed within 50 ticks" (Styrud et al., IV-A).
pub const ACTION_TICK_LIMIT: u32 = 50;

/// Most bricks a task has (the croissant's four): episode results keep positions in
/// arrays of this size, so that an episode allocates nothing.
pub const MAX_BRICKS: usize = 4;

/// A world for one brick task (`planner::duplo`). Its [`worlds::World::reset`] puts
/// the bricks at their start positions, the hand empty, no action under way.
pub trait BrickWorld: worlds::World {
    /// The task this world plays.
    fn spec(&self) -> &Spec;

    /// Position (x, y, z) in metres of brick `brick`, by index into `spec().bricks`.
    fn position(&self, brick: usize) -> [f32; 3];

    /// The brick in the gripper, if any.
    fn held(&self) -> Option<u8>;

    /// Ticks an episode may last before it ends by timeout: [`PHYSICS_TICK_LIMIT`]
    /// unless the world says otherwise.
    fn tick_limit(&self) -> u32 {
        PHYSICS_TICK_LIMIT
    }
}
