//! Nav2's control nodes and its plugin decorators as Gate (rule 9): PipelineSequence,
//! Recovery (RecoveryNode), RoundRobin and Gate, in the manner of Nav2's unit tests
//! (`nav2_behavior_tree/test/plugins/control/`): the children's statuses set tick by
//! tick, the node's result and the children's statuses and halts checked.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::{Node, NodeKind, NodeStatus, Status};
use common::{Scripted, act, build};

const S: Status = Status::Success;
const F: Status = Status::Failure;
const R: Status = Status::Running;
const K: Status = Status::Skipped;
const IDLE: NodeStatus = NodeStatus::Idle;

fn three(kind: NodeKind) -> &'static [Node] {
    build(|b| {
        b.open(kind)?.action(act(0), &[])?.action(act(1), &[])?.action(act(2), &[])?.end()?;
        Ok(())
    })
}

fn children_idle(states: &[bt_core::NodeState]) -> bool {
    states[1..].iter().all(|s| s.status() == IDLE)
}

#[test]
fn pipeline_sequence_fails_with_any_child_and_resets_them_all() {
    for fail_at in 0..3u16 {
        executor!(exec, three(NodeKind::PipelineSequence));
        let mut w = Scripted::new();
        for i in 0..3 {
            w.set(act(i), if i < fail_at { S } else { F });
        }
        assert_eq!(exec.tick(&mut w, 0).unwrap(), F);
        assert!(children_idle(exec.states()));
    }
    // A child before the furthest one fails: the running one is halted.
    executor!(exec, three(NodeKind::PipelineSequence));
    let mut w = Scripted::new();
    w.set(act(0), S).set(act(1), S).set(act(2), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.set(act(0), F);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), F);
    assert_eq!(w.halts(act(2)), 1);
    assert!(children_idle(exec.states()));
}

#[test]
fn pipeline_sequence_lets_earlier_children_run_on() {
    executor!(exec, three(NodeKind::PipelineSequence));
    let mut w = Scripted::new();
    w.set(act(0), R).set(act(1), R).set(act(2), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (1, 0));
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    // The first child runs again but is not the furthest: the tick goes on.
    w.set(act(0), R).set(act(1), S);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), R);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.ticks(act(2))), (3, 2, 1));
    w.set(act(2), S);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), S);
    assert!(children_idle(exec.states()));
    assert_eq!(w.halts(act(0)), 1, "the first child, still Running, is halted at the end");
}

#[test]
fn pipeline_sequence_skips() {
    executor!(exec, three(NodeKind::PipelineSequence));
    let mut w = Scripted::new();
    w.set(act(0), K).set(act(1), S).set(act(2), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), S);
    w.set(act(2), F);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), F);
    w.set(act(1), K).set(act(2), K);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), K);
    assert!(children_idle(exec.states()));
}

fn recovery(retries: u16) -> &'static [Node] {
    build(|b| {
        b.open(NodeKind::Recovery { retries })?.action(act(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    })
}

#[test]
fn recovery_succeeds_with_its_first_child() {
    executor!(exec, recovery(1));
    let mut w = Scripted::new();
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), S);
    assert_eq!(w.ticks(act(1)), 0);
    assert!(children_idle(exec.states()));
}

#[test]
fn recovery_recovers_then_retries_in_the_same_tick() {
    executor!(exec, recovery(1));
    let mut w = Scripted::new();
    w.set(act(0), F).set(act(1), S);
    // A0 fails, A1 recovers, A0 fails again: no retries left.
    assert_eq!(exec.tick(&mut w, 0).unwrap(), F);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (2, 1));
    assert!(children_idle(exec.states()));
    w.clear();
    // A running recovery is resumed next tick.
    w.set(act(1), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    w.set(act(1), S).set(act(0), S);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (2, 2));
}

#[test]
fn recovery_fails_when_the_recovery_fails_or_retries_are_used_up() {
    executor!(exec, recovery(3));
    let mut w = Scripted::new();
    w.set(act(0), F).set(act(1), F);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), F);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (1, 1));
    w.set(act(1), S);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), F);
    // 4 tries of A0, 3 recoveries.
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (5, 4));
    executor!(none, recovery(0));
    let mut w = Scripted::new();
    w.set(act(0), F);
    assert_eq!(none.tick(&mut w, 0).unwrap(), F);
    assert_eq!(w.ticks(act(1)), 0);
}

#[test]
fn recovery_count_is_kept_across_ticks_while_it_runs() {
    executor!(exec, recovery(2));
    let mut w = Scripted::new();
    // Tick 0: A1 runs (recovering); tick 1: it succeeds, A0 runs again.
    w.set(act(0), F).set(act(1), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.set(act(1), S).set(act(0), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    // One recovery used; A0 fails, a second recovery, A0 fails: no more.
    w.set(act(0), F);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), F);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (4, 3));
}

#[test]
fn round_robin_starts_where_the_last_success_left_off() {
    executor!(exec, three(NodeKind::RoundRobin));
    let mut w = Scripted::new();
    w.set(act(0), S).set(act(1), S).set(act(2), S);
    for expect in [0, 1, 2, 0] {
        w.clear();
        assert_eq!(exec.tick(&mut w, 0).unwrap(), S);
        assert_eq!(w.ticks(act(expect)), 1);
        assert!(children_idle(exec.states()));
    }
}

#[test]
fn round_robin_fails_when_all_fail_in_turn_and_keeps_a_running_child() {
    executor!(exec, three(NodeKind::RoundRobin));
    let mut w = Scripted::new();
    w.set(act(0), F).set(act(1), R).set(act(2), F);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.states()[1].status(), NodeStatus::Failure);
    w.set(act(1), F);
    // A1 fails, then A2: three failures since the turn began.
    assert_eq!(exec.tick(&mut w, 1).unwrap(), F);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.ticks(act(2))), (1, 2, 1));
    assert!(children_idle(exec.states()));
    // The turn went back to the first child.
    w.clear();
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
    assert_eq!(w.ticks(act(0)), 1);
}

#[test]
fn round_robin_halted_while_running_starts_over_at_the_first_child() {
    // Fallback[A3, RoundRobin[A0, A1, A2]]
    let nodes = build(|b| {
        b.fallback()?.action(act(3), &[])?;
        b.open(NodeKind::RoundRobin)?.action(act(0), &[])?.action(act(1), &[])?.action(act(2), &[])?.end()?;
        b.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(3), F).set(act(0), F).set(act(1), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.set(act(3), S);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), S);
    assert_eq!(w.halts(act(1)), 1);
    w.set(act(3), F).set(act(0), S);
    w.clear();
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
    assert_eq!(w.ticks(act(0)), 1, "halted Running: the turn is back at the first child");
}

/// A gate that opens when `open` is set, else answers `closed`; records `starting`.
struct GateWorld {
    inner: Scripted,
    open: bool,
    closed: Status,
    asked: Vec<bool>,
}

impl bt_core::BehaviorSet for GateWorld {
    fn condition(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> Status {
        self.inner.condition(leaf, ctx)
    }
    fn action(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> Status {
        if leaf.behavior() == act(9) {
            self.asked.push(ctx.starting);
            return if self.open { S } else { self.closed };
        }
        self.inner.action(leaf, ctx)
    }
    fn halt(&mut self, leaf: &bt_core::Leaf, node: bt_core::NodeId) {
        self.inner.halt(leaf, node);
    }
}

#[test]
fn gate_asks_its_behavior_and_never_stops_a_running_child() {
    let nodes = build(|b| {
        b.gate(act(9), &[])?.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = GateWorld { inner: Scripted::new(), open: true, closed: R, asked: vec![] };
    w.inner.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.open = false;
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(w.inner.ticks(act(0)), 2, "the running child is ticked whatever the gate says");
    w.inner.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
    // Closed: Running (a controller waiting) or Failure (SingleTrigger), child untouched.
    assert_eq!(exec.tick(&mut w, 3).unwrap(), R);
    w.closed = F;
    assert_eq!(exec.tick(&mut w, 4).unwrap(), F);
    assert_eq!(w.inner.ticks(act(0)), 3);
    // Tick 3 starts afresh (the root had finished); tick 4 follows a Running gate.
    assert_eq!(w.asked, [true, false, false, true, false]);
}
