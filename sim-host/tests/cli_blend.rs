//! `sim-host blend` through the real binary, against a controller running
//! `bt_link::serve` in this test with the symbolic cube world (the planner's STRIPS
//! semantics of `planner/domains/cube-sphere`) as its plant.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::{Path, PathBuf};
use std::sync::Arc;

use bt_core::{BehaviorSet, Context, Leaf, Node, NodeId, Status, TickError};
use bt_link::App;
use sim_host::physics::mobile::Agent;
use sim_host::scenario::agents::Acts as _;
use sim_host::scenario::cube::SymbolicCube;

mod cli_common;
mod groot2_common;
mod link_common;
use cli_common::sim_host;
use groot2_common::{ask, client, free_ports, header};

fn domain_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/domains/cube-sphere")
}

fn catalog() -> planner::PddlCatalog {
    planner::PddlCatalog::new(planner::domains::cube_sphere().unwrap().problem())
}

/// The symbolic cube world as a controller's plant: the sphere rolls into the path
/// the first time the robot holds the cube (Example 2), and the world steps after
/// every tick as the scenario's does.
struct Plant {
    world: SymbolicCube,
    blocked: bool,
}

impl Plant {
    fn new() -> Self {
        let mut world = SymbolicCube::new(Arc::new(planner::domains::cube_sphere().unwrap()));
        worlds::World::reset(&mut world);
        Self { world, blocked: false }
    }
}

impl BehaviorSet for Plant {
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        self.world.condition(leaf, ctx)
    }
    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        self.world.action(leaf, ctx)
    }
    fn halt(&mut self, leaf: &Leaf, node: NodeId) {
        self.world.halt(leaf, node);
    }
}

impl App for Plant {
    fn before_tick(&mut self, _: u32) {
        if !self.blocked && self.world.holding_cube() {
            self.blocked = self.world.apply(Agent::BlockPath);
        }
    }
    fn after_tick(&mut self, _: u32, _: Result<Status, TickError>, _: &[Node]) {
        worlds::World::step(&mut self.world);
    }
}

fn blend(addr: &str, extra: &[&str]) -> std::process::Output {
    let dir = domain_dir();
    let (d, p) = (dir.join("domain.pddl"), dir.join("problem.pddl"));
    let mut args = vec!["blend", "--domain", d.to_str().unwrap(), "--problem", p.to_str().unwrap(), "--tcp", addr];
    args.extend_from_slice(extra);
    sim_host(&args)
}

/// The `expand` and `swap` lines of a trace: (failed tick, swap tick named) and the
/// swap ticks the controller reported.
fn swaps(trace: &str) -> (Vec<u32>, Vec<u32>) {
    let named = trace
        .lines()
        .filter_map(|l| l.strip_prefix("expand "))
        .map(|l| l.split_once(" swap_at=").unwrap().1.parse().unwrap())
        .collect();
    let done = trace
        .lines()
        .filter_map(|l| l.strip_prefix("swap "))
        .map(|l| l.split(' ').next().unwrap().parse().unwrap())
        .collect();
    (named, done)
}

/// The conditions a narration expanded, in order.
fn expanded(narration: &str) -> Vec<&str> {
    narration
        .lines()
        .filter_map(|l| l.trim_start().strip_prefix("expansion "))
        .map(|l| l.split('`').nth(1).unwrap())
        .collect()
}

#[test]
fn the_tree_grows_from_the_goal_on_the_controller_into_example_2() {
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("blend.txt");
    let btlog = dir.path().join("blend.btlog");
    let (addr, handle) = link_common::controller::<64, _, _>(catalog(), None, Plant::new());
    let (t, b) = (trace.to_str().unwrap(), btlog.to_str().unwrap());
    let out = blend(&addr, &["--period", "1", "--lead", "2", "--trace", t, "--btlog", b]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}{}", String::from_utf8_lossy(&out.stderr));
    handle.join().unwrap();
    assert!(text.contains("the tree at the start (1 node):"), "{text}");
    assert_eq!(
        expanded(&text),
        [
            "at(cube, goal)",
            "holding(cube)",
            "near(cube)",
            "near(goal)",
            "path-free(goal)",
            "near(sphere)",
            "hand-empty"
        ]
    );
    assert!(text.contains("IncreasePriority moves the new subtree up a level"), "Fig. 4: {text}");
    assert!(text.contains("world: path-free(goal) does not hold"), "the block, seen in the reports: {text}");
    assert!(text.contains("the root succeeds: the goal holds"), "{text}");
    let recorded = std::fs::read_to_string(&trace).unwrap();
    let (named, done) = swaps(&recorded);
    // The trace starts with the goal-only tree; each grown tree swaps in at the tick
    // named, three ticks after the failure (`--lead 2`).
    assert!(recorded.starts_with("image 5a7b268c nodes=1\n"), "{recorded}");
    assert_eq!(done.len(), 7, "{recorded}");
    assert_eq!(done, named, "{recorded}");
    let failed: Vec<u32> = recorded
        .lines()
        .filter_map(|l| l.strip_prefix("expand "))
        .map(|l| l.split(' ').next().unwrap().parse().unwrap())
        .collect();
    assert!(failed.iter().zip(&named).all(|(f, n)| n - f == 3), "{failed:?} {named:?}");
    // The tree the controller ran last is the end of Example 2: the planner's tree for
    // the cube in the hand with the path blocked, grown at run time (Fig. 4, then on).
    let g = Arc::new(planner::domains::cube_sphere().unwrap());
    let c = Arc::new(planner::PddlCatalog::new(g.problem()));
    let mut p = planner::plan(g.clone(), c.clone(), planner::Options::default()).unwrap();
    let changes = planner::parse_changes(&g, "holding(cube), not hand-empty, not path-free(goal)").unwrap();
    planner::expand_at(&mut p.planner, c.as_ref(), &changes, 1000).unwrap();
    let image = bt_formats::Image::new(p.planner.nodes()).encode(bt_core::Catalog::fingerprint(c.as_ref())).unwrap();
    // One Groot2 replay log per tree the controller ran, each with the tree's changes.
    for n in 1..=8 {
        let file = if n == 1 { btlog.clone() } else { dir.path().join(format!("blend-{n}.btlog")) };
        let log = btcpp::btlog::Log::parse(&std::fs::read(&file).unwrap()).unwrap();
        assert!(!log.transitions.is_empty(), "{}", file.display());
    }
    assert!(!dir.path().join("blend-9.btlog").exists());
    let last = recorded.lines().rfind(|l| l.starts_with("swap ")).unwrap();
    assert!(last.contains(&format!("image={:08x} nodes=37", bt_link::image_crc(&image))), "{last}");
}

#[test]
fn the_same_reports_give_the_same_session_whatever_the_timing() {
    // Ticks back to back with no lead, and every 3 ms with a lead of 5: the controller
    // waits for the host, or runs ahead of it; the trees and ticks stay the same apart
    // from when each swap is named.
    let dir = tempfile::tempdir().unwrap();
    let mut traces = Vec::new();
    for (period, lead) in [("0", "0"), ("0", "0"), ("3", "5")] {
        let trace = dir.path().join(format!("{period}-{lead}.txt"));
        let (addr, handle) = link_common::controller::<64, _, _>(catalog(), None, Plant::new());
        let out = blend(&addr, &["--period", period, "--lead", lead, "--trace", trace.to_str().unwrap()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        handle.join().unwrap();
        let t = std::fs::read_to_string(&trace).unwrap();
        // The tick's duration on the controller is the only measured figure.
        traces.push(t.lines().map(|l| l.split(" us=").next().unwrap().to_string()).collect::<Vec<_>>().join("\n"));
    }
    assert_eq!(traces[0], traces[1], "the same settings, the same session");
    // `expand TICK CONDITION nodes=N image=...`: the condition and the tree's size.
    let nodes = |t: &str| {
        t.lines()
            .filter_map(|l| l.strip_prefix("expand "))
            .map(|l| l.split(" image=").next().unwrap().split_once(' ').unwrap().1.to_string())
            .collect::<Vec<_>>()
    };
    assert_eq!(nodes(&traces[0]), nodes(&traces[2]), "the same expansions with another lead");
}

#[test]
fn a_given_tree_grows_from_where_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let (d, p) = (domain_dir().join("domain.pddl"), domain_dir().join("problem.pddl"));
    let tree = dir.path().join("fig3e.bt");
    let out = sim_host(&[
        "plan",
        "--domain",
        d.to_str().unwrap(),
        "--problem",
        p.to_str().unwrap(),
        "--format",
        "image",
        "--out",
        tree.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (addr, handle) = link_common::controller::<64, _, _>(catalog(), None, Plant::new());
    let out = blend(&addr, &["--period", "0", "--lead", "1", "--tree", tree.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}{}", String::from_utf8_lossy(&out.stderr));
    handle.join().unwrap();
    assert!(text.contains("the tree at the start (19 nodes):"), "Fig. 3(e): {text}");
    // Fig. 3(e) already achieves the cube's conditions: only the blocked path and what
    // clearing it needs are expanded.
    assert_eq!(expanded(&text), ["path-free(goal)", "near(sphere)", "hand-empty"], "{text}");
}

/// A world where nothing holds and nothing can be done.
struct Nothing;

impl BehaviorSet for Nothing {
    fn condition(&mut self, _: &Leaf, _: Context<'_>) -> Status {
        Status::Failure
    }
    fn action(&mut self, _: &Leaf, _: Context<'_>) -> Status {
        Status::Failure
    }
    fn halt(&mut self, _: &Leaf, _: NodeId) {}
}

impl App for Nothing {}

#[test]
fn a_condition_that_cannot_be_expanded_ends_with_exit_2_and_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("domain.pddl");
    let p = dir.path().join("problem.pddl");
    std::fs::write(
        &d,
        "(define (domain stuck) (:predicates (done) (ready)) (:action finish :precondition (ready) :effect (and (done) (not (ready)))))",
    )
    .unwrap();
    std::fs::write(&p, "(define (problem stuck-1) (:domain stuck) (:init (ready)) (:goal (done)))").unwrap();
    let g = planner::pddl::read_domain("d", &std::fs::read_to_string(&d).unwrap()).unwrap().0;
    let problem = planner::pddl::read_problem("p", &std::fs::read_to_string(&p).unwrap(), &g).unwrap().0;
    let (addr, handle) = link_common::controller::<16, _, _>(planner::PddlCatalog::new(&problem), None, Nothing);
    let trace = dir.path().join("t.txt");
    let out = sim_host(&[
        "blend",
        "--domain",
        d.to_str().unwrap(),
        "--problem",
        p.to_str().unwrap(),
        "--tcp",
        &addr,
        "--period",
        "0",
        "--trace",
        trace.to_str().unwrap(),
    ]);
    handle.join().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(2), "{text}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("the planner cannot expand the tree") && err.contains("ready"), "{err}");
    assert!(text.contains("expansion 1: `done`"), "{text}");
    // The trace is written all the same, up to the stop.
    let recorded = std::fs::read_to_string(&trace).unwrap();
    assert!(recorded.lines().last().unwrap().starts_with("stop "), "{recorded}");
}

#[test]
fn a_controller_of_another_behavior_set_is_refused_before_anything_is_sent() {
    let tower = planner::duplo::Task::Tower.spec();
    let (addr, handle) = link_common::controller::<64, _, _>(tower, None, Nothing);
    let out = blend(&addr, &[]);
    handle.join().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("runs behavior set") && err.contains("problem.pddl has 0x133dc6ffb352d15f"), "{err}");
}

#[test]
fn the_ticks_given_end_the_session_at_that_tick() {
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("t.txt");
    let (addr, handle) = link_common::controller::<64, _, _>(catalog(), None, Plant::new());
    let out = blend(&addr, &["--period", "0", "--lead", "2", "--ticks", "7", "--trace", trace.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}{}", String::from_utf8_lossy(&out.stderr));
    handle.join().unwrap();
    assert!(text.contains("the ticks given ran out"), "{text}");
    let recorded = std::fs::read_to_string(&trace).unwrap();
    let ticks: Vec<&str> = recorded.lines().filter(|l| l.starts_with("tick ")).collect();
    assert_eq!(ticks.len(), 7, "{recorded}");
    assert!(recorded.lines().last().unwrap().starts_with("stop 7 "), "{recorded}");
}

#[test]
fn a_grown_tree_larger_than_the_controller_holds_ends_with_exit_2_and_the_sizes() {
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("t.txt");
    // Images of at most 100 bytes: Fig. 4's tree (116 bytes) does not fit.
    let (addr, handle) = link_common::controller_of::<64, 100, _, _>(catalog(), None, Plant::new());
    let out = blend(&addr, &["--period", "0", "--lead", "1", "--trace", trace.to_str().unwrap()]);
    handle.join().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(2), "{text}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(
            "the grown tree: the tree has 25 nodes, an image of 116 bytes; the controller holds images of at most 100"
        ),
        "{err}"
    );
    let recorded = std::fs::read_to_string(&trace).unwrap();
    assert!(recorded.lines().last().unwrap().starts_with("stop "), "the controller was stopped: {recorded}");
}

#[test]
fn groot2_is_served_each_grown_tree_under_a_new_uuid() {
    let (addr, handle) = link_common::controller::<64, _, _>(catalog(), None, Plant::new());
    let port = free_ports();
    let dir = domain_dir();
    let (d, p) = (dir.join("domain.pddl"), dir.join("problem.pddl"));
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_sim-host"))
        .args(["blend", "--domain", d.to_str().unwrap(), "--problem", p.to_str().unwrap(), "--tcp", &addr])
        .args(["--period", "5", "--lead", "2", "--groot2", &format!("127.0.0.1:{port}"), "--groot2-linger", "2"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Groot2's place: FULLTREE again and again while the tree grows, then while the
    // bridge holds the last state.
    let ctx = zmq::Context::new();
    let groot = client(&ctx, port);
    let mut uuids: Vec<Vec<u8>> = Vec::new();
    let mut last: Vec<Vec<u8>> = Vec::new();
    let started = std::time::Instant::now();
    // Until the tree of Example 2's end (37 nodes) is served; the bridge holds it 2 s
    // after the session ends.
    while String::from_utf8_lossy(last.get(1).map_or(&[][..], Vec::as_slice)).matches(" _uid=").count() < 37 {
        assert!(started.elapsed().as_secs() < 30, "{} trees seen", uuids.len());
        let tree = ask(&groot, &[header(b'T', uuids.len() as u32)]);
        if uuids.last() != Some(&tree[0][6..].to_vec()) {
            uuids.push(tree[0][6..].to_vec());
        }
        last = tree;
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let status = ask(&groot, &[header(b'S', 1000)]);
    let out = child.wait_with_output().unwrap();
    handle.join().unwrap();
    let (text, err) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "{text}{err}");
    assert!(err.contains("Groot2: the run is over (8 trees served)"), "the goal and 7 grown trees: {err}");
    assert!(uuids.len() >= 2, "the tree was seen to grow: {} UUIDs", uuids.len());
    let mut distinct = uuids.clone();
    distinct.sort();
    distinct.dedup();
    assert_eq!(distinct.len(), uuids.len(), "each tree its own UUID");
    // The last tree served is the grown one: a node a `_uid`, 3 status bytes a node.
    let nodes: usize = text.split(" the tree has ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    assert_eq!(
        String::from_utf8_lossy(&last[1]).matches(" _uid=").count(),
        nodes,
        "{}",
        String::from_utf8_lossy(&last[1])
    );
    assert_eq!(status[1].len(), 3 * nodes);
}
