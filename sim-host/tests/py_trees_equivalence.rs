//! The symbolic world under bt-core reproduces the reference's episodes.
//!
//! The reference runs its trees with py_trees 2.0.16: a Selector for `f(` and the
//! reactive `RSequence` for `s(`, each of which stops ("invalidates") the children after
//! the one it returns at only when that child differs from the one it returned at last
//! time and returned Running (both), Failure (RSequence) or Success (Selector). An
//! action is (re)initialised whenever it is ticked while not Running. bt-core instead
//! halts a Running action *before* an earlier action starts (rule 4), so a start that
//! succeeds at once by a shortcut halts what py_trees would leave running; the world's
//! `HaltRule::ResumeWithinTick` makes up for exactly that. This test runs a small
//! interpreter of those py_trees rules next to bt-core on thousands of random trees and
//! compares whole episodes.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use bt_core::{BehaviorSet, Context, Node, NodeKind, Status, children};
use planner::duplo::Task;
use sim_host::episode::{End, Runner};
use sim_host::symbolic::{HaltRule, SymbolicBrickWorld};
use sim_host::world::BrickWorld;
use worlds::World;

#[path = "fixtures/random_trees.rs"]
mod random_trees;
use random_trees::{Stream, random_tree};

/// py_trees' statuses: Invalid is "not ticked since created or stopped".
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Py {
    Invalid,
    Done(Status),
}

/// The reference's tick rules over a pre-order node array.
struct PyTrees<'a> {
    nodes: &'a [Node],
    status: Vec<Py>,
    current: Vec<Option<usize>>,
}

impl PyTrees<'_> {
    fn stop(&mut self, i: usize) {
        let end = i + usize::from(self.nodes[i].size());
        for j in i..end {
            self.status[j] = Py::Invalid;
            self.current[j] = None;
        }
    }

    fn tick(&mut self, i: usize, w: &mut SymbolicBrickWorld) -> Status {
        let r = match *self.nodes[i].kind() {
            NodeKind::Condition(leaf) => {
                w.condition(&leaf, Context { node: i as u16, now: 0, starting: true, values: &[] })
            }
            NodeKind::Action(leaf) => {
                let starting = self.status[i] != Py::Done(Status::Running);
                w.action(&leaf, Context { node: i as u16, now: 0, starting, values: &[] })
            }
            kind @ (NodeKind::Sequence | NodeKind::Fallback) => {
                let fallback = kind == NodeKind::Fallback;
                let kids: Vec<usize> = children(self.nodes, i as u16).map(usize::from).collect();
                if fallback && self.status[i] != Py::Done(Status::Running) {
                    self.current[i] = kids.first().copied();
                }
                let previous = self.current[i];
                let stops_at =
                    |r: Status| r == Status::Running || r == (if fallback { Status::Success } else { Status::Failure });
                let mut result = if fallback { Status::Failure } else { Status::Success };
                let mut at = kids.last().copied();
                for (k, &c) in kids.iter().enumerate() {
                    let r = self.tick(c, w);
                    if stops_at(r) {
                        if previous != Some(c) {
                            for &later in &kids[k + 1..] {
                                if self.status[later] != Py::Invalid {
                                    self.stop(later);
                                }
                            }
                        }
                        result = r;
                        at = Some(c);
                        break;
                    }
                }
                self.current[i] = at;
                result
            }
            other => panic!("not in the reference: {other:?}"),
        };
        self.status[i] = Py::Done(r);
        r
    }
}

/// One episode under the reference's rules: (end, ticks, final positions, held).
fn reference_episode(task: Task, nodes: &[Node]) -> (End, u32, Vec<[f32; 3]>, Option<u8>) {
    let spec = task.spec();
    let mut w = SymbolicBrickWorld::new(&spec).unwrap().with_halt_rule(HaltRule::Cancel);
    let mut py = PyTrees { nodes, status: vec![Py::Invalid; nodes.len()], current: vec![None; nodes.len()] };
    let limit = w.tick_limit();
    let (mut ticks, mut successes, mut end) = (0, 0, End::Timeout);
    while ticks < limit {
        let r = py.tick(0, &mut w);
        w.step();
        ticks += 1;
        successes = if r == Status::Success { successes + 1 } else { 0 };
        if r == Status::Failure {
            end = End::Failure;
            break;
        }
        if successes == 2 {
            end = End::Success;
            break;
        }
    }
    let positions = (0..spec.bricks.len()).map(|b| w.position(b)).collect();
    (end, ticks, positions, w.held())
}

#[test]
fn bt_core_with_the_resume_rule_gives_the_reference_episodes() {
    let mut differ_under_cancel = 0;
    for task in Task::ALL {
        let spec = task.spec();
        let mut runner = Runner::new(SymbolicBrickWorld::new(&spec).unwrap()).unwrap();
        let mut cancel = Runner::new(SymbolicBrickWorld::new(&spec).unwrap().with_halt_rule(HaltRule::Cancel)).unwrap();
        let mut rng = Stream(0xc0ff_ee00 + task as u64);
        for i in 0..1500 {
            let nodes = random_tree(&spec, &mut rng, 2 + i % 4);
            let expected = reference_episode(task, &nodes);
            let e = runner.run_nodes(&nodes).unwrap();
            let got = (e.end, e.ticks, e.positions().to_vec(), e.held);
            assert_eq!(got, expected, "{task:?} tree {i}: {}", bt_formats::tokens::to_string(&nodes, &spec).unwrap());
            let c = cancel.run_nodes(&nodes).unwrap();
            if (c.end, c.ticks, c.positions().to_vec(), c.held) != expected {
                differ_under_cancel += 1;
            }
        }
    }
    // The rule matters: taken literally, bt-core's halts change many episodes.
    assert!(differ_under_cancel > 100, "only {differ_under_cancel} of 6000 differ under HaltRule::Cancel");
}
