//! The replay model on runs of bt-core's executor: wake-ups (ticked exactly once and as
//! `tickOnce()`), the clocked kinds (`Timeout`, `Delay`, Nav2's `RateController`) and
//! Nav2's control nodes, with the transitions BehaviorTree.CPP (and Nav2's code on it)
//! makes for them written out by hand.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::collections::BTreeMap;
use std::path::Path;

use bt_core::{BehaviorSet, Catalog, Context, Executor, Leaf, NodeId, NodeState, Status, Tree};
use btcpp::btlog::{Log, LogTree, RunLog, Ticking, status_of};
use btcpp::xml::{ImportOptions, Imported, import_text};

const I: u8 = 0;
const R: u8 = 1;
const S: u8 = 2;
const F: u8 = 3;

/// Leaves answering from scripts by type ID (`S`, `F`, `R`, cyclically); every call
/// recorded.
struct Scripted<'a> {
    imported: &'a Imported,
    scripts: BTreeMap<&'a str, (&'a str, usize)>,
    calls: Vec<(usize, u8)>,
}

impl Scripted<'_> {
    fn next(&mut self, leaf: &Leaf, node: NodeId) -> Status {
        let name = self.imported.info(leaf.behavior()).unwrap().name;
        let (script, k) = self.scripts.get_mut(name).unwrap_or_else(|| panic!("no script for {name}"));
        let s = match script.as_bytes()[*k % script.len()] {
            b'S' => Status::Success,
            b'F' => Status::Failure,
            _ => Status::Running,
        };
        *k += 1;
        self.calls.push((usize::from(node), status_of(s)));
        s
    }
}

impl BehaviorSet for Scripted<'_> {
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        self.next(leaf, ctx.node)
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        self.next(leaf, ctx.node)
    }

    fn halt(&mut self, _: &Leaf, _: NodeId) {}
}

/// Imports `xml` (its leaves declared in `models`), runs it on bt-core for one tick per
/// entry of `now`, ticked as `ticking` says, and logs the run: per tick, the root's
/// status and the log's transitions (uid, status).
fn run(xml: &str, scripts: &[(&str, &str)], now: &[u32], ticking: Ticking) -> Vec<(Status, Vec<(u16, u8)>)> {
    let imported = import_text(Path::new("t.xml"), xml, &ImportOptions::default()).unwrap();
    let tree: Tree<'_, 16> = Tree::validate_with(&imported.nodes, &imported.values, &imported).unwrap();
    let mut state = vec![NodeState::IDLE; imported.nodes.len()];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    let mut leaves =
        Scripted { imported: &imported, scripts: scripts.iter().map(|&(n, s)| (n, (s, 0))).collect(), calls: vec![] };
    let log_tree = LogTree::of_imported(&imported).unwrap();
    let mut log = RunLog::new(&log_tree, 0).ticked(ticking);
    let mut roots = vec![];
    for (k, &t) in now.iter().enumerate() {
        let mut root = exec.tick(&mut leaves, t).unwrap();
        if ticking == Ticking::Once {
            while root == Status::Running && exec.take_woken() {
                root = exec.tick(&mut leaves, t).unwrap();
            }
        }
        let calls = std::mem::take(&mut leaves.calls);
        let k = u32::try_from(k).unwrap();
        log.tick(k, i64::from(k) * 1000, t, &calls).unwrap_or_else(|e| panic!("{e}"));
        roots.push(root);
    }
    let log = Log::parse(&log.into_bytes()).unwrap();
    roots
        .into_iter()
        .enumerate()
        .map(|(k, root)| {
            let t = log.transitions.iter().filter(|x| x.0 / 1000 == k as u64).map(|&(_, uid, s)| (uid, s)).collect();
            (root, t)
        })
        .collect()
}

fn doc(tree: &str, models: &str) -> String {
    format!(
        r#"<root BTCPP_format="4"><BehaviorTree ID="Main">{tree}</BehaviorTree><TreeNodesModel>{models}</TreeNodesModel></root>"#
    )
}

const TWO: &str = r#"<Action ID="A"/><Action ID="B"/>"#;

#[test]
fn a_wake_up_ends_the_pass_and_tick_once_goes_on_in_the_same_tick() {
    // SequenceWithMemory (uid 1) over A (2) and B (3), both succeeding at once.
    let xml = doc("<SequenceWithMemory><A/><B/></SequenceWithMemory>", TWO);
    let scripts = [("A", "S"), ("B", "S")];
    let exactly = run(&xml, &scripts, &[0, 1], Ticking::ExactlyOnce);
    assert_eq!(exactly[0], (Status::Running, vec![(1, R), (2, S)]));
    assert_eq!(exactly[1], (Status::Success, vec![(3, S), (2, I), (3, I), (1, S), (1, I)]));
    let once = run(&xml, &scripts, &[0], Ticking::Once);
    assert_eq!(once[0], (Status::Success, vec![(1, R), (2, S), (3, S), (2, I), (3, I), (1, S), (1, I)]));
}

#[test]
fn repeat_and_retry_wake_up_after_a_child_that_finished_at_once() {
    // Repeat (1) of 3 cycles over A (2): each cycle a pass of its own.
    let xml = doc(r#"<Repeat num_cycles="3"><A/></Repeat>"#, r#"<Action ID="A"/>"#);
    let once = run(&xml, &[("A", "S")], &[0], Ticking::Once);
    let cycle = [(2, S), (2, I)];
    let mut want = vec![(1, R)];
    for _ in 0..3 {
        want.extend(cycle);
    }
    want.extend([(1, S), (1, I)]);
    assert_eq!(once[0], (Status::Success, want));
    // A child that was Running and succeeds is ticked again in the same pass.
    let exactly = run(&xml, &[("A", "RSS")], &[0, 1], Ticking::ExactlyOnce);
    assert_eq!(exactly[0], (Status::Running, vec![(1, R), (2, R)]));
    assert_eq!(exactly[1], (Status::Running, vec![(2, S), (2, I), (2, S), (2, I)]));
    // RetryUntilSuccessful: the same on failures.
    let xml = doc(r#"<RetryUntilSuccessful num_attempts="2"><A/></RetryUntilSuccessful>"#, r#"<Action ID="A"/>"#);
    let exactly = run(&xml, &[("A", "F")], &[0, 1], Ticking::ExactlyOnce);
    assert_eq!(exactly[0], (Status::Running, vec![(1, R), (2, F), (2, I)]));
    assert_eq!(exactly[1], (Status::Failure, vec![(2, F), (2, I), (1, F), (1, I)]));
}

#[test]
fn expired_timeouts_halt_before_the_tick_in_the_order_they_expired() {
    // ParallelAll (1) over Timeout 250 ms (2) of A (3) and Timeout 150 ms (4) of B (5);
    // ticks every 100 ms. At 300 ms both have expired, the second 100 ms earlier: its
    // child is halted first, before anything the tick does.
    let xml = doc(
        r#"<ParallelAll max_failures="1"><Timeout msec="250"><A/></Timeout><Timeout msec="150"><B/></Timeout></ParallelAll>"#,
        TWO,
    );
    let ticks = run(&xml, &[("A", "R"), ("B", "R")], &[0, 100, 200, 300], Ticking::ExactlyOnce);
    assert_eq!(ticks[0].1, vec![(1, R), (2, R), (3, R), (4, R), (5, R)]);
    assert_eq!(ticks[1].1, vec![]);
    // 200 ms: B's timeout (150 ms) has expired.
    assert_eq!(ticks[2].1, vec![(5, I), (4, F)]);
    // 300 ms: A's (250 ms) too; then ParallelAll has both and fails.
    assert_eq!(ticks[3], (Status::Failure, vec![(3, I), (2, F), (2, I), (4, I), (1, F), (1, I)]));
    // The same when both expire between the same two ticks: the earlier one first.
    let xml = doc(
        r#"<ParallelAll max_failures="1"><Timeout msec="250"><A/></Timeout><Timeout msec="150"><B/></Timeout></ParallelAll>"#,
        TWO,
    );
    let ticks = run(&xml, &[("A", "R"), ("B", "R")], &[0, 300], Ticking::ExactlyOnce);
    assert_eq!(ticks[1].1[..2], [(5, I), (3, I)]);
}

#[test]
fn a_delay_waits_then_ticks_its_child_and_a_reset_rate_controller_ticks_at_once() {
    // Delay 150 ms (1) of A (2).
    let xml = doc(r#"<Delay delay_msec="150"><A/></Delay>"#, r#"<Action ID="A"/>"#);
    let ticks = run(&xml, &[("A", "S")], &[0, 100, 200], Ticking::ExactlyOnce);
    assert_eq!(ticks[0], (Status::Running, vec![(1, R)]));
    assert_eq!(ticks[1], (Status::Running, vec![]));
    assert_eq!(ticks[2], (Status::Success, vec![(2, S), (2, I), (1, S), (1, I)]));
    // Ticked as tickOnce, the Delay's end is a wake-up: nothing more here, the root
    // finished in the pass.
    let once = run(&xml, &[("A", "S")], &[0, 100, 200], Ticking::Once);
    assert_eq!(once[2].1, ticks[2].1);

    // KeepRunningUntilFailure (1) of RateController 5 Hz (2) of A (3): the child runs
    // on, then waits for the period since its last success.
    let xml = doc(
        r#"<KeepRunningUntilFailure><RateController hz="5"><A/></RateController></KeepRunningUntilFailure>"#,
        r#"<Action ID="A"/>"#,
    );
    let ticks = run(&xml, &[("A", "RS")], &[0, 100, 200, 300], Ticking::ExactlyOnce);
    assert_eq!(ticks[0].1, vec![(1, R), (2, R), (3, R)]);
    // A succeeds: RateController succeeds (then resets its child, as every decorator
    // does), KeepRunningUntilFailure resets it.
    assert_eq!(ticks[1].1, vec![(3, S), (2, S), (3, I), (2, I)]);
    // Idle again: a new activation ticks A at once.
    assert_eq!(ticks[2].1, vec![(2, R), (3, R)]);
    assert_eq!(ticks[3].1, vec![(3, S), (2, S), (3, I), (2, I)]);
}

#[test]
fn nav2_control_nodes_change_status_as_nav2_s_code_does() {
    // PipelineSequence (1) over RateController 5 Hz (2) of A (3), and B (4), which
    // runs on. The pipeline sets no status before its children; the rate controller
    // keeps its Success under it, so it waits for its period (200 ms) before ticking A
    // again.
    let xml = doc(r#"<PipelineSequence><RateController hz="5"><A/></RateController><B/></PipelineSequence>"#, TWO);
    let ticks = run(&xml, &[("A", "S"), ("B", "R")], &[0, 100, 200, 300], Ticking::Once);
    assert_eq!(ticks[0].1, vec![(2, R), (3, S), (2, S), (3, I), (4, R), (1, R)]);
    assert_eq!(ticks[1].1, vec![(2, R)]);
    assert_eq!(ticks[2].1, vec![(3, S), (2, S), (3, I)]);
    assert_eq!(ticks[3].1, vec![(2, R)]);

    // RecoveryNode (1), one retry, over A (2), which fails, and B (3), which recovers.
    // When it gives up it halts itself (Idle) before it takes its result.
    let xml = doc(r#"<RecoveryNode number_of_retries="1"><A/><B/></RecoveryNode>"#, TWO);
    let ticks = run(&xml, &[("A", "F"), ("B", "S")], &[0], Ticking::ExactlyOnce);
    assert_eq!(
        ticks[0],
        (Status::Failure, vec![(1, R), (2, F), (2, I), (3, S), (3, I), (2, F), (2, I), (1, I), (1, F), (1, I)])
    );

    // RoundRobin (1) over A (2), which fails, and B (3): the turn goes on from where it
    // stopped.
    let xml = doc("<RoundRobin><A/><B/></RoundRobin>", TWO);
    let ticks = run(&xml, &[("A", "F"), ("B", "RS")], &[0, 1, 2], Ticking::ExactlyOnce);
    assert_eq!(ticks[0], (Status::Running, vec![(1, R), (2, F), (3, R)]));
    assert_eq!(ticks[1], (Status::Success, vec![(3, S), (2, I), (3, I), (1, S), (1, I)]));
    // Next activation starts after B, with A.
    assert_eq!(ticks[2].1[..2], [(1, R), (2, F)]);
}
