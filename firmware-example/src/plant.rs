//! The plant model: Colledanchise et al. 2019's Fig. 1 world in 2-D.
//!
//! A mobile base (position and facing direction) with a gripper a fixed reach ahead of it, a
//! cube, a sphere that may block the robot's path, and a rectangular goal region. All
//! lengths in metres, angles in radians, one step per control tick. The math is `f32`
//! through nalgebra and libm only (square roots: [`sqrt`]), so the controller and the host
//! compute the same bits.
//!
//! [`Plant`] implements the behavior set of [`crate::catalog`]: conditions read the
//! state, actions change it a bounded step per tick. A leaf whose arguments make no
//! sense for its behavior (say `near(7)`) fails; nothing here can panic.

use bt_core::{BehaviorSet, Context, Leaf, NodeId, Status};
use nalgebra::Vector2;

use crate::catalog::{
    AT, CLEAR_PATH, CUBE, DROP, GOAL, HAND_EMPTY, HOLDING, MOVE_TO, NEAR, OBSTACLE, PATH_FREE, PICK, PLACE, SPHERE,
};

/// A point or direction in the plane, in metres.
pub type Vec2 = Vector2<f32>;

/// The length of `v`: `v.norm()` with the square root taken by [`sqrt`].
#[inline]
#[must_use]
pub fn length(v: Vec2) -> f32 {
    sqrt(v.norm_squared())
}

/// IEEE 754's square root, which rounds correctly: libm's on the host, the FPU's
/// `vsqrt.f32` on a Cortex-M with hardware floating point. Both give the same bits, and
/// the FPU's saves libm's software square root (about 500 bytes of flash).
#[inline]
#[must_use]
pub fn sqrt(x: f32) -> f32 {
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    {
        // SAFETY: `fw_sqrtf` (below) takes and returns an `f32` in `s0` under the
        // hard-float ABI and touches nothing else.
        #[allow(unsafe_code)]
        unsafe {
            fpu::fw_sqrtf(x)
        }
    }
    #[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
    libm::sqrtf(x)
}

// The FPU's square root as a function: `asm!` cannot name the FPU's registers on these
// targets without the unstable `vfp2` target feature, the assembler can.
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[allow(unsafe_code)]
mod fpu {
    core::arch::global_asm!(
        ".section .text.fw_sqrtf,\"ax\",%progbits",
        ".fpu fpv4-sp-d16",
        ".global fw_sqrtf",
        ".type fw_sqrtf,%function",
        ".thumb_func",
        "fw_sqrtf:",
        "vsqrt.f32 s0, s0",
        "bx lr",
        ".size fw_sqrtf, . - fw_sqrtf",
    );

    unsafe extern "C" {
        pub(super) fn fw_sqrtf(x: f32) -> f32;
    }
}

/// Control ticks per second.
pub const TICK_HZ: u32 = 10;
/// Milliseconds per control tick.
pub const PERIOD_MS: u32 = 1000 / TICK_HZ;
/// Base speed, m/s.
pub const SPEED: f32 = 0.5;
/// Distance the base moves in one tick, m.
pub const STEP: f32 = SPEED / TICK_HZ as f32;
/// The neighbourhood `N_l` of a location: the robot is `near` within this distance, m.
pub const NEAR_RADIUS: f32 = 0.7;
/// `move-to` stops this far from an item (at the goal: from its centre), m.
pub const ARRIVE: f32 = 0.4;
/// The gripper sits this far ahead of the base, m.
pub const REACH: f32 = 0.25;
/// A path is free when the sphere's centre stays this far from it (base radius plus
/// sphere radius), m.
pub const CLEARANCE: f32 = 0.35;
/// `clear-path` sets the obstacle down this far beside the robot, m: off the path
/// (more than [`CLEARANCE`]) and still within reach (less than [`NEAR_RADIUS`]).
pub const SET_ASIDE: f32 = 0.5;
/// Half extents of the goal rectangle, m.
pub const GOAL_HALF: Vec2 = Vec2::new(0.4, 0.3);
/// Ticks a grasp takes (`pick`).
pub const PICK_TICKS: u8 = 3;
/// Ticks `place` takes.
pub const PLACE_TICKS: u8 = 3;
/// Ticks `drop` takes.
pub const DROP_TICKS: u8 = 2;
/// Ticks `clear-path` takes.
pub const CLEAR_TICKS: u8 = 4;

/// What the gripper holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hand {
    /// Nothing.
    Empty,
    /// The cube.
    Cube,
}

impl Hand {
    /// `-` or `cube`, as the trace prints it.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Empty => "-",
            Self::Cube => "cube",
        }
    }
}

/// How many times each action finished, and how often actions were halted: what the
/// summary reports and the tests check.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Successful `pick`s.
    pub picks: u16,
    /// Successful `place`s.
    pub places: u16,
    /// Successful `drop`s.
    pub drops: u16,
    /// Successful `clear-path`s.
    pub clears: u16,
    /// `halt` calls.
    pub halts: u16,
}

/// The world's state.
#[derive(Clone, Debug, PartialEq)]
pub struct Plant {
    /// Base position.
    pub robot: Vec2,
    /// The direction the base faces, a unit vector (kept as a vector, not an angle: no
    /// trigonometry on the controller).
    pub facing: Vec2,
    /// What the gripper holds.
    pub hand: Hand,
    /// Cube centre (follows the gripper while held).
    pub cube: Vec2,
    /// Sphere centre.
    pub sphere: Vec2,
    /// Centre of the goal rectangle.
    pub goal: Vec2,
    /// Ticks into the running timed action (pick, place, drop).
    pub progress: u8,
    /// Finished actions and halts.
    pub counters: Counters,
}

impl Default for Plant {
    fn default() -> Self {
        Self::new()
    }
}

impl Plant {
    /// Fig. 1: the robot at the origin facing +x, the cube ahead of it, the goal region
    /// to its upper right, the sphere parked out of every path.
    #[must_use]
    pub fn new() -> Self {
        Self {
            robot: Vec2::new(0.0, 0.0),
            facing: Vec2::new(1.0, 0.0),
            hand: Hand::Empty,
            cube: Vec2::new(3.0, 0.0),
            sphere: Vec2::new(-0.8, 2.0),
            goal: Vec2::new(3.0, 4.0),
            progress: 0,
            counters: Counters::default(),
        }
    }

    /// Where the gripper is.
    #[must_use]
    pub fn gripper(&self) -> Vec2 {
        self.robot + self.facing * REACH
    }

    /// Position of object `id` (cube, sphere or goal centre).
    #[must_use]
    pub fn position(&self, id: u16) -> Option<Vec2> {
        match id {
            CUBE => Some(self.cube),
            SPHERE => Some(self.sphere),
            GOAL => Some(self.goal),
            _ => None,
        }
    }

    /// `near(l)`: the base is within [`NEAR_RADIUS`] of location `l`.
    #[must_use]
    pub fn near(&self, l: u16) -> bool {
        self.position(l).is_some_and(|p| length(p - self.robot) <= NEAR_RADIUS)
    }

    /// `path-free(l)`: the straight path from the base to `l` keeps [`CLEARANCE`] from
    /// the sphere. The path to the sphere itself is free (it ends there).
    #[must_use]
    pub fn path_free(&self, l: u16) -> bool {
        if l == SPHERE {
            return true;
        }
        self.position(l).is_some_and(|p| segment_distance(self.sphere, self.robot, p) > CLEARANCE)
    }

    /// `at(i, goal)`: item `i` lies (not held) inside the goal rectangle.
    #[must_use]
    pub fn at(&self, i: u16, s: u16) -> bool {
        if s != GOAL || (i == CUBE && self.hand == Hand::Cube) {
            return false;
        }
        let p = match i {
            CUBE => self.cube,
            SPHERE => self.sphere,
            _ => return false,
        };
        let d = p - self.goal;
        libm::fabsf(d.x) <= GOAL_HALF.x && libm::fabsf(d.y) <= GOAL_HALF.y
    }

    /// `holding(i)`.
    #[must_use]
    pub fn holding(&self, i: u16) -> bool {
        i == CUBE && self.hand == Hand::Cube
    }

    /// Moves the held cube with the gripper.
    fn carry(&mut self) {
        if self.hand == Hand::Cube {
            self.cube = self.gripper();
        }
    }

    /// One tick of `move-to(l)`: turn towards `l` and drive at most [`STEP`]; Success
    /// once within [`ARRIVE`].
    fn move_to(&mut self, l: u16) -> Status {
        let Some(target) = self.position(l) else {
            return Status::Failure;
        };
        let d = target - self.robot;
        let dist = length(d);
        if dist <= ARRIVE {
            return Status::Success;
        }
        self.facing = d / dist;
        let step = (dist - ARRIVE).min(STEP);
        self.robot += self.facing * step;
        self.carry();
        if dist - step <= ARRIVE { Status::Success } else { Status::Running }
    }

    /// Counts the ticks of a timed action: Running until the `ticks`-th, then Success.
    fn timed(&mut self, starting: bool, ticks: u8) -> bool {
        self.progress = if starting { 1 } else { self.progress.saturating_add(1) };
        if self.progress >= ticks {
            self.progress = 0;
            true
        } else {
            false
        }
    }

    /// `pick(cube)`: close the gripper on the cube over [`PICK_TICKS`] ticks.
    fn pick(&mut self, i: u16, starting: bool) -> Status {
        if i != CUBE || self.hand != Hand::Empty || !self.near(CUBE) {
            return Status::Failure;
        }
        if !self.timed(starting, PICK_TICKS) {
            return Status::Running;
        }
        self.hand = Hand::Cube;
        self.carry();
        self.counters.picks = self.counters.picks.saturating_add(1);
        Status::Success
    }

    /// `place(cube, goal)`: put the held cube at the goal's centre.
    fn place(&mut self, i: u16, s: u16, starting: bool) -> Status {
        if !self.holding(i) || s != GOAL || !self.near(GOAL) {
            return Status::Failure;
        }
        if !self.timed(starting, PLACE_TICKS) {
            return Status::Running;
        }
        self.hand = Hand::Empty;
        self.cube = self.goal;
        self.counters.places = self.counters.places.saturating_add(1);
        Status::Success
    }

    /// `drop(cube)`: open the gripper; the cube stays where the gripper was.
    fn drop_item(&mut self, i: u16, starting: bool) -> Status {
        if !self.holding(i) {
            return Status::Failure;
        }
        if !self.timed(starting, DROP_TICKS) {
            return Status::Running;
        }
        self.hand = Hand::Empty;
        self.counters.drops = self.counters.drops.saturating_add(1);
        Status::Success
    }

    /// `clear-path(sphere, l)`: the arm takes the sphere and, after [`CLEAR_TICKS`]
    /// ticks, sets it down [`SET_ASIDE`] beside the robot, off the path to `l` (on the side
    /// of the path it already lies on; left if right on it).
    fn clear_path(&mut self, i: u16, l: u16, starting: bool) -> Status {
        if i != SPHERE || self.hand != Hand::Empty || !self.near(SPHERE) {
            return Status::Failure;
        }
        let Some(target) = self.position(l) else {
            return Status::Failure;
        };
        if !self.timed(starting, CLEAR_TICKS) {
            return Status::Running;
        }
        let along = target - self.robot;
        let n = length(along);
        if n > 0.0 {
            let left = Vec2::new(-along.y, along.x) / n;
            let side = if left.dot(&(self.sphere - self.robot)) >= 0.0 { 1.0 } else { -1.0 };
            self.sphere = self.robot + left * (side * SET_ASIDE);
        }
        if !self.path_free(l) {
            return Status::Failure;
        }
        self.counters.clears = self.counters.clears.saturating_add(1);
        Status::Success
    }

    /// FNV-1a (32 bit) over the exact bits of the whole state: any difference between
    /// two runs, however small, shows in the digest.
    #[must_use]
    pub fn digest(&self) -> u32 {
        let mut h = 0x811c_9dc5_u32;
        let mut eat = |bytes: [u8; 4]| {
            for b in bytes {
                h = (h ^ u32::from(b)).wrapping_mul(0x0100_0193);
            }
        };
        for v in [
            self.robot.x,
            self.robot.y,
            self.facing.x,
            self.facing.y,
            self.cube.x,
            self.cube.y,
            self.sphere.x,
            self.sphere.y,
        ] {
            eat(v.to_bits().to_le_bytes());
        }
        eat([self.hand as u8, self.progress, 0, 0]);
        h
    }
}

impl BehaviorSet for Plant {
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        let a = |i| leaf.arg(i).unwrap_or(u16::MAX);
        let holds = match leaf.behavior() {
            AT => self.at(a(0), a(1)),
            HOLDING => self.holding(a(0)),
            HAND_EMPTY => self.hand == Hand::Empty,
            NEAR => self.near(a(0)),
            PATH_FREE => self.path_free(a(0)),
            OBSTACLE => a(0) == SPHERE,
            _ => false,
        };
        if holds { Status::Success } else { Status::Failure }
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let a = |i| leaf.arg(i).unwrap_or(u16::MAX);
        match leaf.behavior() {
            MOVE_TO => self.move_to(a(0)),
            PICK => self.pick(a(0), ctx.starting),
            PLACE => self.place(a(0), a(1), ctx.starting),
            DROP => self.drop_item(a(0), ctx.starting),
            CLEAR_PATH => self.clear_path(a(0), a(1), ctx.starting),
            _ => Status::Failure,
        }
    }

    fn halt(&mut self, _: &Leaf, _: NodeId) {
        // The base stops and the gripper stays as it is: an interrupted grasp, place or
        // drop starts over when it is ticked again.
        self.progress = 0;
        self.counters.halts = self.counters.halts.saturating_add(1);
    }
}

/// Distance from point `p` to the segment from `a` to `b`.
#[must_use]
pub fn segment_distance(p: Vec2, a: Vec2, b: Vec2) -> f32 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 { ((p - a).dot(&ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    length(p - (a + ab * t))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distance_measures_to_the_closest_point() {
        let a = Vec2::new(0.0, 0.0);
        let b = Vec2::new(2.0, 0.0);
        assert_eq!(segment_distance(Vec2::new(1.0, 0.5), a, b), 0.5);
        assert_eq!(segment_distance(Vec2::new(3.0, 0.0), a, b), 1.0);
        assert_eq!(segment_distance(Vec2::new(-1.0, 0.0), a, a), 1.0);
    }

    #[test]
    fn the_sphere_on_the_path_blocks_it_and_nothing_else() {
        let mut p = Plant::new();
        assert!(p.path_free(GOAL) && p.path_free(CUBE));
        p.sphere = (p.robot + p.goal) * 0.5;
        assert!(!p.path_free(GOAL));
        assert!(p.path_free(CUBE), "the sphere is not between the robot and the cube");
        assert!(p.path_free(SPHERE), "the path to the obstacle itself is free");
    }

    #[test]
    fn move_to_arrives_near_and_stops() {
        let mut p = Plant::new();
        let mut ticks = 0;
        while p.move_to(CUBE) == Status::Running {
            ticks += 1;
            assert!(ticks < 100);
        }
        assert!(p.near(CUBE));
        let d = length(p.cube - p.robot);
        assert!((d - ARRIVE).abs() < 1e-4, "stopped {d} m from the cube");
        assert_eq!(p.move_to(CUBE), Status::Success, "already there");
    }

    #[test]
    fn pick_takes_its_ticks_and_fails_out_of_reach() {
        let mut p = Plant::new();
        assert_eq!(p.pick(CUBE, true), Status::Failure, "the cube is 3 m away");
        p.robot = Vec2::new(2.6, 0.0);
        assert_eq!(p.pick(CUBE, true), Status::Running);
        assert_eq!(p.pick(CUBE, false), Status::Running);
        assert_eq!(p.pick(CUBE, false), Status::Success);
        assert!(p.holding(CUBE));
        assert_eq!(p.cube, p.gripper());
        assert_eq!(p.pick(CUBE, true), Status::Failure, "the hand is full");
    }

    #[test]
    fn clear_path_sets_the_sphere_aside_within_reach() {
        let mut p = Plant::new();
        p.robot = Vec2::new(3.0, 0.0);
        p.facing = Vec2::new(0.0, 1.0);
        p.sphere = Vec2::new(3.0, 0.5);
        assert!(!p.path_free(GOAL));
        assert_eq!(p.clear_path(SPHERE, GOAL, true), Status::Running);
        for _ in 2..CLEAR_TICKS {
            assert_eq!(p.clear_path(SPHERE, GOAL, false), Status::Running);
        }
        assert_eq!(p.clear_path(SPHERE, GOAL, false), Status::Success);
        assert!(p.path_free(GOAL));
        assert!(p.near(SPHERE), "set down within reach");
        assert_eq!(p.counters.clears, 1);
    }

    #[test]
    fn nonsense_arguments_fail() {
        let mut p = Plant::new();
        let ctx = Context { node: 0, now: 0, starting: true, values: &[] };
        for (behavior, args) in [(NEAR, &[9u16][..]), (AT, &[GOAL, CUBE]), (PICK, &[GOAL]), (MOVE_TO, &[7])] {
            let leaf = Leaf::with_args(behavior, args).unwrap();
            let r = if behavior < MOVE_TO { p.condition(&leaf, ctx) } else { p.action(&leaf, ctx) };
            assert_eq!(r, Status::Failure, "behavior {behavior} {args:?}");
        }
    }

    #[test]
    fn the_digest_sees_the_smallest_change() {
        let p = Plant::new();
        let mut q = p.clone();
        q.robot.x = f32::from_bits(q.robot.x.to_bits() + 1);
        assert_ne!(p.digest(), q.digest());
        assert_eq!(p.digest(), p.clone().digest());
    }
}
