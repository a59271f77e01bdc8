//! Parallel (rule 6): finished children are not re-ticked within an activation; the
//! node returns as soon as a threshold is reached and halts the children still Running;
//! with `count_skipped` (rule 8), children that skip count towards success, as in
//! BehaviorTree.CPP's `gtest_parallel.cpp`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::{NodeKind, NodeStatus, Status};
use common::{Call, R, S, Scripted, act, build};

fn par3(s: u16, f: u16) -> &'static [bt_core::Node] {
    build(|b| {
        b.parallel(s, f)?.action(act(0), &[])?.action(act(1), &[])?.action(act(2), &[])?.end()?;
        Ok(())
    })
}

#[test]
fn ticks_every_child_and_runs_until_all_succeed() {
    executor!(exec, par3(3, 1));
    let mut w = Scripted::new();
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.ticks(act(2))), (1, 1, 1));
    w.set(act(1), Status::Success);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    // A1 finished: it is not ticked again in this activation.
    w.set(act(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Running);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.ticks(act(2))), (3, 2, 3));
    w.set(act(2), Status::Success);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), Status::Success);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.ticks(act(2))), (3, 2, 4));
    assert_eq!((w.halts(act(0)), w.halts(act(1)), w.halts(act(2))), (0, 0, 0));
}

#[test]
fn success_threshold_returns_at_once_and_halts_the_rest() {
    executor!(exec, par3(1, 3));
    let mut w = Scripted::new();
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.set(act(0), Status::Success);
    w.clear();
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Success);
    // A0 succeeded first: A1 and A2 are not ticked, but halted, left to right.
    assert_eq!(
        w.log,
        [
            Call::Tick { behavior: act(0), starting: false },
            Call::Halt { behavior: act(1) },
            Call::Halt { behavior: act(2) }
        ]
    );
    let s: Vec<_> = exec.states().iter().map(|s| s.status()).collect();
    assert_eq!(s, [NodeStatus::Success, NodeStatus::Success, NodeStatus::Idle, NodeStatus::Idle]);
}

#[test]
fn failure_threshold_halts_children_running_before_it() {
    executor!(exec, par3(3, 1));
    let mut w = Scripted::new();
    w.set(act(1), Status::Failure);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Failure);
    // A0 was started in this very tick and is halted; A2 never ticked.
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.ticks(act(2))), (1, 1, 0));
    assert_eq!((w.halts(act(0)), w.halts(act(1)), w.halts(act(2))), (1, 0, 0));
}

#[test]
fn fails_as_soon_as_success_is_out_of_reach() {
    // Needs 3 successes, tolerates 3 failures: one failure already makes it impossible.
    executor!(exec, par3(3, 3));
    let mut w = Scripted::new();
    w.set(act(0), Status::Failure);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Failure);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.ticks(act(2))), (1, 0, 0));
}

#[test]
fn finished_results_are_forgotten_in_the_next_activation() {
    executor!(exec, par3(2, 2));
    let mut w = Scripted::new();
    w.set(act(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.set(act(1), Status::Success);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Success);
    assert_eq!(w.halts(act(2)), 1);
    // New activation: every child is ticked again.
    w.clear();
    w.set(act(0), Status::Running).set(act(1), Status::Running);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Running);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.ticks(act(2))), (1, 1, 1));
}

#[test]
fn parallel_under_a_fallback_is_halted_whole_post_order() {
    // Fallback[ C0?, Par(2,2)[ Seq[C1?, A0!], A1! ] ]
    let nodes = build(|b| {
        b.fallback()?
            .condition(common::cond(0), &[])?
            .parallel(2, 2)?
            .sequence()?
            .condition(common::cond(1), &[])?
            .action(act(0), &[])?
            .end()?
            .action(act(1), &[])?
            .end()?
            .end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(common::cond(1), Status::Success);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.set(common::cond(0), Status::Success);
    let mut changes = common::Changes::default();
    assert_eq!(exec.tick_observed(&mut w, 1, &mut changes).unwrap(), Status::Success);
    assert_eq!((w.halts(act(0)), w.halts(act(1))), (1, 1));
    // Post-order, left to right: C1 (4), A0 (5), Seq (3), A1 (6), then Par (2).
    use NodeStatus::*;
    let idle: Vec<_> = changes.0.iter().filter(|c| c.2 == Idle).map(|c| c.0).collect();
    assert_eq!(idle, [4, 5, 3, 6, 2]);
    assert_eq!(changes.0.last(), Some(&(0, Running, Success)));
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
