use bt_core::{BehaviorInfo, Context, Leaf, Node, NodeId, NodeKind, NodeState, Status, Tree};

use super::*;
use crate::agent::BeforeTicks;
use crate::end::{Failures, Finished, FirstSuccess, SuccessTwice};

/// A counter: `full?` holds at `goal`; `add!` runs one tick, then adds one. Every call,
/// halt and step is written down.
#[derive(Default)]
struct Counter {
    count: u32,
    goal: u32,
    running: bool,
    log: Vec<String>,
}

impl BehaviorSet for Counter {
    fn condition(&mut self, _: &Leaf, ctx: Context<'_>) -> Status {
        self.log.push(format!("full? @{}", ctx.now));
        if self.count >= self.goal { Status::Success } else { Status::Failure }
    }

    fn action(&mut self, _: &Leaf, ctx: Context<'_>) -> Status {
        if self.running && !ctx.starting {
            self.running = false;
            self.count += 1;
            self.log.push("add! done".into());
            return Status::Success;
        }
        self.running = true;
        self.log.push("add! starts".into());
        Status::Running
    }

    fn halt(&mut self, _: &Leaf, _: NodeId) {
        self.running = false;
        self.log.push("halt".into());
    }
}

impl World for Counter {
    fn reset(&mut self) {
        self.count = 0;
        self.running = false;
    }

    fn step(&mut self) {
        self.log.push("step".into());
    }
}

const CATALOG: [BehaviorInfo<'static>; 2] = [BehaviorInfo::condition("full", 0), BehaviorInfo::action("add", 0)];

/// `Fallback(full?, add!)`.
const FILL: [Node; 3] = [
    Node::new(NodeKind::Fallback, 3),
    Node::new(NodeKind::Condition(Leaf::new(0)), 1),
    Node::new(NodeKind::Action(Leaf::new(1)), 1),
];

/// `Sequence(full?, add!)`: fails while not full.
const CHECK: [Node; 3] = [
    Node::new(NodeKind::Sequence, 3),
    Node::new(NodeKind::Condition(Leaf::new(0)), 1),
    Node::new(NodeKind::Action(Leaf::new(1)), 1),
];

fn tree(nodes: &[Node]) -> Tree<'_, 4> {
    Tree::validate(nodes, &CATALOG[..]).unwrap()
}

#[test]
fn a_styrud_episode_ends_on_the_second_success_and_the_world_steps_after_every_tick() {
    let mut w = Counter { goal: 1, ..Counter::default() };
    let mut runner = Runner::new(Settings::new(10, Clock::TENTHS));
    let out =
        runner.run(tree(&FILL), &mut w, &mut (Failures::first(), SuccessTwice::default()), &mut (), &mut ()).unwrap();
    assert_eq!(out, Outcome { stop: Stop::Success, ticks: 3, root: Status::Success });
    assert_eq!(
        w.log,
        ["full? @0", "add! starts", "step", "full? @100", "add! done", "step", "full? @200", "step"],
        "tick 1 at 0 ms"
    );
}

#[test]
fn the_limit_ends_an_episode_and_may_halt_what_runs() {
    for (halt, moves_on) in [(false, true), (true, false)] {
        let mut w = Counter { goal: 5, ..Counter::default() };
        let settings = Settings { halt_at_limit: halt, moves_on_at_limit: moves_on, ..Settings::new(3, Clock::TENTHS) };
        let mut runner = Runner::new(settings);
        let out = runner.run(tree(&FILL), &mut w, &mut Failures::first(), &mut (), &mut ()).unwrap();
        assert_eq!(out, Outcome { stop: Stop::Limit, ticks: 3, root: Status::Running });
        assert_eq!(w.log.last().map(String::as_str), Some(if halt { "halt" } else { "step" }));
        assert_eq!(w.log.iter().filter(|l| *l == "step").count(), if moves_on { 3 } else { 2 });
        assert_eq!(runner.states()[2].status(), if halt { NodeStatus::Idle } else { NodeStatus::Running });
    }
}

#[test]
fn an_end_rule_may_stop_the_world_before_it_moves_on() {
    let mut w = Counter { goal: 0, ..Counter::default() };
    let settings = Settings {
        moves_on_at_stop: false,
        clock: Clock { ms_per_tick: 1, first: 1 },
        ..Settings::new(5, Clock::TENTHS)
    };
    let out = Runner::new(settings).run(tree(&FILL), &mut w, &mut Finished, &mut (), &mut ()).unwrap();
    assert_eq!(out.stop, Stop::Success);
    assert_eq!(w.log, ["full? @1"]);
}

#[test]
fn agents_act_before_the_first_tick_and_between_ticks_only() {
    let mut w = Counter { goal: 2, ..Counter::default() };
    let mut before = Vec::new();
    let mut script = BeforeTicks(|t: u32, w: &mut Counter| {
        before.push(t);
        w.log.push(format!("agent {t}"));
    });
    let settings = Settings { moves_on_at_stop: false, ..Settings::new(10, Clock::TENTHS) };
    let out = Runner::new(settings).run(tree(&CHECK), &mut w, &mut Failures::first(), &mut script, &mut ()).unwrap();
    assert_eq!(out.stop, Stop::Failure);
    assert_eq!(before, [1], "no agent after the tick that ended the episode");
}

/// Grows `CHECK` into `FILL` on the first failure.
struct Grows {
    nodes: Vec<Node>,
    grown: u32,
}

impl Trees<Counter> for Grows {
    type Growth = &'static str;
    type Error = String;

    fn tree<const D: usize>(&self) -> Result<Tree<'_, D>, LoadError> {
        Tree::validate(&self.nodes, &CATALOG[..])
    }

    fn grow(&mut self, tick: u32, states: &[NodeState], world: &mut Counter) -> Result<Option<&'static str>, String> {
        assert_eq!(states[1].status(), NodeStatus::Failure, "the states of the failed tick");
        world.log.push(format!("grow at {tick}"));
        if self.grown > 0 {
            return Err("no more".into());
        }
        self.grown += 1;
        self.nodes = FILL.to_vec();
        Ok(Some("fill"))
    }
}

/// Writes down what it is told.
#[derive(Default)]
struct Log(Vec<String>);

impl Recorder<Counter, &'static str> for Log {
    const LEAVES: bool = true;
    const CHANGES: bool = true;

    fn start(&mut self, _: &Counter, tree: &TreeState<'_>) {
        self.0.push(format!("start {}", tree.nodes.len()));
    }

    fn ticked(&mut self, t: &Ticked<'_>, _: &Counter) {
        self.0.push(format!("tick {} {:?} calls {} changes {}", t.tick, t.root, t.calls.len(), t.changes.len()));
    }

    fn grown(&mut self, tick: u32, growth: &&'static str, nodes: &[Node]) {
        self.0.push(format!("grown {tick} {growth} {}", nodes.len()));
    }

    fn stepped(&mut self, tick: u32, _: Status, _: &[NodeState], w: &Counter) {
        self.0.push(format!("stepped {tick} {}", w.count));
    }

    fn end(&mut self, o: &Outcome, _: &TreeState<'_>, _: &Counter) {
        self.0.push(format!("end {:?} {}", o.stop, o.ticks));
    }
}

#[test]
fn a_tree_that_grows_goes_on_from_the_world_as_it_is() {
    let mut w = Counter { goal: 1, ..Counter::default() };
    let mut trees = Grows { nodes: CHECK.to_vec(), grown: 0 };
    let mut log = Log::default();
    let settings = Settings { moves_on_at_stop: false, ..Settings::new(10, Clock::TENTHS) };
    let out = Runner::new(settings)
        .run_growing::<4, _, _, _, _, _>(&mut trees, &mut w, &mut (Failures::first(), FirstSuccess), &mut (), &mut log)
        .unwrap();
    assert_eq!(out, Outcome { stop: Stop::Success, ticks: 3, root: Status::Success });
    assert_eq!(
        log.0,
        [
            "start 3",
            "tick 1 Failure calls 1 changes 2",
            "grown 1 fill 3",
            "stepped 1 0",
            "tick 2 Running calls 2 changes 3",
            "stepped 2 0",
            "tick 3 Success calls 2 changes 2",
            "end Success 3",
        ]
    );
    // The clock went on across the growth: tick 2 at 100 ms.
    assert!(w.log.contains(&"full? @100".to_string()), "{:?}", w.log);
}

/// `CHECK` in a counter that is full at `goal`, growing at most once (none if
/// `grown`), for at most `limit` ticks until the first Failure it does not grow at.
fn grow_once(goal: u32, grown: u32, limit: u32) -> (Result<Outcome, RunError<String>>, Vec<String>) {
    let mut w = Counter { goal, ..Counter::default() };
    let mut trees = Grows { nodes: CHECK.to_vec(), grown };
    let out = Runner::new(Settings::new(limit, Clock::TENTHS)).run_growing::<4, _, _, _, _, _>(
        &mut trees,
        &mut w,
        &mut Failures::first(),
        &mut (),
        &mut (),
    );
    (out, w.log)
}

#[test]
fn a_tree_that_cannot_grow_ends_the_run_with_the_tick() {
    let err = grow_once(5, 1, 10).0.unwrap_err();
    assert_eq!(err.tick, 1);
    assert_eq!(err.to_string(), "tick 1: no more");
}

#[test]
fn a_tree_that_grows_on_the_last_tick_ends_at_the_limit() {
    let (out, log) = grow_once(1, 0, 1);
    assert_eq!(out.unwrap(), Outcome { stop: Stop::Limit, ticks: 1, root: Status::Failure });
    assert_eq!(log, ["full? @0", "grow at 1", "step"]);
}
