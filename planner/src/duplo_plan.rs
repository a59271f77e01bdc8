//! The planner's model of the brick tasks: the templates of
//! `docs/brick-tasks.md`, grounded with the task's behaviors as leaves.
//!
//! Objects are the bricks `b0..` then the position literals `p0..` of the task. The
//! templates, in the order the planner tries them (the order of the behaviors):
//!
//! * `pick(b)`: no precondition; achieves `picked b?`. Leaf `pick b!`.
//! * `place-at(c, P)`: needs `picked c?`; achieves `c at pos P?`. Leaf `place at P!` —
//!   the brick `c` is the brick of the condition being expanded and does not show in
//!   the leaf; the world places whichever brick is held.
//! * `place-on(c, b)`: needs `picked c?`; achieves `c on b?`. Leaf `place on b!`.
//! * `put-at(i, P)`: achieves `i at pos P?`; `put-on(i, j)`: achieves `i on j?`.
//! * `apply-force(b, L, P)`: needs `b on L?`; achieves `b at pos P?`, where `P` is `b`'s
//!   pressed position on the brick `L` below it (`L` is the first other brick with a
//!   condition `L at pos Q?` exactly one brick height under `P`).
//!   `apply-force-on-base(b, L, P, Q)` is the same when `L`'s position `Q` is not a goal
//!   of the task (balance): it needs `L at pos Q?` first. Leaf `apply force b!`.
//!
//! The goal is the Sequence of the goal conditions in brick order. The model knows no
//! physics: the tree solves the tower and fails croissant, balance and blocking in
//! worlds that have it.

use std::sync::Arc;

use bt_core::Leaf;

use crate::duplo::{BRICK_HEIGHT, Behavior, Spec, Task};
use crate::ground::{Grounding, Vocabulary};
use crate::model::{Atom, DomainBuilder, ModelError, ObjectId, Problem, ProblemBuilder, TemplateId};
use crate::{Options, Plan, PlanError};

const PICK: TemplateId = 0;
const PLACE_AT: TemplateId = 1;
const PLACE_ON: TemplateId = 2;
const PUT_AT: TemplateId = 3;
const PUT_ON: TemplateId = 4;
const FORCE: TemplateId = 5;
const FORCE_ON_BASE: TemplateId = 6;

fn close(a: [f32; 3], b: [f32; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-4)
}

fn problem(spec: &Spec) -> Result<Problem, ModelError> {
    let mut d = DomainBuilder::new("bricks");
    d.types(&["brick", "pos"], "object")?;
    d.predicate("picked", &[("b", "brick")])?;
    d.predicate("at-pos", &[("b", "brick"), ("p", "pos")])?;
    d.predicate("on", &[("b", "brick"), ("c", "brick")])?;
    d.predicate("pressed", &[("b", "brick"), ("l", "brick"), ("p", "pos")])?;
    d.predicate("pressed-on-base", &[("b", "brick"), ("l", "brick"), ("p", "pos"), ("q", "pos")])?;
    d.action("pick", &[("b", "brick")])?.effect("picked", &["b"])?;
    d.action("place-at", &[("c", "brick"), ("p", "pos")])?
        .pre("picked", &["c"])?
        .effect("at-pos", &["c", "p"])?
        .effect_not("picked", &["c"])?;
    d.action("place-on", &[("c", "brick"), ("b", "brick")])?
        .pre("picked", &["c"])?
        .effect("on", &["c", "b"])?
        .effect_not("picked", &["c"])?;
    d.action("put-at", &[("i", "brick"), ("p", "pos")])?.effect("at-pos", &["i", "p"])?;
    d.action("put-on", &[("i", "brick"), ("j", "brick")])?.effect("on", &["i", "j"])?;
    d.action("apply-force", &[("b", "brick"), ("l", "brick"), ("p", "pos")])?
        .pre("pressed", &["b", "l", "p"])?
        .pre("on", &["b", "l"])?
        .effect("at-pos", &["b", "p"])?;
    d.action("apply-force-on-base", &[("b", "brick"), ("l", "brick"), ("p", "pos"), ("q", "pos")])?
        .pre("pressed-on-base", &["b", "l", "p", "q"])?
        .pre("at-pos", &["l", "q"])?
        .pre("on", &["b", "l"])?
        .effect("at-pos", &["b", "p"])?;
    let domain = d.build()?;

    let bricks: Vec<String> = (0..spec.bricks.len()).map(|i| format!("b{i}")).collect();
    let positions: Vec<String> = (0..spec.positions.len()).map(|i| format!("p{i}")).collect();
    let mut p = ProblemBuilder::new(spec.task.name(), &domain);
    p.objects(&bricks.iter().map(String::as_str).collect::<Vec<_>>(), "brick")?;
    p.objects(&positions.iter().map(String::as_str).collect::<Vec<_>>(), "pos")?;
    let b = |i: u8| bricks[usize::from(i)].as_str();
    let q = |i: u8| positions[usize::from(i)].as_str();
    for (i, start) in spec.start.iter().enumerate() {
        for (k, pos) in spec.positions.iter().enumerate() {
            if close(*start, pos.0) {
                p.init("at-pos", &[&bricks[i], &positions[k]])?;
            }
        }
    }
    // The brick below each raised goal-position condition.
    for &beh in &spec.behaviors {
        let Behavior::AtPos(brick, at) = beh else { continue };
        let Some(target) = spec.position(at) else { continue };
        if target[2] <= 0.0 {
            continue;
        }
        let under = [target[0], target[1], target[2] - BRICK_HEIGHT];
        let below = spec.behaviors.iter().find_map(|&x| match x {
            Behavior::AtPos(l, qq) if l != brick && spec.position(qq).is_some_and(|pq| close(pq, under)) => {
                Some((l, qq))
            }
            _ => None,
        });
        let Some((l, qq)) = below else { continue };
        let is_goal = spec.goal.get(usize::from(l)).copied().flatten().is_some_and(|g| close(g, under));
        if is_goal {
            p.init("pressed", &[b(brick), b(l), q(at)])?;
        } else {
            p.init("pressed-on-base", &[b(brick), b(l), q(at), q(qq)])?;
        }
    }
    for (i, goal) in spec.goal.iter().enumerate() {
        let Some(goal) = goal else { continue };
        if let Some(k) = spec.positions.iter().position(|pos| close(pos.0, *goal)) {
            p.goal("at-pos", &[&bricks[i], &positions[k]])?;
        }
    }
    p.build()
}

/// The task's behaviors as the leaves of the model above.
struct Leaves<'a> {
    spec: &'a Spec,
    bricks: u16,
}

impl Leaves<'_> {
    fn leaf(&self, b: Behavior) -> Option<Leaf> {
        self.spec.id_of(b).map(Leaf::new)
    }
    fn brick(&self, o: ObjectId) -> Option<u8> {
        u8::try_from(o).ok().filter(|_| o < self.bricks)
    }
    fn pos(&self, o: ObjectId) -> Option<u8> {
        o.checked_sub(self.bricks).and_then(|p| u8::try_from(p).ok())
    }
}

impl Vocabulary for Leaves<'_> {
    fn condition(&self, problem: &Problem, atom: &Atom<ObjectId>) -> Option<Leaf> {
        let name = problem.domain.predicates.get(usize::from(atom.predicate))?.name.as_str();
        let a = &atom.args;
        let b = match (name, a.as_slice()) {
            ("picked", &[x]) => Behavior::Picked(self.brick(x)?),
            ("at-pos", &[x, p]) => Behavior::AtPos(self.brick(x)?, self.pos(p)?),
            ("on", &[x, y]) => Behavior::On(self.brick(x)?, self.brick(y)?),
            _ => return None,
        };
        self.leaf(b)
    }

    fn action(&self, _: &Problem, template: TemplateId, args: &[ObjectId]) -> Option<Leaf> {
        let b = match (template, args) {
            (PICK, &[x]) => Behavior::Pick(self.brick(x)?),
            (PLACE_AT, &[_, p]) => Behavior::PlaceAt(self.pos(p)?),
            (PLACE_ON, &[_, y]) => Behavior::PlaceOn(self.brick(y)?),
            (PUT_AT, &[x, p]) => Behavior::PutAt(self.brick(x)?, self.pos(p)?),
            (PUT_ON, &[x, y]) => Behavior::PutOn(self.brick(x)?, self.brick(y)?),
            (FORCE | FORCE_ON_BASE, &[x, ..]) => Behavior::ApplyForce(self.brick(x)?),
            _ => return None,
        };
        self.leaf(b)
    }
}

/// The planner's model of a brick task, grounded with the task's behaviors as leaves.
///
/// # Errors
/// Never for the four tasks; [`PlanError::TooLarge`] in principle.
pub fn grounding(task: Task) -> Result<Grounding, PlanError> {
    let spec = task.spec();
    let problem = problem(&spec).map_err(|e| PlanError::NoLeaf { condition: format!("brick model: {e}") })?;
    let leaves = Leaves { spec: &spec, bricks: spec.bricks.len() as u16 };
    Grounding::with_vocabulary(&problem, &leaves)
}

/// Plans a brick task offline; the tree's catalog is `task.spec()`.
///
/// # Errors
/// As [`crate::plan`].
pub fn plan(task: Task, options: Options) -> Result<Plan<Spec>, PlanError> {
    crate::plan(Arc::new(grounding(task)?), Arc::new(task.spec()), options)
}
