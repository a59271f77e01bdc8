//! BehaviorTree.CPP's leaves other than Sleep (rule 12): Script and ScriptCondition,
//! which finish in the tick they are reached, and AlwaysSuccess and AlwaysFailure.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::script::{ScriptFault, Value};
use bt_core::{Code, NodeKind, NodeStatus, TickError};
use common::{F, S, Scripted, act, build};

#[test]
fn always_success_and_always_failure() {
    let nodes = build(|b| {
        b.fallback()?.leaf(NodeKind::AlwaysFailure)?.leaf(NodeKind::AlwaysSuccess)?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    assert_eq!(exec.tick(&mut w, 0).unwrap(), S);
    assert_eq!(exec.status(1), Some(NodeStatus::Failure));
    assert!(w.log.is_empty(), "no behavior is called");
}

/// Program `word`: one word, which the scripted set tells programs apart by.
fn program(word: u16) -> Code {
    Code { start: word, len: 1 }
}

/// The value table of these tests: word `k` is `k`.
const VALUES: [u16; 4] = [0, 1, 2, 3];

#[test]
fn a_script_runs_once_and_succeeds_and_a_script_condition_holds_or_fails() {
    // Sequence[Script(0), ScriptCondition(1), A0]
    let nodes = build(|b| {
        b.sequence()?.leaf(NodeKind::Script(program(0)))?.leaf(NodeKind::ScriptCondition(program(1)))?;
        b.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor_with!(exec, nodes, &VALUES);
    let mut w = Scripted::new();
    w.program(1, Ok(Value::Bool(false))).set(act(0), S);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), F);
    assert_eq!(w.scripts(), [0, 1]);
    assert_eq!(w.ticks(act(0)), 0);
    assert_eq!(exec.status(1), Some(NodeStatus::Success));
    assert_eq!(exec.status(2), Some(NodeStatus::Failure));
    // A number holds when it is 1 (BehaviorTree.CPP's rule).
    w.program(1, Ok(Value::Int(1)));
    w.clear();
    assert_eq!(exec.tick(&mut w, 1).unwrap(), S);
    assert_eq!(w.scripts(), [0, 1]);
    assert_eq!(w.ticks(act(0)), 1);
}

#[test]
fn a_script_fault_ends_the_tick_with_its_node() {
    let nodes = build(|b| {
        b.sequence()?.action(act(0), &[])?.leaf(NodeKind::ScriptCondition(program(2)))?.end()?;
        Ok(())
    });
    executor_with!(exec, nodes, &VALUES);
    let mut w = Scripted::new();
    w.set(act(0), S).program(2, Err(ScriptFault::Unsupported));
    assert_eq!(exec.tick(&mut w, 0), Err(TickError::Script { node: 2, fault: ScriptFault::Unsupported }));
    // A result that is no truth value is a fault too.
    w.program(2, Ok(Value::Int(7)));
    assert_eq!(exec.tick(&mut w, 1), Err(TickError::Script { node: 2, fault: ScriptFault::NotPermitted }));
    assert!(exec.states().iter().all(|s| s.status() == NodeStatus::Idle), "the tree is halted");
}
