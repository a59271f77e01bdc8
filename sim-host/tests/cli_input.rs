//! What the CLI reads, through the real binary: size limits on every input, text that
//! is not UTF-8, token-text errors with line and column, images of other behavior sets,
//! and trees at the limits (the deepest and the largest).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::{Path, PathBuf};
use std::process::Output;

use bt_core::{Catalog, encode, image::max_image_len};
use planner::duplo::Task;

mod cli_common;
use cli_common::sim_host;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// One line, `error: `, exit 2, every part in it; returns the line.
fn assert_error(out: &Output, parts: &[&str]) -> String {
    let err = String::from_utf8(out.stderr.clone()).unwrap();
    assert_eq!(out.status.code(), Some(2), "stderr: {err}");
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("error: "), "{err}");
    for p in parts {
        assert!(err.contains(p), "`{p}` in: {err}");
    }
    err
}

fn image(task: Task, nodes: &[bt_core::Node]) -> Vec<u8> {
    let spec = task.spec();
    let mut buf = vec![0u8; max_image_len(nodes.len())];
    let len = encode(nodes, spec.fingerprint(), &mut buf).unwrap();
    buf.truncate(len);
    buf
}

fn domain() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/domains/cube-sphere/domain.pddl")
}

#[test]
fn endless_inputs_stop_at_their_limit_naming_it_and_the_file() {
    let out = sim_host(&["plan", "--domain", "/dev/zero", "--problem", "/dev/zero"]);
    assert_error(&out, &["/dev/zero: larger than 64 MiB, the most a PDDL file may be"]);
    let out = sim_host(&["plan", "--domain", s(&domain()), "--problem", "/dev/zero"]);
    assert_error(&out, &["/dev/zero", "64 MiB"]);
    let out = sim_host(&["inspect", "/dev/zero"]);
    assert_error(&out, &["/dev/zero: larger than 18,087,957 bytes, the most a tree image may be"]);
    let out = sim_host(&["export", "/dev/zero"]);
    assert_error(&out, &["/dev/zero", "18,087,957 bytes"]);
    let out = sim_host(&["run", "--task", "tower", "--tree", "/dev/zero"]);
    assert_error(&out, &["/dev/zero: larger than 64 MiB, the most a tree file may be"]);
    let out = sim_host(&["btlog", "--from-trace", "x.txt", "--image", "/dev/zero", "--out", "x.btlog"]);
    assert_error(&out, &["/dev/zero: larger than 18,087,957 bytes, the most a tree image may be"]);
    let out = sim_host(&["import", "/dev/zero", "--format", "ascii"]);
    assert_error(&out, &["cannot read /dev/zero: larger than 64 MiB, the most an XML file may be"]);
    let out = sim_host(&["catalog", "/dev/zero"]);
    assert_error(&out, &["cannot read /dev/zero: larger than 64 MiB"]);
    let dir = tempfile::tempdir().unwrap();
    let tower = write(dir.path(), "tower.bt", &image(Task::Tower, &planner::duplo::plan(Task::Tower).unwrap().nodes));
    let out = sim_host(&["btlog", "--from-trace", "/dev/zero", "--image", s(&tower), "--out", "x.btlog"]);
    assert_error(&out, &["/dev/zero: larger than 64 MiB, the most a controller trace may be"]);
    let out = sim_host(&["deploy", "/dev/zero", "--tcp", "127.0.0.1:9"]);
    assert_error(&out, &["/dev/zero: larger than 18,087,957 bytes, the most a tree image may be"]);
}

#[test]
fn an_oversized_file_is_refused_by_its_size() {
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.bt");
    let f = std::fs::File::create(&big).unwrap();
    f.set_len(20_000_000).unwrap(); // sparse: nothing to read
    let out = sim_host(&["inspect", s(&big)]);
    assert_error(&out, &["big.bt: larger than 18,087,957 bytes"]);
    // An image inside a tree file is held to the image's limit.
    let mut bytes = bt_core::image::MAGIC.to_vec();
    bytes.resize(19_000_000, 0);
    let fake = write(dir.path(), "fake.bt", &bytes);
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&fake)]);
    assert_error(&out, &["fake.bt: larger than 18,087,957 bytes, the most a tree image may be"]);
}

#[test]
fn text_that_is_not_utf8_gives_line_column_and_byte_offset() {
    let dir = tempfile::tempdir().unwrap();
    let problem = write(dir.path(), "p.pddl", b"(define (problem p)\n  (:domain cube-sphere) ; caf\xe9\n)");
    let out = sim_host(&["plan", "--domain", s(&domain()), "--problem", s(&problem)]);
    assert_error(&out, &["p.pddl:2:30: not UTF-8 (byte offset 49: 0xe9)"]);
    let tree = write(dir.path(), "t.txt", b"s( pick 0!\n   \xff )");
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&tree)]);
    assert_error(&out, &["t.txt:2:4: not UTF-8 (byte offset 14: 0xff)", "neither a tree image"]);
}

#[test]
fn token_errors_give_line_and_column_and_quote_briefly() {
    let dir = tempfile::tempdir().unwrap();
    let tree = write(dir.path(), "t.txt", b"s(\n  f( picked 0? pick 0! )\n  pick 9!\n)\n");
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&tree)]);
    assert_error(&out, &[&format!("{}:3:3: unknown behavior `pick 9!`", tree.display())]);
    let open = write(dir.path(), "open.txt", b"s( pick 0!\n");
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&open)]);
    assert_error(&out, &["open.txt:2:1: the text ends with 1 control node not closed"]);
    // A huge name: quoted briefly, and the error line stays short.
    let mut huge = b"s( ".to_vec();
    huge.extend(std::iter::repeat_n(b'x', 5_000_000));
    huge.extend(b"! )");
    let huge = write(dir.path(), "huge.txt", &huge);
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&huge)]);
    let err = assert_error(&out, &["huge.txt:1:4: unknown behavior `xxx", "(5000001 characters)"]);
    assert!(err.len() < 300, "{} bytes", err.len());
    // Control bytes in a name are escaped, not printed.
    let nul = write(dir.path(), "nul.txt", b"s( pick\x00\x1b[31m 0! )");
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&nul)]);
    let err = assert_error(&out, &["unknown behavior `pick\\0\\u{1b}[31m 0!`"]);
    assert!(!err.contains('\0') && !err.contains('\u{1b}'), "{err:?}");
}

#[test]
fn an_image_of_another_task_names_that_task() {
    let dir = tempfile::tempdir().unwrap();
    let spec = Task::Croissant.spec();
    let nodes = bt_formats::tokens::parse("s( pick 0! )", &spec).unwrap();
    let img = write(dir.path(), "c.bt", &image(Task::Croissant, &nodes));
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&img)]);
    assert_error(
        &out,
        &["c.bt: an image for the croissant task's behaviors, not the tower task's; run it with --task croissant"],
    );
    // A PDDL domain's image: named, and `run` says what it plays.
    let plan = dir.path().join("cube.bt");
    let out = sim_host(&[
        "plan",
        "--domain",
        s(&domain()),
        "--problem",
        s(&domain().with_file_name("problem.pddl")),
        "--format",
        "image",
        "--out",
        s(&plan),
    ]);
    assert!(out.status.success());
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&plan)]);
    assert_error(&out, &["an image for PDDL domain `cube-sphere`", "brick tasks only"]);
}

#[test]
fn tokens_that_cannot_express_the_plan_keep_the_summary() {
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/domains/cellphone");
    let out = sim_host(&[
        "plan",
        "--domain",
        s(&d.join("domain.pddl")),
        "--problem",
        s(&d.join("problem.pddl")),
        "--format",
        "tokens",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.starts_with("planned: 12 expansions, 104 nodes\n"), "{err}");
    assert!(err.contains("symbolic world: the tree reaches the goal in 13 ticks"), "{err}");
    let last = err.lines().last().unwrap();
    assert_eq!(
        last,
        "error: --format tokens: the token notation cannot express this tree: node 16 is an Inverter; it has \
         only s( f( ) and leaves; write it with --format ascii, dot, xml or image"
    );
}

/// `levels` nested Sequences around one action: a tree of `levels + 1` levels.
fn nested(levels: usize) -> String {
    format!("{}pick 0!{}", "s( ".repeat(levels), " )".repeat(levels))
}

#[test]
fn trees_as_deep_as_the_planner_makes_load_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let spec = Task::Tower.spec();
    let deepest = planner::DEPTH;
    assert_eq!(deepest, 128);
    let text = nested(deepest - 1);
    let tokens = write(dir.path(), "deep.txt", text.as_bytes());
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&tokens)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8(out.stdout).unwrap().contains("128 nodes, depth 128"));
    let img = write(dir.path(), "deep.bt", &image(Task::Tower, &bt_formats::tokens::parse(&text, &spec).unwrap()));
    let out = sim_host(&["inspect", s(&img)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8(out.stdout).unwrap().contains("nodes      128 (depth 128)"));
    let out = sim_host(&["export", s(&img), "--format", "tokens"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));

    // One level more: refused by every loader, naming the limit.
    let text = nested(deepest);
    let tokens = write(dir.path(), "deeper.txt", text.as_bytes());
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&tokens)]);
    assert_error(&out, &["deeper.txt", "limit of 128 levels"]);
    let img = write(dir.path(), "deeper.bt", &image(Task::Tower, &bt_formats::tokens::parse(&text, &spec).unwrap()));
    let out = sim_host(&["inspect", s(&img)]);
    assert_error(&out, &["deeper.bt", "limit of 128 levels"]);
}

#[test]
fn the_largest_tree_a_u16_count_allows_loads() {
    let dir = tempfile::tempdir().unwrap();
    let spec = Task::Tower.spec();
    let most = usize::from(u16::MAX);
    // The condition fails at once: one tick however many leaves follow.
    let text = format!("s( picked 0? {})", "pick 0! ".repeat(most - 2));
    let tokens = write(dir.path(), "big.txt", text.as_bytes());
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&tokens)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8(out.stdout).unwrap().contains("65535 nodes, depth 2"));
    let img = write(dir.path(), "big.bt", &image(Task::Tower, &bt_formats::tokens::parse(&text, &spec).unwrap()));
    let out = sim_host(&["inspect", s(&img)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8(out.stdout).unwrap().contains("nodes      65535 (depth 2)"));
    // One more node: refused, saying where.
    let over = format!("s( picked 0? {})", "pick 0! ".repeat(most - 1));
    let tokens = write(dir.path(), "over.txt", over.as_bytes());
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&tokens)]);
    assert_error(&out, &["over.txt:1:", "more than 65535 nodes, the most a tree holds"]);
}

#[test]
fn an_ascii_tree_given_as_tokens_is_one_line() {
    // A leaf name ran to the first `?` or `!` across lines: the error echoed the tree.
    let dir = tempfile::tempdir().unwrap();
    let ascii = dir.path().join("tower.txt");
    let out = sim_host(&["plan", "--task", "tower", "--out", s(&ascii)]);
    assert!(out.status.success());
    let out = sim_host(&["run", "--task", "tower", "--tree", s(&ascii)]);
    assert_error(&out, &["tower.txt:1:1: `{-}` is not a token"]);
}
