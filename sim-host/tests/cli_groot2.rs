//! `sim-host groot2` through the real binary, against the link controller built for
//! the host (`bt_link::serve` in this test, over TCP on the loopback interface), with a
//! libzmq client in Groot2's place: it sees tree A, A's statuses as the controller
//! reported them, then tree B under a new UUID after a deploy A -> B; bad clients meanwhile
//! are answered or dropped, and the bridge's trace of the session loses nothing of the
//! controller's status stream.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::io::Read as _;
use std::process::{Command, Stdio};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

use bt_core::{BehaviorSet, Catalog as _, Context, Leaf, Node, NodeId, Status};
use bt_link::{App, WireStatus};
use btcpp::btlog::LogTree;

mod cli_common;
mod groot2_common;
mod link_common;
use groot2_common::{ask, client, free_ports, header};
use link_common::{Sent, Tap, catalog, cube_image};

/// Milliseconds between ticks: the tree's clock, so tick = now / PERIOD.
const PERIOD: u32 = 5;

/// Holds the controller before the ticks named, until the test lets it go on.
#[derive(Default)]
struct Pause {
    at: Vec<u32>,
    held: Mutex<Option<u32>>,
    moved: Condvar,
}

impl Pause {
    fn wait_held(&self, tick: u32) {
        let deadline = Instant::now() + Duration::from_secs(60);
        let mut held = self.held.lock().unwrap();
        while *held != Some(tick) {
            assert!(Instant::now() < deadline, "the controller never reached tick {tick}");
            held = self.moved.wait_timeout(held, Duration::from_millis(100)).unwrap().0;
        }
    }

    fn release(&self) {
        *self.held.lock().unwrap() = None;
        self.moved.notify_all();
    }
}

/// Statuses that move every tick: conditions true two ticks in three, actions running
/// three ticks in four (shifted by the behavior id).
struct Moving(Arc<Pause>);

impl BehaviorSet for Moving {
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let t = ctx.now / PERIOD + u32::from(leaf.behavior());
        if t.is_multiple_of(3) { Status::Failure } else { Status::Success }
    }
    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let t = ctx.now / PERIOD + u32::from(leaf.behavior());
        if t % 4 == 3 { Status::Success } else { Status::Running }
    }
    fn halt(&mut self, _: &Leaf, _: NodeId) {}
}

impl App for Moving {
    fn before_tick(&mut self, tick: u32) {
        if self.0.at.contains(&tick) {
            *self.0.held.lock().unwrap() = Some(tick);
            self.0.moved.notify_all();
            let mut held = self.0.held.lock().unwrap();
            while held.is_some() {
                held = self.0.moved.wait(held).unwrap();
            }
        }
    }
}

/// STATUS as BehaviorTree.CPP would fill it from what the controller sent since its
/// last swap: node i is uid i + 1; 10 + X for a node back to Idle from X.
fn expected_status(sent: &[Sent], nodes: usize) -> Vec<u8> {
    let from = sent.iter().rposition(|s| matches!(s, Sent::Swapped(_))).map_or(0, |i| i + 1);
    let code = |s: WireStatus| match s {
        WireStatus::Running => 1,
        WireStatus::Success => 2,
        WireStatus::Failure => 3,
        _ => 0,
    };
    let mut now = vec![0u8; nodes];
    let mut shown = vec![0u8; nodes];
    for s in &sent[from..] {
        if let Sent::Status { node, status, .. } = *s {
            let n = usize::from(node);
            let c = code(status);
            shown[n] = if c == 0 { 10 + now[n] } else { c };
            now[n] = c;
        }
    }
    (0..nodes).flat_map(|i| [(i as u16 + 1).to_le_bytes()[0], (i as u16 + 1).to_le_bytes()[1], shown[i]]).collect()
}

/// Asks STATUS until it is `want` (the bridge gets the stream a moment later).
fn status_becomes(groot: &zmq::Socket, want: &[u8], uuid: &[u8]) {
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        let reply = ask(groot, &[header(b'S', 7)]);
        assert_eq!(reply[0][6..], *uuid);
        if reply[1] == want {
            return;
        }
        assert!(Instant::now() < deadline, "STATUS {:?}\nwanted {want:?}", reply[1]);
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// What bad clients do while the controller ticks; each must leave the bridge serving.
fn bad_clients(ctx: &zmq::Context, port: u16) {
    let groot = client(ctx, port);
    // A short header, an unknown type: BehaviorTree.CPP's error replies.
    assert_eq!(ask(&groot, &[vec![2, b'S', 0, 0, 0]])[0], b"error");
    assert_eq!(ask(&groot, &[header(b'Z', 1)])[1], b"Request not recognized");
    // A hook: refused as BehaviorTree.CPP refuses what it does not serve.
    let hook = br#"{"enabled":true,"uid":2,"mode":0,"once":false,"desired_status":"FAILURE","position":0}"#;
    assert_eq!(ask(&groot, &[header(b'I', 2), hook.to_vec()])[1], b"Request not recognized");
    // Another protocol byte: served, the reply says 2 (BehaviorTree.CPP does not check).
    let mut odd = header(b'S', 3);
    odd[0] = 9;
    assert_eq!(ask(&groot, &[odd])[0][0], 2);
    // A client that sends and vanishes without reading its reply.
    let gone = ctx.socket(zmq::DEALER).unwrap();
    gone.set_linger(100).unwrap();
    gone.connect(&format!("tcp://127.0.0.1:{port}")).unwrap();
    gone.send_multipart([Vec::new(), header(b'T', 4)], 0).unwrap();
    drop(gone);
    // A flood: 2,000 requests from one client without reading. Replies come in order;
    // those past libzmq's high-water marks may be dropped (a busy machine fills them),
    // never doubled or reordered.
    let flood = ctx.socket(zmq::DEALER).unwrap();
    flood.set_linger(0).unwrap();
    flood.set_sndtimeo(2000).unwrap();
    flood.set_rcvtimeo(10_000).unwrap();
    flood.connect(&format!("tcp://127.0.0.1:{port}")).unwrap();
    for k in 0..2000u32 {
        flood.send_multipart([Vec::new(), header(b'S', k)], 0).unwrap();
    }
    let mut answered = Vec::new();
    while let Ok(reply) = flood.recv_multipart(0) {
        let id = u32::from_le_bytes(reply[1][2..6].try_into().unwrap());
        assert!(answered.last().is_none_or(|&last| id > last) && id < 2000, "reply {id} after {answered:?}");
        answered.push(id);
        if id == 1999 {
            break;
        }
        flood.set_rcvtimeo(2000).unwrap();
    }
    assert_eq!(answered.first(), Some(&0), "the flood's first request is answered");
    drop(flood);
    // A message over the size limit: libzmq drops that connection.
    let big = ctx.socket(zmq::DEALER).unwrap();
    big.set_linger(0).unwrap();
    big.connect(&format!("tcp://127.0.0.1:{port}")).unwrap();
    big.send_multipart([Vec::new(), header(b'B', 5), vec![b'x'; 1 << 20]], 0).unwrap();
    drop(big);
    // A second client, alongside the first: both served.
    let second = client(ctx, port);
    assert_eq!(ask(&second, &[header(b'D', 6)])[1], b"[]");
    assert_eq!(ask(&groot, &[header(b'D', 7)])[1], b"[]");
}

fn xml(nodes: &[Node]) -> Vec<u8> {
    LogTree::new(nodes, &catalog()).unwrap().xml().into_bytes()
}

#[test]
fn groot2_sees_a_then_b_with_the_controller_s_statuses_through_a_swap() {
    let dir = tempfile::tempdir().unwrap();
    let (_, a) = cube_image(dir.path());
    let mut storage = vec![Node::EMPTY; 64];
    let a_nodes = bt_core::load::<_, { planner::DEPTH }>(&a, &catalog(), &mut storage).unwrap().nodes().to_vec();
    // B: the planner's tree for the blocked path, same behaviors.
    let g = Arc::new(planner::domains::cube_sphere_blocked().unwrap());
    let c = Arc::new(planner::PddlCatalog::new(g.problem()));
    assert_eq!(c.fingerprint(), catalog().fingerprint());
    let b_nodes = planner::plan(g, c.clone(), planner::Options::default()).unwrap().nodes;
    let b = bt_formats::Image::new(&b_nodes).encode(c.fingerprint()).unwrap();
    let b_path = dir.path().join("b.bt");
    std::fs::write(&b_path, &b).unwrap();

    let pause = Arc::new(Pause { at: vec![10, 40], ..Pause::default() });
    let tap: Tap = Arc::default();
    let (addr, controller) = link_common::tapped::<64, _, _>(catalog(), Some(a), Moving(pause.clone()), tap.clone());
    let port = free_ports();
    let trace = dir.path().join("trace.txt");
    let mut bridge = Command::new(env!("CARGO_BIN_EXE_sim-host"))
        .args(["groot2", "--tcp", &addr, "--listen", &format!("127.0.0.1:{port}"), "--start"])
        .args(["--period", &PERIOD.to_string(), "--deploy", b_path.to_str().unwrap(), "--at-tick", "25"])
        .args(["--ticks", "50", "--trace", trace.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();

    let ctx = zmq::Context::new();
    let groot = client(&ctx, port);
    groot.set_rcvtimeo(30_000).unwrap();
    let tree = ask(&groot, &[header(b'T', 1)]);
    assert_eq!(tree[1], xml(&a_nodes), "FULLTREE is tree A as BehaviorTree.CPP writes it");
    let uuid_a = tree[0][6..].to_vec();
    assert_eq!(ask(&groot, &[header(b'r', 2), b"start".to_vec()]).len(), 2);

    pause.wait_held(10);
    let want = expected_status(&tap.lock().unwrap(), a_nodes.len());
    // Running, Success and Failure among them.
    for shown in [1, 2, 3] {
        assert!(want.chunks(3).any(|c| c[2] == shown), "{want:?} has no status {shown}");
    }
    status_becomes(&groot, &want, &uuid_a);
    let transitions = ask(&groot, &[header(b't', 3)]);
    assert_eq!(transitions[1].len() % 9, 0);
    pause.release();
    bad_clients(&ctx, port);

    pause.wait_held(40);
    let tree = ask(&groot, &[header(b'T', 4)]);
    let uuid_b = tree[0][6..].to_vec();
    assert_ne!(uuid_b, uuid_a, "B is served under a new tree UUID");
    assert_eq!(tree[1], xml(&b_nodes), "FULLTREE is tree B after the swap");
    let want = expected_status(&tap.lock().unwrap(), b_nodes.len());
    assert!(want.chunks(3).any(|c| c[2] >= 10), "{want:?} has no node back to Idle");
    status_becomes(&groot, &want, &uuid_b);
    pause.release();

    let status = bridge.wait().unwrap();
    let mut stdout = String::new();
    bridge.stdout.take().unwrap().read_to_string(&mut stdout).unwrap();
    let mut stderr = String::new();
    bridge.stderr.take().unwrap().read_to_string(&mut stderr).unwrap();
    assert!(status.success(), "{stdout}{stderr}");
    assert!(stdout.contains("deployed") && stdout.contains("swap before tick 25"), "{stdout}");
    controller.join().unwrap();

    // Nothing of the controller's stream is missing from the bridge's trace, in order.
    let sent = tap.lock().unwrap().clone();
    let traced: Vec<Sent> = std::fs::read_to_string(&trace)
        .unwrap()
        .lines()
        .filter_map(|l| {
            let w: Vec<&str> = l.split(' ').collect();
            match w[0] {
                "status" => Some(Sent::Status {
                    tick: w[1].parse().unwrap(),
                    node: w[2].parse().unwrap(),
                    status: match w[3] {
                        "IDLE" => WireStatus::Idle,
                        "SUCCESS" => WireStatus::Success,
                        "FAILURE" => WireStatus::Failure,
                        _ => WireStatus::Running,
                    },
                }),
                "tick" => Some(Sent::Tick(w[1].parse().unwrap())),
                "swap" => Some(Sent::Swapped(w[1].parse().unwrap())),
                _ => None,
            }
        })
        .collect();
    let ticks = traced.iter().filter(|s| matches!(s, Sent::Tick(_))).count();
    assert_eq!(ticks, 50);
    assert_eq!(traced[..], sent[..traced.len()], "the bridge's trace is the controller's stream");
}

/// `sim-host ARGS --groot2 127.0.0.1:PORT --period 0 --groot2-linger 5`, questioned
/// once the run is over: its stderr's first line, then FULLTREE and STATUS.
fn simulated(args: &[&str]) -> (String, Vec<Vec<u8>>, Vec<Vec<u8>>) {
    let port = free_ports();
    let mut child = Command::new(env!("CARGO_BIN_EXE_sim-host"))
        .args(args)
        .args(["--groot2", &format!("127.0.0.1:{port}"), "--period", "0", "--groot2-linger", "5"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The run is over when stderr says so.
    let mut stderr = child.stderr.take().unwrap();
    let mut text = String::new();
    let mut buf = [0u8; 256];
    while !text.contains("the run is over") {
        let n = stderr.read(&mut buf).unwrap();
        assert!(n > 0, "{text}");
        text.push_str(&String::from_utf8_lossy(&buf[..n]));
    }
    let ctx = zmq::Context::new();
    let groot = client(&ctx, port);
    let tree = ask(&groot, &[header(b'T', 1)]);
    let status = ask(&groot, &[header(b'S', 2)]);
    assert!(child.wait().unwrap().success());
    (text, tree, status)
}

#[test]
fn a_simulated_run_is_served_as_it_runs_and_held_after_it() {
    let (text, tree, status) = simulated(&["run", "--task", "tower"]);
    let spec = planner::duplo::Task::Tower.spec();
    let nodes = planner::duplo::plan(planner::duplo::Task::Tower).unwrap().nodes;
    assert_eq!(tree[1], LogTree::new(&nodes, &spec).unwrap().xml().into_bytes(), "{text}");
    assert_eq!(status[1].len(), 3 * nodes.len());
    // The root succeeded: Success, as BehaviorTree.CPP shows it.
    assert_eq!(status[1][2], 2, "{text}");
    assert!(text.contains("1 tree served"), "{text}");
}

#[test]
fn each_expansion_of_a_scenario_is_a_new_tree_for_groot2() {
    let (text, tree, _) = simulated(&["scenario", "cube", "--world", "symbolic"]);
    // The goal alone, then each of the 7 expansions of the story.
    assert!(text.contains("8 trees served"), "{text}");
    let xml = String::from_utf8(tree[1].clone()).unwrap();
    assert_eq!(xml.matches("_uid=").count(), 37, "{xml}");
}

#[test]
fn a_tree_without_names_is_served_with_ids_and_the_bridge_says_so_once() {
    // BehaviorTree.CPP models this binary does not know, and an image without names.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/btcpp/fixtures/groot2/tree.xml");
    let text = std::fs::read_to_string(&path).unwrap();
    let imported = btcpp::xml::import_text(&path, &text, &btcpp::xml::ImportOptions::default()).unwrap();
    let image = bt_formats::Image::new(&imported.nodes).encode(imported.fingerprint()).unwrap();
    assert!(bt_core::image::section(&image, bt_core::image::SECTION_NAMES).unwrap().is_none());
    let (addr, controller) = link_common::controller::<64, _, _>(imported, Some(image), Moving(Arc::default()));
    let port = free_ports();
    let out = Command::new(env!("CARGO_BIN_EXE_sim-host"))
        .args(["groot2", "--tcp", &addr, "--listen", &format!("127.0.0.1:{port}"), "--start"])
        .args(["--period", "5", "--ticks", "20"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert_eq!(stderr.matches("note: ").count(), 1, "{stderr}");
    assert!(stderr.contains("shown as ids"), "{stderr}");
    controller.join().unwrap();
}
