//! `sim-host deploy` and `monitor` through the real binary, against a controller running
//! `bt_link::serve` in this test over a TCP socket on the loopback interface.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::net::TcpListener;
use std::thread::JoinHandle;

use bt_core::Catalog as _;

mod cli_common;
mod link_common;
use cli_common::sim_host;
use link_common::{World, catalog, cube_image};

/// A controller holding at most `NODES` nodes, booted with `boot`, serving one
/// connection on a free port.
fn controller<const NODES: usize>(boot: Option<Vec<u8>>) -> (String, JoinHandle<World>) {
    link_common::controller::<NODES, _, _>(catalog(), boot, World)
}

#[test]
fn deploy_prints_the_verdict_and_the_swap() {
    let dir = tempfile::tempdir().unwrap();
    let (path, _) = cube_image(dir.path());
    let (addr, handle) = controller::<64>(None);
    let out = sim_host(&["deploy", path.to_str().unwrap(), "--tcp", &addr, "--start", "--period", "5"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("behavior set") && text.contains("cube-sphere"), "{text}");
    assert!(text.contains("accepted: ") && text.contains("swaps in at the next tick"), "{text}");
    // One line each: the controller, the verdict, the swap, the start.
    let starts: Vec<&str> = text.lines().map(|l| l.split(' ').next().unwrap_or("")).collect();
    assert_eq!(starts, ["controller", "accepted:", "swapped", "ticking"], "{text}");
    assert!(text.contains("swapped in before tick 0"), "{text}");
    assert!(text.contains("ticking from tick 0 every 5 ms"), "{text}");
    handle.join().unwrap();
}

#[test]
fn strip_names_sends_the_image_without_the_names_the_controller_never_reads() {
    let dir = tempfile::tempdir().unwrap();
    let (_, bare) = cube_image(dir.path());
    // The same tree with names longer than the controller's 640-byte slot.
    let c = catalog();
    let mut nodes = vec![bt_core::Node::EMPTY; 64];
    let tree: bt_core::Tree<'_, 16> = bt_core::load(&bare, &c, &mut nodes).unwrap();
    let mut names = bt_formats::Names::of("the cube tree", &c, c.objects());
    names.title.push_str(&" with a long story".repeat(40));
    let named = bt_formats::Image::new(tree.nodes()).names(&names).encode(c.fingerprint()).unwrap();
    assert!(named.len() > 640 && bare.len() < 640);
    let path = dir.path().join("named.bt");
    std::fs::write(&path, &named).unwrap();
    let (addr, handle) = controller::<64>(None);
    cli_common::one_line_error(
        &sim_host(&["deploy", path.to_str().unwrap(), "--tcp", &addr]),
        "holds images of at most 640 bytes; --strip-names leaves out the ",
    );
    handle.join().unwrap();
    let (addr, handle) = controller::<64>(None);
    let out = sim_host(&["deploy", path.to_str().unwrap(), "--tcp", &addr, "--strip-names"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains(&format!("accepted: {} ({} bytes, ", path.display(), bare.len())), "{text}");
    assert_eq!(std::fs::read(&path).unwrap(), named, "the file is left as it is");
    handle.join().unwrap();
}

#[test]
fn a_refusal_exits_2_with_the_controller_s_reason() {
    let dir = tempfile::tempdir().unwrap();
    let (path, _) = cube_image(dir.path());
    // A controller with room for 8 nodes: the planner's tree has more.
    let (addr, handle) = controller::<8>(None);
    let out = sim_host(&["deploy", path.to_str().unwrap(), "--tcp", &addr]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: the controller at 127.0.0.1:"), "{err}");
    assert!(err.contains("rejected") && err.contains("too-many-nodes"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    handle.join().unwrap();
}

#[test]
fn an_image_for_another_behavior_set_is_refused_before_sending() {
    let dir = tempfile::tempdir().unwrap();
    let spec = planner::duplo::Task::Tower.spec();
    let nodes = bt_formats::tokens::parse("s( f( picked 0? pick 0! ) )", &spec).unwrap();
    let mut buf = vec![0u8; bt_core::image::max_image_len(nodes.len())];
    let n = bt_core::encode(&nodes, spec.fingerprint(), &mut buf).unwrap();
    let path = dir.path().join("tower.bt");
    std::fs::write(&path, &buf[..n]).unwrap();
    let (addr, handle) = controller::<64>(None);
    let out = sim_host(&["deploy", path.to_str().unwrap(), "--tcp", &addr]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("tower.bt: built for behavior set") && err.contains("the controller at"), "{err}");
    assert!(err.contains(&format!("{:#018x}", catalog().fingerprint())), "{err}");
    handle.join().unwrap();
}

#[test]
fn monitor_prints_a_line_per_tick_and_records_the_session() {
    let dir = tempfile::tempdir().unwrap();
    let (_, image) = cube_image(dir.path());
    let (addr, handle) = controller::<64>(Some(image));
    let trace = dir.path().join("run.txt");
    let out = sim_host(&[
        "monitor",
        "--tcp",
        &addr,
        "--start",
        "--period",
        "1",
        "--ticks",
        "3",
        "--trace",
        trace.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}{}", String::from_utf8_lossy(&out.stderr));
    let ticks: Vec<&str> = text.lines().filter(|l| l.starts_with("tick ")).collect();
    assert_eq!(ticks.len(), 3, "{text}");
    // Tick 0 starts the tree: the root goes Running.
    assert!(ticks[0].starts_with("tick 0 RUNNING ") && ticks[0].contains(" 0:R"), "{text}");
    let recorded = std::fs::read_to_string(&trace).unwrap();
    assert!(recorded.starts_with("image "), "{recorded}");
    assert_eq!(recorded.lines().filter(|l| l.starts_with("tick ")).count(), 3, "{recorded}");
    handle.join().unwrap();
}

#[test]
fn monitor_records_a_groot2_replay_log_of_the_status_stream() {
    let dir = tempfile::tempdir().unwrap();
    let (_, image) = cube_image(dir.path());
    let (addr, handle) = controller::<64>(Some(image));
    let (trace, log) = (dir.path().join("run.txt"), dir.path().join("run.btlog"));
    let out = sim_host(&[
        "monitor",
        "--tcp",
        &addr,
        "--start",
        "--period",
        "20",
        "--ticks",
        "3",
        "--trace",
        trace.to_str().unwrap(),
        "--btlog",
        log.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("btlog ") && text.contains("run.btlog"), "{text}");
    handle.join().unwrap();
    let log = btcpp::btlog::Log::parse(&std::fs::read(&log).unwrap()).unwrap();
    assert!(log.xml.contains("<BehaviorTree ID=\"MainTree\"") && log.xml.contains("_uid=\"1\""), "{}", log.xml);
    // Every status change of the trace is a transition, in the same order, at tick × 20 ms;
    // bt-core node n is BehaviorTree.CPP's uid n + 1 in a tree without SubTree nodes.
    let recorded = std::fs::read_to_string(&trace).unwrap();
    let expected: Vec<(u64, u16, u8)> = recorded
        .lines()
        .filter_map(|l| l.strip_prefix("status "))
        .map(|l| {
            let w: Vec<&str> = l.split(' ').collect();
            let tick: u64 = w[0].parse().unwrap();
            let node: u16 = w[1].parse().unwrap();
            let s = match w[2] {
                "IDLE" => 0,
                "RUNNING" => 1,
                "SUCCESS" => 2,
                "FAILURE" => 3,
                other => panic!("status {other}"),
            };
            (tick * 20_000, node + 1, s)
        })
        .collect();
    assert!(!expected.is_empty(), "{recorded}");
    assert_eq!(log.transitions, expected);
}

#[test]
fn an_unreachable_controller_is_one_line_and_exit_2() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    drop(listener);
    let out = sim_host(&["monitor", "--tcp", &addr]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with(&format!("error: cannot connect to {addr}")), "{err}");
    let out = sim_host(&["deploy", "x.bt", "--port", "/dev/no-such-tty", "--tcp", &addr]);
    assert_eq!(out.status.code(), Some(2), "--port and --tcp together");
}
