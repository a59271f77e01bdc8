//! What every brick world offers, symbolic or physics: the task's behaviors (as a
//! [`BehaviorSet`] whose behavior ids index [`Spec::behaviors`]) over a state that
//! advances one tick at a time.
//!
//! An episode alternates `exec.tick(&mut world, t)` and `world.step()`: the tree ticks
//! the behaviors, then the world advances by one tick (0.1 s at 10 Hz).

use bt_core::BehaviorSet;
use planner::duplo::Spec;

/// A world for one brick task (`planner::duplo`).
pub trait BrickWorld: BehaviorSet {
    /// The task this world plays.
    fn spec(&self) -> &Spec;

    /// Advances the world by one tick, after the tree was ticked.
    fn step(&mut self);

    /// Position (x, y, z) in metres of brick `brick`, by index into `spec().bricks`.
    fn position(&self, brick: usize) -> [f32; 3];

    /// The brick in the gripper, if any.
    fn held(&self) -> Option<u8>;
}
