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

/// BehaviorTree.CPP 3's Repeat and RetryUntilSuccessful (`Cycles` with `v3`): every
/// cycle in the same tick, whether the child had been Running or not.
#[test]
fn cycles_of_version_3_loop_within_the_tick() {
    let repeat = NodeKind::Cycles { count: 3, from_slot: false, retry: false, v3: true };
    executor!(exec, over_action(repeat));
    let mut w = Scripted::new();
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), S);
    assert!(!exec.take_woken());
    assert_eq!(w.ticks(act(0)), 3);
    let retry = NodeKind::Cycles { count: 2, from_slot: false, retry: true, v3: true };
    executor!(exec, over_action(retry));
    let mut w = Scripted::new();
    w.set(act(0), F);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), F);
    assert_eq!(w.ticks(act(0)), 2);
    // A Success ends a retry; a Running child is resumed on the next tick.
    executor!(exec, over_action(retry));
    let mut w = Scripted::new();
    w.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), S);
}

/// A count read from a slot on every tick, as BehaviorTree.CPP reads `num_cycles="{n}"`:
/// -1 is no limit, a count that falls below the cycles done ends the node (halting a
/// child still Running), a value that is no count ends the tick with an error.
#[test]
fn cycles_read_their_count_from_a_slot_on_every_tick() {
    use bt_core::script::{ScriptFault, Value, op};
    let kind = NodeKind::Cycles { count: 7, from_slot: true, retry: false, v3: false };
    executor!(exec, over_action(kind));
    let mut w = Scripted::new();
    w.set(act(0), R).program(op::LOAD, Ok(Value::Int(2)));
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(w.scripts(), [op::LOAD]);
    // The child had been Running: its Success is followed by a second cycle at once.
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), S);
    assert_eq!(w.ticks(act(0)), 3);
    // A count that falls to the cycles done ends the node, halting the Running child.
    w.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), R);
    w.program(op::LOAD, Ok(Value::Int(0)));
    assert_eq!(exec.tick(&mut w, 3).unwrap(), S);
    assert_eq!(w.halts(act(0)), 1);
    // -1: no limit; 0 or less: done at once.
    w.program(op::LOAD, Ok(Value::Int(-1))).set(act(0), S);
    for k in 3..6 {
        assert_eq!(exec.tick(&mut w, k).unwrap(), R);
    }
    w.program(op::LOAD, Ok(Value::Int(-5)));
    let ticks = w.ticks(act(0));
    assert_eq!(exec.tick(&mut w, 6).unwrap(), S);
    assert_eq!(w.ticks(act(0)), ticks);
    // A count out of range, a string, a double with a fraction: an error.
    for bad in [Value::Int(70_000), Value::Str(0), Value::Double(1.5)] {
        w.program(op::LOAD, Ok(bad));
        let e = exec.tick(&mut w, 7).unwrap_err();
        assert!(matches!(e, bt_core::TickError::Script { fault: ScriptFault::Conversion { slot: 7 }, .. }), "{e}");
    }
}

/// Version 3's Repeat for ever over a child that finishes at once never returns in
/// BehaviorTree.CPP 3.8; here it yields after 65,535 cycles in a tick, Running, asking
/// to be ticked again.
#[test]
fn cycles_of_version_3_yield_after_65535_cycles_in_a_tick() {
    let forever = NodeKind::Cycles { count: NodeKind::FOREVER, from_slot: false, retry: false, v3: true };
    executor!(exec, over_action(forever));
    let mut w = Scripted::new();
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert!(exec.take_woken());
    assert_eq!(w.ticks(act(0)), 65_535);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(w.ticks(act(0)), 2 * 65_535);
}
