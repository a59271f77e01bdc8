//! The replay model on runs of bt-core's executor: wake-ups (ticked exactly once and as
//! `tickOnce()`), the clocked kinds (`Timeout`, `Delay`, Nav2's `RateController`) and
//! Nav2's control nodes, with the transitions BehaviorTree.CPP (and Nav2's code on it)
//! makes for them written out by hand.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::collections::{BTreeMap, VecDeque};
use std::path::Path;

use bt_core::script::ScriptFault;
use bt_core::{BehaviorSet, Catalog, Context, Executor, Leaf, NodeId, NodeState, Selection, Status, Tree};
use btcpp::btlog::{Log, LogTree, Mismatch, RunLog, Ticking, status_of};
use btcpp::xml::{ImportOptions, Imported, import_text};

const I: u8 = 0;
const R: u8 = 1;
const S: u8 = 2;
const F: u8 = 3;

/// Leaves answering from scripts by type ID (`S`, `F`, `R`, cyclically), and
/// `ManualSelector`s from a list of commands; every call and selection recorded.
struct Scripted<'a> {
    imported: &'a Imported,
    scripts: BTreeMap<&'a str, (&'a str, usize)>,
    calls: Vec<(usize, u8)>,
    commands: VecDeque<Selection>,
    selections: Vec<(usize, Selection)>,
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

    fn select(&mut self, _: u8, ctx: Context<'_>) -> Result<Selection, ScriptFault> {
        let s = self.commands.pop_front().ok_or(ScriptFault::NoSelections)?;
        self.selections.push((usize::from(ctx.node), s));
        Ok(s)
    }
}

/// Per tick: the root's status and the log's transitions (uid, status).
type Ticks = Vec<(Status, Vec<(u16, u8)>)>;

/// Imports `xml` (its leaves declared in `models`), runs it on bt-core for one tick per
/// entry of `now`, ticked as `ticking` says, and logs the run: per tick, the root's
/// status and the log's transitions (uid, status).
fn run(xml: &str, scripts: &[(&str, &str)], now: &[u32], ticking: Ticking) -> Ticks {
    selecting(xml, scripts, &[], now, ticking).unwrap_or_else(|e| panic!("{e}"))
}

/// [`run`] with `ManualSelector`s told `commands` in turn; the log's refusal as it is.
fn selecting(
    xml: &str,
    scripts: &[(&str, &str)],
    commands: &[Selection],
    now: &[u32],
    ticking: Ticking,
) -> Result<Ticks, Mismatch> {
    let imported = import_text(Path::new("t.xml"), xml, &ImportOptions::default()).unwrap();
    let tree: Tree<'_, 16> = Tree::validate_with(&imported.nodes, &imported.values, &imported).unwrap();
    let mut state = vec![NodeState::IDLE; imported.nodes.len()];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    let mut leaves = Scripted {
        imported: &imported,
        scripts: scripts.iter().map(|&(n, s)| (n, (s, 0))).collect(),
        calls: vec![],
        commands: commands.iter().copied().collect(),
        selections: vec![],
    };
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
        let selections = std::mem::take(&mut leaves.selections);
        let k = u32::try_from(k).unwrap();
        log.tick_selecting(k, i64::from(k) * 1000, t, &calls, &selections)?;
        roots.push(root);
    }
    let log = Log::parse(&log.into_bytes()).unwrap();
    Ok(roots
        .into_iter()
        .enumerate()
        .map(|(k, root)| {
            let t = log.transitions.iter().filter(|x| x.0 / 1000 == k as u64).map(|&(_, uid, s)| (uid, s)).collect();
            (root, t)
        })
        .collect())
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

const ABC: &str = r#"<Action ID="A"/><Action ID="B"/><Condition ID="C"/>"#;

#[test]
fn a_manual_selector_marks_itself_running_asks_and_leaves_other_children_as_they_are() {
    use Selection::{Child, Failure, Running};
    // ManualSelector (1) over A (2) and B (3), the root.
    let xml = doc("<ManualSelector><A/><B/></ManualSelector>", TWO);
    let commands = [Child(0), Child(1), Child(1), Running, Child(0), Failure];
    let ticks = selecting(&xml, &[("A", "RS"), ("B", "RS")], &commands, &[0, 1, 2, 3, 4, 5], Ticking::ExactlyOnce)
        .unwrap_or_else(|e| panic!("{e}"));
    let want: [(Status, Vec<(u16, u8)>); 6] = [
        // Running before it asks, then A.
        (Status::Running, vec![(1, R), (2, R)]),
        // B chosen while A runs: A is left Running (bt-core halts it; BT.CPP does not).
        (Status::Running, vec![(3, R)]),
        // B succeeds, so does the root, which alone is reset: A stays Running, B Success.
        (Status::Success, vec![(3, S), (1, S), (1, I)]),
        // Told Running: it returns it, ticking no child.
        (Status::Running, vec![(1, R)]),
        // A again: still Running in BT.CPP, it goes on and succeeds.
        (Status::Success, vec![(2, S), (1, S), (1, I)]),
        // Told Failure: Running first, then the status; the children keep theirs.
        (Status::Failure, vec![(1, R), (1, F), (1, I)]),
    ];
    assert_eq!(ticks, want);
}

#[test]
fn a_manual_selector_halted_halts_its_remembered_child_first_then_the_others() {
    use Selection::Child;
    // ReactiveSequence (1) over C (2) and ManualSelector (3) over A (4) and B (5).
    let xml = doc("<ReactiveSequence><C/><ManualSelector><A/><B/></ManualSelector></ReactiveSequence>", ABC);
    let ticks = selecting(
        &xml,
        &[("C", "SSF"), ("A", "R"), ("B", "R")],
        &[Child(0), Child(1)],
        &[0, 1, 2],
        Ticking::ExactlyOnce,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ticks[0], (Status::Running, vec![(1, R), (2, S), (3, R), (4, R), (2, I)]));
    // B chosen: A left Running.
    assert_eq!(ticks[1], (Status::Running, vec![(2, S), (5, R), (2, I)]));
    // C fails: the ManualSelector is halted, B (the running child it remembers) first,
    // then its children in order (A, still Running), then itself.
    assert_eq!(ticks[2], (Status::Failure, vec![(2, F), (2, I), (5, I), (4, I), (3, I), (1, F), (1, I)]));
}

#[test]
fn repeat_last_selection_ticks_the_same_child_without_asking_or_marking_itself_running() {
    use Selection::Child;
    // ReactiveSequence (1) over C (2) and ManualSelector (3, repeating) over A (4), B (5).
    let xml = doc(
        r#"<ReactiveSequence><C/><ManualSelector repeat_last_selection="true"><A/><B/></ManualSelector></ReactiveSequence>"#,
        ABC,
    );
    // One command for the whole run.
    let ticks = selecting(
        &xml,
        &[("C", "SSFS"), ("A", "R"), ("B", "RRSR")],
        &[Child(1)],
        &[0, 1, 2, 3, 4],
        Ticking::ExactlyOnce,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ticks[0], (Status::Running, vec![(1, R), (2, S), (3, R), (5, R), (2, I)]));
    assert_eq!(ticks[1], (Status::Running, vec![(2, S), (2, I)]));
    assert_eq!(ticks[2], (Status::Failure, vec![(2, F), (2, I), (5, I), (3, I), (1, F), (1, I)]));
    // Reset by the halt, it repeats child 1 from Idle: no Running of its own first.
    // Finished, it is reset by its parent, not halted: B keeps Success.
    assert_eq!(ticks[3], (Status::Success, vec![(1, R), (2, S), (5, S), (3, S), (2, I), (3, I), (1, S), (1, I)]));
    // B, Success since the last tick, goes straight to Running.
    assert_eq!(ticks[4], (Status::Running, vec![(1, R), (2, S), (5, R), (3, R), (2, I)]));
}

#[test]
fn a_manual_selector_without_children_returns_the_status_it_is_told() {
    use Selection::{Failure, Running, Success};
    let xml = doc("<ManualSelector/>", "");
    let ticks = selecting(&xml, &[], &[Success, Running, Failure], &[0, 1, 2], Ticking::ExactlyOnce)
        .unwrap_or_else(|e| panic!("{e}"));
    // It does not mark itself Running before it asks.
    assert_eq!(ticks[0], (Status::Success, vec![(1, S), (1, I)]));
    assert_eq!(ticks[1], (Status::Running, vec![(1, R)]));
    assert_eq!(ticks[2], (Status::Failure, vec![(1, F), (1, I)]));
}

#[test]
fn runs_behaviortree_cpp_cannot_make_are_refused_naming_the_node_and_the_tick() {
    use Selection::{Child, Success};
    // A remembered status repeated: BT.CPP would tick a child past its children.
    let xml = doc(r#"<ManualSelector repeat_last_selection="true"><A/></ManualSelector>"#, TWO);
    let e = selecting(&xml, &[("A", "S")], &[Success], &[0, 1], Ticking::ExactlyOnce).unwrap_err();
    assert_eq!(
        e.to_string(),
        "tick 1: ManualSelector `ManualSelector` (uid 1) repeats its last selection, Success, which \
         BehaviorTree.CPP would take as a child index past its children"
    );
    // A Sequence (2) left Running at its second child, where bt-core halts it: chosen
    // again, BT.CPP goes on with B where the run started over with A.
    let xml = doc("<ManualSelector><Sequence><A/><B/></Sequence><A/></ManualSelector>", TWO);
    let e =
        selecting(&xml, &[("A", "S"), ("B", "R")], &[Child(0), Child(1), Child(0)], &[0, 1, 2], Ticking::ExactlyOnce)
            .unwrap_err();
    assert_eq!(
        e.to_string(),
        "tick 2: BehaviorTree.CPP ticks node 3 (B) where the run ticked node 2 (A); ManualSelector \
         `ManualSelector` (uid 1) left `Sequence` (uid 2) Running at tick 1, where our executor halts it \
         before starting another child (halt before start)"
    );
    // Child 253 of 254: BT.CPP's menu answers 253 for Success.
    let xml = doc(&format!("<ManualSelector>{}</ManualSelector>", "<A/>".repeat(254)), TWO);
    let e = selecting(&xml, &[("A", "S")], &[Child(253)], &[0], Ticking::ExactlyOnce).unwrap_err();
    assert_eq!(
        e.to_string(),
        "tick 0: ManualSelector `ManualSelector` (uid 1) is told to tick child 253, which BehaviorTree.CPP's \
         selection takes for a status"
    );
    // A run that made no selection (a trace without them).
    let xml = doc("<ManualSelector><A/></ManualSelector>", TWO);
    let imported = import_text(Path::new("t.xml"), &xml, &ImportOptions::default()).unwrap();
    let tree = LogTree::of_imported(&imported).unwrap();
    let e = RunLog::new(&tree, 0).tick(0, 0, 0, &[(1, S)]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "tick 0: ManualSelector `ManualSelector` (uid 1) asks for a selection, and the run made none there"
    );
}
