//! Scripted external events (Colledanchise et al. 2019, Section IV and Fig. 1): at fixed ticks, before
//! the tree is ticked, something other than the robot changes the world.
//!
//! The order tells the paper's story once: an agent *helps* (hands the robot the cube it
//! was going to pick), then *undoes* (the cube slips from the hand), then the sphere
//! *blocks* the path and the robot clears it (Example 2), then it blocks again and an
//! agent moves it away before the robot gets there (Fig. 1 b). The tree stays the same
//! throughout: its reactivity handles every event.

use crate::catalog::GOAL;
use crate::plant::{Hand, Plant, Vec2, length};

/// An external event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    /// An external agent puts the cube in the robot's hand.
    Help,
    /// The cube slips from the hand and slides away to the robot's right.
    Slip,
    /// The sphere rolls into the robot's path to the goal.
    Block,
    /// An external agent moves the sphere off the path.
    Unblock,
}

impl Event {
    /// What happens, in words.
    #[must_use]
    pub const fn describe(self) -> &'static str {
        match self {
            Self::Help => "an agent puts the cube in the hand",
            Self::Slip => "the cube slips from the hand",
            Self::Block => "the sphere rolls into the path",
            Self::Unblock => "an agent moves the sphere away",
        }
    }

    /// The event's name in the trace.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Help => "help",
            Self::Slip => "slip",
            Self::Block => "block",
            Self::Unblock => "unblock",
        }
    }
}

/// Why an event could not happen in the state the world was in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Skipped {
    /// `help` while the hand is not empty.
    HandFull,
    /// `slip` while the hand holds nothing.
    HandEmpty,
    /// `block` with the robot already near the goal.
    NoPathLeft,
}

impl Skipped {
    /// Why, in words.
    #[must_use]
    pub const fn reason(self) -> &'static str {
        match self {
            Self::HandFull => "the hand is not empty",
            Self::HandEmpty => "the hand holds nothing",
            Self::NoPathLeft => "the robot is already at the goal",
        }
    }
}

/// The script: events and the ticks they happen at, in tick order.
pub const SCRIPT: [(u32, Event); 5] =
    [(12, Event::Help), (25, Event::Slip), (52, Event::Block), (72, Event::Block), (76, Event::Unblock)];

/// How far the slipping cube slides, to the robot's right, m.
pub const SLIDE: f32 = 0.9;
/// How far ahead of the robot the sphere rolls in, m (at most).
pub const BLOCK_AHEAD: f32 = 1.2;
/// How far sideways the helping agent moves the sphere, m.
pub const MOVE_AWAY: f32 = 1.5;

/// The event scripted for `tick`, if any.
#[must_use]
pub fn event_at(tick: u32) -> Option<Event> {
    SCRIPT.iter().find(|(t, _)| *t == tick).map(|&(_, e)| e)
}

/// Makes `event` happen to `plant`.
///
/// # Errors
/// [`Skipped`] when the world is not in a state where the event makes sense; the world
/// is then unchanged.
pub fn apply(event: Event, plant: &mut Plant) -> Result<(), Skipped> {
    match event {
        Event::Help => {
            if plant.hand != Hand::Empty {
                return Err(Skipped::HandFull);
            }
            plant.hand = Hand::Cube;
            plant.cube = plant.gripper();
        }
        Event::Slip => {
            if plant.hand != Hand::Cube {
                return Err(Skipped::HandEmpty);
            }
            plant.hand = Hand::Empty;
            plant.progress = 0;
            let right = Vec2::new(plant.facing.y, -plant.facing.x);
            plant.cube = plant.gripper() + right * SLIDE;
        }
        Event::Block => {
            let to_goal = plant.goal - plant.robot;
            let dist = length(to_goal);
            if plant.near(GOAL) || dist <= 0.0 {
                return Err(Skipped::NoPathLeft);
            }
            let ahead = BLOCK_AHEAD.min(dist * 0.5);
            plant.sphere = plant.robot + to_goal * (ahead / dist);
        }
        Event::Unblock => {
            let along = plant.goal - plant.robot;
            let n = length(along);
            if n > 0.0 {
                plant.sphere += Vec2::new(-along.y, along.x) * (MOVE_AWAY / n);
            }
        }
    }
    Ok(())
}
