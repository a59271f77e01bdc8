//! BehaviorTree.CPP's loops (rule 12) as one `Loop` kind: while its child is not Running
//! it takes the next element of its queue, a literal one (an assignment program per
//! element) or a blackboard one (`BehaviorSet::pop`), and ticks the child; Running after
//! each Success of the child, Failure when the child fails, `if_empty` once the queue is
//! empty.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::script::QUEUE_KEY;
use bt_core::{Code, Node, NodeKind, Status};
use common::{Call, F, R, S, Scripted, act, build};

/// The int type of a loop table's header (`script::Element::Int`).
const INT: u16 = 1;
/// No name: a built-in loop.
const NO_NAME: u16 = u16::MAX;

/// Loop[A0] over `table` (the whole value table), `if_empty` when the queue is empty.
fn looping(table: &[u16], if_empty: Status) -> &'static [Node] {
    let table = Code { start: 0, len: table.len() as u16 };
    build(|b| {
        b.open(NodeKind::Loop { table, if_empty })?.action(act(0), &[])?.end()?;
        Ok(())
    })
}

#[test]
fn a_literal_queue_gives_one_element_per_tick_then_the_empty_status() {
    // Two elements, whose assignment programs are the words 50 and 51.
    let table = [INT, NO_NAME, 2, 1, 50, 1, 51];
    executor_with!(exec, looping(&table, S), &table);
    let mut w = Scripted::new();
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(w.scripts(), [50, 51]);
    assert_eq!(w.ticks(act(0)), 2);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S, "if_empty");
    assert_eq!(w.ticks(act(0)), 2);
}

#[test]
fn a_running_child_keeps_its_element_and_a_failure_ends_the_loop() {
    let table = [INT, NO_NAME, 3, 1, 50, 1, 51, 1, 52];
    executor_with!(exec, looping(&table, S), &table);
    let mut w = Scripted::new();
    w.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(w.scripts(), [50], "no element is taken while the child runs");
    w.set(act(0), F);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), F);
    assert_eq!(w.scripts(), [50]);
}

#[test]
fn a_blackboard_queue_is_popped_by_the_behavior_set_until_it_is_empty() {
    let table = [QUEUE_KEY | INT, NO_NAME, 0, 1];
    executor_with!(exec, looping(&table, F), &table);
    let mut w = Scripted::new();
    w.set(act(0), S);
    w.queue = 2;
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), F, "if_empty");
    assert_eq!(w.ticks(act(0)), 2);
    // Asked when starting (BehaviorTree.CPP reads the entry afresh), then on each tick.
    let pops: Vec<_> =
        w.log.iter().filter_map(|c| if let Call::Pop { starting, .. } = *c { Some(starting) } else { None }).collect();
    assert_eq!(pops, [true, false, false]);
}
