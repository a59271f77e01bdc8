//! Decorators: Inverter, ForceSuccess, ForceFailure, Repeat, Retry, Timeout (rule 7:
//! they count ticks and activations, never time).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::{NodeKind, Status};
use common::{Scripted, act, build, over_action};

fn once(kind: NodeKind, child: Status) -> Status {
    executor!(exec, over_action(kind));
    let mut w = Scripted::new();
    w.set(act(0), child);
    exec.tick(&mut w, 0).unwrap()
}

#[test]
fn inverter_swaps_success_and_failure() {
    assert_eq!(once(NodeKind::Inverter, Status::Success), Status::Failure);
    assert_eq!(once(NodeKind::Inverter, Status::Failure), Status::Success);
    assert_eq!(once(NodeKind::Inverter, Status::Running), Status::Running);
}

#[test]
fn force_success_and_force_failure() {
    assert_eq!(once(NodeKind::ForceSuccess, Status::Failure), Status::Success);
    assert_eq!(once(NodeKind::ForceSuccess, Status::Success), Status::Success);
    assert_eq!(once(NodeKind::ForceSuccess, Status::Running), Status::Running);
    assert_eq!(once(NodeKind::ForceFailure, Status::Success), Status::Failure);
    assert_eq!(once(NodeKind::ForceFailure, Status::Failure), Status::Failure);
    assert_eq!(once(NodeKind::ForceFailure, Status::Running), Status::Running);
}

#[test]
fn repeat_runs_one_iteration_per_tick_until_n_successes() {
    executor!(exec, over_action(NodeKind::Repeat(3)));
    let mut w = Scripted::new();
    w.set(act(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Success);
    assert_eq!(w.ticks(act(0)), 3);
    // A new activation counts from zero again.
    assert_eq!(exec.tick(&mut w, 3).unwrap(), Status::Running);
    assert_eq!(w.ticks(act(0)), 4);
}

#[test]
fn repeat_counts_only_completed_iterations_and_stops_on_failure() {
    executor!(exec, over_action(NodeKind::Repeat(2)));
    let mut w = Scripted::new();
    w.set(act(0), Status::Running);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.set(act(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running); // 1 of 2
    w.set(act(0), Status::Running);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Running);
    w.set(act(0), Status::Failure);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), Status::Failure);
    assert_eq!(w.ticks(act(0)), 4);
}

#[test]
fn retry_gives_n_attempts() {
    executor!(exec, over_action(NodeKind::Retry(3)));
    let mut w = Scripted::new();
    w.set(act(0), Status::Failure);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Failure);
    assert_eq!(w.ticks(act(0)), 3);
}

#[test]
fn retry_stops_at_the_first_success() {
    executor!(exec, over_action(NodeKind::Retry(3)));
    let mut w = Scripted::new();
    w.set(act(0), Status::Failure);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.set(act(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Success);
    w.set(act(0), Status::Failure);
    // Fresh activation: three attempts again.
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 4).unwrap(), Status::Failure);
}

#[test]
fn timeout_halts_a_child_still_running_after_n_ticks() {
    executor!(exec, over_action(NodeKind::Timeout(3)));
    let mut w = Scripted::new();
    // `now` jumps wildly: the timeout counts ticks, not time.
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 1_000_000).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 7).unwrap(), Status::Failure);
    assert_eq!((w.ticks(act(0)), w.halts(act(0))), (3, 1));
}

#[test]
fn timeout_passes_through_a_result_in_time() {
    executor!(exec, over_action(NodeKind::Timeout(3)));
    let mut w = Scripted::new();
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    w.set(act(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Success);
    // The next activation gets three fresh ticks.
    w.set(act(0), Status::Running);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 4).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 5).unwrap(), Status::Failure);
    assert_eq!(w.halts(act(0)), 1);
}

#[test]
fn timeout_count_is_reset_when_halted_from_above() {
    // Seq[C0?, Timeout(2)[A0!]]
    let nodes = build(|b| {
        b.sequence()?.condition(common::cond(0), &[])?.timeout(2)?.action(act(0), &[])?.end()?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(common::cond(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.set(common::cond(0), Status::Failure);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Failure);
    w.set(common::cond(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), Status::Failure);
    assert_eq!((w.ticks(act(0)), w.halts(act(0))), (3, 2));
}
