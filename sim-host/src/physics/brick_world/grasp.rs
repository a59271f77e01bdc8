//! How bricks join and part: the grasp joint ([`PhysicsBrickWorld::attach`],
//! [`PhysicsBrickWorld::release`]), the bricks riding on a held one, and pressing one
//! brick onto another into one rigid body ([`PhysicsBrickWorld::press`]).

use super::*;

impl PhysicsBrickWorld {
    pub(super) fn attach(&mut self, brick: u8) -> bool {
        let (Some(p), Some(&(body, offset))) = (self.pose_of(brick), self.carrier.get(usize::from(brick))) else {
            return false;
        };
        let want = self.tool - Vector::new(0.0, 0.0, GRIP_HEIGHT);
        let d = p.translation - want;
        let up = p.rotation * Vector::Z;
        if d.x.abs() > GRASP_TOLERANCE
            || d.y.abs() > GRASP_TOLERANCE
            || d.z.abs() > GRASP_TOLERANCE
            || up.z < GRASP_MIN_UPRIGHT
        {
            return false;
        }
        let joint = FixedJointBuilder::new()
            .local_frame1(Pose::from_translation(Vector::new(0.0, 0.0, -GRIP_HEIGHT)))
            .local_frame2(offset)
            .contacts_enabled(false);
        let j = self.world.impulse_joints.insert(self.gripper, body, joint, true);
        self.at_grasp = (0..self.bricks.len()).filter_map(|k| u8::try_from(k).ok()).map(|k| self.pos(k)).collect();
        self.grasp = Some((brick, j));
        self.board_riders(brick, body);
        true
    }

    /// Finds the bricks resting, aligned, on the assembly of `brick` (body `held`), and
    /// on those, and makes their bodies kinematic riders of `held`.
    pub(super) fn board_riders(&mut self, brick: u8, held: RigidBodyHandle) {
        let count = u8::try_from(self.bricks.len()).unwrap_or(u8::MAX);
        let mut carried: Vec<u8> = self.assembly(brick);
        let mut bodies = vec![held];
        loop {
            let next = (0..count).find(|&k| {
                self.body(k).is_some_and(|b| !bodies.contains(&b))
                    && carried.iter().any(|&m| Self::on_top(self.pos(k), self.pos(m)))
            });
            let Some(k) = next else { break };
            let Some(b) = self.body(k) else { break };
            bodies.push(b);
            carried.extend(self.assembly(k));
        }
        let Some(held_pose) = self.world.bodies.get(held).map(|b| *b.position()) else { return };
        for &b in bodies.iter().skip(1) {
            if let Some(body) = self.world.bodies.get_mut(b) {
                let rel = held_pose.inverse() * *body.position();
                body.set_body_type(RigidBodyType::KinematicPositionBased, true);
                self.riders.push((b, rel));
            }
        }
    }

    /// Moves the riders with the held body: to `held`'s pose now (`snap`: at once), or
    /// as their kinematic target for the next step.
    pub(super) fn carry_riders(&mut self, snap: bool) {
        let Some(held) = self.held_brick().and_then(|b| self.body(b)) else { return };
        let Some(held_pose) = self.world.bodies.get(held).map(|b| *b.position()) else { return };
        for &(h, rel) in &self.riders {
            if let Some(body) = self.world.bodies.get_mut(h) {
                if snap {
                    body.set_position(held_pose * rel, true);
                } else {
                    body.set_next_kinematic_position(held_pose * rel);
                }
            }
        }
    }

    /// Brick b rides on what is held.
    pub(super) fn is_rider(&self, b: u8) -> bool {
        self.body(b).is_some_and(|h| self.riders.iter().any(|&(r, _)| r == h))
    }

    /// Puts what is held exactly where the grasp holds it.
    pub(super) fn snap_held(&mut self) {
        let Some(held) = self.held_brick() else { return };
        let Some(held_pose) = self.pose_of(held) else { return };
        let correction = self.grasp_pose() * held_pose.inverse();
        if let Some(body) = self.body(held).and_then(|h| self.world.bodies.get_mut(h)) {
            let at = correction * *body.position();
            body.set_position(at, true);
        }
        self.carry_riders(true);
        self.moved = true;
    }

    pub(super) fn release(&mut self) {
        if let Some((b, j)) = self.grasp.take() {
            self.world.impulse_joints.remove(j, true);
            if let Some(body) = self.body(b).and_then(|h| self.world.bodies.get_mut(h)) {
                body.set_linvel(Vector::ZERO, true);
                body.set_angvel(Vector::ZERO, true);
            }
            self.events.push(BrickEvent::Released { tick: self.tick, brick: b });
        }
        for (h, _) in core::mem::take(&mut self.riders) {
            if let Some(body) = self.world.bodies.get_mut(h) {
                body.set_body_type(RigidBodyType::Dynamic, true);
                body.set_linvel(Vector::ZERO, true);
                body.set_angvel(Vector::ZERO, true);
            }
        }
    }

    /// Presses brick b: if it sits aligned on a brick, it becomes part of that brick's
    /// rigid body, one brick height above it, and so does every other brick whose top
    /// its footprint overlaps at the same level (a long brick bridging several bricks
    /// snaps onto all their studs).
    pub(super) fn press(&mut self, brick: u8) {
        if self.fixed_below(usize::from(brick)).is_some() {
            return;
        }
        let count = u8::try_from(self.bricks.len()).unwrap_or(u8::MAX);
        let below = (0..count)
            .filter(|&j| j != brick && Self::on_top(self.pos(brick), self.pos(j)))
            .max_by(|&a, &b| self.pos(a).z.total_cmp(&self.pos(b).z));
        let Some(below) = below else { return };
        let (Some(upper), Some(lower)) = (self.pose_of(brick), self.pose_of(below)) else { return };
        let footprint = |i: u8| self.spec.bricks.get(usize::from(i)).map(|&k| bricks::dimensions(k));
        let Some(up) = footprint(brick) else { return };
        // Where brick b goes: on the studs of `below`, centred and square.
        let pressed = lower * Pose::from_translation(Vector::new(0.0, 0.0, BRICK_HEIGHT));
        let mut joins = vec![(brick, pressed)];
        for j in 0..count {
            if j == brick || j == below || self.assembly(below).contains(&j) {
                continue;
            }
            let (Some(pj), Some(d)) = (self.pose_of(j), footprint(j)) else { continue };
            let p = pj.translation;
            let overlap_x = (p.x - upper.translation.x).abs() < (d.x + up.x) / 2.0 - 0.001;
            let overlap_y = (p.y - upper.translation.y).abs() < (d.y + up.y) / 2.0 - 0.001;
            if overlap_x && overlap_y && (p.z - lower.translation.z).abs() < 0.001 {
                // Where it is relative to b, one brick height under it, square.
                let rel = upper.inverse() * pj;
                let rel = Vector::new(rel.translation.x, rel.translation.y, -BRICK_HEIGHT);
                joins.push((j, pressed * Pose::from_translation(rel)));
            }
        }
        self.merge(below, &joins);

        if let Some(b) = self.below.get_mut(usize::from(brick)) {
            *b = Some(below);
        }
        self.events.push(BrickEvent::Fixed { tick: self.tick, brick, below });
    }

    /// Makes one rigid body of the assembly of brick `host` and the assemblies of the
    /// bricks in `moves`, each brick of `moves` landing at its world pose (its assembly
    /// moving with it). The new body replaces the old ones: rapier solves a body whose
    /// collider set changed without its contacts for a step, a fresh body it does not.
    pub(super) fn merge(&mut self, host: u8, moves: &[(u8, Pose)]) {
        let Some(host_pose) = self.pose_of(host) else { return };
        let Some(&(host_body, host_offset)) = self.carrier.get(usize::from(host)) else { return };
        let body_pose = host_pose * host_offset.inverse();
        // World pose of every brick of the merged bodies.
        let mut old_bodies = vec![host_body];
        let mut targets: Vec<(u8, Pose)> = Vec::new();
        for &(j, target) in moves {
            let (Some(now), Some(jb)) = (self.pose_of(j), self.body(j)) else { continue };
            if old_bodies.contains(&jb) {
                continue;
            }
            old_bodies.push(jb);
            let shift = target * now.inverse();
            for k in self.assembly(j) {
                if let Some(p) = self.pose_of(k) {
                    targets.push((k, shift * p));
                }
            }
        }
        for k in self.assembly(host) {
            if let Some(p) = self.pose_of(k) {
                targets.push((k, p));
            }
        }
        let new_body = self.world.bodies.insert(rapier3d::prelude::RigidBodyBuilder::dynamic().pose(body_pose).build());
        for (k, world_pose) in targets {
            let offset = body_pose.inverse() * world_pose;
            let moved = self.shapes.get(usize::from(k)).cloned().unwrap_or_default();
            let mut fresh = Vec::with_capacity(moved.len());
            for (collider, local) in moved {
                let w = &mut self.world;
                if let Some(mut col) =
                    w.colliders.remove(collider, &mut w.islands, &mut w.bodies, &mut w.soft_bodies, false)
                {
                    col.set_position_wrt_parent(offset * local);
                    fresh.push((w.colliders.insert_with_parent(col, new_body, &mut w.bodies), local));
                }
            }
            if let Some(slot) = self.shapes.get_mut(usize::from(k)) {
                *slot = fresh;
            }
            if let Some(slot) = self.carrier.get_mut(usize::from(k)) {
                *slot = (new_body, offset);
            }
        }
        self.moved = true;
        for old in old_bodies {
            let w = &mut self.world;
            w.bodies.remove(
                old,
                &mut w.islands,
                &mut w.colliders,
                &mut w.impulse_joints,
                &mut w.multibody_joints,
                &mut w.soft_bodies,
                false,
            );
        }
    }
}
