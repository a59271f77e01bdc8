//! The fast symbolic brick world of Styrud et al., exactly as `docs/brick-tasks.md`
//! defines it: bricks are points (the centre of their bottom face), the gripper holds at
//! most one, and each task's *mode* adds the physics the planner does not know about.
//!
//! # Behaviors
//!
//! - `pick b!` needs an empty hand; the brick is held and lifted by [`PICK_HEIGHT`].
//! - `place at P!` / `place on b!` need a held brick; it moves to `P`, or onto `b` at
//!   `b + (0, 0, BRICK_HEIGHT + NOT_PRESSED_GAP)` (sitting on the studs, not pressed),
//!   and the hand empties. A place that fails leaves the brick held (and lifted).
//! - `apply force b!` needs an empty hand (else Failure). If `b` is on top of some brick
//!   `L` (the on-top test below), `b` drops to `L.z + BRICK_HEIGHT` (pressed); the first
//!   such `L` in brick order. Success whenever the hand is empty.
//! - `put i on j!` / `put i at P!`: pick and place in one action.
//! - `picked b?`: `b` is held. `b at pos P?`: the distance from `b` to `P` is below
//!   [`POSITION_MARGIN`]. `i on j?`: |dx| and |dy| below [`ON_TOP_MARGIN`] and
//!   `0 < dz <= BRICK_HEIGHT + ON_TOP_MARGIN`.
//!
//! # Timing
//!
//! Every action returns Running on its first tick and applies its effect on the next
//! (its second tick), returning Success or Failure then; so an action never runs long
//! enough for the 50-tick limit ([`crate::world::ACTION_TICK_LIMIT`]). Shortcuts when an
//! action starts: `pick b!` succeeds at once if it already holds `b` and fails if it
//! holds another; `place …!` fails at once on an empty hand; `apply force b!` fails at
//! once while holding; `put i on j!` succeeds at once if `i` is already on `j`; `put i at
//! P!` succeeds at once if `i` is already there and fails if another brick is held.
//!
//! # Modes
//!
//! - croissant: placing brick 2 or 3 fails while |brick1.y| < [`CROISSANT_CLEARANCE`]
//!   (the long brick is in the way).
//! - balance: placing 0 on 1 lands it offset by [`BALANCE_TIP`] in y (it tips); placing
//!   brick 2 at a position while brick 1 sits at y == 0.0 raises it by `BRICK_HEIGHT`.
//! - blocking: placing at a position fails if another brick is within
//!   [`POSITION_MARGIN`] of it; placing brick 2 at a position fails if another brick
//!   has exactly the same x and |dy| < [`BLOCKING_CONE_REACH`] (the cone collides);
//!   anything placed on brick 2 ends [`BLOCKING_CONE_LIFT`] higher (it cannot stack on
//!   the cone).
//!
//! # Decisions where the reference is silent
//!
//! These follow the published Python state machine the reference describes.
//! - Outside the blocking mode nothing is ever in the way: a place at an occupied spot,
//!   or onto a brick that carries another, succeeds and the bricks overlap.
//! - A place that a mode makes fail fails on the action's second tick, when its effect
//!   would apply (the start-of-action shortcuts know no mode physics); the brick stays
//!   held, lifted by the pick height.
//! - `put` picks as `pick` does, which needs an empty hand: `put i …!` while holding `i`
//!   itself starts (Running) and fails on its second tick. When its place fails, the
//!   brick stays held.
//! - `halt` cancels an action before its effect: the world does not change. What the
//!   next tick of the same node does is the world's [`HaltRule`]: by default
//!   ([`HaltRule::ResumeWithinTick`]) an action halted and started again *within the
//!   same tick* carries on as if never halted; otherwise it starts afresh (shortcuts
//!   included). See [`HaltRule`] for why.
//! - Picking a brick that carries another leaves the upper one where it is.
//! - Coordinates are `f32`, as in [`planner::duplo::Spec`]; the exact comparisons of the
//!   modes (`y == 0.0`, same `x`) compare coordinates copied from position literals and
//!   start positions, so they hold exactly as in the reference.
//! - The Python state machine raises, in the balance mode, the *behavior's* position
//!   literal along with the brick (a shared object), so the same node placing again
//!   aims 0.0192 higher each time; that is not part of the reference's definition and is
//!   not reproduced: every place at `P` aims at `P`.

use bt_core::{BehaviorSet, Context, Leaf, NodeId, Status};
use planner::duplo::{BRICK_HEIGHT, Behavior, Mode, Spec};

use crate::text::count;
use crate::world::{BrickWorld, MAX_BRICKS, SYMBOLIC_TICK_LIMIT};

/// Metres a picked brick is lifted.
pub const PICK_HEIGHT: f32 = 0.04;
/// Metres between a brick placed on another and the pressed height: it sits on the
/// studs until `apply force` presses it.
pub const NOT_PRESSED_GAP: f32 = 0.002;
/// Metres: `at pos` holds below this distance.
pub const POSITION_MARGIN: f32 = 0.001;
/// Metres: the on-top test's margin in x, y and above the brick height in z.
pub const ON_TOP_MARGIN: f32 = 0.003;
/// Croissant mode: bricks 2 and 3 cannot be placed while |brick1.y| is below this.
pub const CROISSANT_CLEARANCE: f32 = 0.01;
/// Balance mode: metres in y brick 0 lands off brick 1 when placed on it (it tips).
pub const BALANCE_TIP: f32 = 0.01;
/// Blocking mode: metres in y within which the cone of brick 2 collides with a brick at
/// the same x.
pub const BLOCKING_CONE_REACH: f32 = 0.1;
/// Blocking mode: metres higher than normal a brick placed on brick 2 ends.
pub const BLOCKING_CONE_LIFT: f32 = 0.05;

/// A task the symbolic world cannot play.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SymbolicError {
    /// More bricks than [`MAX_BRICKS`].
    #[error("task {task}: {}, the symbolic world holds at most {MAX_BRICKS}", crate::text::count(*.count, "brick"))]
    TooManyBricks {
        /// The task's name.
        task: &'static str,
        /// Its number of bricks.
        count: usize,
    },
    /// The task's lists disagree, or a behavior names a brick or position it lacks.
    #[error("task {task}: {what}")]
    BadSpec {
        /// The task's name.
        task: &'static str,
        /// What is wrong.
        what: String,
    },
}

/// What an action halted by the executor does when the tree starts it again.
///
/// bt-core halts before it starts (rule 4 of `bt_core::exec`): when an earlier action
/// of a reactive parent starts again, the Running action after it is halted first, even
/// if the earlier one then succeeds at once by a start-of-action shortcut and the tick
/// goes on to the halted one. The reference's py_trees halts only once the earlier child
/// returned Running or Failure, so there the later action simply continues. With
/// Sequence and Fallback only, an action halted and reached again within the same tick
/// is exactly one py_trees would not have halted, and nothing changed the world in
/// between (only start-of-action shortcuts ran, which change nothing); so resuming it
/// reproduces the reference's episodes. Under [`HaltRule::Cancel`], the common GP idiom
/// `s( pick 1! place on 0! )` never places: `pick 1!` restarts every tick and its
/// shortcut success comes after the place was halted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum HaltRule {
    /// An action halted and started again within the same tick (before the next
    /// [`worlds::World::step`]) carries on: the reference's outcomes.
    #[default]
    ResumeWithinTick,
    /// A halted action always starts afresh: bt-core's semantics taken literally.
    Cancel,
}

/// Most actions remembered as halted within one tick (one per Running branch; trees of
/// Sequences and Fallbacks have one).
const HALTED_SLOTS: usize = 4;

/// Where a place puts the held brick.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Target {
    At([f32; 3]),
    On(u8),
}

/// A behavior with its position literals resolved: what a tick executes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Picked(u8),
    AtPos(u8, [f32; 3]),
    On(u8, u8),
    Pick(u8),
    Place(Target),
    ApplyForce(u8),
    Put(u8, Target),
}

/// The symbolic brick world of one task. Built once; [`worlds::World::reset`] restores the
/// start state in place without allocating, so one world runs any number of episodes.
#[derive(Clone, Debug)]
pub struct SymbolicBrickWorld {
    spec: Spec,
    /// Indexed by behavior id.
    ops: Vec<Op>,
    mode: Mode,
    start: [[f32; 3]; MAX_BRICKS],
    pos: [[f32; 3]; MAX_BRICKS],
    held: Option<u8>,
    ticks: u32,
    halt_rule: HaltRule,
    /// Nodes halted during the current tick, before their effect.
    halted: [NodeId; HALTED_SLOTS],
    halted_len: usize,
}

impl SymbolicBrickWorld {
    /// The world of `spec`'s task, in its start state.
    ///
    /// # Errors
    /// [`SymbolicError`] when the task has more than [`MAX_BRICKS`] bricks, its lists
    /// disagree, or a behavior names a brick or position literal it does not have.
    pub fn new(spec: &Spec) -> Result<Self, SymbolicError> {
        let task = spec.task.name();
        let n = spec.bricks.len();
        if n > MAX_BRICKS {
            return Err(SymbolicError::TooManyBricks { task, count: n });
        }
        if spec.start.len() != n || spec.goal.len() != n {
            let what = format!(
                "{}, {} and {}",
                count(n, "brick"),
                count(spec.start.len(), "start position"),
                count(spec.goal.len(), "goal position")
            );
            return Err(SymbolicError::BadSpec { task, what });
        }
        let brick = |b: u8| {
            if usize::from(b) < n {
                Ok(b)
            } else {
                Err(SymbolicError::BadSpec { task, what: format!("a behavior names brick {b}, it has {n}") })
            }
        };
        let at = |p: u8| {
            spec.position(p).ok_or_else(|| SymbolicError::BadSpec {
                task,
                what: format!("a behavior names position {p}, it has {}", spec.positions.len()),
            })
        };
        let ops = spec
            .behaviors
            .iter()
            .map(|&b| {
                Ok(match b {
                    Behavior::Picked(i) => Op::Picked(brick(i)?),
                    Behavior::AtPos(i, p) => Op::AtPos(brick(i)?, at(p)?),
                    Behavior::On(i, j) => Op::On(brick(i)?, brick(j)?),
                    Behavior::Pick(i) => Op::Pick(brick(i)?),
                    Behavior::PlaceAt(p) => Op::Place(Target::At(at(p)?)),
                    Behavior::PlaceOn(j) => Op::Place(Target::On(brick(j)?)),
                    Behavior::ApplyForce(i) => Op::ApplyForce(brick(i)?),
                    Behavior::PutAt(i, p) => Op::Put(brick(i)?, Target::At(at(p)?)),
                    Behavior::PutOn(i, j) => Op::Put(brick(i)?, Target::On(brick(j)?)),
                })
            })
            .collect::<Result<Vec<_>, SymbolicError>>()?;
        let mut start = [[0.0; 3]; MAX_BRICKS];
        start[..n].copy_from_slice(&spec.start);
        Ok(Self {
            spec: spec.clone(),
            ops,
            mode: spec.mode,
            start,
            pos: start,
            held: None,
            ticks: 0,
            halt_rule: HaltRule::default(),
            halted: [0; HALTED_SLOTS],
            halted_len: 0,
        })
    }

    /// Uses another [`HaltRule`].
    #[must_use]
    pub fn with_halt_rule(mut self, rule: HaltRule) -> Self {
        self.halt_rule = rule;
        self
    }

    /// The [`HaltRule`] in force.
    #[must_use]
    pub fn halt_rule(&self) -> HaltRule {
        self.halt_rule
    }

    /// Forgets that `node` was halted this tick; true if it was.
    #[inline]
    fn take_halted(&mut self, node: NodeId) -> bool {
        let n = self.halted_len.min(HALTED_SLOTS);
        match self.halted[..n].iter().position(|&h| h == node) {
            Some(i) => {
                self.halted.copy_within(i + 1..n, i);
                self.halted_len = n - 1;
                true
            }
            None => false,
        }
    }

    /// Ticks stepped since the last reset.
    #[must_use]
    pub fn ticks(&self) -> u32 {
        self.ticks
    }

    /// Moves brick `brick` to `position` and sets what the hand holds, for setting up a
    /// situation by hand (tests, what-if runs). Out-of-range bricks are ignored.
    pub fn set_state(&mut self, positions: &[[f32; 3]], held: Option<u8>) {
        let n = self.spec.bricks.len();
        for (slot, &p) in self.pos[..n].iter_mut().zip(positions) {
            *slot = p;
        }
        self.held = held.filter(|&h| usize::from(h) < n);
    }

    // Brick indices were checked against the task in `new` (< MAX_BRICKS); the modulo
    // only keeps the indexing free of a panic path.
    #[inline(always)]
    fn p(&self, b: u8) -> [f32; 3] {
        self.pos[usize::from(b) % MAX_BRICKS]
    }

    #[inline(always)]
    fn p_mut(&mut self, b: u8) -> &mut [f32; 3] {
        &mut self.pos[usize::from(b) % MAX_BRICKS]
    }

    /// `upper` is on top of `lower`: |dx| and |dy| below the on-top margin, and
    /// `0 < dz <= BRICK_HEIGHT + ON_TOP_MARGIN`.
    #[inline]
    fn on_top(&self, upper: u8, lower: u8) -> bool {
        let (u, l) = (self.p(upper), self.p(lower));
        let dz = u[2] - l[2];
        (u[0] - l[0]).abs() < ON_TOP_MARGIN
            && (u[1] - l[1]).abs() < ON_TOP_MARGIN
            && 0.0 < dz
            && dz <= BRICK_HEIGHT + ON_TOP_MARGIN
    }

    /// Brick `b` is within the position margin of `at`.
    #[inline]
    fn at_pos(&self, b: u8, at: [f32; 3]) -> bool {
        distance(self.p(b), at) < POSITION_MARGIN
    }

    /// The effect of picking `b`: needs an empty hand.
    fn pick(&mut self, b: u8) -> bool {
        if self.held.is_some() {
            return false;
        }
        self.held = Some(b);
        self.p_mut(b)[2] += PICK_HEIGHT;
        true
    }

    /// The effect of placing the held brick, with the mode's physics.
    fn place(&mut self, target: Target) -> bool {
        let Some(h) = self.held else { return false };
        let n = self.spec.bricks.len() as u8;
        if self.mode == Mode::Croissant && (h == 2 || h == 3) && self.p(1)[1].abs() < CROISSANT_CLEARANCE {
            return false;
        }
        let mut to = match target {
            Target::At(p) => p,
            Target::On(b) => {
                let l = self.p(b);
                [l[0], l[1], l[2] + (BRICK_HEIGHT + NOT_PRESSED_GAP)]
            }
        };
        match (self.mode, target) {
            (Mode::Balance, Target::On(1)) if h == 0 => to[1] += BALANCE_TIP,
            (Mode::Balance, Target::At(_)) if h == 2 && self.p(1)[1] == 0.0 => to[2] += BRICK_HEIGHT,
            (Mode::Blocking, Target::At(_)) => {
                let others = (0..n).filter(|&i| i != h);
                if h == 2
                    && others.clone().any(|i| {
                        let o = self.p(i);
                        to[0] == o[0] && (to[1] - o[1]).abs() < BLOCKING_CONE_REACH
                    })
                {
                    return false;
                }
                if others.clone().any(|i| distance(self.p(i), to) < POSITION_MARGIN) {
                    return false;
                }
            }
            (Mode::Blocking, Target::On(2)) => to[2] += BLOCKING_CONE_LIFT,
            _ => {}
        }
        *self.p_mut(h) = to;
        self.held = None;
        true
    }

    /// The effect of pressing `b`: needs an empty hand.
    fn apply_force(&mut self, b: u8) -> bool {
        if self.held.is_some() {
            return false;
        }
        let n = self.spec.bricks.len() as u8;
        if let Some(l) = (0..n).find(|&l| l != b && self.on_top(b, l)) {
            self.p_mut(b)[2] = self.p(l)[2] + BRICK_HEIGHT;
        }
        true
    }

    /// First tick of an action: a shortcut result, or Running.
    fn start(&self, op: Op) -> Status {
        let shortcut = match op {
            Op::Pick(b) => match self.held {
                Some(h) if h == b => Some(Status::Success),
                Some(_) => Some(Status::Failure),
                None => None,
            },
            Op::Place(_) => self.held.is_none().then_some(Status::Failure),
            Op::ApplyForce(_) => self.held.is_some().then_some(Status::Failure),
            Op::Put(i, Target::On(j)) => self.on_top(i, j).then_some(Status::Success),
            Op::Put(i, Target::At(p)) => {
                if self.at_pos(i, p) {
                    Some(Status::Success)
                } else {
                    self.held.is_some_and(|h| h != i).then_some(Status::Failure)
                }
            }
            Op::Picked(_) | Op::AtPos(..) | Op::On(..) => Some(Status::Failure),
        };
        shortcut.unwrap_or(Status::Running)
    }

    /// Second tick of an action: its effect.
    fn finish(&mut self, op: Op) -> Status {
        let done = match op {
            Op::Pick(b) => self.pick(b),
            Op::Place(target) => self.place(target),
            Op::ApplyForce(b) => self.apply_force(b),
            Op::Put(i, target) => self.pick(i) && self.place(target),
            Op::Picked(_) | Op::AtPos(..) | Op::On(..) => false,
        };
        if done { Status::Success } else { Status::Failure }
    }
}

#[inline(always)]
fn distance(a: [f32; 3], b: [f32; 3]) -> f32 {
    let (dx, dy, dz) = (a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    (dx * dx + dy * dy + dz * dz).sqrt()
}

impl BehaviorSet for SymbolicBrickWorld {
    #[inline]
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        let holds = match self.ops.get(usize::from(leaf.behavior())) {
            Some(&Op::Picked(b)) => self.held == Some(b),
            Some(&Op::AtPos(b, p)) => self.at_pos(b, p),
            Some(&Op::On(i, j)) => self.on_top(i, j),
            _ => false,
        };
        if holds { Status::Success } else { Status::Failure }
    }

    #[inline]
    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let Some(&op) = self.ops.get(usize::from(leaf.behavior())) else { return Status::Failure };
        if !ctx.starting || (self.halted_len > 0 && self.take_halted(ctx.node)) {
            self.finish(op)
        } else {
            self.start(op)
        }
    }

    /// Cancels the action before its effect: nothing in the world changes. Under
    /// [`HaltRule::ResumeWithinTick`] the node is remembered until the next step.
    #[inline]
    fn halt(&mut self, _: &Leaf, node: NodeId) {
        if self.halt_rule == HaltRule::ResumeWithinTick {
            if self.halted_len >= HALTED_SLOTS {
                // More Running branches than slots (Parallel nodes): forget the oldest.
                self.halted.copy_within(1.., 0);
                self.halted_len = HALTED_SLOTS - 1;
            }
            if let Some(slot) = self.halted.get_mut(self.halted_len) {
                *slot = node;
                self.halted_len += 1;
            }
        }
    }
}

impl worlds::World for SymbolicBrickWorld {
    fn reset(&mut self) {
        self.pos = self.start;
        self.held = None;
        self.ticks = 0;
        self.halted_len = 0;
    }

    /// Nothing moves between ticks: actions take effect when ticked. Halted actions are
    /// forgotten.
    #[inline]
    fn step(&mut self) {
        self.ticks = self.ticks.wrapping_add(1);
        self.halted_len = 0;
    }
}

impl BrickWorld for SymbolicBrickWorld {
    fn spec(&self) -> &Spec {
        &self.spec
    }

    fn position(&self, brick: usize) -> [f32; 3] {
        if brick < self.spec.bricks.len() { self.pos[brick] } else { [f32::NAN; 3] }
    }

    fn held(&self) -> Option<u8> {
        self.held
    }

    fn tick_limit(&self) -> u32 {
        SYMBOLIC_TICK_LIMIT
    }
}

#[cfg(test)]
mod tests;
