//! `sim-host plan`, and `inspect`/`export` on planner images, through the real binary.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod cli_common;
use cli_common::sim_host;

fn domains() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/domains")
}

#[test]
fn plans_pddl_and_says_whether_the_tree_reaches_the_goal() {
    let d = domains().join("cube-sphere/domain.pddl");
    let p = domains().join("cube-sphere/problem-blocked.pddl");
    let out = sim_host(&["plan", "--domain", d.to_str().unwrap(), "--problem", p.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("--> clear-path(sphere, goal)"), "{text}");
    assert!(text.contains("moved the new subtree up a level"), "{text}");
    assert!(text.contains("symbolic world: the tree reaches the goal in 7 ticks"), "{text}");
}

#[test]
fn image_round_trips_through_inspect_and_export() {
    let dir = tempfile::tempdir().unwrap();
    let img = dir.path().join("cube.bt");
    let d = domains().join("cube-sphere/domain.pddl");
    let p = domains().join("cube-sphere/problem.pddl");
    let args = ["plan", "--domain", d.to_str().unwrap(), "--problem", p.to_str().unwrap(), "--format", "image"];
    let out = sim_host(&[&args[..], &["--out", img.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let out = sim_host(&["inspect", img.to_str().unwrap()]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("PDDL problem `cube-to-goal` of domain `cube-sphere` (names from the image)"), "{text}");
    assert!(text.contains("--> place(cube, goal)"), "{text}");
    let out = sim_host(&["export", img.to_str().unwrap(), "--format", "xml"]);
    let xml = String::from_utf8(out.stdout).unwrap();
    assert!(xml.contains("<place _uid=\"") && xml.contains("\" i=\"cube\" s=\"goal\"/>"), "{xml}");
    assert!(xml.contains("<Action ID=\"place\">"), "{xml}");
    let out = sim_host(&["export", img.to_str().unwrap(), "--format", "dot"]);
    assert!(String::from_utf8(out.stdout).unwrap().starts_with("digraph bt {"));
}

#[test]
fn brick_tasks_and_errors() {
    let out = sim_host(&["plan", "--task", "tower", "--format", "tokens"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("s( f( 0 at pos (0.0, 0.05, 0.0)? "), "{text}");
    assert!(String::from_utf8(out.stderr).unwrap().contains("sim-host run"));

    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.pddl");
    std::fs::write(
        &bad,
        "(define (domain x) (:predicates (p))\n  (:action a :parameters () :precondition (q) :effect (p)))",
    )
    .unwrap();
    let out = sim_host(&["plan", "--domain", bad.to_str().unwrap(), "--problem", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.ends_with(":2:44: unknown predicate `q` (declared: p)\n"), "{err}");
    assert_eq!(err.lines().count(), 1);

    let target = dir.path().join("never.bt");
    let out = sim_host(&[
        "plan",
        "--domain",
        bad.to_str().unwrap(),
        "--problem",
        bad.to_str().unwrap(),
        "--out",
        target.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!target.exists());
}

#[test]
fn leaves_with_more_than_three_arguments_go_into_the_image_and_back() {
    // IPC 2006 storage: `drop` has five parameters, `lift` five, `move` four.
    let ipc = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/tests/fixtures/ipc/storage");
    let (d, p) = (ipc.join("domain.pddl"), ipc.join("p01.pddl"));
    let dir = tempfile::tempdir().unwrap();
    let img = dir.path().join("storage.bt");
    let args = ["plan", "--domain", d.to_str().unwrap(), "--problem", p.to_str().unwrap(), "--format", "image"];
    let out = sim_host(&[&args[..], &["--out", img.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("the tree reaches the goal"));
    let out = sim_host(&["inspect", img.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("--> drop(hoist0, crate0, "), "{text}");
    let out =
        sim_host(&["plan", "--domain", d.to_str().unwrap(), "--problem", p.to_str().unwrap(), "--format", "tokens"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("--format tokens cannot write leaves with more than 3 arguments"), "{err}");
}

#[test]
fn a_planned_tree_deeper_than_64_levels_loads_in_inspect_and_export() {
    // A 40-cell corridor: each step backchains two levels deeper.
    let dir = tempfile::tempdir().unwrap();
    let (d, p, img) = (dir.path().join("d.pddl"), dir.path().join("p.pddl"), dir.path().join("c.bt"));
    std::fs::write(
        &d,
        "(define (domain corridor) (:requirements :strips) (:predicates (at ?c) (adj ?a ?b))
           (:action move :parameters (?a ?b) :precondition (and (at ?a) (adj ?a ?b))
              :effect (and (at ?b) (not (at ?a)))))",
    )
    .unwrap();
    let cells: Vec<String> = (0..40).map(|i| format!("c{i}")).collect();
    let adj: Vec<String> = (0..39).map(|i| format!("(adj c{i} c{})", i + 1)).collect();
    let problem = format!(
        "(define (problem walk) (:domain corridor) (:objects {}) (:init (at c0) {}) (:goal (at c39)))",
        cells.join(" "),
        adj.join(" ")
    );
    std::fs::write(&p, problem).unwrap();
    let args = ["plan", "--domain", d.to_str().unwrap(), "--problem", p.to_str().unwrap(), "--format", "image"];
    let out = sim_host(&[&args[..], &["--out", img.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let out = sim_host(&["inspect", img.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("nodes      157 (depth 79)"), "{text}");
    let out = sim_host(&["export", img.to_str().unwrap(), "--format", "dot"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn the_summary_says_which_method_made_the_tree_and_why_others_gave_up() {
    // The Sussman anomaly: Algorithm 1 oscillates, the search's plan makes the tree.
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("sussman.pddl");
    std::fs::write(
        &p,
        "(define (problem sussman) (:domain blocks) (:objects a b c - block)
           (:init (on c a) (on-table a) (on-table b) (clear c) (clear b) (hand-empty))
           (:goal (and (on a b) (on b c))))",
    )
    .unwrap();
    let d = domains().join("blocks/domain.pddl");
    let out = sim_host(&["plan", "--domain", d.to_str().unwrap(), "--problem", p.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("algorithm-1 gave up: the tree oscillates, repeating"), "{text}");
    assert!(text.contains("made by "), "{text}");
    assert!(text.contains("the tree reaches the goal in"), "{text}");
}

#[test]
fn one_tick_is_singular() {
    let dir = tempfile::tempdir().unwrap();
    let d = domains().join("cube-sphere/domain.pddl");
    // The goal holds at the start: the tree reaches it on its first tick.
    let text = std::fs::read_to_string(domains().join("cube-sphere/problem.pddl"))
        .unwrap()
        .replace("(:goal (and (at cube goal)))", "(:goal (and (hand-empty)))");
    let p = dir.path().join("p.pddl");
    std::fs::write(&p, text).unwrap();
    let out = sim_host(&["plan", "--domain", d.to_str().unwrap(), "--problem", p.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("planned: 0 expansions, 1 node\n"), "{text}");
    assert!(text.contains("symbolic world: the tree reaches the goal in 1 tick from the initial state"), "{text}");
}

#[test]
fn max_bytes_cuts_the_closure_to_fit_and_refuses_what_cannot_fit() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/tests/fixtures/ipc/blocks");
    let (d, p) = (dir.join("domain.pddl"), dir.join("probBLOCKS-4-0.pddl"));
    let tmp = tempfile::tempdir().unwrap();
    let image = tmp.path().join("tree.bt");
    let run = |extra: &[&str]| {
        let args = ["plan", "--domain", d.to_str().unwrap(), "--problem", p.to_str().unwrap()];
        let out = sim_host(&[&args[..], &["--format", "image", "--out", image.to_str().unwrap()], extra].concat());
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let (code, text, err) = run(&[]);
    assert_eq!(code, Some(0), "{err}");
    let whole = std::fs::metadata(&image).unwrap().len();
    assert!(text.contains("image ") && text.contains(" bytes, "), "{text}");
    std::fs::remove_file(&image).unwrap();
    // Half the bytes: the closure is cut; the image without names fits.
    let (code, text, err) = run(&["--max-bytes", "500"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(text.contains("the closure over disturbances cut to") || text.contains("left out to fit"), "{text}");
    let bare = bt_formats::image::strip_names(&std::fs::read(&image).unwrap()).unwrap();
    assert!(bare.len() <= 500 && (bare.len() as u64) < whole, "{} {whole}", bare.len());
    std::fs::remove_file(&image).unwrap();
    // Too few for even the plain tree: an error naming the sizes, and nothing written.
    let (code, _, err) = run(&["--max-bytes", "60"]);
    assert_ne!(code, Some(0));
    assert!(err.contains("does not fit even without its closure") && err.contains("60 bytes"), "{err}");
    assert!(!image.exists());
    let (code, _, err) = run(&["--timeout", "0"]);
    assert_ne!(code, Some(0));
    assert!(err.contains("--timeout must be a number of seconds above 0"), "{err}");
}
