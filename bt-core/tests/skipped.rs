//! Skipped (rule 8) in the papers' kinds: a Sequence or Fallback whose children all skip
//! skips and stays Running, decorators pass it on, and a leaf that skips is Idle, counted
//! like BehaviorTree.CPP's `gtest_skipping.cpp`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::{NodeKind, NodeStatus};
use common::{F, K, R, S, Scripted, act, build};

#[test]
fn a_sequence_whose_children_all_skip_skips_and_stays_running() {
    let nodes = build(|b| {
        b.sequence()?;
        b.open(NodeKind::RunOnce { then_skip: true })?.action(act(0), &[])?.end()?;
        b.open(NodeKind::RunOnce { then_skip: true })?.action(act(1), &[])?.end()?;
        b.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), S).set(act(1), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), S);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), K);
    assert_eq!(exec.status(0), Some(NodeStatus::Running), "a control node that skips stays Running");
    assert_eq!(exec.tick(&mut w, 2).unwrap(), K);
}

#[test]
fn inverter_and_force_pass_skipped_on_keep_running_turns_it_into_running() {
    for (kind, want) in [
        (NodeKind::Inverter, K),
        (NodeKind::ForceSuccess, K),
        (NodeKind::ForceFailure, K),
        (NodeKind::KeepRunningUntilFailure, R),
        (NodeKind::RepeatCycles(2), K),
    ] {
        let nodes = build(|b| {
            b.open(kind)?.open(NodeKind::RunOnce { then_skip: true })?.action(act(0), &[])?.end()?.end()?;
            Ok(())
        });
        executor!(exec, nodes);
        let mut w = Scripted::new();
        w.set(act(0), F);
        exec.tick(&mut w, 0).unwrap();
        assert_eq!(exec.tick(&mut w, 1).unwrap(), want, "{kind:?}");
    }
}

#[test]
fn a_behavior_may_skip_its_leaf_is_then_idle() {
    let nodes = build(|b| {
        b.sequence()?.action(act(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), K).set(act(1), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), S);
    assert_eq!(exec.status(1), Some(NodeStatus::Idle));
    w.set(act(1), K);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), K);
}
