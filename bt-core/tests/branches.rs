//! The control nodes whose children have parts to play (rule 9): IfThenElse and
//! WhileDoElse, counted like BehaviorTree.CPP's `gtest_if_then_else.cpp` and
//! `gtest_while_do_else.cpp`, and Nav2's RecoveryNode, in the manner of Nav2's unit
//! tests.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::{Node, NodeKind, NodeStatus, Status};
use common::{F, R, S, Scripted, act, build, children_idle, cond};

fn if_then_else(condition: Status, then: Status, otherwise: Option<Status>) -> (Status, Scripted) {
    let nodes = build(|b| {
        b.open(NodeKind::IfThenElse)?.action(act(0), &[])?.action(act(1), &[])?;
        if otherwise.is_some() {
            b.action(act(2), &[])?;
        }
        b.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), condition).set(act(1), then).set(act(2), otherwise.unwrap_or(F));
    let r = exec.tick(&mut w, 0).unwrap();
    (r, w)
}

#[test]
fn if_then_else_picks_a_branch() {
    let (r, w) = if_then_else(S, S, Some(F));
    assert_eq!((r, w.ticks(act(1)), w.ticks(act(2))), (S, 1, 0));
    let (r, w) = if_then_else(F, F, Some(S));
    assert_eq!((r, w.ticks(act(1)), w.ticks(act(2))), (S, 0, 1));
    let (r, w) = if_then_else(F, S, None);
    assert_eq!((r, w.ticks(act(1))), (F, 0));
    let (r, w) = if_then_else(S, F, Some(S));
    assert_eq!((r, w.ticks(act(2))), (F, 0));
    let (r, w) = if_then_else(R, S, Some(S));
    assert_eq!((r, w.ticks(act(1)), w.ticks(act(2))), (R, 0, 0));
}

#[test]
fn if_then_else_stays_with_the_running_branch() {
    let nodes = build(|b| {
        b.open(NodeKind::IfThenElse)?.condition(cond(0), &[])?.action(act(1), &[])?.action(act(2), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), S).set(act(1), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    // The condition changes; the branch runs on without it being ticked.
    w.set(cond(0), F);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(w.ticks(cond(0)), 1);
    w.set(act(1), S);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
    assert_eq!((w.ticks(act(1)), w.ticks(act(2)), w.halts(act(1))), (3, 0, 0));
    // Then it starts over with the condition.
    w.set(act(2), F);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), F);
    assert_eq!((w.ticks(cond(0)), w.ticks(act(2))), (2, 1));
}

#[test]
fn while_do_else_switches_branches_halting_the_other_first() {
    let nodes = build(|b| {
        b.open(NodeKind::WhileDoElse)?.condition(cond(0), &[])?.action(act(1), &[])?.action(act(2), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), S).set(act(1), R).set(act(2), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.set(cond(0), F);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(w.halts(act(1)), 1);
    // The halt came before the else branch started.
    let pos = |c: common::Call| w.log.iter().position(|&l| l == c).unwrap();
    assert!(
        pos(common::Call::Halt { behavior: act(1) }) < pos(common::Call::Tick { behavior: act(2), starting: true })
    );
    w.set(cond(0), S);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), R);
    assert_eq!((w.halts(act(1)), w.halts(act(2))), (1, 1));
    assert_eq!(w.ticks(cond(0)), 3, "the condition is ticked on every tick");
    w.set(act(1), S);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), S);
    assert!(exec.states()[1..].iter().all(|s| s.status() == NodeStatus::Idle));
}

#[test]
fn while_do_else_with_two_children_fails_with_its_condition() {
    let nodes = build(|b| {
        b.open(NodeKind::WhileDoElse)?.condition(cond(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), S).set(act(1), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.set(cond(0), F);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), F);
    assert_eq!(w.halts(act(1)), 1);
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
