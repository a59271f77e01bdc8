//! Brick bodies: shapes, masses and friction of each [`BrickKind`].
//!
//! A brick's rigid-body origin is its reference point, the centre of its bottom face,
//! so the body's translation is the position the tasks talk about. Every brick lies
//! with its long side along **y** (see [`dimensions`] for why).

use planner::duplo::{BRICK_2X2, BRICK_HEIGHT, BrickKind};
use rapier3d::prelude::{
    CoefficientCombineRule, ColliderBuilder, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle, Vector,
};

/// Height of the stud layer on top of a brick: an unpressed brick rests this much
/// higher than a pressed one (the reference's not-pressed gap).
pub const STUD_HEIGHT: f32 = 0.002;
/// Friction coefficient of brick plastic on plastic and on the table.
pub const FRICTION: f32 = 0.5;
/// Mass of a 2x2 brick, kg; longer bricks scale with their length.
pub const MASS_2X2: f32 = 0.006;
/// Mass of the solid 2x2 block on the unbalanced long brick, kg: as heavy as the long
/// brick itself, which puts the centre of mass 20 mm off-centre along y: beyond the
/// half-width of a 2x2 base (15.5 mm), well inside the half-length of a 4x2 (31 mm).
pub const MASS_BLOCK: f32 = 0.018;
/// Height of the cone on the blocking task's brick 2, m.
pub const CONE_HEIGHT: f32 = 0.03;

/// Size of a brick's main box and where its centre of mass lies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dimensions {
    /// Extent along x, m.
    pub x: f32,
    /// Extent along y (the long side), m.
    pub y: f32,
    /// Height without studs, m.
    pub z: f32,
    /// Total mass, kg.
    pub mass: f32,
    /// Offset of the centre of mass from the footprint's centre along y, m.
    pub mass_offset_y: f32,
}

/// The dimensions of a brick kind.
///
/// The long side lies along y for every task: the tasks' start positions leave no room
/// for anything else (the balance task's 8x2 brick at x = -0.05 would overlap brick 1
/// at x = 0 if it lay along x), and it is what makes the paper's physics appear by
/// itself: the croissant's long brick overhangs the side bricks' spots, and in the
/// blocking task spot C overlaps spots B and D.
#[must_use]
pub fn dimensions(kind: BrickKind) -> Dimensions {
    let (len, mass, offset) = match kind {
        BrickKind::TwoByTwo => (BRICK_2X2, MASS_2X2, 0.0),
        BrickKind::FourByTwo | BrickKind::FourByTwoWithCone => (2.0 * BRICK_2X2, 2.0 * MASS_2X2, 0.0),
        BrickKind::LongUnbalanced => {
            let brick = 4.0 * MASS_2X2;
            let arm = 2.0 * BRICK_2X2 - BRICK_2X2 / 2.0;
            (4.0 * BRICK_2X2, brick + MASS_BLOCK, MASS_BLOCK * arm / (brick + MASS_BLOCK))
        }
    };
    Dimensions { x: BRICK_2X2, y: len, z: BRICK_HEIGHT, mass, mass_offset_y: offset }
}

/// Inserts brick `kind` with its reference point at `at`, returning its body.
pub(crate) fn insert(world: &mut PhysicsWorld, kind: BrickKind, at: [f32; 3]) -> RigidBodyHandle {
    let d = dimensions(kind);
    let (hx, hy, hz) = (d.x / 2.0, d.y / 2.0, d.z / 2.0);
    let body = RigidBodyBuilder::dynamic().translation(Vector::new(at[0], at[1], at[2])).build();
    let handle = world.bodies.insert(body);
    let solid = |b: ColliderBuilder| {
        b.friction(FRICTION).friction_combine_rule(CoefficientCombineRule::Average).restitution(0.0)
    };
    // The stud layer: a thin pad on the top face, slightly inset so that side contacts
    // between neighbours are the main boxes'.
    let pad = |hy_pad: f32, y: f32| {
        solid(ColliderBuilder::cuboid(hx - 0.001, hy_pad - 0.001, STUD_HEIGHT / 2.0))
            .translation(Vector::new(0.0, y, d.z + STUD_HEIGHT / 2.0))
            .density(0.0)
    };
    let brick_mass = match kind {
        BrickKind::LongUnbalanced => d.mass - MASS_BLOCK,
        BrickKind::FourByTwoWithCone => d.mass - CONE_MASS,
        _ => d.mass,
    };
    let main = solid(ColliderBuilder::cuboid(hx, hy, hz)).translation(Vector::new(0.0, 0.0, hz)).mass(brick_mass);
    world.colliders.insert_with_parent(main, handle, &mut world.bodies);
    match kind {
        BrickKind::TwoByTwo | BrickKind::FourByTwo => {
            world.colliders.insert_with_parent(pad(hy, 0.0), handle, &mut world.bodies);
        }
        BrickKind::LongUnbalanced => {
            // A solid 2x2 block on the +y end; studs on the rest of the top.
            let block_y = hy - BRICK_2X2 / 2.0;
            let block = solid(ColliderBuilder::cuboid(hx, BRICK_2X2 / 2.0, hz))
                .translation(Vector::new(0.0, block_y, d.z + hz))
                .mass(MASS_BLOCK);
            world.colliders.insert_with_parent(block, handle, &mut world.bodies);
            let rest = hy - BRICK_2X2 / 2.0;
            world.colliders.insert_with_parent(pad(rest, -BRICK_2X2 / 2.0), handle, &mut world.bodies);
        }
        BrickKind::FourByTwoWithCone => {
            // parry's cone points along +y; turn it to point up.
            let cone = solid(ColliderBuilder::cone(CONE_HEIGHT / 2.0, hx))
                .translation(Vector::new(0.0, 0.0, d.z + CONE_HEIGHT / 2.0))
                .rotation(Vector::new(core::f32::consts::FRAC_PI_2, 0.0, 0.0))
                .mass(CONE_MASS);
            world.colliders.insert_with_parent(cone, handle, &mut world.bodies);
        }
    }
    handle
}

/// Mass of the cone, kg.
const CONE_MASS: f32 = 0.002;

/// Height of the top a brick offers to a brick placed on it (studs included), above
/// its reference point, m.
#[must_use]
pub(crate) fn stack_height() -> f32 {
    BRICK_HEIGHT + STUD_HEIGHT
}

/// Inserts the table: a fixed slab whose top face is `z = 0`.
pub(crate) fn insert_table(world: &mut PhysicsWorld) {
    let body = world.bodies.insert(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -0.01)).build());
    let slab = ColliderBuilder::cuboid(0.5, 0.5, 0.01)
        .friction(FRICTION)
        .friction_combine_rule(CoefficientCombineRule::Average)
        .restitution(0.0);
    world.colliders.insert_with_parent(slab, body, &mut world.bodies);
}
