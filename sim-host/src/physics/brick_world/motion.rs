//! How the actions move the gripper: an action is planned into phases when it starts
//! ([`PhysicsBrickWorld::plan`]), and each rapier step advances the running phase with
//! a guarded motion ([`PhysicsBrickWorld::guard`]: a shape cast of the fingers, the palm
//! and the held brick that stops at the first contact).

use super::*;

impl PhysicsBrickWorld {
    /// Plans an action; `Err(status)` is an immediate outcome.
    pub(super) fn plan(&self, behavior: Behavior) -> Result<Vec<Phase>, Status> {
        use Phase::*;
        let held = self.held_brick();
        let pick = |b: u8| vec![Rise, Fingers(OPEN), Over(Spot::Grasp(b)), Descend(Spot::Grasp(b)), Grasp(b), Rise];
        let place = |spot: Spot| vec![Rise, Over(spot), Descend(spot), SetDown(spot), Fingers(OPEN), Rise];
        match behavior {
            Behavior::Pick(b) => {
                if !self.known_brick(b) {
                    return Err(Status::Failure);
                }
                match held {
                    Some(h) if h == b => Err(Status::Success),
                    Some(_) => Err(Status::Failure),
                    None => Ok(pick(b)),
                }
            }
            Behavior::PlaceAt(p) => match (held, self.position_of(p)) {
                (Some(_), Some(at)) => Ok(place(Spot::At(at))),
                _ => Err(Status::Failure),
            },
            Behavior::PlaceOn(b) => match held {
                Some(h) if h != b && self.known_brick(b) && !self.is_rider(b) => Ok(place(Spot::On(b))),
                _ => Err(Status::Failure),
            },
            Behavior::PutAt(i, p) => {
                let Some(at) = self.position_of(p) else { return Err(Status::Failure) };
                if !self.known_brick(i) {
                    return Err(Status::Failure);
                }
                if self.is_at(i, at) {
                    return Err(Status::Success);
                }
                match held {
                    Some(h) if h == i => Ok(place(Spot::At(at))),
                    Some(_) => Err(Status::Failure),
                    None => Ok([pick(i), place(Spot::At(at))].concat()),
                }
            }
            Behavior::PutOn(i, j) => {
                if !self.known_brick(i) || !self.known_brick(j) || i == j {
                    return Err(Status::Failure);
                }
                if self.is_on(i, j) {
                    return Err(Status::Success);
                }
                match held {
                    Some(h) if h == i && self.is_rider(j) => Err(Status::Failure),
                    Some(h) if h == i => Ok(place(Spot::On(j))),
                    Some(_) => Err(Status::Failure),
                    None => Ok([pick(i), place(Spot::On(j))].concat()),
                }
            }
            Behavior::ApplyForce(b) => {
                if held.is_some() || !self.known_brick(b) {
                    return Err(Status::Failure);
                }
                Ok(vec![
                    Rise,
                    Fingers(SHUT),
                    Over(Spot::Press(b)),
                    Descend(Spot::Press(b)),
                    Press(b),
                    Rise,
                    Fingers(OPEN),
                ])
            }
            Behavior::Picked(_) | Behavior::AtPos(..) | Behavior::On(..) => Err(Status::Failure),
        }
    }

    /// Tool-point target of a spot, from the bodies as they are now.
    pub(super) fn resolve(&self, spot: Spot) -> Vector {
        match spot {
            Spot::Grasp(b) => self.pos(b) + Vector::new(0.0, 0.0, GRIP_HEIGHT),
            Spot::At(p) => Vector::from_array(p) + Vector::new(0.0, 0.0, GRIP_HEIGHT + PLACE_CLEARANCE),
            Spot::On(b) => self.pos(b) + Vector::new(0.0, 0.0, bricks::stack_height() + GRIP_HEIGHT + PLACE_CLEARANCE),
            Spot::Press(b) => {
                let top = if self.fixed_below(usize::from(b)).is_some() {
                    BRICK_HEIGHT + STUD_HEIGHT
                } else {
                    bricks::stack_height()
                };
                self.pos(b) + Vector::new(0.0, 0.0, top + FINGERTIP_DEPTH + 0.001)
            }
        }
    }

    /// The gripper's shapes (fingers at gap `gap`, palm) at tool point `tool`.
    pub(super) fn gripper_shapes(tool: Vector, gap: f32) -> [(SharedShape, Pose); 3] {
        let finger_hz = (FINGER_TOP + FINGERTIP_DEPTH) / 2.0;
        let finger_z = (FINGER_TOP - FINGERTIP_DEPTH) / 2.0;
        let finger = SharedShape::new(Cuboid::new(Vector::new(FINGER_HX, FINGER_HY, finger_hz)));
        let palm = SharedShape::new(Cuboid::new(Vector::from_array(PALM)));
        let fx = gap + FINGER_HX;
        [
            (finger.clone(), Pose::from_translation(tool + Vector::new(-fx, 0.0, finger_z))),
            (finger, Pose::from_translation(tool + Vector::new(fx, 0.0, finger_z))),
            (palm, Pose::from_translation(tool + Vector::new(0.0, 0.0, FINGER_TOP + PALM[2]))),
        ]
    }

    /// The first thing the gripper (and what it holds) meets moving by `motion`.
    pub(super) fn guard(&self, motion: Vector) -> Option<Option<u8>> {
        let held = self.held_brick();
        let members = held.map(|b| self.assembly(b)).unwrap_or_default();
        let mut ignore = vec![self.gripper];
        ignore.extend(members.iter().filter_map(|&m| self.body(m)));
        ignore.extend(self.riders.iter().map(|&(h, _)| h));
        let mut hit = None;
        let mut consider = |h: Option<(ColliderHandle, f32)>| {
            if let Some((c, toi)) = h
                && hit.is_none_or(|(_, t)| toi < t)
            {
                hit = Some((c, toi));
            }
        };
        for (shape, pose) in Self::gripper_shapes(self.tool, self.gap) {
            consider(engine::sweep(&self.world, shape.as_ref(), &pose, motion, &ignore));
        }
        if let Some(held_pose) = held.and_then(|b| self.pose_of(b)) {
            // What is held, where the grasp holds it (not where the joint lags it).
            let correction = self.grasp_pose() * held_pose.inverse();
            let carried = held.and_then(|b| self.body(b)).into_iter().chain(self.riders.iter().map(|&(h, _)| h));
            for body in carried.filter_map(|h| self.world.bodies.get(h)) {
                for &c in body.colliders() {
                    if let Some(col) = self.world.colliders.get(c) {
                        let pose = correction * *col.position();
                        consider(engine::sweep(&self.world, col.shape(), &pose, motion, &ignore));
                    }
                }
            }
        }
        let (c, _) = hit?;
        Some(self.brick_of(c))
    }

    /// Advances the running job by one rapier step: moves the gripper's kinematic target.
    pub(super) fn advance_job(&mut self, dt: f32) {
        let Some(mut job) = self.job.take() else { return };
        let mut budget = 4; // instantaneous phases that may complete within one step
        while job.outcome.is_none() && budget > 0 {
            budget -= 1;
            let Some(&phase) = job.phases.get(job.next) else {
                job.outcome = Some(Status::Success);
                break;
            };
            let done = match phase {
                Phase::Rise | Phase::Over(_) | Phase::Descend(_) => {
                    let target = *job.target.get_or_insert_with(|| match phase {
                        Phase::Rise => {
                            Vector::new(self.tool.x, self.tool.y, self.tool.z.max(self.params.travel_height))
                        }
                        Phase::Over(s) => {
                            let t = self.resolve(s);
                            Vector::new(t.x, t.y, self.tool.z)
                        }
                        Phase::Descend(s @ (Spot::At(_) | Spot::On(_))) => {
                            self.resolve(s) + Vector::new(0.0, 0.0, APPROACH)
                        }
                        Phase::Descend(s) => self.resolve(s),
                        _ => self.tool,
                    });
                    let d = target - self.tool;
                    let max = self.params.speed * dt;
                    let len = d.length();
                    let motion = if len <= max { d } else { d * (max / len) };
                    // An empty gripper backing straight up is not stopped by a brick
                    // that rocks up under it after being let go.
                    let guarded = !(matches!(phase, Phase::Rise) && self.grasp.is_none());
                    if len > 0.0 {
                        if let Some(by) = self.guard(motion).filter(|_| guarded) {
                            self.events.push(BrickEvent::Blocked { tick: self.tick, by });
                            if let Phase::Descend(Spot::Press(b)) = phase {
                                // Pressing through whatever lies on top.
                                if let Some(p) = job.phases.get_mut(job.next) {
                                    *p = Phase::Press(b);
                                }
                                job.target = None;
                                continue;
                            }
                            job.outcome = Some(Status::Failure);
                            break;
                        }
                        self.tool += motion;
                    }
                    let arrived = len <= max;
                    if arrived {
                        self.tool = target;
                    }
                    budget = 0; // a motion uses the step
                    arrived
                }
                Phase::Fingers(gap) => {
                    let d = gap - self.gap;
                    let max = FINGER_SPEED * dt;
                    if d.abs() <= max {
                        self.gap = gap;
                        true
                    } else {
                        self.gap += max.copysign(d);
                        budget = 0;
                        false
                    }
                }
                Phase::Grasp(b) => {
                    self.gap = ON_BRICK;
                    if self.attach(b) {
                        self.events.push(BrickEvent::Grasped { tick: self.tick, brick: b });
                        true
                    } else {
                        self.events.push(BrickEvent::Missed { tick: self.tick, brick: b });
                        job.outcome = Some(Status::Failure);
                        break;
                    }
                }
                Phase::SetDown(spot) => {
                    let motion = self.resolve(spot) - self.tool;
                    if let Some(by) = self.guard(motion) {
                        self.events.push(BrickEvent::Blocked { tick: self.tick, by });
                        job.outcome = Some(Status::Failure);
                        break;
                    }
                    self.tool += motion;
                    // The brick covers the last millimetres with the fingers.
                    self.snap_held();
                    self.release();
                    budget = 0;
                    true
                }
                Phase::Press(b) => {
                    if job.wait == 0 {
                        job.wait = (PRESS_SECONDS / dt).round().max(1.0) as u32;
                    }
                    job.wait -= 1;
                    budget = 0;
                    if job.wait == 0 {
                        self.press(b);
                        true
                    } else {
                        false
                    }
                }
            };
            if done {
                job.next += 1;
                job.target = None;
                if job.next >= job.phases.len() {
                    job.outcome = Some(Status::Success);
                }
            }
        }
        if let Some(g) = self.world.bodies.get_mut(self.gripper) {
            g.set_next_kinematic_translation(self.tool);
        }
        self.carry_riders(false);
        self.job = Some(job);
    }
}
