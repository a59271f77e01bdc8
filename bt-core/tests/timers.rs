//! The kinds that read the clock (rule 10): TimeLimit (BehaviorTree.CPP's `Timeout`),
//! Delay and RateController. `now` is in milliseconds here, as for imported trees.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::{NodeKind, NodeStatus, Span};
use common::{Call, F, R, S, Scripted, act, build, cond, over_action};

fn span(ms: u32) -> Span {
    Span::new(ms).unwrap()
}

#[test]
fn time_limit_halts_a_child_that_runs_past_its_span() {
    executor!(exec, over_action(NodeKind::TimeLimit(span(100))));
    let mut w = Scripted::new();
    w.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 1000).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1099).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1100).unwrap(), F);
    assert_eq!((w.ticks(act(0)), w.halts(act(0))), (2, 1));
    assert!(exec.take_woken(), "an expired timer asks for a tick");
    // A new activation starts a new clock.
    assert_eq!(exec.tick(&mut w, 1150).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1249).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1250).unwrap(), F);
}

#[test]
fn time_limit_lets_a_child_that_finishes_in_time_through_and_zero_never_expires() {
    executor!(exec, over_action(NodeKind::TimeLimit(span(100))));
    let mut w = Scripted::new();
    w.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 99).unwrap(), S);
    executor!(zero, over_action(NodeKind::TimeLimit(span(0))));
    w.set(act(0), R);
    for t in [0, 10_000, 1_000_000] {
        assert_eq!(zero.tick(&mut w, t).unwrap(), R);
    }
}

#[test]
fn an_expired_time_limit_halts_its_child_before_the_tick_starts() {
    // Sequence[C0, TimeLimit(50)[A0]]: the halt comes before C0's tick, as
    // BehaviorTree.CPP's timer halts it before the next tick.
    let nodes = build(|b| {
        b.sequence()?.condition(cond(0), &[])?;
        b.open(NodeKind::TimeLimit(span(50)))?.action(act(0), &[])?.end()?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), S).set(act(0), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.clear();
    assert_eq!(exec.tick(&mut w, 60).unwrap(), F);
    assert_eq!(w.log, [Call::Halt { behavior: act(0) }, Call::Tick { behavior: cond(0), starting: true }]);
}

#[test]
fn time_spans_survive_the_clock_wrapping() {
    executor!(exec, over_action(NodeKind::TimeLimit(span(100))));
    let mut w = Scripted::new();
    w.set(act(0), R);
    let start = u32::MAX - 30;
    assert_eq!(exec.tick(&mut w, start).unwrap(), R);
    assert_eq!(exec.tick(&mut w, start.wrapping_add(99)).unwrap(), R);
    assert_eq!(exec.tick(&mut w, start.wrapping_add(100)).unwrap(), F);
}

#[test]
fn delay_ticks_its_child_once_its_span_has_passed() {
    executor!(exec, over_action(NodeKind::Delay(span(100))));
    let mut w = Scripted::new();
    w.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 99).unwrap(), R);
    assert_eq!(w.ticks(act(0)), 0);
    assert!(!exec.take_woken());
    assert_eq!(exec.tick(&mut w, 100).unwrap(), R);
    assert!(exec.take_woken(), "the delay's end asks for a tick");
    assert_eq!(w.ticks(act(0)), 1);
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 150).unwrap(), S);
    // Starts over.
    assert_eq!(exec.tick(&mut w, 160).unwrap(), R);
    assert_eq!(w.ticks(act(0)), 2);
}

#[test]
fn rate_controller_ticks_its_child_at_most_once_per_span() {
    // PipelineSequence[RateController(1000)[A0], A1]: the Nav2 shape (replan at 1 Hz
    // while following the path).
    let nodes = build(|b| {
        b.open(NodeKind::PipelineSequence)?;
        b.open(NodeKind::RateController(span(1000)))?.action(act(0), &[])?.end()?;
        b.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), S).set(act(1), R);
    for t in (0..3000).step_by(100) {
        assert_eq!(exec.tick(&mut w, t).unwrap(), R);
    }
    // At 0, 1000 and 2000 ms.
    assert_eq!(w.ticks(act(0)), 3);
    assert_eq!(w.ticks(act(1)), 30);
    assert_eq!(w.halts(act(1)), 0);
}

#[test]
fn rate_controller_keeps_ticking_a_running_child_and_starts_afresh_when_reset() {
    executor!(exec, over_action(NodeKind::RateController(span(1000))));
    let mut w = Scripted::new();
    w.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 10).unwrap(), R);
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 20).unwrap(), S);
    // The root finished; a root has no parent to reset it, so it starts afresh.
    assert_eq!(exec.tick(&mut w, 30).unwrap(), S);
    assert_eq!(w.ticks(act(0)), 4);
    assert_eq!(exec.status(0), Some(NodeStatus::Success));
}

/// A period that never expires (Nav2's `hz="0.0000001"`, "plan once"): the child is
/// ticked when the node starts and while it runs, never again in the activation.
#[test]
fn a_rate_controller_that_never_expires_ticks_its_child_once_per_activation() {
    let nodes = build(|b| {
        b.open(NodeKind::PipelineSequence)?;
        b.open(NodeKind::RateController(Span::NEVER))?.action(act(0), &[])?.end()?;
        b.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), R).set(act(1), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 10).unwrap(), R);
    for now in [1_000, 16_777_215, 4_000_000_000, u32::MAX] {
        assert_eq!(exec.tick(&mut w, now).unwrap(), R);
    }
    assert_eq!(w.ticks(act(0)), 2);
}
