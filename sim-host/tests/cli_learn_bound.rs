//! `sim-host learn --max-bytes / --max-nodes` through the real binary: the tree it
//! writes fits the bound where the unbounded run's does not, a PDDL tree fits without
//! its names section, and bounds no tree can meet are refused by name.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

mod cli_common;
use cli_common::{ok, one_line_error, sim_host, sim_host_threads};

const DOMAIN: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../planner/domains/cube-sphere/domain.pddl");
const BLOCKED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../planner/domains/cube-sphere/problem-blocked.pddl");

/// Bytes (names section left out, as the controller holds it) and nodes of an image.
fn size(image: &Path) -> (usize, usize) {
    let bare = bt_formats::image::strip_names(&std::fs::read(image).unwrap()).unwrap();
    let header = bt_core::image::read_header(&bare).unwrap();
    (bare.len(), usize::from(header.node_count))
}

#[test]
fn the_learned_brick_tree_fits_where_the_unbounded_one_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let learn = |out: &str, extra: &[&str]| {
        let out = dir.path().join(out);
        let mut args = vec!["learn", "--task", "blocking", "--seeds", "1", "--generations", "150", "--out"];
        args.push(out.to_str().unwrap());
        args.extend_from_slice(extra);
        ok(&sim_host(&args));
        size(&out.join("blocking-baseline-symbolic-seed1/best.bt"))
    };
    // The planner's blocking tree has a 64-byte image; unbounded, GP grows past it.
    let free = learn("free", &[]);
    assert!(free.0 > 64, "{free:?}");
    let bounded = learn("bounded", &["--max-bytes", "64", "--max-nodes", "14"]);
    assert!(bounded.0 <= 64 && bounded.1 <= 14, "{bounded:?}");
    let record = std::fs::read_to_string(dir.path().join("bounded/blocking-baseline-symbolic-seed1/run.txt")).unwrap();
    assert!(record.contains("max_bytes = 64\nmax_nodes = 14\n"), "{record}");
}

#[test]
fn a_learned_pddl_tree_fits_without_its_names_with_islands_and_repeats() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let run = |threads: &str, folder: &str| {
        let out = format!("{out}/{folder}");
        let args = [
            "learn",
            "--domain",
            DOMAIN,
            "--problem",
            BLOCKED,
            "--seeds",
            "2",
            "--generations",
            "20",
            "--islands",
            "2",
            "--max-bytes",
            "130",
            "--max-nodes",
            "29",
            "--out",
            &out,
        ];
        ok(&sim_host_threads(threads, &args));
        let run = Path::new(&out).join("cube-to-goal-blocked-baseline-islands2-strips-seed2");
        let record = std::fs::read_to_string(run.join("run.txt")).unwrap();
        // The baseline (Algorithm 1's tree, which has no closure to cut) fits as it is.
        assert!(record.contains("planner_fit = image 130 bytes, 29 nodes\n"), "{record}");
        let best = run.join("best.bt");
        (size(&best), std::fs::read(best).unwrap())
    };
    let (one, image) = run("1", "one");
    assert!(one.0 <= 130 && one.1 <= 29, "{one:?}");
    // The same seed gives the same tree on one thread or two.
    assert_eq!(run("2", "two").1, image);
}

#[test]
fn bounds_no_tree_meets_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("runs");
    let learn = |extra: &[&str]| {
        let mut args = vec!["learn", "--task", "tower", "--seeds", "1", "--out", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        sim_host(&args)
    };
    one_line_error(&learn(&["--max-bytes", "0"]), "--max-bytes 0: too small for any tree");
    one_line_error(&learn(&["--max-nodes", "1"]), "--max-nodes 1: too small for any tree");
    one_line_error(
        &learn(&["--max-bytes", "100", "--max-nodes", "40"]),
        "--max-bytes 100 --max-nodes 40: the planner's tree for tower (the baseline) has an image of 112 bytes",
    );
    // Without a baseline, GP learns from random trees within the bound.
    ok(&learn(&["--variant", "none", "--generations", "10", "--max-bytes", "40"]));
    assert!(size(&out.join("tower-none-symbolic-seed1/best.bt")).0 <= 40);
}
