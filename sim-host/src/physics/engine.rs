//! The rapier3d set-up both physics worlds share: a z-up world with parameters for
//! centimetre-sized bodies, and shape casts for guarded motions.

use rapier3d::parry::query::ShapeCastOptions;
use rapier3d::parry::shape::Shape;
use rapier3d::prelude::{
    ColliderHandle, IntegrationParameters, PhysicsWorld, Pose, QueryFilter, RigidBodyHandle, Vector,
};

/// Standard gravity, along -z.
pub(crate) const GRAVITY: f32 = 9.81;

/// Natural frequency of contact constraints, Hz.
pub(crate) const CONTACT_HZ: f32 = 100.0;
/// Damping ratio of contact constraints.
pub(crate) const CONTACT_DAMPING: f32 = 20.0;

/// A fresh rapier world: gravity along -z, `dt` per step, `solver_iterations` solver
/// substeps, and error tolerances scaled to `length_unit` (the size of typical bodies;
/// rapier's defaults assume one metre, which would allow millimetres of penetration).
pub(crate) fn new_world(dt: f32, solver_iterations: usize, length_unit: f32) -> PhysicsWorld {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -GRAVITY);
    world.integration_parameters = IntegrationParameters {
        dt,
        min_ccd_dt: dt / 100.0,
        num_solver_iterations: solver_iterations.max(1),
        length_unit,
        // Speculative contacts within half a millimetre (rapier's default, 0.02 length
        // units, is 0.2 mm here): more, and a held brick lowered 1 mm beside another drags
        // it along; less, and the balance task's long brick rocks off a 4x2 base.
        normalized_prediction_distance: 0.05,
        ..IntegrationParameters::default()
    };
    // Stiffer contacts than rapier's defaults (30 Hz, 60 Hz against fixed bodies): at
    // those a brick rests 0.2 mm deep in the table and 0.7 mm deep in the studs of the
    // brick below, which the 1 mm position margin cannot absorb. At 100 Hz it is about
    // 0.1 mm. Stiffer still (200-300 Hz) makes a loose stack of three bricks jitter and
    // walk off; strong damping keeps 100 Hz still enough to sleep.
    for softness in
        [&mut world.integration_parameters.contact_softness, &mut world.integration_parameters.static_contact_softness]
    {
        softness.natural_frequency = CONTACT_HZ;
        softness.damping_ratio = CONTACT_DAMPING;
    }
    world
}

/// The first collider that `shape`, at `pose`, hits when it moves by `motion` (a
/// straight sweep), ignoring colliders of the bodies in `ignore`. Shapes that touch
/// something at the start but move away from it do not count as hits.
pub(crate) fn sweep(
    world: &PhysicsWorld,
    shape: &dyn Shape,
    pose: &Pose,
    motion: Vector,
    ignore: &[RigidBodyHandle],
) -> Option<(ColliderHandle, f32)> {
    let keep = |_: ColliderHandle, c: &rapier3d::prelude::Collider| c.parent().is_none_or(|p| !ignore.contains(&p));
    let query = world.broad_phase.as_query_pipeline(
        world.narrow_phase.query_dispatcher(),
        &world.bodies,
        &world.colliders,
        QueryFilter::new().exclude_sensors().predicate(&keep),
    );
    let options = ShapeCastOptions {
        max_time_of_impact: 1.0,
        target_distance: 0.0,
        stop_at_penetration: false,
        compute_impact_geometry_on_penetration: false,
    };
    query.cast_shape(pose, motion, shape, options).map(|(h, hit)| (h, hit.time_of_impact))
}
