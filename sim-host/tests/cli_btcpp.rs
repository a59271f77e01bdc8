//! `sim-host import`, `catalog`, `run --btlog` and `btlog --from-trace`, through the
//! real binary.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

mod cli_common;
use cli_common::{ok, sim_host};

const TREE: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ReactiveFallback>
      <AtGoal/>
      <Sequence><SubTree ID="Approach"/><Dock side="left"/></Sequence>
    </ReactiveFallback>
  </BehaviorTree>
  <BehaviorTree ID="Approach"><Retry num_attempts="3"><MoveTo/></Retry></BehaviorTree>
  <TreeNodesModel>
    <Condition ID="AtGoal"/>
    <Action ID="MoveTo"/>
    <Action ID="Dock"><input_port name="side" type="std::string"/></Action>
  </TreeNodesModel>
</root>"#;

#[test]
fn import_writes_the_tree_or_a_located_error_and_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let tree = dir.path().join("tree.xml");
    // A typo'd decorator: refused with its place, nothing written.
    std::fs::write(&tree, TREE).unwrap();
    let out_file = dir.path().join("tree.bt");
    let out = sim_host(&["import", tree.to_str().unwrap(), "--out", out_file.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("tree.xml:8:31: `Retry` is neither a BehaviorTree.CPP built-in node"), "{err}");
    assert!(!out_file.exists());

    std::fs::write(
        &tree,
        TREE.replace("<Retry ", "<RetryUntilSuccessful ").replace("</Retry>", "</RetryUntilSuccessful>"),
    )
    .unwrap();
    let out = sim_host(&["import", tree.to_str().unwrap(), "--format", "ascii"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("RetryUntilSuccessful(3)") && text.contains("--> Dock(side=left)"), "{text}");
    assert!(text.ends_with(")\n"), "the view ends its last line: {text:?}");
    let summary = String::from_utf8_lossy(&out.stderr);
    assert!(
        summary.contains("imported `Main`") && summary.contains("6 nodes, 1 constant, 0 blackboard slots"),
        "{summary}"
    );
}

#[test]
fn catalog_prints_the_set_and_its_fingerprint() {
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../btcpp/tests/fixtures/nav2/nav2_tree_nodes.xml");
    let out = sim_host(&["catalog", models.to_str().unwrap()]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("behavior set 0xf6713800ea1f907b: 74 behaviors"), "{text}");
    let rust = String::from_utf8(sim_host(&["catalog", models.to_str().unwrap(), "--rust"]).stdout).unwrap();
    assert!(rust.contains("pub const FINGERPRINT: u64 = 0xf6713800ea1f907b;"));
}

fn transitions(bytes: &[u8]) -> usize {
    assert_eq!(&bytes[..19], b"BTCPP4-FileLogger2\x01");
    let n = i32::from_le_bytes(bytes[19..23].try_into().unwrap()) as usize;
    assert!(std::str::from_utf8(&bytes[23..23 + n]).unwrap().starts_with("<root BTCPP_format=\"4\">"));
    assert_eq!((bytes.len() - 31 - n) % 9, 0);
    (bytes.len() - 31 - n) / 9
}

#[test]
fn runs_and_controller_traces_become_replay_logs() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("tower.btlog");
    let out = sim_host(&["run", "--task", "tower", "--btlog", log.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let first = std::fs::read(&log).unwrap();
    assert!(transitions(&first) > 100);
    // The simulated clock: the same run, the same bytes.
    assert!(sim_host(&["run", "--task", "tower", "--btlog", log.to_str().unwrap()]).status.success());
    assert_eq!(std::fs::read(&log).unwrap(), first);

    // A controller's trace of `s( picked 0? pick 0! )` on the tower task's behaviors.
    let image = dir.path().join("t.bt");
    let xml = dir.path().join("t.xml");
    std::fs::write(
        &xml,
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><ReactiveSequence><picked_0 name="picked 0?"/><pick_0 name="pick 0!"/></ReactiveSequence></BehaviorTree></root>"#,
    )
    .unwrap();
    let out = sim_host(&["import", xml.to_str().unwrap(), "--behaviors", "tower", "--out", image.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let trace = dir.path().join("run.txt");
    std::fs::write(
        &trace,
        "boot image=40B nodes=3 hz=20\ntick 0 RUNNING ran=1S,2R act=x halt=-\ntick 1 FAILURE ran=1F halt=2\n",
    )
    .unwrap();
    let out_log = dir.path().join("run.btlog");
    let out = sim_host(&[
        "btlog",
        "--from-trace",
        trace.to_str().unwrap(),
        "--image",
        image.to_str().unwrap(),
        "--out",
        out_log.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // Tick 0: Seq Running, C Success, A Running, C Idle (the reactive sequence resets the
    // condition); tick 1: C Failure, C Idle, A Idle (halted), Seq Failure, Seq Idle.
    assert_eq!(transitions(&std::fs::read(&out_log).unwrap()), 9);
    // A trace the tree cannot have made.
    std::fs::write(&trace, "tick 0 RUNNING ran=2R halt=-\n").unwrap();
    let out = sim_host(&[
        "btlog",
        "--from-trace",
        trace.to_str().unwrap(),
        "--image",
        image.to_str().unwrap(),
        "--out",
        out_log.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("run.txt:1: tick 0: BehaviorTree.CPP ticks node 1"));
}

/// A tick of a run: its leaf calls, and which nodes are Running after it.
type RunTick = (Vec<(usize, bt_core::Status)>, Vec<bool>);

/// The run's leaf calls and Running nodes, tick by tick, from the episode itself.
#[derive(Default)]
struct Calls {
    ticks: Vec<RunTick>,
    current: Vec<(usize, bt_core::Status)>,
}

impl<W: sim_host::world::BrickWorld + ?Sized> worlds::Recorder<W> for Calls {
    const LEAVES: bool = true;

    fn ticked(&mut self, tick: &worlds::record::Ticked<'_>, _: &W) {
        self.current = tick.calls.iter().map(|&(node, status)| (usize::from(node), status)).collect();
    }

    fn stepped(&mut self, _: u32, _: bt_core::Status, states: &[bt_core::NodeState], _: &W) {
        let running = states.iter().map(|s| s.status() == bt_core::NodeStatus::Running).collect();
        self.ticks.push((std::mem::take(&mut self.current), running));
    }
}

#[test]
fn run_btlog_of_an_imported_tree_with_wake_ups_is_the_run() {
    // Repeat and SequenceWithMemory end a tick after a child that finished at once (a
    // wake-up): the log must follow the run tick by tick.
    let dir = tempfile::tempdir().unwrap();
    let xml = dir.path().join("t.xml");
    std::fs::write(
        &xml,
        r#"<root BTCPP_format="4"><BehaviorTree ID="Tower">
  <Repeat num_cycles="2">
    <SequenceWithMemory>
      <Inverter><picked_0 name="picked 0?"/></Inverter>
      <pick_0 name="pick 0!"/>
      <place_at name="place at (0.0, 0.05, 0.0)!"/>
    </SequenceWithMemory>
  </Repeat>
</BehaviorTree></root>"#,
    )
    .unwrap();
    let image = dir.path().join("t.bt");
    ok(&sim_host(&["import", xml.to_str().unwrap(), "--behaviors", "tower", "--out", image.to_str().unwrap()]));
    let log_file = dir.path().join("t.btlog");
    let out = ok(&sim_host(&[
        "run",
        "--task",
        "tower",
        "--tree",
        image.to_str().unwrap(),
        "--btlog",
        log_file.to_str().unwrap(),
    ]));
    assert!(out.contains("btlog    "), "{out}");
    let log = btcpp::btlog::Log::parse(&std::fs::read(&log_file).unwrap()).unwrap();
    for element in [
        "<Repeat name=\"Repeat\" _uid=\"1\" num_cycles=\"2\">",
        "<SequenceWithMemory name=\"SequenceWithMemory\" _uid=\"2\">",
    ] {
        assert!(log.xml.contains(element), "{}", log.xml);
    }

    // The same episode, in process.
    let spec = planner::duplo::Task::Tower.spec();
    let bytes = std::fs::read(&image).unwrap();
    let mut nodes = vec![bt_core::Node::EMPTY; 6];
    let tree: bt_core::Tree<'_, 16> = bt_core::load(&bytes, &spec, &mut nodes).unwrap();
    let mut runner =
        sim_host::episode::Runner::new(sim_host::symbolic::SymbolicBrickWorld::new(&spec).unwrap()).unwrap();
    let mut run = Calls::default();
    runner.run_recorded(tree, &mut run).unwrap();
    // Ticks that end after the Inverter's condition (SequenceWithMemory's wake-up).
    let wake_ups = run.ticks.iter().filter(|(calls, _)| calls.len() == 1 && calls[0].0 == 3).count();
    assert!(wake_ups > 0, "the tree does not test wake-ups: {:?}", run.ticks);

    // Tick k is at k x 100 ms in the log. Per tick: the leaves that changed status are
    // the run's calls, in order, but for an action Running since the last tick that
    // runs on; the nodes Running after the tick are the run's (uid = node + 1).
    let leaves = [3usize, 4, 5];
    let mut status = [0u8; 7];
    let mut before = vec![false; 6];
    for (k, (calls, running)) in run.ticks.iter().enumerate() {
        let mut changed = vec![];
        for &(_, uid, s) in log.transitions.iter().filter(|t| t.0 / 100_000 == k as u64) {
            let node = usize::from(uid) - 1;
            if s != 0 && leaves.contains(&node) {
                changed.push((node, s));
            }
            status[usize::from(uid)] = s;
        }
        let expected: Vec<(usize, u8)> = calls
            .iter()
            .map(|&(node, s)| (node, btcpp::btlog::status_of(s)))
            .filter(|&(node, s)| !(s == 1 && before[node]))
            .collect();
        assert_eq!(changed, expected, "tick {k}: the leaf transitions are not the run's calls");
        let logged: Vec<bool> = (1..=6).map(|uid| status[uid] == 1).collect();
        assert_eq!(&logged, running, "tick {k}: Running nodes");
        before.clone_from(running);
    }
    assert!(log.transitions.iter().all(|t| t.0 / 100_000 < run.ticks.len() as u64));
}

#[test]
fn an_imported_delay_counts_milliseconds_of_simulated_time() {
    // An episode's tick k is at k x 100 ms: Delay(300 ms) lets its child run on tick 3,
    // as it would on a controller ticking at 10 Hz (not on tick 300).
    assert_eq!(sim_host::episode::TICK_MS, 100);
    let dir = tempfile::tempdir().unwrap();
    let xml = dir.path().join("t.xml");
    std::fs::write(
        &xml,
        r#"<root BTCPP_format="4"><BehaviorTree ID="Tower">
  <Delay delay_msec="300"><pick_0 name="pick 0!"/></Delay>
</BehaviorTree></root>"#,
    )
    .unwrap();
    let image = dir.path().join("t.bt");
    ok(&sim_host(&["import", xml.to_str().unwrap(), "--behaviors", "tower", "--out", image.to_str().unwrap()]));
    let spec = planner::duplo::Task::Tower.spec();
    let bytes = std::fs::read(&image).unwrap();
    let mut nodes = vec![bt_core::Node::EMPTY; 2];
    let tree: bt_core::Tree<'_, 16> = bt_core::load(&bytes, &spec, &mut nodes).unwrap();
    assert!(matches!(tree.nodes()[0].kind(), bt_core::NodeKind::Delay(d) if d.get() == 300));
    let mut runner =
        sim_host::episode::Runner::new(sim_host::symbolic::SymbolicBrickWorld::new(&spec).unwrap()).unwrap();
    let mut run = Calls::default();
    runner.run_recorded(tree, &mut run).unwrap();
    let first = run.ticks.iter().position(|(calls, _)| calls.iter().any(|&(node, _)| node == 1));
    assert_eq!(first, Some(3), "{:?}", run.ticks);
}

#[test]
fn a_trace_of_a_tree_with_a_value_table_becomes_a_replay_log() {
    // IPC 2006 storage: `lift` and `drop` have five parameters, so the planner's tree has
    // extended leaves and its image a value table.
    let ipc = Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/tests/fixtures/ipc/storage");
    let (d, p) = (ipc.join("domain.pddl"), ipc.join("p01.pddl"));
    let dir = tempfile::tempdir().unwrap();
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let image = dir.path().join("storage.bt");
    let out = sim_host(&["plan", "--domain", &s(&d), "--problem", &s(&p), "--format", "image", "--out", &s(&image)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let tree = String::from_utf8(sim_host(&["inspect", &s(&image)]).stdout).unwrap();
    // Node ids in pre-order (the root is 0): where the trace's leaves are.
    let id = |label: &str| tree.lines().skip_while(|l| !l.is_empty()).skip(1).position(|l| l.contains(label)).unwrap();
    let (stored, at_area, lifting) = (id("--> in(crate0, depot0)"), id("--> at(hoist0, loadarea)"), id("lifting("));
    let lift = id("--> lift(hoist0, crate0, container-0-0, loadarea, container0)");
    assert_eq!((stored, at_area, lifting, lift), (1, 4, 9, 15), "{tree}");
    // The hoist is at the load area and lifts the crate (conditions 11 to 14 hold), then
    // the crate is stored.
    let trace = dir.path().join("run.txt");
    std::fs::write(
        &trace,
        "boot image=460B nodes=19 hz=20\n\
         tick 0 RUNNING ran=1F,4S,9F,11S,12S,13S,14S,15R halt=-\n\
         tick 1 SUCCESS ran=1S halt=15\n",
    )
    .unwrap();
    let log = dir.path().join("run.btlog");
    let out = sim_host(&["btlog", "--from-trace", &s(&trace), "--image", &s(&image), "--out", &s(&log)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("(2 ticks, "), "{}", String::from_utf8_lossy(&out.stderr));
    let parsed = btcpp::btlog::Log::parse(&std::fs::read(&log).unwrap()).unwrap();
    // The extended leaf keeps its five arguments as ports (in BehaviorTree.CPP's order).
    assert!(
        parsed.xml.contains(
            r#"<lift name="lift" _uid="16" h="hoist0" a2="loadarea" c="crate0" a1="container-0-0" p="container0"/>"#
        ),
        "{}",
        parsed.xml
    );
    // uid 16 (node 15, lift) starts Running at tick 0 and is halted (Idle) at tick 1.
    let lift_changes: Vec<(u64, u8)> =
        parsed.transitions.iter().filter(|t| t.1 == 16).map(|&(usec, _, status)| (usec, status)).collect();
    assert_eq!(lift_changes, [(0, 1), (50_000, 0)], "{:?}", parsed.transitions);

    // `export` writes the same arguments in every notation that has room for them.
    let xml = String::from_utf8(sim_host(&["export", &s(&image), "--format", "xml"]).stdout).unwrap();
    assert!(
        xml.contains(r#"<lift _uid="16" h="hoist0" c="crate0" a1="container-0-0" a2="loadarea" p="container0"/>"#),
        "{xml}"
    );
    let dot = String::from_utf8(sim_host(&["export", &s(&image), "--format", "dot"]).stdout).unwrap();
    assert!(dot.contains("lift(hoist0, crate0, container-0-0, loadarea, container0)"), "{dot}");
    cli_common::one_line_error(
        &sim_host(&["export", &s(&image), "--format", "tokens"]),
        "--format tokens cannot write node 15: it has 5 arguments, the notation at most 3",
    );
}

#[test]
fn imported_leaves_with_more_than_three_ports_keep_them_in_every_notation() {
    let dir = tempfile::tempdir().unwrap();
    let xml = dir.path().join("move.xml");
    std::fs::write(
        &xml,
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><ReactiveSequence><IsReady/><MoveTo x="1" y="2" z="3" speed="fast" frame="map"/></ReactiveSequence></BehaviorTree>
<TreeNodesModel><Condition ID="IsReady"/><Action ID="MoveTo"><input_port name="x"/><input_port name="y"/><input_port name="z"/><input_port name="speed"/><input_port name="frame"/></Action></TreeNodesModel></root>"#,
    )
    .unwrap();
    let x = xml.to_str().unwrap();
    for format in ["ascii", "dot"] {
        let out = sim_host(&["import", x, "--format", format]);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{format}: {}", String::from_utf8_lossy(&out.stderr));
        assert!(text.contains("MoveTo(x=1, y=2, z=3, speed=fast, frame=map)"), "{format}: {text}");
    }
    cli_common::one_line_error(
        &sim_host(&["import", x, "--format", "tokens"]),
        "--format tokens cannot write node 2, `MoveTo`: it has 5 arguments, the notation at most 3",
    );
}

#[test]
fn the_models_name_an_imported_images_behaviors() {
    // An imported image carries its names; one without them (stripped) takes them from
    // the files `import` read, for inspect, export and btlog, and models of another
    // set are refused.
    let x = Path::new(env!("CARGO_MANIFEST_DIR")).join("../btcpp/tests/fixtures/btcpp-examples");
    let (tree, models) = (x.join("t05_crossdoor.xml"), x.join("example_nodes.xml"));
    let (tree, models) = (tree.to_str().unwrap(), models.to_str().unwrap());
    let dir = tempfile::tempdir().unwrap();
    let named = dir.path().join("t05-named.bt");
    let named = named.to_str().unwrap();
    ok(&sim_host(&["import", tree, "--nodes", models, "--main", "MainTree", "--out", named]));
    let shown = ok(&sim_host(&["inspect", named]));
    assert!(shown.contains("--> IsDoorClosed") && shown.contains("--> PassThroughDoor"), "{shown}");
    assert!(
        shown.contains("(BehaviorTree.CPP tree `MainTree` of t05_crossdoor.xml (names from the image))"),
        "{shown}"
    );
    let image = dir.path().join("t05.bt");
    std::fs::write(&image, bt_formats::image::strip_names(&std::fs::read(named).unwrap()).unwrap()).unwrap();
    let image = image.to_str().unwrap();
    let bare = ok(&sim_host(&["inspect", image]));
    assert!(bare.contains("--> #14") && !bare.contains("IsDoorClosed"), "{bare}");
    let named = ok(&sim_host(&["inspect", image, "--nodes", tree, "--nodes", models]));
    assert!(named.contains("--> IsDoorClosed") && named.contains("--> PassThroughDoor"), "{named}");
    let xml = ok(&sim_host(&["export", image, "--format", "xml", "--nodes", models]));
    assert!(xml.contains("<IsDoorClosed"), "{xml}");

    let trace = dir.path().join("run.txt");
    std::fs::write(&trace, "tick 0 RUNNING ran=3S,5F,7R\ntick 1 SUCCESS ran=7S,9S\n").unwrap();
    let log = dir.path().join("run.btlog");
    let t = trace.to_str().unwrap();
    ok(&sim_host(&["btlog", "--from-trace", t, "--image", image, "--out", log.to_str().unwrap(), "--nodes", models]));
    let parsed = btcpp::btlog::Log::parse(&std::fs::read(&log).unwrap()).unwrap();
    assert!(parsed.xml.contains("<IsDoorClosed") && parsed.xml.contains("<PickLock"), "{}", parsed.xml);

    // Models of another behavior set: one line naming both fingerprints, exit 2.
    let other = dir.path().join("other.xml");
    std::fs::write(&other, r#"<root><TreeNodesModel><Action ID="Fly"/></TreeNodesModel></root>"#).unwrap();
    cli_common::one_line_error(
        &sim_host(&["inspect", image, "--nodes", other.to_str().unwrap()]),
        "but the models of --nodes",
    );
}

/// Imports Nav2's `file` with Nav2's models into `dir`; the image's path.
fn nav2_image(dir: &Path, file: &str) -> String {
    let nav2 = Path::new(env!("CARGO_MANIFEST_DIR")).join("../btcpp/tests/fixtures/nav2");
    let (tree, models) = (nav2.join(file), nav2.join("nav2_tree_nodes.xml"));
    let image = dir.join(file.replace(".xml", ".bt"));
    let image = image.to_str().unwrap().to_string();
    ok(&sim_host(&["import", tree.to_str().unwrap(), "--nodes", models.to_str().unwrap(), "--out", &image]));
    image
}

/// The tree `inspect` prints (the lines after the facts).
fn inspected_tree(image: &str) -> String {
    let text = ok(&sim_host(&["inspect", image]));
    text.split_once("\n\n").unwrap().1.to_string()
}

#[test]
fn an_imported_nav2_image_shows_its_ports_as_written_without_the_models() {
    let dir = tempfile::tempdir().unwrap();
    let image = nav2_image(dir.path(), "follow_point.xml");
    let shown = ok(&sim_host(&["inspect", &image]));
    assert!(
        shown.contains(
            "behaviors  0xf6713800ea1f907b (BehaviorTree.CPP tree `FollowPoint` of follow_point.xml (names from the image))"
        ),
        "{shown}"
    );
    assert_eq!(
        inspected_tree(&image),
        "{-} PipelineSequence
    --> ControllerSelector(topic_name=controller_selector, default_controller=FollowPath, selected_controller={selected_controller})
    --> PlannerSelector(topic_name=planner_selector, default_planner=GridBased, selected_planner={selected_planner})
    -^- RateController(1000)
        {*} SequenceWithMemory
            -^- Gate GoalUpdater(input_goal={goal}, output_goal={updated_goal})
                --> ComputePathToPose(goal={updated_goal}, planner_id={selected_planner}, path={path}, error_code_id={compute_path_error_code}, error_msg={compute_path_error_msg})
            --> TruncatePath(input_path={path}, distance=1.0, output_path={truncated_path})
    -^- KeepRunningUntilFailure
        --> FollowPath(path={truncated_path}, controller_id={selected_controller}, tracking_feedback={tracking_feedback}, error_code_id={follow_path_error_code}, error_msg={follow_path_error_msg})
"
    );
    // btlog names the nodes and ports from the image too (of a tree without plugin
    // decorators, which replay logs do not have).
    let image = nav2_image(dir.path(), "navigate_w_replanning_time.xml");
    let trace = dir.path().join("run.txt");
    std::fs::write(&trace, "tick 0 RUNNING ran=1S,2S,4S,5R halt=-\n").unwrap();
    let log = dir.path().join("run.btlog");
    ok(&sim_host(&[
        "btlog",
        "--from-trace",
        trace.to_str().unwrap(),
        "--image",
        &image,
        "--out",
        log.to_str().unwrap(),
    ]));
    let parsed = btcpp::btlog::Log::parse(&std::fs::read(&log).unwrap()).unwrap();
    assert!(
        parsed.xml.contains(
            r#"<ComputePathToPose name="ComputePathToPose" _uid="5" goal="{goal}" planner_id="{selected_planner}" "#
        ),
        "{}",
        parsed.xml
    );
    assert!(parsed.xml.contains(r#"default_planner="GridBased""#), "{}", parsed.xml);
}

#[test]
fn an_imported_gate_decorator_tree_inspects_with_and_without_names() {
    // Nav2's DistanceController is a plugin decorator: a Gate whose behavior is an action.
    let dir = tempfile::tempdir().unwrap();
    let image = nav2_image(dir.path(), "navigate_w_replanning_distance.xml");
    let tree = inspected_tree(&image);
    assert!(tree.contains("\n    -^- Gate DistanceController(distance=1.0)\n"), "{tree}");
    assert!(tree.contains("--> ComputePathToPose(goal={goal}, planner_id={selected_planner}, path={path}, "), "{tree}");
    // Without its names it is still shown, by ids.
    let bare = dir.path().join("bare.bt");
    std::fs::write(&bare, bt_formats::image::strip_names(&std::fs::read(&image).unwrap()).unwrap()).unwrap();
    let tree = inspected_tree(bare.to_str().unwrap());
    assert!(tree.contains("\n    -^- Gate #25(4, 32767, 32767)\n"), "{tree}");
}

#[test]
fn an_imported_image_exported_as_xml_imports_back_to_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    for file in
        ["follow_point.xml", "navigate_w_replanning_distance.xml", "navigate_to_pose_w_replanning_and_recovery.xml"]
    {
        let image = nav2_image(dir.path(), file);
        let xml = dir.path().join("again.xml");
        ok(&sim_host(&["export", &image, "--format", "xml", "--out", xml.to_str().unwrap()]));
        let again = dir.path().join("again.bt");
        ok(&sim_host(&["import", xml.to_str().unwrap(), "--out", again.to_str().unwrap()]));
        // The same nodes, values, constants, slots and fingerprint: the controller's bytes.
        let strip = |p: &Path| bt_formats::image::strip_names(&std::fs::read(p).unwrap()).unwrap();
        assert_eq!(strip(&again), strip(Path::new(&image)), "{file}");
        assert_eq!(inspected_tree(again.to_str().unwrap()), inspected_tree(&image), "{file}");
    }
}

#[test]
fn scripts_import_with_the_enums_their_program_registers() {
    let x = Path::new(env!("CARGO_MANIFEST_DIR")).join("../btcpp/tests/fixtures/btcpp-examples");
    let tree = x.join("t09_scripting.xml");
    let nodes = x.join("example_nodes.xml");
    let (tree, nodes) = (tree.to_str().unwrap(), nodes.to_str().unwrap());
    let ascii = |enums: &[&str]| {
        let mut args = vec!["import", tree, "--nodes", nodes, "--format", "ascii"];
        for e in enums {
            args.extend(["--enum", e]);
        }
        let out = sim_host(&args);
        let shown = ok(&out);
        (shown, String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let (shown, with) = ascii(&["RED=1", "BLUE=2", "THE_ANSWER=42"]);
    assert!(shown.contains("-^- Precondition") && shown.contains("--> Script"), "{shown}");
    let (_, without) = ascii(&[]);
    // Without them RED, BLUE and THE_ANSWER are blackboard keys: one more slot each.
    assert!(with.contains("4 blackboard slots") && without.contains("7 blackboard slots"), "{with}\n{without}");
    let bad = sim_host(&["import", tree, "--nodes", nodes, "--enum", "RED"]);
    assert_eq!(bad.status.code(), Some(2));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(err.contains("expected NAME=VALUE"), "{err}");
}

#[test]
fn imports_take_the_other_documents_and_casts_their_program_registers() {
    let x = Path::new(env!("CARGO_MANIFEST_DIR")).join("../btcpp/tests/fixtures/btcpp-examples");
    let path = |f: &str| x.join(f).to_str().unwrap().to_string();
    let nodes = path("example_nodes.xml");
    // t07's program registers SubA and SubB from two more documents first; the tree file's
    // only tree is the main one.
    let (tree, a, b) =
        (path("t07_load_multiple_xml.xml"), path("t07_load_multiple_xml_1.xml"), path("t07_load_multiple_xml_2.xml"));
    let shown = ok(&sim_host(&["import", &tree, "--nodes", &nodes, "--nodes", &a, "--nodes", &b, "--format", "ascii"]));
    assert!(shown.contains("Executing SubA") && shown.contains("Executing SubB"), "{shown}");
    // t19's registerPolymorphicCast<Cat, Animal>() and <Sphynx, Cat>().
    let tree = path("t19_polymorphic_ports.xml");
    let refused = sim_host(&["import", &tree, "--nodes", &nodes, "--format", "ascii"]);
    assert_eq!(refused.status.code(), Some(2));
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(err.contains("blackboard key `pet` is used as Animal::Ptr here and as Cat::Ptr"), "{err}");
    let casts = ["--cast", "Cat::Ptr=Animal::Ptr", "--cast", "Sphynx::Ptr=Cat::Ptr"];
    let mut args = vec!["import", tree.as_str(), "--nodes", nodes.as_str(), "--format", "ascii"];
    args.extend(casts);
    ok(&sim_host(&args));
    let bad = sim_host(&["import", &tree, "--nodes", &nodes, "--cast", "Cat::Ptr"]);
    assert_eq!(bad.status.code(), Some(2));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(err.contains("expected DERIVED=BASE"), "{err}");
}
