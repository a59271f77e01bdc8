//! Sequence and Fallback (rules 2, 3, 5, 6): the reactive ones tick and halt per node;
//! the with-memory ones resume at the Running child, memory kept only while the node is
//! Running.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::{NodeStatus, Status};
use common::{Call, Scripted, act, build, cond};

#[test]
fn sequence_returns_first_failure_and_skips_the_rest() {
    let nodes = build(|b| {
        b.sequence()?.condition(cond(0), &[])?.condition(cond(1), &[])?.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), Status::Success).set(cond(1), Status::Failure);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Failure);
    assert_eq!((w.ticks(cond(0)), w.ticks(cond(1)), w.ticks(act(0))), (1, 1, 0));
    assert_eq!(w.halts(act(0)), 0);
}

#[test]
fn sequence_succeeds_only_when_all_children_succeed() {
    let nodes = build(|b| {
        b.sequence()?.condition(cond(0), &[])?.condition(cond(1), &[])?.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), Status::Success).set(cond(1), Status::Success).set(act(0), Status::Running);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.set(act(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Success);
    // Reactive: the conditions are ticked again on every tick.
    assert_eq!((w.ticks(cond(0)), w.ticks(cond(1)), w.ticks(act(0))), (2, 2, 2));
    assert_eq!(w.halts(act(0)), 0);
}

#[test]
fn re_ticking_a_finished_action_restarts_it_and_halts_the_running_one_first() {
    // Seq[A0!, A1!]: A0 succeeds, A1 runs. On the next tick the reactive sequence ticks
    // A0 again: that is a new start of A0, so A1 is halted before it (rule 4), then
    // started afresh.
    let nodes = build(|b| {
        b.sequence()?.action(act(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), Status::Success).set(act(1), Status::Running);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.clear();
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    assert_eq!(
        w.log,
        [
            Call::Halt { behavior: act(1) },
            Call::Tick { behavior: act(0), starting: true },
            Call::Tick { behavior: act(1), starting: true },
        ]
    );
}

#[test]
fn sequence_rechecks_its_condition_every_tick_and_halts_the_running_action() {
    let nodes = build(|b| {
        b.sequence()?.condition(cond(0), &[])?.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), Status::Success);
    for t in 0..3 {
        assert_eq!(exec.tick(&mut w, t).unwrap(), Status::Running);
    }
    assert_eq!(w.ticks(act(0)), 3);
    let starts: Vec<_> =
        w.log.iter().filter(|c| matches!(c, Call::Tick { behavior, .. } if *behavior == act(0))).collect();
    assert_eq!(
        starts,
        [
            &Call::Tick { behavior: act(0), starting: true },
            &Call::Tick { behavior: act(0), starting: false },
            &Call::Tick { behavior: act(0), starting: false }
        ]
    );
    w.set(cond(0), Status::Failure);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), Status::Failure);
    assert_eq!((w.ticks(act(0)), w.halts(act(0))), (3, 1));
    assert_eq!(exec.status(2), Some(NodeStatus::Idle));
    // Halted once only, even if the condition stays false.
    assert_eq!(exec.tick(&mut w, 4).unwrap(), Status::Failure);
    assert_eq!(w.halts(act(0)), 1);
}

#[test]
fn fallback_returns_first_success_and_skips_the_rest() {
    let nodes = build(|b| {
        b.fallback()?.condition(cond(0), &[])?.condition(cond(1), &[])?.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), Status::Failure).set(cond(1), Status::Success);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Success);
    assert_eq!((w.ticks(cond(0)), w.ticks(cond(1)), w.ticks(act(0))), (1, 1, 0));
}

#[test]
fn fallback_fails_when_all_children_fail() {
    let nodes = build(|b| {
        b.fallback()?.condition(cond(0), &[])?.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), Status::Failure);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Failure);
    assert_eq!((w.ticks(cond(0)), w.ticks(act(0)), w.halts(act(0))), (1, 1, 0));
}

#[test]
fn fallback_higher_priority_condition_halts_running_action() {
    // Fallback[ goal?, Work! ]: once the goal holds, Work! is halted (it is not reached).
    let nodes = build(|b| {
        b.fallback()?.condition(cond(0), &[])?.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    w.set(cond(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Success);
    assert_eq!((w.ticks(cond(0)), w.ticks(act(0)), w.halts(act(0))), (3, 2, 1));
    assert_eq!(exec.status(0), Some(NodeStatus::Success));
    assert_eq!(exec.status(2), Some(NodeStatus::Idle));
}

#[test]
fn fallback_of_sequences_switches_branch_and_halts_the_abandoned_one() {
    // Fallback[ Seq[C0?, A0!], A1! ]
    let nodes = build(|b| {
        b.fallback()?.sequence()?.condition(cond(0), &[])?.action(act(0), &[])?.end()?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (1, 0));
    w.set(cond(0), Status::Failure);
    w.clear();
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    assert_eq!(
        w.log,
        [
            Call::Tick { behavior: cond(0), starting: true },
            Call::Halt { behavior: act(0) },
            Call::Tick { behavior: act(1), starting: true }
        ]
    );
}

#[test]
fn a_new_activation_starts_after_the_root_finishes() {
    let nodes = build(|b| {
        b.sequence()?.action(act(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), Status::Success).set(act(1), Status::Success);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Success);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Success);
    assert!(w.log.iter().all(|c| matches!(c, Call::Tick { starting: true, .. })));
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (2, 2));
}

#[test]
fn statuses_show_what_happened_on_the_last_tick() {
    // Fallback[ C0?, Seq[C1?, A0!], A1! ]
    let nodes = build(|b| {
        b.fallback()?
            .condition(cond(0), &[])?
            .sequence()?
            .condition(cond(1), &[])?
            .action(act(0), &[])?
            .end()?
            .action(act(1), &[])?
            .end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(1), Status::Failure);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    let s: Vec<_> = exec.states().iter().map(|s| s.status()).collect();
    use NodeStatus::*;
    assert_eq!(s, [Running, Failure, Failure, Failure, Idle, Running]);
    // C0 now holds: everything after it is reset, the running action halted.
    w.set(cond(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Success);
    let s: Vec<_> = exec.states().iter().map(|s| s.status()).collect();
    assert_eq!(s, [Success, Success, Idle, Idle, Idle, Idle]);
    assert_eq!(w.halts(act(1)), 1);
}

#[test]
fn sequence_with_memory_does_not_retick_children_that_succeeded() {
    let nodes = build(|b| {
        b.sequence_with_memory()?.condition(cond(0), &[])?.action(act(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), Status::Success).set(act(0), Status::Running);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.set(act(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running); // A1 runs now
    // The condition turns false: a memory sequence does not look back.
    w.set(cond(0), Status::Failure);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Running);
    assert_eq!((w.ticks(cond(0)), w.ticks(act(0)), w.ticks(act(1))), (1, 2, 2));
    w.set(act(1), Status::Success);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), Status::Success);
    assert_eq!((w.ticks(cond(0)), w.ticks(act(0)), w.ticks(act(1))), (1, 2, 3));
    assert_eq!((w.halts(act(0)), w.halts(act(1))), (0, 0));
}

#[test]
fn sequence_with_memory_starts_over_after_it_finished() {
    let nodes = build(|b| {
        b.sequence_with_memory()?.action(act(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), Status::Success).set(act(1), Status::Failure);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Failure);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Failure);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (2, 2));
}

#[test]
fn fallback_with_memory_does_not_retick_children_that_failed() {
    let nodes = build(|b| {
        b.fallback_with_memory()?.action(act(0), &[])?.action(act(1), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), Status::Failure).set(act(1), Status::Running);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    // A0 would succeed now, but it already failed in this activation.
    w.set(act(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (1, 2));
    w.set(act(1), Status::Failure);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Failure);
    // New activation: A0 is tried again and now succeeds.
    assert_eq!(exec.tick(&mut w, 3).unwrap(), Status::Success);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.halts(act(1))), (2, 3, 0));
}

#[test]
fn memory_is_forgotten_when_the_node_is_halted() {
    // Seq[ C0?, SeqMem[A0!, A1!] ]: C0 fails while A1 runs, so the memory sequence is
    // halted; when C0 holds again it starts over at A0.
    let nodes = build(|b| {
        b.sequence()?
            .condition(cond(0), &[])?
            .sequence_with_memory()?
            .action(act(0), &[])?
            .action(act(1), &[])?
            .end()?
            .end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), Status::Success).set(act(0), Status::Success).set(act(1), Status::Running);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (1, 2));
    w.set(cond(0), Status::Failure);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Failure);
    assert_eq!((w.halts(act(0)), w.halts(act(1))), (0, 1));
    w.set(cond(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), Status::Running);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1))), (2, 3));
}

#[test]
fn memory_nodes_in_a_reactive_parent_are_halted_by_a_higher_priority_branch() {
    // Fallback[ C0?, FbMem[A0!, A1!] ]
    let nodes = build(|b| {
        b.fallback()?
            .condition(cond(0), &[])?
            .fallback_with_memory()?
            .action(act(0), &[])?
            .action(act(1), &[])?
            .end()?
            .end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(act(0), Status::Failure).set(act(1), Status::Running);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.set(cond(0), Status::Success);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Success);
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.halts(act(1))), (1, 1, 1));
}
