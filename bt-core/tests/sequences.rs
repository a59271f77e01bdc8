//! BehaviorTree.CPP's and Nav2's sequences (rule 9): SequenceStar (BehaviorTree.CPP's
//! `SequenceWithMemory`), PipelineSequence and RoundRobin, counted like BehaviorTree.CPP's
//! `gtest_sequence.cpp` and Nav2's unit tests (`nav2_behavior_tree/test/plugins/control/`):
//! the children's statuses set tick by tick, the node's result and the children's
//! statuses and halts checked.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::{Node, NodeKind, NodeStatus};
use common::{F, K, R, S, Scripted, act, build, children_idle, cond};

#[test]
fn sequence_star_keeps_its_place_after_a_failure() {
    // SequenceStar[A0, C0, A1]: C0 fails twice, then succeeds.
    let nodes = build(|b| {
        b.open(NodeKind::SequenceStar)?.action(act(0), &[])?.condition(cond(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), S).set(cond(0), F).set(act(1), S);
    // A0 succeeds having been Idle: the tick ends there and asks to be ticked again.
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert!(exec.take_woken());
    assert_eq!(exec.tick(&mut w, 1).unwrap(), F);
    // Resumes at C0, not at A0.
    assert_eq!(exec.tick(&mut w, 2).unwrap(), F);
    assert_eq!(w.ticks(act(0)), 1);
    assert_eq!(w.ticks(cond(0)), 2);
    w.set(cond(0), S);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 4).unwrap(), S);
    assert_eq!((w.ticks(act(0)), w.ticks(cond(0)), w.ticks(act(1))), (1, 3, 1));
    // Finished: starts again from the first child, all children reset.
    assert!(exec.states()[1..].iter().all(|s| s.status() == NodeStatus::Idle));
    assert_eq!(exec.tick(&mut w, 5).unwrap(), R);
    assert_eq!(w.ticks(act(0)), 2);
}

#[test]
fn sequence_star_resumes_where_it_was_halted() {
    // Fallback[C0, SequenceStar[A0, A1]]: halted while A1 runs, it resumes at A1.
    let nodes = build(|b| {
        b.fallback()?.condition(cond(0), &[])?;
        b.open(NodeKind::SequenceStar)?.action(act(0), &[])?.action(act(1), &[])?.end()?;
        b.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), F).set(act(0), S).set(act(1), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    w.set(cond(0), S);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
    assert_eq!(w.halts(act(1)), 1);
    w.set(cond(0), F);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), R);
    assert_eq!(w.ticks(act(0)), 1, "A0 is not ticked again");
    // Tick 0 ended after A0 (wake-up); A1 ran on ticks 1 and 3.
    assert_eq!(w.ticks(act(1)), 2);
}

#[test]
fn sequence_star_goes_on_at_once_after_a_child_that_was_running() {
    let nodes = build(|b| {
        b.open(NodeKind::SequenceStar)?.action(act(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), R).set(act(1), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert!(!exec.woken(), "no wake-up after a child that was Running");
    assert_eq!(w.ticks(act(1)), 1);
}

fn three(kind: NodeKind) -> &'static [Node] {
    build(|b| {
        b.open(kind)?.action(act(0), &[])?.action(act(1), &[])?.action(act(2), &[])?.end()?;
        Ok(())
    })
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

/// BehaviorTree.CPP 3's SequenceStar: no wake-up between children, its place kept after
/// a Failure and through a reset, lost when it is halted while Running.
#[test]
fn sequence_star_v3_goes_on_at_once_and_forgets_its_place_when_halted() {
    // SequenceStarV3[A0, C0, A1].
    let nodes = build(|b| {
        b.open(NodeKind::SequenceStarV3)?.action(act(0), &[])?.condition(cond(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), S).set(cond(0), F).set(act(1), R);
    // A0 succeeds and C0 is ticked in the same tick, without a wake-up.
    assert_eq!(exec.tick(&mut w, 0).unwrap(), F);
    assert!(!exec.take_woken());
    // Resumes at C0 after the failure.
    w.set(cond(0), S);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!((w.ticks(act(0)), w.ticks(cond(0)), w.ticks(act(1))), (1, 2, 1));
    // Halted while A1 runs: back to A0.
    exec.halt_all(&mut w);
    assert_eq!(w.halts(act(1)), 1);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), R);
    assert_eq!(w.ticks(act(0)), 2);
    // Under a reactive parent that resets it after its failure, it keeps its place:
    // Sequence[C1, SequenceStarV3[A0, C0]].
    let nodes = build(|b| {
        b.sequence()?.condition(cond(1), &[])?;
        b.open(NodeKind::SequenceStarV3)?.action(act(0), &[])?.condition(cond(0), &[])?.end()?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(1), S).set(act(0), S).set(cond(0), F);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), F);
    w.set(cond(1), F);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), F);
    w.set(cond(1), S).set(cond(0), S);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
    assert_eq!((w.ticks(act(0)), w.ticks(cond(0))), (1, 2));
}
