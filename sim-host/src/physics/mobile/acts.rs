//! What external agents can do to the world ([`Agent`], [`MobileWorld::apply`]) and the
//! world's narration ([`MobileEvent`]).

use super::{CUBE, GOAL, MobileWorld, SPHERE};

/// What an external agent does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Agent {
    /// Takes the cube out of the gripper and puts it on the floor beside the robot.
    TakeCube,
    /// Rolls the sphere into the straight path from the robot to the goal.
    BlockPath,
    /// Rolls the sphere away, out of every path.
    UnblockPath,
    /// Puts the cube into the empty gripper.
    HandCube,
    /// Puts the cube on the goal region.
    CubeToGoal,
}

impl Agent {
    /// Every agent act.
    pub const ALL: [Agent; 5] =
        [Agent::TakeCube, Agent::BlockPath, Agent::UnblockPath, Agent::HandCube, Agent::CubeToGoal];

    /// The act in words, as the narration says it.
    #[must_use]
    pub fn describe(self) -> &'static str {
        match self {
            Self::TakeCube => "an agent takes the cube from the gripper",
            Self::BlockPath => "an agent rolls the sphere into the path to the goal",
            Self::UnblockPath => "an agent rolls the sphere out of the way",
            Self::HandCube => "an agent puts the cube into the gripper",
            Self::CubeToGoal => "an agent puts the cube on the goal",
        }
    }
}

/// A line of narration: what happened at which tick.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MobileEvent {
    /// The tick.
    pub tick: u32,
    /// What happened, in plain words.
    pub text: String,
}

impl core::fmt::Display for MobileEvent {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "tick {}: {}", self.tick, self.text)
    }
}

impl MobileWorld {
    /// Makes an agent act now, between ticks: before the world steps into the next tick,
    /// whose number the event carries. Returns whether the act made sense in the
    /// current state (then it is in the event log).
    pub fn apply(&mut self, agent: Agent) -> bool {
        let ok = match agent {
            Agent::TakeCube if self.held() == Some(CUBE) => {
                self.release(None);
                let at = self.beside();
                self.put(CUBE, at);
                true
            }
            Agent::BlockPath => {
                let mid = [(self.base_at[0] + GOAL[0]) / 2.0, (self.base_at[1] + GOAL[1]) / 2.0];
                if self.held() == Some(SPHERE) {
                    self.release(None);
                }
                self.put(SPHERE, mid);
                true
            }
            Agent::UnblockPath if self.held() != Some(SPHERE) => {
                self.put(SPHERE, [1.5, 2.5]);
                true
            }
            Agent::HandCube if self.held().is_none() => {
                self.attach(CUBE);
                true
            }
            Agent::CubeToGoal if self.held() != Some(CUBE) => {
                self.put(CUBE, GOAL);
                true
            }
            _ => false,
        };
        if ok {
            self.events.push(MobileEvent { tick: self.tick.saturating_add(1), text: agent.describe().into() });
        }
        ok
    }
}
