//! BehaviorTree.CPP's control nodes that bt-core has as kinds of their own (rule 9):
//! SequenceStar (its `SequenceWithMemory`), IfThenElse, WhileDoElse, ParallelAll, and
//! Parallel with `count_skipped`. Counted like BehaviorTree.CPP's `gtest_sequence.cpp`,
//! `gtest_if_then_else.cpp`, `gtest_while_do_else.cpp` and `gtest_parallel.cpp`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::{NodeKind, NodeStatus, Status};
use common::{Scripted, act, build, cond};

const S: Status = Status::Success;
const F: Status = Status::Failure;
const R: Status = Status::Running;

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

#[test]
fn parallel_counts_skipped_children_only_when_asked() {
    // Parallel(success 2, failure 1)[RunOnce(then skip)[A0], A1]: once A0 has run, it
    // skips; with count_skipped, A1's success is enough.
    for (count_skipped, want) in [(true, S), (false, R)] {
        let nodes = build(|b| {
            b.open(NodeKind::Parallel { success_threshold: 2, failure_threshold: 1, count_skipped })?;
            b.open(NodeKind::RunOnce { then_skip: true })?.action(act(0), &[])?.end()?;
            b.action(act(1), &[])?.end()?;
            Ok(())
        });
        executor!(exec, nodes);
        let mut w = Scripted::new();
        w.set(act(0), S).set(act(1), S);
        assert_eq!(exec.tick(&mut w, 0).unwrap(), S);
        assert_eq!(exec.tick(&mut w, 1).unwrap(), want, "count_skipped {count_skipped}");
        assert_eq!(w.ticks(act(0)), 1);
    }
}
