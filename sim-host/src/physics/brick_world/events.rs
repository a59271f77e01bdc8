//! What happens in the world, in words, for narration.

/// Something that happened in the world, for narration.
#[derive(Clone, Debug, PartialEq)]
pub enum BrickEvent {
    /// The gripper closed on a brick.
    Grasped {
        /// Tick.
        tick: u32,
        /// Brick.
        brick: u8,
    },
    /// The gripper opened and let a brick go.
    Released {
        /// Tick.
        tick: u32,
        /// Brick.
        brick: u8,
    },
    /// A guarded motion met something and stopped.
    Blocked {
        /// Tick.
        tick: u32,
        /// The brick that was hit, or `None` for the table.
        by: Option<u8>,
    },
    /// A brick was pressed onto the one below and fixed to it.
    Fixed {
        /// Tick.
        tick: u32,
        /// The pressed brick.
        brick: u8,
        /// The brick below.
        below: u8,
    },
    /// The fingers closed on nothing graspable.
    Missed {
        /// Tick.
        tick: u32,
        /// The brick aimed at.
        brick: u8,
    },
}

impl core::fmt::Display for BrickEvent {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            Self::Grasped { tick, brick } => write!(f, "tick {tick}: the gripper grasps brick {brick}"),
            Self::Released { tick, brick } => write!(f, "tick {tick}: the gripper releases brick {brick}"),
            Self::Blocked { tick, by: Some(b) } => {
                write!(f, "tick {tick}: the gripper's motion is blocked by brick {b}")
            }
            Self::Blocked { tick, by: None } => write!(f, "tick {tick}: the gripper's motion is blocked by the table"),
            Self::Fixed { tick, brick, below } => write!(f, "tick {tick}: brick {brick} is pressed onto brick {below}"),
            Self::Missed { tick, brick } => write!(f, "tick {tick}: the fingers close but miss brick {brick}"),
        }
    }
}
