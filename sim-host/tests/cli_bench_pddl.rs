//! `sim-host bench-pddl` through the real binary, on one of the planner's IPC fixtures.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod cli_common;
use cli_common::sim_host;

/// The assembly instance's line of the bench's output with `--close-nodes nodes`.
fn assembly(nodes: &str) -> String {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/tests/fixtures/ipc");
    let args = ["bench-pddl", dir.to_str().unwrap(), "--only", "assembly/prob01", "--timeout", "60"];
    let out = sim_host(&[&args[..], &["--episodes", "20", "--close-nodes", nodes]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("1 instance, timeout 60 s"), "{text}");
    text.lines().find(|l| l.starts_with("assembly/prob01.pddl:")).unwrap_or_else(|| panic!("{text}")).to_owned()
}

/// The `disturbed N/20` count of a result line.
fn reached(line: &str) -> u32 {
    let at = line.find("disturbed ").unwrap_or_else(|| panic!("{line}")) + "disturbed ".len();
    line[at..].split('/').next().unwrap().parse().unwrap()
}

#[test]
fn close_nodes_bounds_the_closure_the_disturbed_episodes_measure() {
    // 0: the plan's regression tree alone, which agents doing its actions out of turn
    // defeat; a budget of 2,000 nodes already closes it over most of them.
    let plain = assembly("0");
    assert!(plain.contains("solved") && plain.contains("regression"), "{plain}");
    let closed = assembly("2000");
    let nodes = |l: &str| -> usize {
        let w: Vec<&str> = l.split_whitespace().collect();
        let i = w.iter().position(|x| *x == "nodes").unwrap_or_else(|| panic!("{l}"));
        w[i - 1].parse().unwrap()
    };
    assert!(nodes(&plain) < nodes(&closed), "{plain}\n{closed}");
    assert!(reached(&plain) < reached(&closed), "{plain}\n{closed}");
}

#[test]
fn the_bench_reports_the_state_variables_a_tree_does_not_pin() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/tests/fixtures/mini-openstacks");
    let out = sim_host(&["bench-pddl", dir.to_str().unwrap(), "--timeout", "60", "--episodes", "5"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let line = text.lines().position(|l| l.starts_with("p01.pddl:") || l.contains("/p01.pddl:"));
    let at = line.unwrap_or_else(|| panic!("{text}"));
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[at].contains("solved") && lines[at].contains("search-guided"), "{text}");
    assert_eq!(
        lines[at + 1].trim(),
        "state variables not pinned: stacks-avail/1 (each step also has its groundings from the other values the plan visits up to three actions from its own)",
        "{text}"
    );
}

/// A stand-in for Fast Downward's driver: writes the plan recorded for the blocks
/// fixture to the file `--plan-file` names, as `fast-downward.py --alias lama-first
/// --plan-file PLAN DOMAIN PROBLEM` does.
fn fake_fast_downward(dir: &std::path::Path) -> std::path::PathBuf {
    use std::os::unix::fs::PermissionsExt as _;
    let plan = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../planner/tests/fixtures/ipc/blocks/probBLOCKS-4-0.plan")
        .canonicalize()
        .unwrap();
    let script = dir.join("fast-downward");
    let text = format!(
        "#!/bin/sh\n[ \"$1 $2 $3\" = \"--alias lama-first --plan-file\" ] || exit 3\ncp '{}' \"$4\"\n",
        plan.display()
    );
    std::fs::write(&script, text).unwrap();
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    script
}

#[test]
fn fast_downward_runs_side_by_side_and_the_coverage_plot_is_drawn() {
    let tmp = tempfile::tempdir().unwrap();
    let fd = fake_fast_downward(tmp.path());
    let plot = tmp.path().join("coverage.svg");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/tests/fixtures/ipc");
    let out = sim_host(&[
        "bench-pddl",
        dir.to_str().unwrap(),
        "--only",
        "blocks/probBLOCKS-4-0",
        "--timeout",
        "30",
        "--episodes",
        "2",
        "--fast-downward",
        fd.to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let line = text.lines().find(|l| l.starts_with("blocks/probBLOCKS-4-0.pddl:")).unwrap_or_else(|| panic!("{text}"));
    assert!(line.contains("| FD lama-first solved"), "{line}");
    assert!(text.contains("FD lama-first solved | FD lama-first valid | FD lama-first median s"), "{text}");
    assert!(
        text.contains(
            "Against Fast Downward lama-first (timeout 30 s): solved by ours alone 0, by it alone 0, by both 1"
        ),
        "{text}"
    );
    assert!(
        text.contains("- time to the first tree (before its closure over disturbances): at most 2x its time"),
        "{text}"
    );
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(
        svg.starts_with("<svg") && svg.contains("FD lama-first: 1") && svg.contains("ours (sim-host plan): 1"),
        "{svg}"
    );
}

#[test]
fn a_plot_that_is_neither_png_nor_svg_is_refused_before_anything_runs() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/tests/fixtures/ipc");
    let out = sim_host(&["bench-pddl", dir.to_str().unwrap(), "--plot", "coverage.pdf"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("coverage.pdf") && err.contains(".png or .svg"), "{err}");
}
