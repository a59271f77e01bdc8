//! The four brick tasks of Styrud et al. on rapier3d.
//!
//! # The world
//!
//! - **Table**: a fixed slab, top face at z = 0.
//! - **Bricks**: dynamic boxes, long side along y ([`dimensions`]): a 2x2 brick is
//!   0.031 x 0.031 x 0.0192 m and 6 g, a 4x2 twice as long (12 g), the balance task's 8x2
//!   four times (24 g) with a solid 2x2 block of 24 g on its +y end, which puts the centre
//!   of mass 23 mm off-centre: it tips on a 2x2 base (half-width 15.5 mm) and stands on a
//!   4x2 lying along y (half-length 31 mm). The blocking task's brick 2 carries a cone
//!   (30 mm tall) on its top. Every brick but the cone brick has a 2 mm stud layer on
//!   top, so an unpressed brick rests 2 mm high, as in the reference. Friction 0.5,
//!   no restitution.
//! - **Gripper**: a kinematic two-finger gripper. Its tool point (between the
//!   fingertips) moves in straight lines at [`BrickParams::speed`]; between places it
//!   travels at [`BrickParams::travel_height`]. Its geometry — two fingers 4 x 16 x 51
//!   mm closing along x on the brick's long faces, and a palm 55 mm above the fingertips
//!   (high enough to clear the cone) — takes part in no contact: every motion is
//!   *guarded*, a shape cast of the fingers, the palm and the held brick along the
//!   motion, and stops at the first contact, which makes the action fail.
//! - **Grasp**: when the fingers close on a brick a fixed joint is created between the
//!   gripper and the brick (friction grasping of 6 g bricks by a kinematic gripper
//!   jitters), holding it centred between the fingertips and upright; it is removed
//!   when the fingers open. Grasping a brick of a pressed assembly lifts the assembly.
//!   Bricks sitting loose and aligned on what is grasped (the on-top test below) ride
//!   along on its studs, as on a real brick: they follow it kinematically until the
//!   fingers open, and a place onto one of them fails at once. (The symbolic world
//!   leaves them hanging where they were; here the alternative was a lift that stops
//!   at the brick on top.)
//! - **Studs**: pressing a brick that sits aligned on another (the reference's on-top
//!   test: |dx|, |dy| < 3 mm, 0 < dz <= 22.2 mm) fixes it exactly one brick height above
//!   the lower one, as studs would: both become one rigid body (bricks whose tops the
//!   pressed brick also overlaps at the same level join too, so the croissant's long
//!   brick snaps onto all three bricks under it). A fixed joint was tried first: a
//!   jointed pair of 6 g bodies shoves a brick landing on it sideways by millimetres.
//!
//! # Time
//!
//! One tick is 0.1 s (10 Hz) of [`BrickParams::steps_per_tick`] rapier steps. An
//! episode alternates `exec.tick(&mut world, t)` and [`worlds::World::step`]. An action
//! returns Running on its first tick (it only plans its motion) and reports its outcome
//! on the tick after the motion ends; it fails when it has not completed 50 ticks after
//! it started. A halted action stops the gripper where it is; the grasp stays as it is.
//! An action halted and started again within the same tick carries on, as in the
//! symbolic world ([`HaltRule`], default `ResumeWithinTick`): the GP idiom
//! `s( pick 1! place on 0! )` restarts `pick 1!` every tick (it succeeds at once while
//! the brick is held), which halts the place before the tick reaches it again. Unlike
//! the symbolic world, the brick is let go before the place reports (the fingers open
//! and the gripper rises), so there the idiom picks the brick up again: a real robot
//! ticking that tree would too.
//!
//! # Perception
//!
//! While the gripper holds a brick, the tree sees every brick where it was when the
//! fingers closed; once they open it sees the bodies as they are. This is what the
//! published AGX behaviors of Styrud et al. do for `at pos` ("don't update when currently
//! gripping a brick or it might end prematurely"), extended to `on` and to the puts'
//! "already there" shortcuts so that all of them agree. Without it a multi-tick put
//! exposes its brick in mid-air to the reactive tree: in the blocking task, `put 0 at
//! A!` lifting brick 0 off brick 1 makes an earlier `put 0 on 1!` in the same sequence
//! start again and carry it back, and the two undo each other until the tick limit
//! (the symbolic world, where a put takes effect at once, never shows that state).
//! `picked b?` is live.
//!
//! # Behaviors
//!
//! Conditions: `picked b?` is the grasp joint; `b at pos P?` is the distance of b's
//! reference point from P below 1 mm; `i on j?` is the on-top test above; both as the
//! tree sees the bricks (*Perception*).
//! Actions, with the reference's shortcuts when they start:
//!
//! - `pick b!`: succeeds at once if b is held, fails at once if another brick is. Rise
//!   to travel height, move over b, descend with open fingers, close, lift.
//! - `place at P!` / `place on b!`: fail at once on an empty hand. Rise, move over P
//!   (or over b's top, studs included), descend until the held brick is 0.5 mm above
//!   its place, open, rise. A descent that meets anything (an occupied spot, a brick
//!   overhanging it, the cone) stops: the action fails and the brick stays held.
//! - `put i at P!` / `put i on j!`: succeed at once if i is already there as the tree
//!   sees it; fail at once if another brick is held; otherwise pick (unless i is held)
//!   then place.
//! - `apply force b!`: fails at once while holding. Rise, close the fingers fully, move
//!   over b, descend onto its top (stopping early on anything above it: the force then
//!   goes through that), press for 0.2 s, rise. If b sits aligned on a brick, it is
//!   fixed to it. Succeeds whenever the hand was empty.

use bt_core::{BehaviorSet, Context, Leaf, NodeId, Status};
use planner::duplo::{BRICK_HEIGHT, Behavior, Spec};
use rapier3d::parry::shape::{Cuboid, SharedShape};
use rapier3d::prelude::{
    ColliderHandle, FixedJointBuilder, ImpulseJointHandle, PhysicsWorld, Pose, RigidBodyHandle, RigidBodyType, Vector,
};

use super::PhysicsError;
use super::bricks::{self, STUD_HEIGHT};
use super::engine;

mod events;
mod grasp;
mod motion;
mod params;

use crate::symbolic::HaltRule;
use crate::text::count;
use crate::world::BrickWorld;
pub use events::BrickEvent;
pub use params::BrickParams;

/// Length of the step that finds contacts after bodies were moved by hand, s.
const REFRESH_DT: f32 = 1e-5;

/// Seconds per tick (10 Hz).
pub const TICK_SECONDS: f32 = 0.1;
/// Ticks after which an action that has not completed fails.
pub const ACTION_TIMEOUT_TICKS: u32 = 50;
/// `at pos` margin, m.
pub const POSITION_MARGIN: f32 = 0.001;
/// `on` margin in x and y, m.
pub const ON_TOP_MARGIN: f32 = 0.003;
/// Highest dz for `on`: one brick, the studs, and 1 mm, m.
pub const ON_TOP_MAX_DZ: f32 = BRICK_HEIGHT + STUD_HEIGHT + 0.001;

/// Tool point height above a held brick's reference point: the fingers grip the middle
/// of the brick.
const GRIP_HEIGHT: f32 = BRICK_HEIGHT / 2.0;
/// Gap left under a brick being placed before the fingers open, m.
const PLACE_CLEARANCE: f32 = 0.00005;
/// A place descends at speed to this height above the brick's place and covers the
/// rest, and opens, within one rapier step: a held brick is never inside the margins of
/// `at pos` or `on` at a tick boundary, so a reactive tree never sees its goal reached
/// (and halts the place) while the brick is still in the fingers.
const APPROACH: f32 = 0.003;
/// Fingertips below the tool point, m.
const FINGERTIP_DEPTH: f32 = 0.006;
/// Finger half-thickness (x), half-width (y) and top above the tool point, m.
const FINGER_HX: f32 = 0.002;
const FINGER_HY: f32 = 0.008;
const FINGER_TOP: f32 = 0.045;
/// Palm half-extents, m; it sits on top of the fingers.
const PALM: [f32; 3] = [0.025, 0.012, 0.005];
/// Finger gaps (fingertip inner face from the tool point along x), m.
const OPEN: f32 = 0.0155 + 0.003;
const ON_BRICK: f32 = 0.0155;
const SHUT: f32 = 0.0;
/// Finger speed, m/s.
const FINGER_SPEED: f32 = 0.05;
/// How long `apply force` presses, s.
const PRESS_SECONDS: f32 = 0.2;
/// A grasp fails on a brick tilted more than this (cosine of the angle: 45°).
const GRASP_MIN_UPRIGHT: f32 = core::f32::consts::FRAC_1_SQRT_2;
/// How far the tool point may be from the brick when the fingers close, m.
const GRASP_TOLERANCE: f32 = 0.004;

/// Where a motion goes: resolved to a tool-point position when the motion starts.
#[derive(Clone, Copy, Debug)]
enum Spot {
    /// Grasp height of brick b.
    Grasp(u8),
    /// Place the held brick with its reference point at P.
    At([f32; 3]),
    /// Place the held brick on top of brick b.
    On(u8),
    /// Fingertips just above brick b's top.
    Press(u8),
}

#[derive(Clone, Copy, Debug)]
enum Phase {
    /// Straight up to travel height.
    Rise,
    /// At travel height, over the spot.
    Over(Spot),
    /// Guarded descent to the spot (for places: to [`APPROACH`] above it).
    Descend(Spot),
    /// The last [`APPROACH`] of a place and the release, within one rapier step.
    SetDown(Spot),
    /// Fingers to a gap.
    Fingers(f32),
    /// Attach brick b.
    Grasp(u8),
    /// Press brick b for a while, then fix it.
    Press(u8),
}

/// The running action.
#[derive(Debug)]
struct Job {
    node: NodeId,
    ticks: u32,
    phases: Vec<Phase>,
    next: usize,
    /// Tool point target of the current motion and whether it started.
    target: Option<Vector>,
    /// Steps left in a timed phase.
    wait: u32,
    outcome: Option<Status>,
}

/// A brick task on rapier3d: implements [`BrickWorld`] (and so `bt_core::BehaviorSet`)
/// over [`planner::duplo::Spec`]. See the module docs for the physics.
pub struct PhysicsBrickWorld {
    spec: Spec,
    params: BrickParams,
    world: PhysicsWorld,
    bricks: Vec<RigidBodyHandle>,
    gripper: RigidBodyHandle,
    tool: Vector,
    gap: f32,
    grasp: Option<(u8, ImpulseJointHandle)>,
    /// Every brick's position when the fingers last closed on a brick: what conditions
    /// see while the grasp lasts.
    at_grasp: Vec<Vector>,
    /// Bodies resting on what is held when the fingers closed (a brick sitting loose on
    /// the studs of the lifted one): they ride along, kinematic, each with its pose in
    /// the held body's frame, until the fingers open.
    riders: Vec<(RigidBodyHandle, Pose)>,
    /// Per brick: the body carrying it (its own, or that of the pressed assembly it is
    /// part of) and its frame in that body's frame.
    carrier: Vec<(RigidBodyHandle, Pose)>,
    /// Per brick: its colliders and their poses in the brick's frame.
    shapes: Vec<Vec<(ColliderHandle, Pose)>>,
    /// Per brick: the brick it was pressed onto, aligned.
    below: Vec<Option<u8>>,
    /// Bodies were moved by hand or rebuilt: contacts must be found again before the
    /// next step (rapier solves a step with the contacts found at the end of the last).
    moved: bool,
    job: Option<Job>,
    /// Jobs halted since the last step, kept for [`HaltRule::ResumeWithinTick`].
    halted: Vec<Job>,
    halt_rule: HaltRule,
    tick: u32,
    events: Vec<BrickEvent>,
}

impl core::fmt::Debug for PhysicsBrickWorld {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("PhysicsBrickWorld")
            .field("task", &self.spec.task)
            .field("tick", &self.tick)
            .field("tool", &self.tool)
            .field("held", &self.held())
            .finish_non_exhaustive()
    }
}

impl PhysicsBrickWorld {
    /// A fresh world for `spec` with the default parameters.
    ///
    /// # Errors
    /// [`PhysicsError::BadSpec`] when the spec's brick, start and goal lists differ in
    /// length or a start position is not finite.
    pub fn new(spec: &Spec) -> Result<Self, PhysicsError> {
        Self::with_params(spec, BrickParams::default())
    }

    /// A fresh world for `spec` with `params`.
    ///
    /// # Errors
    /// As [`PhysicsBrickWorld::new`], and [`PhysicsError::BadParameter`].
    pub fn with_params(spec: &Spec, params: BrickParams) -> Result<Self, PhysicsError> {
        params.check()?;
        let bad = |what: String| PhysicsError::BadSpec { task: spec.task.name(), what };
        if spec.start.len() != spec.bricks.len() || spec.goal.len() != spec.bricks.len() {
            return Err(bad(format!(
                "{}, {}, {}",
                count(spec.bricks.len(), "brick"),
                count(spec.start.len(), "start position"),
                count(spec.goal.len(), "goal")
            )));
        }
        if spec.bricks.len() > usize::from(u8::MAX) {
            return Err(bad(format!("{}; at most 255", count(spec.bricks.len(), "brick"))));
        }
        if let Some(i) = spec.start.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            return Err(bad(format!("start position of brick {i} is not finite")));
        }
        let dt = TICK_SECONDS / params.steps_per_tick as f32;
        let mut world = engine::new_world(dt, params.solver_iterations, 0.01);
        world.integration_parameters.num_internal_pgs_iterations = params.pgs_iterations;
        bricks::insert_table(&mut world);
        let bricks: Vec<RigidBodyHandle> =
            spec.bricks.iter().zip(&spec.start).map(|(&k, &at)| bricks::insert(&mut world, k, at)).collect();
        let tool = Vector::new(0.0, 0.0, params.travel_height);
        let gripper =
            world.bodies.insert(rapier3d::prelude::RigidBodyBuilder::kinematic_position_based().translation(tool));
        Ok(Self {
            below: vec![None; bricks.len()],
            moved: false,
            carrier: bricks.iter().map(|&h| (h, Pose::IDENTITY)).collect(),
            shapes: bricks
                .iter()
                .map(|&h| {
                    let handles = world.bodies.get(h).map(|b| b.colliders().to_vec()).unwrap_or_default();
                    handles
                        .into_iter()
                        .map(|c| {
                            let local = world.colliders.get(c).and_then(|c| c.position_wrt_parent().copied());
                            (c, local.unwrap_or(Pose::IDENTITY))
                        })
                        .collect()
                })
                .collect(),
            spec: spec.clone(),
            params,
            world,
            bricks,
            gripper,
            tool,
            gap: OPEN,
            grasp: None,
            at_grasp: Vec::new(),
            riders: Vec::new(),
            job: None,
            halted: Vec::new(),
            halt_rule: HaltRule::default(),
            tick: 0,
            events: Vec::new(),
        })
    }

    /// Uses another [`HaltRule`] (default: [`HaltRule::ResumeWithinTick`], as in the
    /// symbolic world and for the same reason).
    #[must_use]
    pub fn with_halt_rule(mut self, rule: HaltRule) -> Self {
        self.halt_rule = rule;
        self
    }

    /// The [`HaltRule`] in force.
    #[must_use]
    pub fn halt_rule(&self) -> HaltRule {
        self.halt_rule
    }

    /// Ticks stepped so far.
    #[must_use]
    pub fn tick(&self) -> u32 {
        self.tick
    }

    /// The gripper's tool point (between the fingertips), m.
    #[must_use]
    pub fn gripper(&self) -> [f32; 3] {
        self.tool.to_array()
    }

    /// Full pose of brick `brick`: position of its reference point and orientation as a
    /// quaternion (x, y, z, w).
    #[must_use]
    pub fn pose(&self, brick: usize) -> Option<([f32; 3], [f32; 4])> {
        let p = self.pose_of(u8::try_from(brick).ok()?)?;
        Some((p.translation.to_array(), p.rotation.to_array()))
    }

    /// The brick that `brick` is fixed onto by a press, if any.
    #[must_use]
    pub fn fixed_below(&self, brick: usize) -> Option<u8> {
        self.below.get(brick).copied().flatten()
    }

    /// What happened so far, in order.
    #[must_use]
    pub fn events(&self) -> &[BrickEvent] {
        &self.events
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> BrickParams {
        self.params
    }

    /// The body carrying brick b.
    fn body(&self, brick: u8) -> Option<RigidBodyHandle> {
        self.carrier.get(usize::from(brick)).map(|&(h, _)| h)
    }

    fn pose_of(&self, brick: u8) -> Option<Pose> {
        let &(body, offset) = self.carrier.get(usize::from(brick))?;
        Some(*self.world.bodies.get(body)?.position() * offset)
    }

    /// Brick b and every brick pressed together with it, in index order.
    fn assembly(&self, brick: u8) -> Vec<u8> {
        let Some(body) = self.body(brick) else { return Vec::new() };
        (0..self.carrier.len())
            .filter(|&k| self.carrier.get(k).is_some_and(|&(h, _)| h == body))
            .filter_map(|k| u8::try_from(k).ok())
            .collect()
    }

    /// Where the grasp holds the brick in the fingers.
    fn grasp_pose(&self) -> Pose {
        Pose::from_translation(self.tool - Vector::new(0.0, 0.0, GRIP_HEIGHT))
    }

    fn pos(&self, brick: u8) -> Vector {
        self.pose_of(brick).map_or(Vector::splat(f32::NAN), |p| p.translation)
    }

    /// The brick a collider belongs to.
    fn brick_of(&self, collider: ColliderHandle) -> Option<u8> {
        let i = self.shapes.iter().position(|cs| cs.iter().any(|&(c, _)| c == collider))?;
        u8::try_from(i).ok()
    }

    /// Where the tree sees brick b: where it is, or while the gripper holds a brick,
    /// where it was when the fingers closed (see the module docs, *Perception*).
    fn seen(&self, brick: u8) -> Vector {
        match self.grasp {
            Some(_) => self.at_grasp.get(usize::from(brick)).copied().unwrap_or(Vector::splat(f32::NAN)),
            None => self.pos(brick),
        }
    }

    /// The reference's on-top test on two positions.
    fn on_top(upper: Vector, lower: Vector) -> bool {
        let d = upper - lower;
        d.x.abs() < ON_TOP_MARGIN && d.y.abs() < ON_TOP_MARGIN && d.z > 0.0 && d.z <= ON_TOP_MAX_DZ
    }

    /// `i on j`, as the tree sees it.
    fn is_on(&self, i: u8, j: u8) -> bool {
        i != j && Self::on_top(self.seen(i), self.seen(j))
    }

    /// `brick at pos p`, as the tree sees it.
    fn is_at(&self, brick: u8, p: [f32; 3]) -> bool {
        (self.seen(brick) - Vector::from_array(p)).length() < POSITION_MARGIN
    }

    fn position_of(&self, p: planner::duplo::Position) -> Option<[f32; 3]> {
        self.spec.position(p)
    }

    fn held_brick(&self) -> Option<u8> {
        self.grasp.map(|(b, _)| b)
    }

    fn known_brick(&self, b: u8) -> bool {
        usize::from(b) < self.bricks.len()
    }

    fn condition_of(&self, behavior: Behavior) -> Status {
        let ok = match behavior {
            Behavior::Picked(b) => self.held_brick() == Some(b),
            Behavior::AtPos(b, p) => self.known_brick(b) && self.position_of(p).is_some_and(|at| self.is_at(b, at)),
            Behavior::On(i, j) => self.known_brick(i) && self.known_brick(j) && self.is_on(i, j),
            _ => false,
        };
        if ok { Status::Success } else { Status::Failure }
    }

    fn quiet(&self) -> bool {
        self.job.as_ref().is_none_or(|j| j.outcome.is_some())
            && self.carrier.iter().all(|&(h, _)| self.world.bodies.get(h).is_none_or(|b| b.is_sleeping()))
    }
}

impl worlds::World for PhysicsBrickWorld {
    fn reset(&mut self) {
        // The spec and parameters were checked when the world was made, so rebuilding
        // from them cannot fail; a rapier world has no cheaper exact reset.
        if let Ok(fresh) = Self::with_params(&self.spec, self.params) {
            *self = fresh.with_halt_rule(self.halt_rule);
        }
    }

    /// Advances the physics by one tick. Actions halted during the tick are forgotten.
    fn step(&mut self) {
        self.halted.clear();
        let dt = self.world.integration_parameters.dt;
        for _ in 0..self.params.steps_per_tick {
            if self.quiet() {
                // Nothing moves and nothing will: skipping the step changes nothing.
                break;
            }
            self.advance_job(dt);
            if core::mem::take(&mut self.moved) {
                // A step of 10 us finds the contacts where the bodies now are.
                self.world.integration_parameters.dt = REFRESH_DT;
                self.world.step();
                self.world.integration_parameters.dt = dt;
            }
            self.world.step();
        }
        self.tick = self.tick.saturating_add(1);
    }
}

impl BrickWorld for PhysicsBrickWorld {
    fn spec(&self) -> &Spec {
        &self.spec
    }

    fn position(&self, brick: usize) -> [f32; 3] {
        u8::try_from(brick).map_or([f32::NAN; 3], |b| self.pos(b).to_array())
    }

    fn held(&self) -> Option<u8> {
        self.held_brick()
    }
}

impl BehaviorSet for PhysicsBrickWorld {
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        self.spec.behavior(leaf.behavior()).map_or(Status::Failure, |b| self.condition_of(b))
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let Some(behavior) = self.spec.behavior(leaf.behavior()) else { return Status::Failure };
        let mut resumed = false;
        if ctx.starting
            && let Some(i) = self.halted.iter().position(|j| j.node == ctx.node)
        {
            // Halted and started again within the tick (ResumeWithinTick): carry on.
            self.job = Some(self.halted.swap_remove(i));
            resumed = true;
        }
        let ours = self.job.as_ref().is_some_and(|j| j.node == ctx.node);
        if (ctx.starting && !resumed) || !ours {
            self.job = None;
            return match self.plan(behavior) {
                Err(status) => status,
                Ok(phases) => {
                    self.job =
                        Some(Job { node: ctx.node, ticks: 0, phases, next: 0, target: None, wait: 0, outcome: None });
                    Status::Running
                }
            };
        }
        let Some(job) = self.job.as_mut() else { return Status::Failure };
        job.ticks += 1;
        let outcome = match job.outcome {
            Some(s) => s,
            None if job.ticks >= ACTION_TIMEOUT_TICKS => Status::Failure,
            None => return Status::Running,
        };
        self.job = None;
        outcome
    }

    /// Stops the action where it is. Under [`HaltRule::ResumeWithinTick`] its job is
    /// kept until the next step, in case the tick comes back to it.
    fn halt(&mut self, _: &Leaf, node: NodeId) {
        if self.job.as_ref().is_some_and(|j| j.node == node)
            && let Some(job) = self.job.take()
            && self.halt_rule == HaltRule::ResumeWithinTick
        {
            self.halted.push(job);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner::duplo::Task;
    use worlds::World as _;

    #[test]
    fn bricks_start_where_the_reference_puts_them() {
        for task in Task::ALL {
            let spec = task.spec();
            let mut w = PhysicsBrickWorld::new(&spec).unwrap();
            for _ in 0..5 {
                w.step();
            }
            for (i, start) in spec.start.iter().enumerate() {
                let p = w.position(i);
                let d = (Vector::from_array(p) - Vector::from_array(*start)).length();
                assert!(d < 2e-4, "{task:?} brick {i} at {p:?}, start {start:?}");
            }
        }
    }

    #[test]
    fn the_long_brick_tips_on_a_2x2_and_stands_on_a_4x2() {
        let d = bricks::dimensions(planner::duplo::BrickKind::LongUnbalanced);
        assert!(d.mass_offset_y > bricks::dimensions(planner::duplo::BrickKind::TwoByTwo).y / 2.0);
        assert!(d.mass_offset_y < bricks::dimensions(planner::duplo::BrickKind::FourByTwo).y / 2.0);
    }

    #[test]
    fn a_bad_spec_is_an_error() {
        let mut spec = Task::Tower.spec();
        spec.start.pop();
        assert!(matches!(PhysicsBrickWorld::new(&spec), Err(PhysicsError::BadSpec { .. })));
        let p = BrickParams { steps_per_tick: 0, ..BrickParams::default() };
        assert!(matches!(
            PhysicsBrickWorld::with_params(&Task::Tower.spec(), p),
            Err(PhysicsError::BadParameter { name: "steps_per_tick", .. })
        ));
    }
}
