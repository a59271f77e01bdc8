//! Nav2's default trees against Nav2's models: every file imports whole (its SubTrees
//! flattened, Nav2's control nodes and plugin decorators lowered), loads as an image,
//! and runs in bt-core's executor with scripted leaves, as Nav2 would tick it.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::{Path, PathBuf};

use bt_core::{BehaviorSet, Catalog, Context, Executor, Leaf, Node, NodeId, NodeKind, NodeState, Status, Tree};
use btcpp::xml::{ImportOptions, Imported, import};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/nav2")
}

fn trees() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml") && !p.ends_with("nav2_tree_nodes.xml"))
        .collect();
    files.sort();
    files
}

fn import_nav2(f: &Path) -> Imported {
    let options = ImportOptions { models: vec![dir().join("nav2_tree_nodes.xml")], ..ImportOptions::default() };
    import(f, &options).unwrap_or_else(|e| panic!("{e}"))
}

/// Every leaf and gate answers from a script: conditions and gates by `condition`,
/// actions by `action`, which see the behavior's name and the tick. Halts are counted.
struct Script<'c> {
    catalog: &'c dyn Catalog,
    tick: u32,
    action: fn(&str, u32) -> Status,
    condition: fn(&str, u32) -> Status,
    ticked: Vec<String>,
    /// `ticked.len()` at the end of each tick.
    per_tick: Vec<usize>,
    halts: usize,
}

impl Script<'_> {
    fn name(&self, leaf: &Leaf) -> String {
        self.catalog.info(leaf.behavior()).map(|i| i.name.to_string()).unwrap()
    }
}

impl BehaviorSet for Script<'_> {
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        let name = self.name(leaf);
        self.ticked.push(name.clone());
        (self.condition)(&name, self.tick)
    }

    fn action(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        let name = self.name(leaf);
        self.ticked.push(name.clone());
        // Plugin decorators (gates) are declared as actions: they answer as conditions.
        if is_gate(&name) { (self.condition)(&name, self.tick) } else { (self.action)(&name, self.tick) }
    }

    fn halt(&mut self, _: &Leaf, _: NodeId) {
        self.halts += 1;
    }
}

fn is_gate(name: &str) -> bool {
    matches!(
        name,
        "DistanceController"
            | "SpeedController"
            | "GoalUpdater"
            | "PathLongerOnApproach"
            | "GoalUpdatedController"
            | "SingleTrigger"
    )
}

/// Ticks `imported` every 100 ms for `ticks` ticks (Nav2's default 10 Hz loop, `now` in
/// milliseconds), re-ticking while the tree asks to be woken as BehaviorTree.CPP's
/// `tickOnce` does; the root's status per tick.
fn run(imported: &Imported, ticks: u32, script: &mut Script<'_>) -> Vec<Status> {
    let tree: Tree<'_, 64> = Tree::validate_with(&imported.nodes, &imported.values, imported).unwrap();
    let mut state = vec![NodeState::IDLE; imported.nodes.len()];
    let mut exec = Executor::new(tree, &mut state).unwrap();
    let mut out = Vec::new();
    for t in 0..ticks {
        script.tick = t;
        let mut s = exec.tick(script, t * 100).unwrap();
        while s == Status::Running && exec.take_woken() {
            s = exec.tick(script, t * 100).unwrap();
        }
        out.push(s);
        script.per_tick.push(script.ticked.len());
    }
    out
}

fn kinds(nodes: &[Node]) -> Vec<&'static str> {
    let mut k: Vec<&'static str> = nodes.iter().map(|n| n.kind().name()).collect();
    k.sort_unstable();
    k.dedup();
    k
}

#[test]
fn every_default_tree_imports_and_loads_as_an_image() {
    let files = trees();
    assert_eq!(files.len(), 15);
    let mut all_kinds: Vec<&'static str> = Vec::new();
    for f in &files {
        let imported = import_nav2(f);
        let image = imported.image().unwrap();
        let mut nodes = vec![Node::EMPTY; imported.nodes.len()];
        let mut values = vec![0u16; image.len()];
        let loaded: Tree<'_, 64> = bt_core::load_with(&image, &imported, &mut nodes, &mut values)
            .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        assert_eq!(loaded.nodes(), &imported.nodes[..]);
        println!(
            "{:<75} {:>3} nodes {:>5} bytes",
            f.file_name().unwrap().to_string_lossy(),
            imported.nodes.len(),
            image.len()
        );
        all_kinds.extend(kinds(&imported.nodes));
    }
    all_kinds.sort_unstable();
    all_kinds.dedup();
    // Nav2's own nodes are all there, as bt-core kinds.
    for k in ["PipelineSequence", "Recovery", "RoundRobin", "RateController", "Gate"] {
        assert!(all_kinds.contains(&k), "{k} not in {all_kinds:?}");
    }
}

#[test]
fn navigate_to_pose_succeeds_when_every_action_does() {
    let imported = import_nav2(&dir().join("navigate_to_pose_w_replanning_and_recovery.xml"));
    let mut script = Script {
        catalog: &imported,
        tick: 0,
        action: |_, _| Status::Success,
        condition: |_, _| Status::Success,
        ticked: Vec::new(),
        per_tick: Vec::new(),
        halts: 0,
    };
    let statuses = run(&imported, 1, &mut script);
    assert_eq!(statuses, [Status::Success]);
    // The five selectors; then `GlobalUpdatedGoal` succeeds, so its Inverter fails and
    // with it the check whether the old path will do: the planner plans; then the
    // controller follows. Nothing else (no recovery).
    assert_eq!(
        script.ticked,
        [
            "ProgressCheckerSelector",
            "GoalCheckerSelector",
            "PathHandlerSelector",
            "ControllerSelector",
            "PlannerSelector",
            "GlobalUpdatedGoal",
            "ComputePathToPose",
            "FollowPath"
        ],
    );
    assert_eq!(script.halts, 0);
}

#[test]
fn navigate_to_pose_replans_at_the_rate_controller_s_rate_while_following() {
    let imported = import_nav2(&dir().join("navigate_to_pose_w_replanning_and_recovery.xml"));
    // FollowPath runs for ever; everything else succeeds.
    let mut script = Script {
        catalog: &imported,
        tick: 0,
        action: |name, _| if name == "FollowPath" { Status::Running } else { Status::Success },
        condition: |_, _| Status::Success,
        ticked: Vec::new(),
        per_tick: Vec::new(),
        halts: 0,
    };
    // 3 s at 10 Hz: the planner runs at tick 0 and then once per second (hz="1.0").
    let statuses = run(&imported, 31, &mut script);
    assert!(statuses.iter().all(|&s| s == Status::Running), "{statuses:?}");
    let plans = script.ticked.iter().filter(|n| *n == "ComputePathToPose").count();
    let follows = script.ticked.iter().filter(|n| *n == "FollowPath").count();
    assert_eq!(plans, 4, "{:?}", script.ticked);
    assert_eq!(follows, 31);
    assert_eq!(script.halts, 0);
}

#[test]
fn navigate_to_pose_gives_up_after_its_recoveries() {
    let imported = import_nav2(&dir().join("navigate_to_pose_w_replanning_and_recovery.xml"));
    // Following always fails; recoveries would help and succeed; the goal is never
    // updated.
    let mut script = Script {
        catalog: &imported,
        tick: 0,
        action: |name, _| if name == "FollowPath" { Status::Failure } else { Status::Success },
        condition: |name, _| if name.starts_with("WouldA") { Status::Success } else { Status::Failure },
        ticked: Vec::new(),
        per_tick: Vec::new(),
        halts: 0,
    };
    let statuses = run(&imported, 50, &mut script);
    let end = statuses.iter().position(|&s| s != Status::Running).expect("the tree ends");
    assert_eq!(statuses[end], Status::Failure, "{statuses:?}");
    // NavigateRecovery's number_of_retries="6": six rounds of RecoveryActions, one child
    // of the RoundRobin each: the clearing Sequence, Spin, Wait, BackUp, the clearing
    // Sequence, Spin.
    // Every leaf answers at once, so all of it happens in the tick that fails.
    let turns: Vec<&str> = script.ticked[..script.per_tick[end]]
        .iter()
        .map(String::as_str)
        .filter(|n| ["Spin", "Wait", "BackUp"].contains(n))
        .collect();
    assert_eq!(end, 0);
    assert_eq!(turns, ["Spin", "Wait", "BackUp", "Spin"]);
}

#[test]
fn every_default_tree_runs_on_scripted_leaves_without_error() {
    // Leaves that succeed, fail and run in a fixed pattern over the ticks.
    fn action(name: &str, tick: u32) -> Status {
        let h = name.bytes().fold(tick.wrapping_mul(2_654_435_761), |h, b| h.rotate_left(5) ^ u32::from(b));
        [Status::Success, Status::Running, Status::Running, Status::Failure][(h % 4) as usize]
    }
    fn condition(name: &str, tick: u32) -> Status {
        let h = name.bytes().fold(tick.wrapping_mul(40_503), |h, b| h.rotate_left(3) ^ u32::from(b));
        if h % 3 == 0 { Status::Failure } else { Status::Success }
    }
    for f in &trees() {
        let imported = import_nav2(f);
        let mut script = Script {
            catalog: &imported,
            tick: 0,
            action,
            condition,
            ticked: Vec::new(),
            per_tick: Vec::new(),
            halts: 0,
        };
        let statuses = run(&imported, 100, &mut script);
        assert_eq!(statuses.len(), 100);
        assert!(!script.ticked.is_empty(), "{}", f.display());
        // The same script gives the same run.
        let mut again = Script {
            catalog: &imported,
            tick: 0,
            action,
            condition,
            ticked: Vec::new(),
            per_tick: Vec::new(),
            halts: 0,
        };
        assert_eq!(run(&imported, 100, &mut again), statuses, "{}", f.display());
        assert_eq!(again.ticked, script.ticked);
        assert!(imported.nodes.iter().all(|n| !matches!(n.kind(), NodeKind::Repeat(_) | NodeKind::Retry(_))));
    }
}

/// A script that also records every call by node, for the replay log.
struct Calls<'s, 'c> {
    script: &'s mut Script<'c>,
    calls: Vec<(usize, u8)>,
}

impl BehaviorSet for Calls<'_, '_> {
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let node = usize::from(ctx.node);
        let s = self.script.condition(leaf, ctx);
        self.calls.push((node, btcpp::btlog::status_of(s)));
        s
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let node = usize::from(ctx.node);
        let s = self.script.action(leaf, ctx);
        self.calls.push((node, btcpp::btlog::status_of(s)));
        s
    }

    fn halt(&mut self, leaf: &Leaf, node: NodeId) {
        self.script.halt(leaf, node);
    }
}

#[test]
fn replay_logs_follow_the_runs_of_the_default_trees() {
    use btcpp::btlog::{Log, LogTree, RunLog, Ticking};
    fn action(name: &str, tick: u32) -> Status {
        let h = name.bytes().fold(tick.wrapping_mul(2_654_435_761), |h, b| h.rotate_left(5) ^ u32::from(b));
        [Status::Success, Status::Running, Status::Running, Status::Failure][(h % 4) as usize]
    }
    fn condition(name: &str, tick: u32) -> Status {
        let h = name.bytes().fold(tick.wrapping_mul(40_503), |h, b| h.rotate_left(3) ^ u32::from(b));
        if h % 3 == 0 { Status::Failure } else { Status::Success }
    }
    let mut logged = 0;
    for f in &trees() {
        let imported = import_nav2(f);
        // Plugin decorators (gates) too: their answers are the run's.
        let tree = LogTree::of_imported(&imported).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let mut script = Script {
            catalog: &imported,
            tick: 0,
            action,
            condition,
            ticked: Vec::new(),
            per_tick: Vec::new(),
            halts: 0,
        };
        let bt: Tree<'_, 64> = Tree::validate_with(&imported.nodes, &imported.values, &imported).unwrap();
        let mut state = vec![NodeState::IDLE; imported.nodes.len()];
        let mut exec = Executor::new(bt, &mut state).unwrap();
        let mut log = RunLog::new(&tree, 0).ticked(Ticking::Once);
        let mut running = Vec::new();
        for t in 0..100u32 {
            script.tick = t;
            let mut calls = Calls { script: &mut script, calls: Vec::new() };
            let mut s = exec.tick(&mut calls, t * 100).unwrap();
            while s == Status::Running && exec.take_woken() {
                s = exec.tick(&mut calls, t * 100).unwrap();
            }
            let calls = calls.calls;
            log.tick(t, i64::from(t) * 100_000, t * 100, &calls).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            running.push(exec.states().iter().map(|s| s.status() == bt_core::NodeStatus::Running).collect::<Vec<_>>());
        }
        // After every tick, the log's Running nodes are the run's.
        let log = Log::parse(&log.into_bytes()).unwrap();
        let mut status = vec![0u8; tree.nodes.len() + 1];
        for (t, run) in running.iter().enumerate() {
            for &(_, uid, s) in log.transitions.iter().filter(|x| x.0 / 100_000 == t as u64) {
                status[usize::from(uid)] = s;
            }
            for n in tree.nodes.iter().filter(|n| n.core.is_some()) {
                let core = n.core.unwrap();
                assert_eq!(
                    status[usize::from(n.uid)] == 1,
                    run[core],
                    "{}: tick {t}: node {core} ({})",
                    f.display(),
                    n.name
                );
            }
        }
        logged += 1;
    }
    // All 15, the 5 with plugin decorators too.
    assert_eq!(logged, 15);
}
