//! The Fig. 3(e) tree of Colledanchise et al. (ICRA 2019) in a scripted world,
//! under the three reactivity situations of its Problem 1: an external agent undoes an
//! action (the tree re-does it), does an action for the robot (the tree skips it), and an
//! achieving action fails so another one is tried. The tree never changes.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use bt_core::{BehaviorInfo, BehaviorSet, Builder, Context, Executor, Leaf, Node, NodeId, NodeState, Status, Tree};

// Behaviors, as a controller would declare them.
const ON_GOAL: u16 = 0; //   o_c ∈ GoalRect
const HOLDING: u16 = 1; //   h = c
const NEAR: u16 = 2; //      o_r ∈ N_p        (p: a place)
const FREE: u16 = 3; //      τ ⊆ CollFree     (τ: a path)
const HAND_EMPTY: u16 = 4; // h = ∅
const MOVE_TO: u16 = 5; //   MoveTo(p, τ)
const PICK: u16 = 6; //      Pick(c)
const PLACE: u16 = 7; //     Place(c, p)

const BEHAVIORS: [BehaviorInfo<'static>; 8] = [
    BehaviorInfo::condition("cube on goal?", 0),
    BehaviorInfo::condition("holding cube?", 0),
    BehaviorInfo::condition("near", 1),
    BehaviorInfo::condition("free", 1),
    BehaviorInfo::condition("hand empty?", 0),
    BehaviorInfo::action("MoveTo", 2),
    BehaviorInfo::action("Pick", 0),
    BehaviorInfo::action("Place", 0),
];

// Places and paths.
const CUBE: u16 = 0; //  wherever the cube is
const GOAL: u16 = 1;
const TO_CUBE: u16 = 0;
const TO_GOAL: u16 = 1;
const TO_GOAL_ALT: u16 = 2;

/// Fig. 3(e); with `alternative`, the atomic BT of `o_r ∈ N_goal` has a second
/// achieving action, MoveTo(goal) along another path (Fig. 2 with two actions).
fn fig3e(storage: &mut [Node], alternative: bool) -> &[Node] {
    let mut b = Builder::<16>::new(storage);
    b.fallback().unwrap().condition(ON_GOAL, &[]).unwrap();
    b.sequence().unwrap();
    {
        b.fallback().unwrap().condition(HOLDING, &[]).unwrap();
        b.sequence().unwrap();
        b.fallback().unwrap().condition(NEAR, &[CUBE]).unwrap();
        b.sequence().unwrap().condition(FREE, &[TO_CUBE]).unwrap().action(MOVE_TO, &[CUBE, TO_CUBE]).unwrap();
        b.end().unwrap().end().unwrap();
        b.condition(HAND_EMPTY, &[]).unwrap().action(PICK, &[]).unwrap();
        b.end().unwrap().end().unwrap();
    }
    {
        b.fallback().unwrap().condition(NEAR, &[GOAL]).unwrap();
        b.sequence()
            .unwrap()
            .condition(FREE, &[TO_GOAL])
            .unwrap()
            .action(MOVE_TO, &[GOAL, TO_GOAL])
            .unwrap()
            .end()
            .unwrap();
        if alternative {
            b.sequence()
                .unwrap()
                .condition(FREE, &[TO_GOAL_ALT])
                .unwrap()
                .action(MOVE_TO, &[GOAL, TO_GOAL_ALT])
                .unwrap()
                .end()
                .unwrap();
        }
        b.end().unwrap();
    }
    b.action(PLACE, &[]).unwrap();
    b.end().unwrap().end().unwrap();
    b.finish().unwrap()
}

/// A 1-D world: the robot drives along a line at 4 units per tick; the cube lies
/// somewhere, is in the hand, or on the goal. External agents act at scripted ticks.
#[derive(Debug)]
struct World {
    robot: i32,
    cube: Option<i32>, // None: in the hand
    goal: i32,
    blocked: [bool; 3],
    /// Obstacles the robot will bump into on a path; seen only after bumping.
    hidden: [bool; 3],
    /// Running action and its progress (ticks since start).
    busy: Option<(u16, u32)>,
    log: Vec<String>,
}

impl World {
    fn new() -> Self {
        Self { robot: 0, cube: Some(20), goal: 40, blocked: [false; 3], hidden: [false; 3], busy: None, log: vec![] }
    }
    fn place(&self, p: u16) -> i32 {
        if p == GOAL { self.goal } else { self.cube.unwrap_or(self.robot) }
    }
    fn near(&self, p: u16) -> bool {
        (self.robot - self.place(p)).abs() <= 1
    }
    fn cube_on_goal(&self) -> bool {
        self.cube == Some(self.goal)
    }
    fn count(&self, what: &str) -> usize {
        self.log.iter().filter(|l| l.as_str() == what).count()
    }
}

fn b(v: bool) -> Status {
    if v { Status::Success } else { Status::Failure }
}

impl BehaviorSet for World {
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        match leaf.behavior() {
            ON_GOAL => b(self.cube_on_goal()),
            HOLDING => b(self.cube.is_none()),
            NEAR => b(self.near(leaf.args()[0])),
            FREE => b(!self.blocked[usize::from(leaf.args()[0])]),
            HAND_EMPTY => b(self.cube.is_some()),
            other => panic!("not a condition: {other}"),
        }
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let name = match leaf.behavior() {
            MOVE_TO => format!("MoveTo({}, {})", ["cube", "goal"][usize::from(leaf.args()[0])], leaf.args()[1]),
            PICK => "Pick".to_string(),
            PLACE => "Place".to_string(),
            other => panic!("not an action: {other}"),
        };
        if ctx.starting {
            assert!(self.busy.is_none(), "{name} starts while {:?} still runs", self.busy);
            self.log.push(format!("start {name}"));
            self.busy = Some((leaf.behavior(), 0));
        }
        let result = match leaf.behavior() {
            MOVE_TO => {
                let path = usize::from(leaf.args()[1]);
                if self.hidden[path] {
                    // Bumped into it: the path is now known to be blocked.
                    self.hidden[path] = false;
                    self.blocked[path] = true;
                    Status::Failure
                } else {
                    let target = self.place(leaf.args()[0]);
                    let step = (target - self.robot).clamp(-4, 4);
                    self.robot += step;
                    b(self.near(leaf.args()[0])).min_running()
                }
            }
            PICK => {
                if self.cube.is_some() && self.near(CUBE) {
                    self.cube = None;
                    Status::Success
                } else {
                    Status::Failure
                }
            }
            PLACE => {
                if self.cube.is_none() && self.near(GOAL) {
                    self.cube = Some(self.goal);
                    Status::Success
                } else {
                    Status::Failure
                }
            }
            _ => unreachable!(),
        };
        if result != Status::Running {
            self.log.push(format!("{name} {result}"));
            self.busy = None;
        }
        result
    }

    fn halt(&mut self, leaf: &Leaf, _: NodeId) {
        self.log.push(format!("halt {}", BEHAVIORS[usize::from(leaf.behavior())].name));
        self.busy = None;
    }
}

trait MinRunning {
    fn min_running(self) -> Status;
}
impl MinRunning for Status {
    /// Moving: Success on arrival, Running on the way.
    fn min_running(self) -> Status {
        if self == Status::Success { Status::Success } else { Status::Running }
    }
}

/// Ticks until the root succeeds (or 100 ticks), applying `event` before each tick.
fn run(world: &mut World, alternative: bool, mut event: impl FnMut(u32, &mut World)) -> (Status, u32) {
    let mut storage = [Node::EMPTY; 32];
    let nodes = fig3e(&mut storage, alternative);
    let tree = Tree::<16>::validate(nodes, &BEHAVIORS).unwrap();
    let mut state = [NodeState::IDLE; 32];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    for t in 0..100 {
        event(t, world);
        let s = exec.tick(world, t).unwrap();
        if s != Status::Running {
            return (s, t);
        }
    }
    (Status::Running, 100)
}

#[test]
fn fig3e_has_the_papers_shape() {
    let mut storage = [Node::EMPTY; 32];
    let nodes = fig3e(&mut storage, false);
    let tree = Tree::<16>::validate(nodes, &BEHAVIORS).unwrap();
    assert_eq!(
        tree.display(&BEHAVIORS).to_string(),
        "\
[o] Fallback
    --> cube on goal?
    {-} Sequence
        [o] Fallback
            --> holding cube?
            {-} Sequence
                [o] Fallback
                    --> near(0)
                    {-} Sequence
                        --> free(0)
                        --> MoveTo(0, 0)
                --> hand empty?
                --> Pick
        [o] Fallback
            --> near(1)
            {-} Sequence
                --> free(1)
                --> MoveTo(1, 1)
        --> Place
"
    );
}

#[test]
fn nominal_run_reaches_the_goal() {
    let mut w = World::new();
    let (status, _) = run(&mut w, false, |_, _| {});
    assert_eq!(status, Status::Success);
    assert!(w.cube_on_goal());
    assert_eq!(
        w.log,
        [
            "start MoveTo(cube, 0)",
            "MoveTo(cube, 0) SUCCESS",
            "start Pick",
            "Pick SUCCESS",
            "start MoveTo(goal, 1)",
            "MoveTo(goal, 1) SUCCESS",
            "start Place",
            "Place SUCCESS"
        ]
    );
}

#[test]
fn an_undone_action_is_redone() {
    // The cube slips out of the hand on the way to the goal: the tree picks it up
    // again (MoveTo(goal) is halted first), then carries on.
    let mut w = World::new();
    let (status, _) = run(&mut w, false, |t, w| {
        if t == 6 {
            assert!(w.cube.is_none() && w.robot > 20, "carrying the cube at tick 6");
            w.cube = Some(w.robot);
        }
    });
    assert_eq!(status, Status::Success);
    assert!(w.cube_on_goal());
    assert_eq!(w.count("start Pick"), 2, "{:?}", w.log);
    assert_eq!(w.count("start MoveTo(cube, 0)"), 1, "the cube fell where the robot is: no need to move");
    assert_eq!(w.count("halt MoveTo"), 1);
    let halt = w.log.iter().position(|l| l == "halt MoveTo").unwrap();
    assert_eq!(w.log[halt + 1], "start Pick", "halted before the new action starts");
}

#[test]
fn a_helped_action_is_skipped() {
    // On the way to the cube, an external agent puts it in the robot's hand: the tree
    // skips MoveTo(cube) and Pick and heads for the goal.
    let mut w = World::new();
    let (status, _) = run(&mut w, false, |t, w| {
        if t == 2 {
            w.cube = None;
        }
    });
    assert_eq!(status, Status::Success);
    assert!(w.cube_on_goal());
    assert_eq!(w.count("start Pick"), 0);
    assert_eq!(&w.log[..3], ["start MoveTo(cube, 0)", "halt MoveTo", "start MoveTo(goal, 1)"]);
}

#[test]
fn a_failing_achieving_action_gives_way_to_the_next() {
    // Something unseen blocks the usual path to the goal: MoveTo along it fails (and
    // the path is then known to be blocked), so the second achieving action is used.
    let mut w = World::new();
    w.hidden[usize::from(TO_GOAL)] = true;
    let (status, _) = run(&mut w, true, |_, _| {});
    assert_eq!(status, Status::Success);
    assert!(w.cube_on_goal());
    assert_eq!(w.count("MoveTo(goal, 1) FAILURE"), 1);
    assert_eq!(w.count("start MoveTo(goal, 2)"), 1);
    assert_eq!(w.count("MoveTo(goal, 2) SUCCESS"), 1);
}
