//! `sim-host run` through the real binary: good trees from tokens and images, and every
//! bad input as one line and exit code 2, with no partial output file.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::{Path, PathBuf};
use std::process::Output;

use bt_core::{Catalog, encode, image::max_image_len};
use planner::duplo::Task;

mod cli_common;
use cli_common::sim_host;

#[path = "fixtures/planner_trees.rs"]
mod planner_trees;

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn image(task: Task, text: &str) -> Vec<u8> {
    let spec = task.spec();
    let nodes = bt_formats::tokens::parse(text, &spec).unwrap();
    let mut buf = vec![0u8; max_image_len(nodes.len())];
    let len = encode(&nodes, spec.fingerprint(), &mut buf).unwrap();
    buf.truncate(len);
    buf
}

fn stdout(out: &Output) -> String {
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// Asserts a one-line error containing every one of `parts`, exit 2, nothing on stdout.
fn assert_error(out: &Output, parts: &[&str]) {
    assert_eq!(out.status.code(), Some(2), "stdout: {}", String::from_utf8_lossy(&out.stdout));
    let err = String::from_utf8(out.stderr.clone()).unwrap();
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("error: "), "{err}");
    for p in parts {
        assert!(err.contains(p), "`{p}` in: {err}");
    }
    assert!(out.stdout.is_empty(), "nothing printed on failure");
}

fn fitness_line(text: &str) -> &str {
    let lines: Vec<&str> = text.lines().filter(|l| l.starts_with("fitness")).collect();
    assert_eq!(lines.len(), 1, "{text}");
    lines[0]
}

#[test]
fn runs_the_planners_tower_from_tokens_and_from_an_image() {
    let dir = tempfile::tempdir().unwrap();
    let tokens = write(dir.path(), "tower.txt", planner_trees::TOWER.as_bytes());
    let text =
        stdout(&sim_host(&["run", "--task", "tower", "--world", "symbolic", "--tree", tokens.to_str().unwrap()]));
    assert_eq!(
        fitness_line(&text),
        "fitness  -3.000  length 3.000  distance 0.000  failure 0.000  timeout 0.000  held 0.000"
    );
    assert!(text.contains("outcome  Success"), "{text}");
    assert!(text.contains("30 nodes"), "{text}");
    assert!(text.contains("--> apply force 2!"), "the tree is printed: {text}");
    assert!(text.contains("brick 2  at ( 0.0000,  0.0500,  0.0384)  goal ( 0.0000,  0.0500,  0.0384)"), "{text}");

    let img = write(dir.path(), "tower.bt", &image(Task::Tower, planner_trees::TOWER));
    let from_image = stdout(&sim_host(&["run", "--task", "tower", "--tree", img.to_str().unwrap()]));
    assert_eq!(fitness_line(&from_image), fitness_line(&text));
}

#[test]
fn prints_each_fitness_term_of_a_failing_tree() {
    let dir = tempfile::tempdir().unwrap();
    let tree = write(dir.path(), "croissant.txt", planner_trees::CROISSANT.as_bytes());
    let text = stdout(&sim_host(&["run", "--task", "croissant", "--tree", tree.to_str().unwrap()]));
    let line = fitness_line(&text);
    assert!(line.starts_with("fitness  -294.868  length 3.300  distance 241.568  failure 50.000"), "{line}");
    assert!(text.contains("held     brick 2"), "{text}");
}

#[test]
fn draws_the_episode_as_svg() {
    let dir = tempfile::tempdir().unwrap();
    let tree = write(dir.path(), "blocking.txt", planner_trees::BLOCKING.as_bytes());
    let svg = dir.path().join("run.svg");
    let text = stdout(&sim_host(&[
        "run",
        "--task",
        "blocking",
        "--tree",
        tree.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
    ]));
    assert!(text.contains(&format!("picture  {}", svg.display())), "{text}");
    let doc = std::fs::read_to_string(&svg).unwrap();
    assert!(doc.starts_with("<svg ") && doc.trim_end().ends_with("</svg>"));
    assert!(doc.contains("blocking task, symbolic world"));
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        let plain = write(dir.path(), "plain.txt", b"x");
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&svg), mode(&plain), "the picture gets a new file's usual permissions");
    }
}

#[test]
fn bad_arguments_are_one_line_and_exit_2() {
    let out = sim_host(&["run", "--task", "towr", "--tree", "x"]);
    assert_error(&out, &["unknown task `towr`", "tower, croissant, balance, blocking"]);
    let out = sim_host(&["run", "--task", "tower", "--world", "gazebo", "--tree", "x"]);
    assert_error(&out, &["gazebo", "symbolic, physics"]);
    assert_error(&sim_host(&["run", "--tree", "x"]), &["--task"]);
}

#[test]
fn the_planners_tree_is_the_default_and_solves_only_the_tower() {
    // Styrud et al.: the planner's tree alone solves the tower and fails the other three.
    for (task, solved) in [("tower", true), ("croissant", false), ("balance", false), ("blocking", false)] {
        let out = sim_host(&["run", "--task", task]);
        assert!(out.status.success(), "{task}: {}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(text.contains("the planner's tree"), "{text}");
        let fitness: f64 = text
            .lines()
            .find_map(|l| l.strip_prefix("fitness"))
            .and_then(|l| l.split_whitespace().next())
            .unwrap()
            .parse()
            .unwrap();
        if solved {
            assert!(text.contains("outcome  Success"), "{text}");
            assert!(fitness > -5.0, "{task}: {fitness}");
        } else {
            assert!(!text.contains("outcome  Success"), "{task}: {text}");
            assert!(fitness < -15.0, "{task}: {fitness}");
        }
    }
}

#[test]
fn the_physics_world_builds_the_tower_with_the_planners_tree() {
    let out = sim_host(&["run", "--task", "tower", "--world", "physics"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("tower (default mode), physics world"), "{text}");
    assert!(text.contains("outcome  Success"), "{text}");
}

#[test]
fn bad_tree_files_are_one_line_and_exit_2_and_leave_no_picture() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("out.svg");
    let run = |tree: &Path, task: &str| {
        sim_host(&["run", "--task", task, "--tree", tree.to_str().unwrap(), "--svg", svg.to_str().unwrap()])
    };
    // Unreadable.
    let absent = dir.path().join("absent.txt");
    assert_error(&run(&absent, "tower"), &["cannot read", "absent.txt"]);
    // Bad tokens: the column of the fault.
    let bad = write(dir.path(), "bad.txt", b"s( pick 0! pick 9! )");
    assert_error(&run(&bad, "tower"), &["bad.txt:1:12: unknown behavior `pick 9!`"]);
    let unclosed = write(dir.path(), "unclosed.txt", b"s( pick 0!");
    assert_error(&run(&unclosed, "tower"), &["unclosed.txt", "not closed"]);
    // Neither image nor text.
    let binary = write(dir.path(), "binary.bt", &[0xff, 0xfe, 0x00, 0x01]);
    assert_error(&run(&binary, "tower"), &["binary.bt:1:1: not UTF-8", "neither a tree image"]);
    // A corrupted image.
    let mut bytes = image(Task::Tower, planner_trees::TOWER);
    bytes[20] ^= 0xff;
    let corrupt = write(dir.path(), "corrupt.bt", &bytes);
    assert_error(&run(&corrupt, "tower"), &["corrupt.bt", "CRC-32"]);
    // An image of another task's behaviors.
    let croissant = write(dir.path(), "croissant.bt", &image(Task::Croissant, planner_trees::CROISSANT));
    assert_error(&run(&croissant, "tower"), &["croissant.bt", "croissant task"]);
    // A truncated image.
    let whole = image(Task::Tower, planner_trees::TOWER);
    let short = write(dir.path(), "short.bt", &whole[..10]);
    assert_error(&run(&short, "tower"), &["short.bt", "truncated"]);
    assert!(!svg.exists(), "no picture from a failed run");
}

#[test]
fn an_unwritable_picture_is_an_error_and_prints_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let tree = write(dir.path(), "t.txt", planner_trees::TOWER.as_bytes());
    let target = dir.path().join("no-such-dir").join("p.svg");
    let out =
        sim_host(&["run", "--task", "tower", "--tree", tree.to_str().unwrap(), "--svg", target.to_str().unwrap()]);
    assert_error(&out, &["no-such-dir"]);
    assert!(!target.exists());
}

#[test]
fn help_explains_tasks_worlds_and_fitness() {
    let text = stdout(&sim_host(&["run", "--help"]));
    for word in ["tower", "croissant", "balance", "blocking", "symbolic", "physics", "Fitness", "BTIM", "s( f("] {
        assert!(text.contains(word), "`{word}` in --help: {text}");
    }
}
