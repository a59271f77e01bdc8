//! SequenceWithMemory and FallbackWithMemory (rule 6): resume at the Running child,
//! memory kept only while the node is Running.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::Status;
use common::{Scripted, act, build, cond};

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
