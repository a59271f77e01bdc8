//! The four brick (LEGO DUPLO) tasks of Styrud et al., exactly as the
//! reference definitions give them (`docs/brick-tasks.md`): bricks, start and
//! goal positions, world mode, and the ordered list of behaviors each task uses.
//!
//! This is the contract between the planner (which plans over these behaviors, taking
//! the first achieving action in list order), the worlds of `sim-host` (which implement
//! them) and `gp` (which draws random leaves from them). Each behavior is a grounded
//! leaf without arguments: in a bt-core tree its behavior id is its index in
//! [`Task::behaviors`], and its name is exactly the reference's (`picked 0?`,
//! `place at (0.0, 0.05, 0.0)!`, ...), which is also its token in the notation of Styrud et al.

use bt_core::{BehaviorId, BehaviorInfo, LeafKind};

pub use crate::duplo_plan::grounding;

/// Plans the task with the templates of the reference (see [`grounding`]); the tree's
/// leaves are this task's behaviors, its catalog `task.spec()`.
///
/// ```
/// use planner::duplo::{self, Task};
/// let plan = duplo::plan(Task::Tower)?;
/// assert_eq!(
///     bt_formats::tokens::to_string(&plan.nodes, plan.catalog.as_ref())?,
///     "s( f( 0 at pos (0.0, 0.05, 0.0)? s( f( picked 0? pick 0! ) place at (0.0, 0.05, 0.0)! ) ) \
///      f( 1 at pos (0.0, 0.05, 0.0192)? s( f( 1 on 0? s( f( picked 1? pick 1! ) place on 0! ) ) apply force 1! ) ) \
///      f( 2 at pos (0.0, 0.05, 0.0384)? s( f( 2 on 1? s( f( picked 2? pick 2! ) place on 1! ) ) apply force 2! ) ) )"
/// );
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// As [`crate::plan`]; never for the four tasks.
pub fn plan(task: Task) -> Result<crate::Plan<Spec>, crate::PlanError> {
    crate::duplo_plan::plan(task, crate::Options::default())
}

/// Metres: brick height without studs.
pub const BRICK_HEIGHT: f32 = 0.0192;
/// Metres: length of a 2x2 brick.
pub const BRICK_2X2: f32 = 0.031;

/// One of the four tasks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Task {
    /// Task 1: a tower of three 2x2 bricks.
    Tower,
    /// Task 2: three bricks in a U on the table, a long brick on the middle one.
    Croissant,
    /// Task 3: lift an unbalanced long brick to one brick's height on a wide base.
    Balance,
    /// Task 4: stack two bricks where a third, carrying a cone, is in the way.
    Blocking,
}

/// The physics a task's world has that the planner does not know about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mode {
    /// Nothing unexpected.
    Default,
    /// The long brick 1 blocks placing bricks 2 and 3 once it lies near y = 0.
    Croissant,
    /// Brick 0 tips when placed on brick 1; brick 2 placed near brick 1 rises.
    Balance,
    /// Occupied spots, the cone on brick 2.
    Blocking,
}

/// Brick shapes (studs along x by y).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BrickKind {
    /// 2x2, 0.031 m square.
    TwoByTwo,
    /// 4x2, twice as long in x.
    FourByTwo,
    /// 8x2 with an extra 2x2 block on one end: its mass is off-centre.
    LongUnbalanced,
    /// 4x2 with a cone on top: nothing stays on it.
    FourByTwoWithCone,
}

/// A behavior of a brick task, with its arguments (brick indices and positions from
/// [`Task::positions`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Behavior {
    /// `picked b?`: brick `b` is held.
    Picked(u8),
    /// `b at pos P?`: brick `b` is within the position margin of position `P`.
    AtPos(u8, Position),
    /// `i on j?`: brick `i` is on top of brick `j`.
    On(u8, u8),
    /// `pick b!`.
    Pick(u8),
    /// `place at P!`: put the held brick at `P`.
    PlaceAt(Position),
    /// `place on b!`: put the held brick on brick `b`.
    PlaceOn(u8),
    /// `apply force b!`: press brick `b` onto the brick below.
    ApplyForce(u8),
    /// `put i at P!`: pick and place in one action.
    PutAt(u8, Position),
    /// `put i on j!`: pick and place on a brick in one action.
    PutOn(u8, u8),
}

/// Index into [`Task::positions`].
pub type Position = u8;

impl Behavior {
    /// Condition or action.
    #[must_use]
    pub const fn kind(&self) -> LeafKind {
        match self {
            Self::Picked(_) | Self::AtPos(..) | Self::On(..) => LeafKind::Condition,
            _ => LeafKind::Action,
        }
    }
}

/// Everything a task is.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// The task.
    pub task: Task,
    /// Brick shapes, by brick index.
    pub bricks: Vec<BrickKind>,
    /// Start positions (x, y, z) of the bricks, metres.
    pub start: Vec<[f32; 3]>,
    /// Goal position of each brick that has one.
    pub goal: Vec<Option<[f32; 3]>>,
    /// What the world does that the planner does not know.
    pub mode: Mode,
    /// Position literals the behaviors name, as (x, y, z) and as written in names.
    pub positions: Vec<([f32; 3], &'static str)>,
    /// The behaviors, conditions first, in the reference order.
    pub behaviors: Vec<Behavior>,
    /// Names, parallel to `behaviors`.
    pub names: Vec<String>,
}

impl Task {
    /// All four, in the paper's order.
    pub const ALL: [Task; 4] = [Task::Tower, Task::Croissant, Task::Balance, Task::Blocking];

    /// The task's name on the command line: `tower`, `croissant`, `balance`, `blocking`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Tower => "tower",
            Self::Croissant => "croissant",
            Self::Balance => "balance",
            Self::Blocking => "blocking",
        }
    }

    /// The task with that command-line name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|t| t.name() == name)
    }

    /// The world mode.
    #[must_use]
    pub const fn mode(self) -> Mode {
        match self {
            Self::Tower => Mode::Default,
            Self::Croissant => Mode::Croissant,
            Self::Balance => Mode::Balance,
            Self::Blocking => Mode::Blocking,
        }
    }

    /// The position literals used by this task's behaviors.
    #[must_use]
    pub fn positions(self) -> Vec<([f32; 3], &'static str)> {
        match self {
            Self::Tower => vec![
                ([0.0, 0.05, 0.0], "(0.0, 0.05, 0.0)"),
                ([0.0, 0.05, 0.0192], "(0.0, 0.05, 0.0192)"),
                ([0.0, 0.05, 0.0384], "(0.0, 0.05, 0.0384)"),
            ],
            Self::Croissant => vec![
                ([0.0, 0.0, 0.0], "(0.0, 0.0, 0.0)"),
                ([0.0, 0.0, 0.0192], "(0.0, 0.0, 0.0192)"),
                ([0.016, -0.032, 0.0], "(0.016, -0.032, 0.0)"),
                ([0.016, 0.032, 0.0], "(0.016, 0.032, 0.0)"),
            ],
            Self::Balance => vec![([0.0, 0.0, 0.0192], "(0.0, 0.0, 0.0192)"), ([0.0, 0.0, 0.0], "(0.0, 0.0, 0.0)")],
            Self::Blocking => vec![
                ([-0.1, 0.0, 0.0], "(-0.1, 0.0, 0.0)"),
                ([-0.1, 0.0, 0.0192], "(-0.1, 0.0, 0.0192)"),
                ([0.0, 0.0, 0.0], "(0.0, 0.0, 0.0)"),
                ([0.0, 0.05, 0.0], "(0.0, 0.05, 0.0)"),
                ([0.0, -0.05, 0.0], "(0.0, -0.05, 0.0)"),
            ],
        }
    }

    /// The behaviors, conditions first, each group in the reference order. The planner
    /// takes the first achieving action in this order; GP draws leaves uniformly from it.
    #[must_use]
    pub fn behaviors(self) -> Vec<Behavior> {
        use Behavior::*;
        let pairs = |n: u8| -> Vec<(u8, u8)> {
            (0..n).flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j))).collect()
        };
        let mut v = Vec::new();
        match self {
            Self::Tower => {
                v.extend((0..3).map(Picked));
                v.extend([AtPos(0, 0), AtPos(1, 1), AtPos(2, 2)]);
                v.extend(pairs(3).into_iter().map(|(i, j)| On(i, j)));
                v.extend((0..3).map(Pick));
                v.push(PlaceAt(0));
                v.extend((0..3).map(PlaceOn));
                v.extend((0..3).map(ApplyForce));
            }
            Self::Croissant => {
                v.extend((0..4).map(Picked));
                v.extend([AtPos(0, 0), AtPos(1, 1), AtPos(2, 2), AtPos(3, 3)]);
                v.extend(pairs(4).into_iter().map(|(i, j)| On(i, j)));
                v.extend((0..4).map(Pick));
                v.extend([PlaceAt(0), PlaceAt(2), PlaceAt(3)]);
                v.extend((0..4).map(PlaceOn));
                v.extend((0..4).map(ApplyForce));
            }
            Self::Balance => {
                v.push(AtPos(0, 0));
                v.extend((0..3).map(|i| AtPos(i, 1)));
                v.extend(pairs(3).into_iter().map(|(i, j)| On(i, j)));
                v.extend((0..3).map(Pick));
                v.extend((0..3).map(|i| PutAt(i, 1)));
                v.extend([PutOn(0, 1), PutOn(0, 2), PutOn(1, 2), PutOn(2, 1)]);
                v.extend((0..3).map(ApplyForce));
            }
            Self::Blocking => {
                v.extend([AtPos(0, 0), AtPos(1, 1)]);
                v.extend((0..3).map(|i| AtPos(i, 2)));
                v.extend([On(0, 1), On(1, 0)]);
                v.extend((0..3).map(Pick));
                for p in [2, 0, 3, 4] {
                    v.extend((0..3).map(|i| PutAt(i, p)));
                }
                v.extend([PutOn(0, 1), PutOn(1, 0)]);
                v.extend((0..3).map(ApplyForce));
            }
        }
        v
    }

    /// The behavior's name, exactly as the reference writes it.
    #[must_use]
    pub fn behavior_name(self, b: Behavior) -> String {
        let positions = self.positions();
        let p = |i: Position| positions.get(usize::from(i)).map_or("(?)", |p| p.1);
        match b {
            Behavior::Picked(i) => format!("picked {i}?"),
            Behavior::AtPos(i, at) => format!("{i} at pos {}?", p(at)),
            Behavior::On(i, j) => format!("{i} on {j}?"),
            Behavior::Pick(i) => format!("pick {i}!"),
            Behavior::PlaceAt(at) => format!("place at {}!", p(at)),
            Behavior::PlaceOn(i) => format!("place on {i}!"),
            Behavior::ApplyForce(i) => format!("apply force {i}!"),
            Behavior::PutAt(i, at) => format!("put {i} at {}!", p(at)),
            Behavior::PutOn(i, j) => format!("put {i} on {j}!"),
        }
    }

    /// Everything about the task.
    #[must_use]
    pub fn spec(self) -> Spec {
        use BrickKind::*;
        type Layout = (Vec<BrickKind>, Vec<[f32; 3]>, Vec<Option<[f32; 3]>>);
        let (bricks, start, goal): Layout = match self {
            Self::Tower => (
                vec![TwoByTwo; 3],
                vec![[-0.05, -0.1, 0.0], [0.0, -0.1, 0.0], [0.05, -0.1, 0.0]],
                vec![Some([0.0, 0.05, 0.0]), Some([0.0, 0.05, 0.0192]), Some([0.0, 0.05, 0.0384])],
            ),
            Self::Croissant => (
                vec![TwoByTwo, FourByTwo, TwoByTwo, TwoByTwo],
                vec![[-0.05, -0.1, 0.0], [0.0, -0.1, 0.0], [0.05, -0.1, 0.0], [0.1, -0.1, 0.0]],
                vec![
                    Some([0.0, 0.0, 0.0]),
                    Some([0.0, 0.0, 0.0192]),
                    Some([0.016, -0.032, 0.0]),
                    Some([0.016, 0.032, 0.0]),
                ],
            ),
            Self::Balance => (
                vec![LongUnbalanced, TwoByTwo, FourByTwo],
                vec![[-0.05, -0.1, 0.0], [0.0, -0.1, 0.0], [0.05, -0.1, 0.0]],
                vec![Some([0.0, 0.0, 0.0192]), None, None],
            ),
            Self::Blocking => (
                vec![FourByTwo, FourByTwo, FourByTwoWithCone],
                vec![[0.0, -0.05, 0.0], [0.0, 0.05, 0.0], [-0.1, 0.0, 0.0]],
                vec![Some([-0.1, 0.0, 0.0]), Some([-0.1, 0.0, 0.0192]), Some([0.0, 0.0, 0.0])],
            ),
        };
        let behaviors = self.behaviors();
        let names = behaviors.iter().map(|&b| self.behavior_name(b)).collect();
        Spec { task: self, bricks, start, goal, mode: self.mode(), positions: self.positions(), behaviors, names }
    }
}

impl Spec {
    /// The behavior with id `id` (its index).
    #[must_use]
    pub fn behavior(&self, id: BehaviorId) -> Option<Behavior> {
        self.behaviors.get(usize::from(id)).copied()
    }

    /// The id of a behavior of this task.
    #[must_use]
    pub fn id_of(&self, b: Behavior) -> Option<BehaviorId> {
        self.behaviors.iter().position(|&x| x == b).and_then(|i| BehaviorId::try_from(i).ok())
    }

    /// The id of the behavior with this name.
    #[must_use]
    pub fn id_by_name(&self, name: &str) -> Option<BehaviorId> {
        self.names.iter().position(|n| n == name).and_then(|i| BehaviorId::try_from(i).ok())
    }

    /// Coordinates of position `p`.
    #[must_use]
    pub fn position(&self, p: Position) -> Option<[f32; 3]> {
        self.positions.get(usize::from(p)).map(|p| p.0)
    }
}

/// The task's behaviors as a bt-core behavior set: each without arguments, named as in
/// the reference.
impl bt_core::Catalog for Spec {
    fn len(&self) -> usize {
        self.behaviors.len()
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        let b = self.behavior(id)?;
        let name = self.names.get(usize::from(id))?;
        Some(BehaviorInfo { name, kind: b.kind(), arity: 0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bt_core::Catalog;

    #[test]
    fn behavior_counts_match_the_paper() {
        // Styrud et al.: 35 behaviors for croissant, 23 for balance.
        let count =
            |t: Task| (t.behaviors().len(), t.behaviors().iter().filter(|b| b.kind() == LeafKind::Condition).count());
        assert_eq!(count(Task::Tower), (12 + 10, 12));
        assert_eq!(count(Task::Croissant), (35, 20));
        assert_eq!(count(Task::Balance), (23, 10));
        assert_eq!(count(Task::Blocking), (27, 7));
    }

    #[test]
    fn names_are_the_references() {
        let s = Task::Tower.spec();
        assert_eq!(&s.names[..4], ["picked 0?", "picked 1?", "picked 2?", "0 at pos (0.0, 0.05, 0.0)?"]);
        assert_eq!(s.names[6..12], ["0 on 1?", "0 on 2?", "1 on 0?", "1 on 2?", "2 on 0?", "2 on 1?"]);
        assert_eq!(
            s.names[12..],
            [
                "pick 0!",
                "pick 1!",
                "pick 2!",
                "place at (0.0, 0.05, 0.0)!",
                "place on 0!",
                "place on 1!",
                "place on 2!",
                "apply force 0!",
                "apply force 1!",
                "apply force 2!"
            ]
        );
        let b = Task::Blocking.spec();
        assert_eq!(
            &b.names[10..16],
            [
                "put 0 at (0.0, 0.0, 0.0)!",
                "put 1 at (0.0, 0.0, 0.0)!",
                "put 2 at (0.0, 0.0, 0.0)!",
                "put 0 at (-0.1, 0.0, 0.0)!",
                "put 1 at (-0.1, 0.0, 0.0)!",
                "put 2 at (-0.1, 0.0, 0.0)!"
            ]
        );
        let bal = Task::Balance.spec();
        assert_eq!(bal.names[0], "0 at pos (0.0, 0.0, 0.0192)?");
        assert_eq!(
            bal.names[13..17],
            ["put 0 at (0.0, 0.0, 0.0)!", "put 1 at (0.0, 0.0, 0.0)!", "put 2 at (0.0, 0.0, 0.0)!", "put 0 on 1!"]
        );
    }

    #[test]
    fn spec_is_a_catalog_with_unique_names_and_fingerprints() {
        let mut fps = Vec::new();
        for t in Task::ALL {
            let s = t.spec();
            let mut names = s.names.clone();
            names.sort();
            names.dedup();
            assert_eq!(names.len(), s.names.len(), "{t:?}");
            assert_eq!(s.id_by_name(&s.names[3]), Some(3));
            assert_eq!(Task::from_name(t.name()), Some(t));
            fps.push(s.fingerprint());
        }
        fps.sort_unstable();
        fps.dedup();
        assert_eq!(fps.len(), 4);
    }
}
