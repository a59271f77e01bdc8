//! The mobile manipulator of Colledanchise et al. 2019 Fig. 1 on rapier3d: a base moving in the plane,
//! a gripper, the cube, the sphere and the goal region, with external agents.
//!
//! # The world
//!
//! - **Floor**: a fixed slab, top face at z = 0. The goal region is the square of side
//!   [`GOAL_SIZE`] centred at [`GOAL`].
//! - **Base**: kinematic, a [`BASE_HALF`] square footprint, moving in straight lines at
//!   most [`BASE_SPEED`]. Like the brick gripper it takes part in no contact: its motion
//!   is guarded by a shape cast of the footprint and stops at the first contact.
//! - **Cube** (object 0): a 0.1 m dynamic box of 0.5 kg. **Sphere** (object 1): a
//!   dynamic ball of radius 0.15 m and 1 kg, damped so it does not roll forever.
//! - **Gripper**: holds an item by a fixed joint to the base, in front of it at
//!   [`HOLD_HEIGHT`].
//!
//! # Behaviors
//!
//! Exactly the cube-sphere contract (`planner/domains/cube-sphere/domain.pddl`): ids are
//! [`CATALOG`]'s indices; arguments are objects (cube = 0, sphere = 1, goal = 2).
//!
//! - `at(i, s)`: item i lies inside the goal region (s must be the goal).
//! - `holding(i)`, `hand-empty`: the grasp joint.
//! - `near(l)`: the base is within [`NEAR`] of l (planar distance, centre to centre).
//! - `path-free(l)`: a shape cast of the base's footprint along the straight path to l
//!   (up to where it would be near l) hits nothing but l itself and what is held.
//! - `obstacle(i)`: static: the sphere.
//! - `move-to(l)`: drives towards l until near it; fails when its guarded motion meets
//!   something.
//! - `pick(i)`: needs near(i) and an empty hand; reaches for 0.5 s, then holds i.
//! - `place(i, s)`: needs holding(i) and near(s); sets i down at the goal's centre.
//! - `drop(i)`: needs holding(i); sets i down [`SET_ASIDE`] beside the robot, off its
//!   straight path to the goal.
//! - `clear-path(i, l)`: needs obstacle(i), near(i) and an empty hand; reaches for 0.5 s,
//!   then lifts i and sets it down [`CLEAR_OFFSET`] aside of the straight line from the
//!   base to l.
//!
//! Actions return Running on their first tick and fail after 50 ticks without
//! completing, as in the brick world; `move-to` gets the ticks its straight drive takes
//! plus [`MOVE_MARGIN_TICKS`] when that is longer (the drive from the start to the goal
//! alone takes 51).
//!
//! # External agents
//!
//! [`Agent`] acts happen between ticks, before the world steps into the next tick
//! ([`MobileWorld::apply`], whose event carries that tick): taking the cube from the
//! hand, rolling the sphere into the path to the goal and away again, handing the cube
//! to the robot, putting the cube on the goal. Who acts when is a [`worlds::Agent`]: a
//! script, a story or a seeded generator ([`crate::scenario::agents`]);
//! [`MobileWorld::events`] is the narration.

use bt_core::{BehaviorInfo, BehaviorSet, Context, Leaf, NodeId, Status};
use rapier3d::parry::shape::Cuboid;
use rapier3d::prelude::{
    ColliderBuilder, FixedJointBuilder, ImpulseJointHandle, PhysicsWorld, Pose, RigidBodyBuilder, RigidBodyHandle,
    Vector,
};

use super::engine;

mod acts;

pub use acts::{Agent, MobileEvent};

/// The behavior set, in the contract's order: predicates, then actions.
pub const CATALOG: [BehaviorInfo<'static>; 11] = [
    BehaviorInfo::condition("at", 2),
    BehaviorInfo::condition("holding", 1),
    BehaviorInfo::condition("hand-empty", 0),
    BehaviorInfo::condition("near", 1),
    BehaviorInfo::condition("path-free", 1),
    BehaviorInfo::condition("obstacle", 1),
    BehaviorInfo::action("move-to", 1),
    BehaviorInfo::action("pick", 1),
    BehaviorInfo::action("place", 2),
    BehaviorInfo::action("drop", 1),
    BehaviorInfo::action("clear-path", 2),
];

/// Object indices of the problem.
pub const CUBE: u16 = 0;
/// The sphere.
pub const SPHERE: u16 = 1;
/// The goal region.
pub const GOAL_OBJECT: u16 = 2;

/// Where the cube lies at the start, m: off the straight line from the robot's start
/// to the goal, so that only the sphere can block that path.
pub const CUBE_START: [f32; 2] = [1.0, -1.0];
/// Centre of the goal region, m.
pub const GOAL: [f32; 2] = [3.0, 0.0];
/// Side of the goal region, m.
pub const GOAL_SIZE: f32 = 0.6;
/// Half-extents of the base's footprint (x, y) and its height, m.
pub const BASE_HALF: [f32; 3] = [0.2, 0.2, 0.15];
/// Base speed limit, m/s.
pub const BASE_SPEED: f32 = 0.5;
/// `near` distance, m.
pub const NEAR: f32 = 0.5;
/// Height at which the gripper holds an item, m.
pub const HOLD_HEIGHT: f32 = 0.4;
/// How far beside itself the robot drops something (`drop`), and an agent puts the
/// cube it takes from the gripper, m.
pub const SET_ASIDE: f32 = 0.6;
/// How far `clear-path` moves the obstacle aside, m.
pub const CLEAR_OFFSET: f32 = 1.0;

const CUBE_HALF: f32 = 0.05;
const SPHERE_RADIUS: f32 = 0.15;
const STEPS_PER_TICK: u32 = 2;
const REACH_TICKS: u32 = 5;
/// Ticks a drive may take beyond its straight path's before it fails.
pub const MOVE_MARGIN_TICKS: u32 = 10;
/// A move-to has arrived when it is this close to its stopping distance, m.
const ARRIVED: f32 = 1e-4;

#[derive(Clone, Copy, Debug)]
enum Job {
    MoveTo(u16),
    Reach { item: u16, left: u32 },
    Carry { to: [f32; 2], then_release: bool, left: u32 },
    Clear { to: [f32; 2], left: u32 },
}

#[derive(Debug)]
struct Running {
    node: NodeId,
    ticks: u32,
    /// Ticks after which it fails if it has not completed.
    limit: u32,
    job: Job,
    outcome: Option<Status>,
}

/// The world of Colledanchise et al. 2019 Fig. 1. See the module docs.
pub struct MobileWorld {
    world: PhysicsWorld,
    base: RigidBodyHandle,
    base_at: [f32; 2],
    items: [RigidBodyHandle; 2],
    grasp: Option<(u16, ImpulseJointHandle)>,
    running: Option<Running>,
    tick: u32,
    events: Vec<MobileEvent>,
}

impl core::fmt::Debug for MobileWorld {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("MobileWorld").field("tick", &self.tick).field("base", &self.base_at).finish_non_exhaustive()
    }
}

impl Default for MobileWorld {
    fn default() -> Self {
        Self::new()
    }
}

impl MobileWorld {
    /// The start of Example 1: robot at the origin, cube at [`CUBE_START`], sphere at (1.5, 1.5)
    /// off every path, the goal at (3, 0); no agents.
    #[must_use]
    pub fn new() -> Self {
        let mut world = engine::new_world(super::brick_world::TICK_SECONDS / STEPS_PER_TICK as f32, 4, 0.1);
        let floor = world.bodies.insert(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -0.05)));
        world.colliders.insert_with_parent(ColliderBuilder::cuboid(10.0, 10.0, 0.05), floor, &mut world.bodies);
        let cube = world.bodies.insert(RigidBodyBuilder::dynamic().translation(Vector::new(
            CUBE_START[0],
            CUBE_START[1],
            CUBE_HALF,
        )));
        world.colliders.insert_with_parent(
            ColliderBuilder::cuboid(CUBE_HALF, CUBE_HALF, CUBE_HALF).mass(0.5).friction(0.8),
            cube,
            &mut world.bodies,
        );
        let sphere = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(1.5, 1.5, SPHERE_RADIUS))
                .angular_damping(5.0)
                .linear_damping(2.0),
        );
        world.colliders.insert_with_parent(
            ColliderBuilder::ball(SPHERE_RADIUS).mass(1.0).friction(0.8),
            sphere,
            &mut world.bodies,
        );
        let base = world.bodies.insert(RigidBodyBuilder::kinematic_position_based().translation(Vector::ZERO));
        Self {
            world,
            base,
            base_at: [0.0, 0.0],
            items: [cube, sphere],
            grasp: None,
            running: None,
            tick: 0,
            events: Vec::new(),
        }
    }

    /// Ticks stepped so far.
    #[must_use]
    pub fn tick(&self) -> u32 {
        self.tick
    }

    /// The base's position in the plane, m.
    #[must_use]
    pub fn base(&self) -> [f32; 2] {
        self.base_at
    }

    /// Position of the cube (0) or the sphere (1), m.
    #[must_use]
    pub fn item(&self, item: u16) -> Option<[f32; 3]> {
        let h = *self.items.get(usize::from(item))?;
        Some(self.world.bodies.get(h)?.translation().to_array())
    }

    /// The item in the gripper.
    #[must_use]
    pub fn held(&self) -> Option<u16> {
        self.grasp.map(|(i, _)| i)
    }

    /// The narration so far.
    #[must_use]
    pub fn events(&self) -> &[MobileEvent] {
        &self.events
    }

    fn say(&mut self, text: impl Into<String>) {
        self.events.push(MobileEvent { tick: self.tick, text: text.into() });
    }

    fn location(&self, l: u16) -> Option<[f32; 2]> {
        if l == GOAL_OBJECT {
            return Some(GOAL);
        }
        self.item(l).map(|p| [p[0], p[1]])
    }

    fn near(&self, l: u16) -> bool {
        self.location(l).is_some_and(|p| dist(p, self.base_at) <= NEAR)
    }

    fn in_goal(&self, i: u16) -> bool {
        self.item(i).is_some_and(|p| {
            (p[0] - GOAL[0]).abs() <= GOAL_SIZE / 2.0 && (p[1] - GOAL[1]).abs() <= GOAL_SIZE / 2.0 && p[2] < 0.3
        })
    }

    fn footprint() -> Cuboid {
        Cuboid::new(Vector::from_array(BASE_HALF))
    }

    /// What the footprint meets moving by `motion` from where the base is: ignoring the
    /// held item and `target`.
    fn blocked(&self, motion: [f32; 2], target: Option<u16>) -> bool {
        let mut ignore = vec![self.base];
        ignore.extend(self.held().and_then(|i| self.items.get(usize::from(i)).copied()));
        ignore.extend(target.and_then(|i| self.items.get(usize::from(i)).copied()));
        let pose = Pose::from_translation(Vector::new(self.base_at[0], self.base_at[1], BASE_HALF[2] + 0.01));
        let motion = Vector::new(motion[0], motion[1], 0.0);
        engine::sweep(&self.world, &Self::footprint(), &pose, motion, &ignore).is_some()
    }

    /// The straight path to l, up to where the base would be near l.
    fn path_free(&self, l: u16) -> bool {
        let Some(to) = self.location(l) else { return false };
        let d = dist(to, self.base_at);
        if d <= NEAR {
            return true;
        }
        let k = (d - NEAR * 0.9) / d;
        let motion = [(to[0] - self.base_at[0]) * k, (to[1] - self.base_at[1]) * k];
        !self.blocked(motion, Some(l))
    }

    /// Holds `item` by a fixed joint; a hand that already holds something is left as it
    /// is (a second joint would never be released).
    fn attach(&mut self, item: u16) {
        if self.grasp.is_some() {
            return;
        }
        let Some(&h) = self.items.get(usize::from(item)) else { return };
        let hand = self.hand();
        if let Some(b) = self.world.bodies.get_mut(h) {
            b.set_position(Pose::from_translation(hand), true);
            b.set_linvel(Vector::ZERO, true);
            b.set_angvel(Vector::ZERO, true);
        }
        let joint = FixedJointBuilder::new()
            .local_frame1(Pose::from_translation(hand - Vector::new(self.base_at[0], self.base_at[1], 0.0)))
            .contacts_enabled(false);
        let j = self.world.impulse_joints.insert(self.base, h, joint, true);
        self.grasp = Some((item, j));
    }

    fn release(&mut self, at: Option<[f32; 2]>) {
        let Some((item, j)) = self.grasp.take() else { return };
        self.world.impulse_joints.remove(j, true);
        let Some(&h) = self.items.get(usize::from(item)) else { return };
        if let Some(b) = self.world.bodies.get_mut(h) {
            let z = if item == CUBE { CUBE_HALF } else { SPHERE_RADIUS };
            let xy = at.unwrap_or([b.translation().x, b.translation().y]);
            b.set_position(Pose::from_translation(Vector::new(xy[0], xy[1], z + 0.001)), true);
            b.set_linvel(Vector::ZERO, true);
            b.set_angvel(Vector::ZERO, true);
        }
    }

    /// Where the robot sets something down to keep it out of its own way: [`SET_ASIDE`]
    /// to the right of the straight line from the base to the goal.
    fn beside(&self) -> [f32; 2] {
        let (dx, dy) = (GOAL[0] - self.base_at[0], GOAL[1] - self.base_at[1]);
        let n = (dx * dx + dy * dy).sqrt();
        let (px, py) = if n > 1e-3 { (dy / n, -dx / n) } else { (0.0, -1.0) };
        [self.base_at[0] + px * SET_ASIDE, self.base_at[1] + py * SET_ASIDE]
    }

    fn hand(&self) -> Vector {
        Vector::new(self.base_at[0] + BASE_HALF[0] + 0.1, self.base_at[1], HOLD_HEIGHT)
    }

    fn put(&mut self, item: u16, at: [f32; 2]) {
        let Some(&h) = self.items.get(usize::from(item)) else { return };
        let z = if item == CUBE { CUBE_HALF } else { SPHERE_RADIUS };
        if let Some(b) = self.world.bodies.get_mut(h) {
            b.set_position(Pose::from_translation(Vector::new(at[0], at[1], z + 0.001)), true);
            b.set_linvel(Vector::ZERO, true);
            b.set_angvel(Vector::ZERO, true);
        }
    }

    fn condition_of(&self, id: u16, args: &[u16]) -> bool {
        let a = |i: usize| args.get(i).copied().unwrap_or(u16::MAX);
        match id {
            0 => a(1) == GOAL_OBJECT && a(0) < 2 && self.in_goal(a(0)),
            1 => self.held() == Some(a(0)),
            2 => self.held().is_none(),
            3 => self.near(a(0)),
            4 => self.path_free(a(0)),
            5 => a(0) == SPHERE,
            _ => false,
        }
    }

    fn start(&mut self, id: u16, args: &[u16]) -> Result<Job, Status> {
        let a = |i: usize| args.get(i).copied().unwrap_or(u16::MAX);
        let fail = Err(Status::Failure);
        match id {
            6 if a(0) <= GOAL_OBJECT => {
                if self.near(a(0)) {
                    Err(Status::Success)
                } else {
                    Ok(Job::MoveTo(a(0)))
                }
            }
            7 if a(0) < 2 && self.near(a(0)) && self.held().is_none() => {
                Ok(Job::Reach { item: a(0), left: REACH_TICKS })
            }
            8 if a(0) < 2 && a(1) == GOAL_OBJECT && self.held() == Some(a(0)) && self.near(GOAL_OBJECT) => {
                Ok(Job::Carry { to: GOAL, then_release: true, left: REACH_TICKS })
            }
            9 if a(0) < 2 && self.held() == Some(a(0)) => {
                let aside = self.beside();
                self.release(Some(aside));
                self.say("the robot drops what it holds");
                Err(Status::Success)
            }
            10 if a(0) == SPHERE && self.near(SPHERE) && self.held().is_none() && a(1) <= GOAL_OBJECT => {
                let (Some(s), Some(l)) = (self.location(SPHERE), self.location(a(1))) else { return fail };
                // Aside of the line from the base to l, on the sphere's side.
                let (dx, dy) = (l[0] - self.base_at[0], l[1] - self.base_at[1]);
                let n = (dx * dx + dy * dy).sqrt().max(1e-6);
                let (px, py) = (-dy / n, dx / n);
                let side =
                    if (s[0] - self.base_at[0]) * px + (s[1] - self.base_at[1]) * py >= 0.0 { 1.0 } else { -1.0 };
                self.say("the robot reaches for the sphere to clear the path");
                Ok(Job::Clear {
                    to: [s[0] + side * px * CLEAR_OFFSET, s[1] + side * py * CLEAR_OFFSET],
                    left: REACH_TICKS,
                })
            }
            _ => fail,
        }
    }

    /// Ticks a job may take before it fails: [`ACTION_TIMEOUT_TICKS`], and for a drive
    /// the ticks its straight path takes at [`BASE_SPEED`] plus [`MOVE_MARGIN_TICKS`] if
    /// that is longer. (The start to the goal is 2.55 m, 51 ticks of driving: with a
    /// flat 50 it timed out whenever an agent handed over the cube before the robot
    /// had driven anywhere.)
    ///
    /// [`ACTION_TIMEOUT_TICKS`]: super::brick_world::ACTION_TIMEOUT_TICKS
    fn time_limit(&self, job: &Job) -> u32 {
        let flat = super::brick_world::ACTION_TIMEOUT_TICKS;
        let Job::MoveTo(l) = *job else { return flat };
        let Some(to) = self.location(l) else { return flat };
        let metres = (dist(to, self.base_at) - NEAR * 0.9).max(0.0);
        let drive = (metres / (BASE_SPEED * super::brick_world::TICK_SECONDS)).ceil();
        // At most the table's diagonal's worth of ticks; a NaN becomes 0.
        let drive = drive.min(10_000.0) as u32;
        flat.max(drive + MOVE_MARGIN_TICKS)
    }

    /// Advances the running job by one tick's worth of motion.
    fn advance(&mut self) {
        let Some(mut r) = self.running.take() else { return };
        if r.outcome.is_none() {
            r.outcome = match r.job {
                Job::MoveTo(l) => match self.location(l) {
                    None => Some(Status::Failure),
                    Some(to) => {
                        let d = dist(to, self.base_at);
                        let goal_d = NEAR * 0.9;
                        // Arrived within a tenth of a millimetre: the last step is cut
                        // to the remaining distance, and f32 rounding may leave a hair.
                        if d <= goal_d + ARRIVED {
                            Some(Status::Success)
                        } else {
                            let step = (d - goal_d).min(BASE_SPEED * super::brick_world::TICK_SECONDS);
                            let m = [(to[0] - self.base_at[0]) / d * step, (to[1] - self.base_at[1]) / d * step];
                            if self.blocked(m, Some(l)) {
                                self.say("the robot's path is blocked");
                                Some(Status::Failure)
                            } else {
                                self.base_at = [self.base_at[0] + m[0], self.base_at[1] + m[1]];
                                None
                            }
                        }
                    }
                },
                Job::Reach { item, left } => {
                    if left == 0 {
                        match self.held() {
                            // An agent handed it over while the robot reached for it.
                            Some(h) if h == item => Some(Status::Success),
                            Some(_) => Some(Status::Failure),
                            None => {
                                self.attach(item);
                                self.say(if item == CUBE {
                                    "the robot picks up the cube"
                                } else {
                                    "the robot picks up the sphere"
                                });
                                Some(Status::Success)
                            }
                        }
                    } else {
                        r.job = Job::Reach { item, left: left - 1 };
                        None
                    }
                }
                Job::Clear { to, left } if left > 0 => {
                    r.job = Job::Clear { to, left: left - 1 };
                    None
                }
                Job::Clear { to, .. } => {
                    self.put(SPHERE, to);
                    self.say("the robot lifts the sphere and sets it down out of the path");
                    Some(Status::Success)
                }
                Job::Carry { to, then_release, left } if left > 0 => {
                    r.job = Job::Carry { to, then_release, left: left - 1 };
                    None
                }
                Job::Carry { to, then_release, .. } => {
                    if then_release {
                        let held = self.held();
                        self.release(Some(to));
                        if held == Some(CUBE) {
                            self.say("the robot places the cube");
                        } else {
                            self.say("the robot sets the sphere down out of the way");
                        }
                    }
                    Some(Status::Success)
                }
            };
        }
        self.running = Some(r);
    }

    /// Advances the world by one tick: the running action moves, physics runs.
    pub fn step(&mut self) {
        self.tick = self.tick.saturating_add(1);
        self.advance();
        if let Some(b) = self.world.bodies.get_mut(self.base) {
            b.set_next_kinematic_translation(Vector::new(self.base_at[0], self.base_at[1], 0.0));
        }
        for _ in 0..STEPS_PER_TICK {
            self.world.step();
        }
    }
}

fn dist(a: [f32; 2], b: [f32; 2]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

impl worlds::World for MobileWorld {
    /// Back to the start of Example 1 (a rapier world has no cheaper exact reset).
    fn reset(&mut self) {
        *self = Self::new();
    }

    fn step(&mut self) {
        MobileWorld::step(self);
    }
}

impl BehaviorSet for MobileWorld {
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        if self.condition_of(leaf.behavior(), leaf.args()) { Status::Success } else { Status::Failure }
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let ours = self.running.as_ref().is_some_and(|r| r.node == ctx.node);
        if ctx.starting || !ours {
            self.running = None;
            return match self.start(leaf.behavior(), leaf.args()) {
                Err(s) => s,
                Ok(job) => {
                    let limit = self.time_limit(&job);
                    self.running = Some(Running { node: ctx.node, ticks: 0, limit, job, outcome: None });
                    Status::Running
                }
            };
        }
        let Some(r) = self.running.as_mut() else { return Status::Failure };
        r.ticks += 1;
        let out = match r.outcome {
            Some(s) => s,
            None if r.ticks >= r.limit => Status::Failure,
            None => return Status::Running,
        };
        self.running = None;
        out
    }

    fn halt(&mut self, _: &Leaf, node: NodeId) {
        if self.running.as_ref().is_some_and(|r| r.node == node) {
            self.running = None;
        }
    }
}
