//! BehaviorTree.CPP's ParallelAll (rule 9): every child runs to the end; then the
//! failures are counted, as in BehaviorTree.CPP's `gtest_parallel.cpp`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::NodeKind;
use common::{F, R, S, Scripted, act, build};

#[test]
fn parallel_all_waits_for_every_child_then_counts_failures() {
    for (max_failures, want) in [(1, F), (2, S), (0, F)] {
        let nodes = build(|b| {
            b.open(NodeKind::ParallelAll { max_failures })?;
            b.action(act(0), &[])?.action(act(1), &[])?.action(act(2), &[])?.end()?;
            Ok(())
        });
        executor!(exec, nodes);
        let mut w = Scripted::new();
        w.set(act(0), F).set(act(1), R).set(act(2), S);
        assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
        w.set(act(1), S);
        // A0 and A2 finished: not ticked again.
        assert_eq!(exec.tick(&mut w, 1).unwrap(), if max_failures == 0 { F } else { want });
        assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.ticks(act(2))), (1, 2, 1));
    }
    // max_failures 0: it fails even with no failure.
    let nodes = build(|b| {
        b.open(NodeKind::ParallelAll { max_failures: 0 })?.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), F);
}

#[test]
fn parallel_all_does_not_stop_early() {
    let nodes = build(|b| {
        b.open(NodeKind::ParallelAll { max_failures: 1 })?.action(act(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), F).set(act(1), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(w.halts(act(1)), 0);
}

/// BehaviorTree.CPP 3's Parallel counts anew on every tick, in child order: a child
/// that finished earlier counts where it stands, so a later Running child is still
/// ticked before it; the first threshold reached decides and every child is reset.
#[test]
fn parallel_v3_counts_in_child_order_on_every_tick() {
    let nodes = build(|b| {
        b.open(NodeKind::ParallelV3 { success_threshold: 2, failure_threshold: 2 })?;
        b.action(act(0), &[])?.action(act(1), &[])?.action(act(2), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), R).set(act(1), R).set(act(2), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    // A0 succeeds: one success; A1 (Running) is ticked before A2 is counted as the
    // second, as 3.8 sweeps (version 4 would stop at A0 and halt A1).
    w.set(act(0), S).clear();
    assert_eq!(exec.tick(&mut w, 1).unwrap(), S);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.ticks(act(2))), (1, 1, 0));
    assert_eq!(w.halts(act(1)), 1);
    assert!(common::children_idle(exec.states()));
    // Failure once success is out of reach: two of three failed with 2 to succeed.
    let nodes = build(|b| {
        b.open(NodeKind::ParallelV3 { success_threshold: 2, failure_threshold: 3 })?;
        b.action(act(0), &[])?.action(act(1), &[])?.action(act(2), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), F).set(act(1), F).set(act(2), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), F);
    assert_eq!(w.ticks(act(2)), 0);
}
