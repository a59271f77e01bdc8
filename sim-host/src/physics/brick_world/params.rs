//! The world's tunable simulation parameters.

use super::*;

/// Tunable simulation parameters. The defaults are the tested ones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrickParams {
    /// rapier steps per 0.1 s tick.
    pub steps_per_tick: u32,
    /// rapier solver iterations (substeps) per step.
    pub solver_iterations: usize,
    /// rapier's inner Gauss-Seidel iterations per solver iteration. With 1 (rapier's
    /// default) the balance task's long brick set on the 4x2 base rocks, walks
    /// millimetres off and is knocked aside by the press, so the reference's published
    /// balance solution fails (-58.0 instead of -0.6); 3 keeps it still for 13-26% more
    /// time per episode (8 solver iterations do it too, at three times the time).
    pub pgs_iterations: usize,
    /// Gripper speed, m/s.
    pub speed: f32,
    /// Tool point height while travelling, m.
    pub travel_height: f32,
}

impl Default for BrickParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl BrickParams {
    /// The tested settings, as a constant.
    pub const DEFAULT: Self =
        Self { steps_per_tick: 5, solver_iterations: 4, pgs_iterations: 3, speed: 0.3, travel_height: 0.09 };

    pub(super) fn check(&self) -> Result<(), PhysicsError> {
        let bad = |name, value: f64, why| Err(PhysicsError::BadParameter { name, value, why });
        if !(1..=1000).contains(&self.steps_per_tick) {
            return bad("steps_per_tick", f64::from(self.steps_per_tick), "must be 1..=1000");
        }
        if !(1..=100).contains(&self.solver_iterations) {
            return bad("solver_iterations", self.solver_iterations as f64, "must be 1..=100");
        }
        if !(1..=100).contains(&self.pgs_iterations) {
            return bad("pgs_iterations", self.pgs_iterations as f64, "must be 1..=100");
        }
        if !(self.speed > 0.0 && self.speed <= 10.0) {
            return bad("speed", f64::from(self.speed), "must be in (0, 10] m/s");
        }
        if !(self.travel_height >= 0.08 && self.travel_height <= 1.0) {
            return bad("travel_height", f64::from(self.travel_height), "must be in [0.08, 1] m");
        }
        Ok(())
    }
}
