//! The decorators that decide whether their child runs (rules 9, 12): Gate (a behavior
//! of the set: Nav2's plugin decorators), in the manner of Nav2's unit tests, Guard
//! (BehaviorTree.CPP's scripted attributes) and Precondition.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::script::{Hook, Value};
use bt_core::{Code, NodeKind, Status};
use common::{F, K, R, S, Scripted, act, build};

/// A gate that opens when `open` is set, else answers `closed`; records `starting`.
struct GateWorld {
    inner: Scripted,
    open: bool,
    closed: Status,
    asked: Vec<bool>,
}

impl bt_core::BehaviorSet for GateWorld {
    fn condition(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> Status {
        self.inner.condition(leaf, ctx)
    }
    fn action(&mut self, leaf: &bt_core::Leaf, ctx: bt_core::Context<'_>) -> Status {
        if leaf.behavior() == act(9) {
            self.asked.push(ctx.starting);
            return if self.open { S } else { self.closed };
        }
        self.inner.action(leaf, ctx)
    }
    fn halt(&mut self, leaf: &bt_core::Leaf, node: bt_core::NodeId) {
        self.inner.halt(leaf, node);
    }
}

#[test]
fn gate_asks_its_behavior_and_never_stops_a_running_child() {
    let nodes = build(|b| {
        b.gate(act(9), &[])?.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = GateWorld { inner: Scripted::new(), open: true, closed: R, asked: vec![] };
    w.inner.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.open = false;
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(w.inner.ticks(act(0)), 2, "the running child is ticked whatever the gate says");
    w.inner.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
    // Closed: Running (a controller waiting) or Failure (SingleTrigger), child untouched.
    assert_eq!(exec.tick(&mut w, 3).unwrap(), R);
    w.closed = F;
    assert_eq!(exec.tick(&mut w, 4).unwrap(), F);
    assert_eq!(w.inner.ticks(act(0)), 3);
    // Tick 3 starts afresh (the root had finished); tick 4 follows a Running gate.
    assert_eq!(w.asked, [true, false, false, true, false]);
}

/// A guard's table with the hooks `hooks` (in `Hook` order), hook `h`'s program the one
/// word `HOOK + h`.
fn guard_table(hooks: &[Hook]) -> Vec<u16> {
    let mask = hooks.iter().fold(0u16, |m, &h| m | 1 << h as u16);
    let mut table = vec![mask];
    for &h in hooks {
        table.extend([1, HOOK + h as u16]);
    }
    table
}

const HOOK: u16 = 100;

/// Guard[A0] with `hooks`; the value table holds its table and nothing else.
fn guarded(hooks: &[Hook]) -> (&'static [bt_core::Node], Vec<u16>) {
    let table = guard_table(hooks);
    let code = Code { start: 0, len: table.len() as u16 };
    let nodes = build(|b| {
        b.open(NodeKind::Guard(code))?.action(act(0), &[])?.end()?;
        Ok(())
    });
    (nodes, table)
}

#[test]
fn a_guard_decides_before_its_node_starts_and_runs_its_hooks_when_it_finishes() {
    let (nodes, values) = guarded(&[Hook::SkipIf, Hook::OnSuccess, Hook::Post]);
    executor_with!(exec, nodes, &values);
    let mut w = Scripted::new();
    w.set(act(0), S);
    // `_skipIf` holds: Skipped, the node untouched, no `_onSuccess` or `_post`.
    assert_eq!(exec.tick(&mut w, 0).unwrap(), K);
    assert_eq!(w.scripts(), [HOOK + Hook::SkipIf as u16]);
    assert_eq!(w.ticks(act(0)), 0);
    w.program(HOOK + Hook::SkipIf as u16, Ok(Value::Bool(false)));
    w.clear();
    assert_eq!(exec.tick(&mut w, 1).unwrap(), S);
    assert_eq!(w.ticks(act(0)), 1);
    assert_eq!(w.scripts(), [HOOK + Hook::SkipIf as u16, HOOK + Hook::OnSuccess as u16, HOOK + Hook::Post as u16]);
}

#[test]
fn a_guard_whose_while_stops_holding_halts_its_running_node_and_skips() {
    let (nodes, values) = guarded(&[Hook::While, Hook::OnHalted]);
    executor_with!(exec, nodes, &values);
    let mut w = Scripted::new();
    w.set(act(0), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(w.ticks(act(0)), 2);
    w.program(HOOK + Hook::While as u16, Ok(Value::Bool(false)));
    w.clear();
    assert_eq!(exec.tick(&mut w, 2).unwrap(), K);
    assert_eq!(w.ticks(act(0)), 0);
    assert_eq!(w.halts(act(0)), 1);
    assert_eq!(w.scripts(), [HOOK + Hook::While as u16, HOOK + Hook::OnHalted as u16]);
}

#[test]
fn a_precondition_lets_its_child_go_and_does_not_ask_again_until_it_finishes() {
    let nodes = build(|b| {
        b.open(NodeKind::Precondition { code: Code { start: 0, len: 1 }, otherwise: F })?;
        b.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor_with!(exec, nodes, &[7]);
    let mut w = Scripted::new();
    w.program(7, Ok(Value::Bool(false))).set(act(0), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), F, "its `else` status");
    assert_eq!(w.ticks(act(0)), 0);
    w.program(7, Ok(Value::Bool(true)));
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    // Running: the child goes on without the program being asked.
    w.program(7, Ok(Value::Bool(false)));
    w.clear();
    assert_eq!(exec.tick(&mut w, 2).unwrap(), R);
    w.set(act(0), S);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), S);
    assert_eq!(w.scripts(), [0u16; 0]);
    assert_eq!(w.ticks(act(0)), 2);
    // Finished: it asks again.
    assert_eq!(exec.tick(&mut w, 4).unwrap(), F);
    assert_eq!(w.scripts(), [7]);
}

/// BehaviorTree.CPP 3's BlackboardCheck (`Check`): asked on every tick; a mismatch, or a
/// program that faults (a key not set), halts a Running child and returns `otherwise`.
#[test]
fn a_check_asks_on_every_tick_and_halts_its_child_on_a_mismatch() {
    use bt_core::script::ScriptFault;
    let code = Code { start: 0, len: 1 };
    let nodes = build(|b| {
        b.open(NodeKind::Check { code, otherwise: R })?.action(act(0), &[])?.end()?;
        Ok(())
    });
    executor_with!(exec, nodes, &[77]);
    let mut w = Scripted::new();
    w.set(act(0), R).program(77, Ok(Value::Bool(true)));
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    assert_eq!(w.scripts(), [77, 77]);
    w.program(77, Ok(Value::Bool(false)));
    assert_eq!(exec.tick(&mut w, 2).unwrap(), R);
    assert_eq!((w.ticks(act(0)), w.halts(act(0))), (2, 1));
    w.program(77, Err(ScriptFault::Unset { slot: 0 }));
    assert_eq!(exec.tick(&mut w, 3).unwrap(), R);
    assert_eq!(w.ticks(act(0)), 2);
    w.program(77, Ok(Value::Bool(true))).set(act(0), S);
    assert_eq!(exec.tick(&mut w, 4).unwrap(), S);
}
