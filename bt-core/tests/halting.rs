//! Halting: rule 3 (abandoned branches are halted once, post-order), rule 4 (halt before
//! start), `halt_all`, and the usage error of rule 1.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::{NodeStatus, Status, TickError};
use common::{Call, Changes, Scripted, act, build, cond};

/// Fallback[ Seq[C0?, C1?, A0!], A1! ]
fn two_branches() -> &'static [bt_core::Node] {
    build(|b| {
        b.fallback()?
            .sequence()?
            .condition(cond(0), &[])?
            .condition(cond(1), &[])?
            .action(act(0), &[])?
            .end()?
            .action(act(1), &[])?
            .end()?;
        Ok(())
    })
}

#[test]
fn the_old_branch_is_halted_before_the_new_action_is_ticked() {
    executor!(exec, two_branches());
    let mut w = Scripted::new();
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running); // A1 runs
    w.set(cond(0), Status::Success).set(cond(1), Status::Success);
    w.clear();
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    assert_eq!(
        w.log,
        [
            Call::Tick { behavior: cond(0), starting: true },
            Call::Tick { behavior: cond(1), starting: true },
            Call::Halt { behavior: act(1) },
            Call::Tick { behavior: act(0), starting: true },
        ]
    );
}

#[test]
fn coming_back_to_the_old_branch_without_starting_anything_halts_nothing() {
    executor!(exec, two_branches());
    let mut w = Scripted::new();
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running); // A1 runs
    w.set(cond(0), Status::Success); // C1 still fails: the new branch gives up early
    w.clear();
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    assert_eq!(
        w.log,
        [
            Call::Tick { behavior: cond(0), starting: true },
            Call::Tick { behavior: cond(1), starting: true },
            Call::Tick { behavior: act(1), starting: false },
        ]
    );
    assert_eq!(w.halts(act(1)), 0);
}

#[test]
fn a_new_action_that_fails_at_once_still_halted_the_old_one_which_restarts() {
    executor!(exec, two_branches());
    let mut w = Scripted::new();
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.set(cond(0), Status::Success).set(cond(1), Status::Success).set(act(0), Status::Failure);
    w.clear();
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    assert_eq!(
        w.log,
        [
            Call::Tick { behavior: cond(0), starting: true },
            Call::Tick { behavior: cond(1), starting: true },
            Call::Halt { behavior: act(1) },
            Call::Tick { behavior: act(0), starting: true },
            Call::Tick { behavior: act(1), starting: true },
        ]
    );
}

#[test]
fn preemption_across_levels_halts_innermost_first_and_each_action_once() {
    // Fallback[ Seq[C0?, A0!], Seq[ Fallback[ Seq[C1?, A1!], A2! ], A3! ] ]
    // Tick 0: C0 and C1 fail, A2 runs.  Tick 1: C1 holds, A1 starts: A2 is halted first.
    // Tick 2: C0 holds, A0 starts: A1 is halted first.
    let nodes = build(|b| {
        b.fallback()?
            .sequence()?
            .condition(cond(0), &[])?
            .action(act(0), &[])?
            .end()?
            .sequence()?
            .fallback()?
            .sequence()?
            .condition(cond(1), &[])?
            .action(act(1), &[])?
            .end()?
            .action(act(2), &[])?
            .end()?
            .action(act(3), &[])?
            .end()?
            .end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    w.set(cond(1), Status::Success);
    w.clear();
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    let halt_then_start: Vec<_> =
        w.log.iter().filter(|c| !matches!(c, Call::Tick { starting: false, .. })).copied().collect();
    assert_eq!(
        halt_then_start,
        [
            Call::Tick { behavior: cond(0), starting: true },
            Call::Tick { behavior: cond(1), starting: true },
            Call::Halt { behavior: act(2) },
            Call::Tick { behavior: act(1), starting: true },
        ]
    );
    w.set(cond(0), Status::Success);
    w.clear();
    assert_eq!(exec.tick(&mut w, 2).unwrap(), Status::Running);
    assert_eq!(
        w.log,
        [
            Call::Tick { behavior: cond(0), starting: true },
            Call::Halt { behavior: act(1) },
            Call::Tick { behavior: act(0), starting: true }
        ]
    );
    assert_eq!((w.halts(act(0)), w.halts(act(1)), w.halts(act(2)), w.halts(act(3))), (0, 1, 0, 0));
}

#[test]
fn halt_all_halts_every_running_action_once_and_resets() {
    let nodes = build(|b| {
        b.parallel(2, 2)?.action(act(0), &[])?.sequence()?.action(act(1), &[])?.end()?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    exec.halt_all(&mut w);
    assert_eq!((w.halts(act(0)), w.halts(act(1))), (1, 1));
    assert!(exec.states().iter().all(|s| s.status() == NodeStatus::Idle));
    exec.halt_all(&mut w);
    assert_eq!((w.halts(act(0)), w.halts(act(1))), (1, 1));
    w.clear();
    assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Running);
    assert!(w.log.iter().all(|c| matches!(c, Call::Tick { starting: true, .. })));
}

#[test]
fn a_condition_returning_running_is_an_error_and_stops_the_tree() {
    // Seq[ A0!, C0? ] with A0 running, then C0 misbehaves.
    let nodes = build(|b| {
        b.parallel(2, 1)?.action(act(0), &[])?.condition(cond(0), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), Status::Running);
    assert_eq!(exec.tick(&mut w, 0), Err(TickError::ConditionRunning { node: 2, behavior: cond(0) }));
    assert_eq!(w.halts(act(0)), 1, "the action started in this tick is halted");
    assert!(exec.states().iter().all(|s| s.status() == NodeStatus::Idle));
}

#[test]
fn the_observer_sees_every_change_in_order() {
    executor!(exec, two_branches());
    let mut w = Scripted::new();
    let mut seen = Changes::default();
    exec.tick_observed(&mut w, 0, &mut seen).unwrap();
    use NodeStatus::*;
    assert_eq!(seen.0, [(2, Idle, Failure), (1, Idle, Failure), (5, Idle, Running), (0, Idle, Running)]);
    seen.0.clear();
    w.set(cond(0), Status::Success).set(cond(1), Status::Success);
    exec.tick_observed(&mut w, 1, &mut seen).unwrap();
    assert_eq!(
        seen.0,
        [(2, Failure, Success), (3, Idle, Success), (5, Running, Idle), (4, Idle, Running), (1, Failure, Running)]
    );
}

#[test]
fn each_node_is_visited_at_most_once_per_tick() {
    executor!(exec, two_branches());
    let mut w = Scripted::new();
    for t in 0..6u32 {
        let flip = if t % 2 == 0 { Status::Success } else { Status::Failure };
        w.set(cond(0), flip).set(cond(1), flip);
        w.clear();
        exec.tick(&mut w, t).unwrap();
        for b in [cond(0), cond(1), act(0), act(1)] {
            assert!(w.ticks(b) <= 1, "behavior {b} ticked {} times in tick {t}", w.ticks(b));
        }
    }
}

#[test]
fn an_action_that_runs_on_leaves_every_ancestor_running_and_halts_nothing() {
    // Fallback[ C0?, Inverter[ Repeat(5)[ SeqWithMemory[ Seq[ C1?, ForceSuccess[
    //     Retry(3)[ Fallback[ C2?, A0! ] ] ] ] ] ] ] ]
    // Every ancestor of A0 passes Running through; while A0 runs on, the tick ends at it
    // (see `Executor`), and nothing above it may change.
    use bt_core::NodeKind;
    let nodes = build(|b| {
        b.fallback()?.condition(cond(0), &[])?;
        b.open(NodeKind::Inverter)?.open(NodeKind::Repeat(5))?.open(NodeKind::SequenceWithMemory)?;
        b.sequence()?.condition(cond(1), &[])?;
        b.open(NodeKind::ForceSuccess)?.open(NodeKind::Retry(3))?;
        b.fallback()?.condition(cond(2), &[])?.action(act(0), &[])?;
        for _ in 0..8 {
            b.end()?;
        }
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(1), Status::Success).set(act(0), Status::Running);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), Status::Running);
    let first: Vec<NodeStatus> = exec.states().iter().map(|s| s.status()).collect();
    assert!(first.iter().skip(1).all(|&s| s != NodeStatus::Idle), "every node was ticked: {first:?}");
    for t in 1..4 {
        let mut seen = Changes::default();
        w.clear();
        assert_eq!(exec.tick_observed(&mut w, t, &mut seen).unwrap(), Status::Running);
        assert_eq!(seen.0, [], "tick {t}: no status changes");
        assert_eq!(exec.states().iter().map(|s| s.status()).collect::<Vec<_>>(), first, "tick {t}");
        assert_eq!(
            w.log,
            [
                Call::Tick { behavior: cond(0), starting: true },
                Call::Tick { behavior: cond(1), starting: true },
                Call::Tick { behavior: cond(2), starting: true },
                Call::Tick { behavior: act(0), starting: false },
            ],
            "tick {t}: the conditions again, then the action runs on"
        );
    }
    // The goal holds: the root returns at its first child and halts the running branch.
    w.set(cond(0), Status::Success);
    w.clear();
    assert_eq!(exec.tick(&mut w, 4).unwrap(), Status::Success);
    assert_eq!(w.log, [Call::Tick { behavior: cond(0), starting: true }, Call::Halt { behavior: act(0) }]);
    assert!(exec.states().iter().skip(2).all(|s| s.status() == NodeStatus::Idle));
}
