//! What every brick world offers, symbolic or physics: the task's behaviors (as a
//! [`BehaviorSet`] whose behavior ids index [`Spec::behaviors`]) over a state that
//! advances one tick at a time.
//!
//! An episode alternates `exec.tick(&mut world, t)` and `world.step()`: the tree ticks
//! the behaviors, then the world advances by one tick (0.1 s at 10 Hz).
//! [`crate::episode::Runner`] runs episodes under seed 003's rules over any `BrickWorld`.

use bt_core::BehaviorSet;
use planner::duplo::Spec;

/// Ticks in an episode of a physics world: 20 s at 10 Hz (seed 003, Section IV).
pub const PHYSICS_TICK_LIMIT: u32 = 200;

/// Ticks in an episode of the fast symbolic world (the reference's limit).
pub const SYMBOLIC_TICK_LIMIT: u32 = 30;

/// "Actions will return Failure if not completed within 50 ticks" (seed 003, IV-A).
pub const ACTION_TICK_LIMIT: u32 = 50;

/// Most bricks a task has (the croissant's four): episode results keep positions in
/// arrays of this size, so that an episode allocates nothing.
pub const MAX_BRICKS: usize = 4;

/// A world for one brick task (`planner::duplo`).
pub trait BrickWorld: BehaviorSet {
    /// The task this world plays.
    fn spec(&self) -> &Spec;

    /// Puts the world back in the task's start state, in place: the bricks at their
    /// start positions, the hand empty, no action under way. An episode starts with it,
    /// so one world serves any number of episodes.
    fn reset(&mut self);

    /// Advances the world by one tick, after the tree was ticked.
    fn step(&mut self);

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
