//! BehaviorTree.CPP's `ManualSelector` with the choice made by the behavior set
//! (`BehaviorSet::select`, tick rule 13): which child it ticks or which status it
//! returns, when it asks, what it halts and when, and the faults. Counted per node as
//! BehaviorTree.CPP's own tests count ticks and halts, against a reading of its
//! `manual_node.cpp`.
#![cfg(feature = "btcpp")]
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod common;
use bt_core::script::ScriptFault;
use bt_core::{ArgumentFault, Builder, LoadError, Node, NodeKind, NodeStatus, Selection, Status, TickError, Tree};
use common::{Call, F, R, S, Scripted, act, build, cond};

/// ManualSelector[A0, A1, A2] at the root.
fn three(repeat_last: bool) -> &'static [Node] {
    build(|b| {
        b.open(NodeKind::ManualSelector { repeat_last })?;
        b.action(act(0), &[])?.action(act(1), &[])?.action(act(2), &[])?.end()?;
        Ok(())
    })
}

#[test]
fn it_asks_on_every_tick_even_while_its_child_runs_and_returns_what_the_child_returns() {
    executor!(exec, three(false));
    let mut w = Scripted::new();
    w.choose(Selection::Child(1)).set(act(1), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    w.set(act(1), F);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), F);
    assert_eq!(
        w.log,
        [
            Call::Select { node: 0, children: 3, starting: true },
            Call::Tick { behavior: act(1), starting: true },
            // Asked again while A1 runs (BehaviorTree.CPP asks its operator every tick).
            Call::Select { node: 0, children: 3, starting: false },
            Call::Tick { behavior: act(1), starting: false },
            Call::Select { node: 0, children: 3, starting: false },
            Call::Tick { behavior: act(1), starting: false },
        ]
    );
    assert_eq!((w.ticks(act(0)), w.ticks(act(2)), w.halts(act(1))), (0, 0, 0));
    assert_eq!(exec.status(0), Some(NodeStatus::Failure));
    // A new activation: the set is told it starts afresh.
    w.clear();
    w.choose(Selection::Child(0)).set(act(0), S);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), S);
    assert_eq!(w.log[0], Call::Select { node: 0, children: 3, starting: true });
}

#[test]
fn another_choice_halts_the_running_child_before_the_chosen_one_starts() {
    executor!(exec, three(false));
    let mut w = Scripted::new();
    w.choose(Selection::Child(0)).set(act(0), R).set(act(2), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.clear();
    w.choose(Selection::Child(2));
    assert_eq!(exec.tick(&mut w, 1).unwrap(), R);
    // BehaviorTree.CPP would leave A0 Running; halt before start halts it first.
    assert_eq!(
        w.log,
        [
            Call::Select { node: 0, children: 3, starting: false },
            Call::Halt { behavior: act(0) },
            Call::Tick { behavior: act(2), starting: true },
        ]
    );
    assert_eq!(exec.status(1), Some(NodeStatus::Idle));
    assert_eq!(exec.status(3), Some(NodeStatus::Running));
    // Choosing A0 again starts it afresh, after halting A2.
    w.clear();
    w.choose(Selection::Child(0));
    assert_eq!(exec.tick(&mut w, 2).unwrap(), R);
    assert_eq!(w.log[1..], [Call::Halt { behavior: act(2) }, Call::Tick { behavior: act(0), starting: true }]);
    assert_eq!((w.halts(act(0)), w.halts(act(2))), (0, 1));
}

#[test]
fn finished_children_keep_their_status_as_in_behaviortree_cpp() {
    executor!(exec, three(false));
    let mut w = Scripted::new();
    w.choose(Selection::Child(0)).set(act(0), S).set(act(1), F);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), S);
    w.choose(Selection::Child(1));
    assert_eq!(exec.tick(&mut w, 1).unwrap(), F);
    let statuses: Vec<_> = exec.states().iter().map(|s| s.status()).collect();
    assert_eq!(statuses, [NodeStatus::Failure, NodeStatus::Success, NodeStatus::Failure, NodeStatus::Idle]);
    assert_eq!(w.halts(act(0)) + w.halts(act(1)), 0);
}

#[test]
fn a_status_is_returned_without_ticking_a_child() {
    executor!(exec, three(false));
    let mut w = Scripted::new();
    for (s, want) in [(Selection::Success, S), (Selection::Failure, F), (Selection::Running, R)] {
        w.choose(s);
        assert_eq!(exec.tick(&mut w, 0).unwrap(), want, "{s:?}");
        assert_eq!(exec.status(0), Some(want.into()));
    }
    assert_eq!((w.ticks(act(0)), w.ticks(act(1)), w.ticks(act(2))), (0, 0, 0));
    assert_eq!(w.selects(), 3);
}

#[test]
fn running_leaves_a_running_child_as_it_is_and_success_or_failure_halt_it() {
    for (s, halts) in [(Selection::Running, 0), (Selection::Success, 1), (Selection::Failure, 1)] {
        executor!(exec, three(false));
        let mut w = Scripted::new();
        w.choose(Selection::Child(1)).set(act(1), R);
        assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
        w.choose(s);
        exec.tick(&mut w, 1).unwrap();
        assert_eq!(w.halts(act(1)), halts, "{s:?}");
        assert_eq!(w.ticks(act(1)), 1, "{s:?}: A1 is not ticked");
        let a1 = if halts == 0 { NodeStatus::Running } else { NodeStatus::Idle };
        assert_eq!(exec.status(2), Some(a1), "{s:?}");
        if s == Selection::Running {
            // Chosen again, A1 goes on where it was.
            w.choose(Selection::Child(1));
            assert_eq!(exec.tick(&mut w, 2).unwrap(), R);
            assert_eq!(w.log.last(), Some(&Call::Tick { behavior: act(1), starting: false }));
        }
    }
}

#[test]
fn repeat_last_selection_asks_once_for_the_life_of_the_executor() {
    executor!(exec, three(true));
    let mut w = Scripted::new();
    w.choose(Selection::Child(1)).set(act(1), R);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    // Another answer is ready, but it is not asked again.
    w.choose(Selection::Child(2)).set(act(1), S);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), S);
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
    // Not even after a halt of the whole tree.
    exec.halt_all(&mut w);
    assert_eq!(exec.tick(&mut w, 3).unwrap(), S);
    assert_eq!(w.selects(), 1);
    assert_eq!((w.ticks(act(1)), w.ticks(act(2))), (4, 0));
    // A remembered status is returned again (BehaviorTree.CPP indexes past its children).
    executor!(exec, three(true));
    let mut w = Scripted::new();
    w.choose(Selection::Failure);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), F);
    w.choose(Selection::Child(0)).set(act(0), S);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), F);
    assert_eq!((w.selects(), w.ticks(act(0))), (1, 0));
}

#[test]
fn without_children_it_asks_for_a_status_on_every_tick() {
    let nodes = build(|b| {
        b.open(NodeKind::ManualSelector { repeat_last: true })?.end()?;
        Ok(())
    });
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.choose(Selection::Running);
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.choose(Selection::Success);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), S);
    // repeat_last_selection does not apply: BehaviorTree.CPP asks for a status each time.
    assert_eq!(
        w.log,
        [Call::Select { node: 0, children: 0, starting: true }, Call::Select { node: 0, children: 0, starting: false }]
    );
    w.choose(Selection::Child(0));
    assert_eq!(exec.tick(&mut w, 2), Err(TickError::NoSuchChild { node: 0, child: 0, children: 0 }));
}

/// `parent`[C0, ManualSelector(repeat last)[A0, A1]]: the selector is node 2.
fn after_a_condition(parent: NodeKind) -> &'static [Node] {
    build(|b| {
        b.open(parent)?.condition(cond(0), &[])?;
        b.open(NodeKind::ManualSelector { repeat_last: true })?.action(act(0), &[])?.action(act(1), &[])?.end()?;
        b.end()?;
        Ok(())
    })
}

#[test]
fn a_child_it_does_not_have_ends_the_tick_with_its_place() {
    let nodes = after_a_condition(NodeKind::Sequence);
    executor!(exec, nodes);
    let mut w = Scripted::new();
    w.set(cond(0), S).set(act(0), R).choose(Selection::Child(0));
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.choose(Selection::Child(2));
    // With repeat_last_selection it would not ask: a fresh executor over the same tree.
    executor!(exec, nodes);
    let e = exec.tick(&mut w, 1).unwrap_err();
    assert_eq!(e, TickError::NoSuchChild { node: 2, child: 2, children: 2 });
    assert_eq!(e.code(), "no-such-child");
    assert_eq!(e.to_string(), "manual selector node 2 has 2 children; the behavior set chose child 2 (counted from 0)");
    // The choice that failed is not remembered: the next tick asks again.
    w.choose(Selection::Child(1)).set(act(1), S);
    let before = w.selects();
    assert_eq!(exec.tick(&mut w, 2).unwrap(), S);
    assert_eq!(w.selects(), before + 1);
    // A set that gives no selections refuses, and the tick ends with that fault.
    w.selection = None;
    executor!(exec, nodes);
    let e = exec.tick(&mut w, 3).unwrap_err();
    assert_eq!(e, TickError::Script { node: 2, fault: ScriptFault::NoSelections });
    assert_eq!(
        e.to_string(),
        "script node 2: this behavior set gives no selections (BehaviorSet::select), which a ManualSelector needs: \
         the operator's choice of a child or a status"
    );
}

#[test]
fn halting_it_halts_its_running_child_and_keeps_the_last_selection() {
    executor!(exec, after_a_condition(NodeKind::Fallback));
    let mut w = Scripted::new();
    w.set(cond(0), F).set(act(1), R).choose(Selection::Child(1));
    assert_eq!(exec.tick(&mut w, 0).unwrap(), R);
    w.set(cond(0), S);
    assert_eq!(exec.tick(&mut w, 1).unwrap(), S);
    assert_eq!(w.halts(act(1)), 1);
    assert!(exec.states()[2..].iter().all(|s| s.status() == NodeStatus::Idle));
    w.set(cond(0), F).choose(Selection::Child(0));
    assert_eq!(exec.tick(&mut w, 2).unwrap(), R);
    assert_eq!(w.log.last(), Some(&Call::Tick { behavior: act(1), starting: true }));
    assert_eq!((w.selects(), w.ticks(act(0))), (1, 0));
}

#[test]
fn a_skipped_child_leaves_it_running_when_it_asked_and_as_it_was_when_it_repeated() {
    // ManualSelector[RunOnce(then skip)[A0]] at the root: A0 runs once, then skips.
    for (repeat_last, after_skip) in [(true, NodeStatus::Idle), (false, NodeStatus::Running)] {
        let nodes = build(|b| {
            b.open(NodeKind::ManualSelector { repeat_last })?;
            b.open(NodeKind::RunOnce { then_skip: true })?.action(act(0), &[])?.end()?.end()?;
            Ok(())
        });
        executor!(exec, nodes);
        let mut w = Scripted::new();
        w.choose(Selection::Child(0)).set(act(0), S);
        assert_eq!(exec.tick(&mut w, 0).unwrap(), S);
        assert_eq!(exec.tick(&mut w, 1).unwrap(), Status::Skipped);
        // Asking, BehaviorTree.CPP's node marks itself Running first, and a skip keeps
        // that; repeating, it keeps its status: Idle, as the finished root was reset.
        assert_eq!(exec.status(0), Some(after_skip), "repeat_last {repeat_last}");
    }
}

#[test]
fn at_most_255_children_load() {
    let catalog = common::catalog();
    for (children, ok) in [(255u16, true), (256, false)] {
        let mut storage = vec![Node::EMPTY; 300];
        let mut b = Builder::<4>::new(&mut storage);
        b.open(NodeKind::ManualSelector { repeat_last: false }).unwrap();
        for _ in 0..children {
            b.condition(cond(0), &[]).unwrap();
        }
        b.end().unwrap();
        let nodes = b.finish().unwrap();
        let got = Tree::<4>::validate(nodes, catalog.as_slice()).map(|_| ());
        let want = if ok {
            Ok(())
        } else {
            Err(LoadError::BadArgument {
                node: 0,
                fault: ArgumentFault::TooManyChildren { kind: "ManualSelector", children: 256, limit: 255 },
            })
        };
        assert_eq!(got, want);
    }
}
