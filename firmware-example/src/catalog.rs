//! The behavior set of the cube/sphere world, exactly as the contract
//! `planner/domains/cube-sphere/domain.pddl` fixes it: the predicates in declaration
//! order as conditions (ids 0-5), then the actions in declaration order (ids 6-10),
//! named by their PDDL names, arity = parameter count. A leaf's arguments are object
//! indices in the problem's `:objects` order: cube = 0, sphere = 1, goal = 2.
//!
//! `build.rs` includes this file too, so the image it makes and the firmware that loads
//! it share one declaration; the fingerprint is a compile-time constant.

use bt_core::{BehaviorId, BehaviorInfo};

/// `(at ?i - item ?s - spot)`: the item lies at the spot.
pub const AT: BehaviorId = 0;
/// `(holding ?i - item)`: the hand holds the item.
pub const HOLDING: BehaviorId = 1;
/// `(hand-empty)`.
pub const HAND_EMPTY: BehaviorId = 2;
/// `(near ?l - location)`: the robot is next to the location.
pub const NEAR: BehaviorId = 3;
/// `(path-free ?l - location)`: the robot's path to the location is collision-free.
pub const PATH_FREE: BehaviorId = 4;
/// `(obstacle ?i - item)`: static, the item may be cleared out of a path.
pub const OBSTACLE: BehaviorId = 5;
/// `(move-to ?l - location)`.
pub const MOVE_TO: BehaviorId = 6;
/// `(pick ?i - item)`.
pub const PICK: BehaviorId = 7;
/// `(place ?i - item ?s - spot)`.
pub const PLACE: BehaviorId = 8;
/// `(drop ?i - item)`: drop what the hand holds.
pub const DROP: BehaviorId = 9;
/// `(clear-path ?i - item ?l - location)`: push the obstacle off the path to `l`.
pub const CLEAR_PATH: BehaviorId = 10;

/// The behavior set, in id order.
pub const BEHAVIORS: [BehaviorInfo<'static>; 11] = [
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

/// The behavior set's fingerprint, as every image for it carries.
pub const FINGERPRINT: u64 = bt_core::fingerprint(&BEHAVIORS);

/// Object `cube` (an item).
pub const CUBE: u16 = 0;
/// Object `sphere` (an item, and an obstacle).
pub const SPHERE: u16 = 1;
/// Object `goal` (a spot).
pub const GOAL: u16 = 2;

/// Object names, by index.
pub const OBJECTS: [&str; 3] = ["cube", "sphere", "goal"];

/// The name of object `id`, or `?` for an index the problem does not have.
#[must_use]
pub fn object_name(id: u16) -> &'static str {
    OBJECTS.get(usize::from(id)).copied().unwrap_or("?")
}
