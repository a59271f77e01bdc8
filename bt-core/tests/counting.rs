//! BehaviorTree.CPP's counting decorators (rules 9, 11): RepeatCycles (its `Repeat`),
//! RetryUntilSuccessful, KeepRunningUntilFailure and RunOnce, counted like
//! BehaviorTree.CPP's `gtest_decorator.cpp`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::{NodeKind, NodeStatus};
use common::{F, K, R, S, Scripted, act, build, over_action};

#[test]
fn repeat_cycles_ends_the_tick_after_a_child_that_finished_at_once() {
    executor!(exec, over_action(NodeKind::RepeatCycles(3)));
    let mut w = Scripted::new();
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert!(exec.take_woken());
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert!(exec.take_woken());
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
    assert!(!exec.take_woken());
    assert_eq!(w.ticks(act(0)), 3);
}

#[test]
fn repeat_cycles_ticks_again_at_once_after_a_child_that_was_running() {
    executor!(exec, over_action(NodeKind::RepeatCycles(3)));
    let mut w = Scripted::new();
    w.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.set(act(0), S);
    // Finishes (cycle 1), ticked again in the same tick (cycle 2, was Idle): wake-up.
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(w.ticks(act(0)), 3);
    assert!(exec.take_woken());
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
}

#[test]
fn repeat_cycles_fails_with_its_child_and_zero_cycles_succeed() {
    executor!(exec, over_action(NodeKind::RepeatCycles(5)));
    let mut w = Scripted::new();
    w.set(act(0), F);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), F);
    executor!(zero, over_action(NodeKind::RepeatCycles(0)));
    let mut w = Scripted::new();
    assert_eq!(zero.tick(&mut w, 0).unwrap(), S);
    assert_eq!(w.ticks(act(0)), 0);
}

#[test]
fn repeat_cycles_forever_never_loops_within_a_tick() {
    executor!(exec, over_action(NodeKind::RepeatCycles(NodeKind::FOREVER)));
    let mut w = Scripted::new();
    w.set(act(0), S);
    for t in 0..100 {
        assert_eq!(exec.tick(&mut w, t).unwrap(), R);
    }
    assert_eq!(w.ticks(act(0)), 100);
}

#[test]
fn retry_until_successful_counts_attempts() {
    executor!(exec, over_action(NodeKind::RetryUntilSuccessful(3)));
    let mut w = Scripted::new();
    w.set(act(0), F);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), F);
    assert_eq!(w.ticks(act(0)), 3);
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), S);
    executor!(zero, over_action(NodeKind::RetryUntilSuccessful(0)));
    assert_eq!(zero.tick(&mut w, 0).unwrap(), F);
}

#[test]
fn keep_running_until_failure() {
    executor!(exec, over_action(NodeKind::KeepRunningUntilFailure));
    let mut w = Scripted::new();
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.status(1), Some(NodeStatus::Idle), "the child is reset after a Success");
    w.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    w.set(act(0), F);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), F);
    assert_eq!(w.ticks(act(0)), 3);
}

#[test]
fn run_once_runs_its_child_once_ever() {
    for (then_skip, after) in [(true, K), (false, F)] {
        // Sequence[RunOnce[A0], A1]
        let nodes = build(|b| {
            b.sequence_with_memory()?;
            b.open(NodeKind::RunOnce { then_skip })?.action(act(0), &[])?.end()?;
            b.action(act(1), &[])?.end()?;
            Ok(())
        });
        executor!(exec, nodes);
        let mut w = Scripted::new();
        w.set(act(0), R).set(act(1), S);
        assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
        w.set(act(0), F);
        assert_eq!(exec.tick(&mut w, 1).unwrap(), F);
        // Skipped: the sequence goes on; not skipped: the remembered Failure.
        let want = if after == K { S } else { F };
        assert_eq!(exec.tick(&mut w, 2).unwrap(), want);
        // A halt of everything does not make it run again.
        exec.halt_all(&mut w);
        assert_eq!(exec.tick(&mut w, 3).unwrap(), want);
        assert_eq!(w.ticks(act(0)), 2);
        assert_eq!(w.ticks(act(1)), if after == K { 2 } else { 0 });
        if after == K {
            assert_eq!(exec.status(1), Some(NodeStatus::Idle), "a RunOnce that skips is Idle");
        }
    }
}
