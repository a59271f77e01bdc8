//! Spreading `sim-host learn` over processes and machines, through the real binary:
//! `--list` commands run by GNU parallel and `--index` runs give the folders one process
//! gives; a run being made elsewhere is refused; interrupted runs are cleaned up; grids
//! that repeat entries or exceed the limits are refused before any work.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::fs::OpenOptions;
use std::path::Path;
use std::process::{Command, Stdio};

mod cli_common;
use cli_common::{ok, one_line_error, sim_host};

/// Every file under `dir`, by path relative to it (hidden entries too).
fn tree(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push((p.strip_prefix(dir).unwrap().display().to_string(), std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

const GRID: [&str; 8] =
    ["learn", "--task", "tower,blocking", "--variant", "none,baseline", "--seeds", "1..2", "--generations"];

fn grid(out: &str, extra: &[&str]) -> Vec<String> {
    let mut args: Vec<String> = GRID.iter().map(|s| s.to_string()).collect();
    args.extend(["6", "--out", out].map(String::from));
    args.extend(extra.iter().map(|s| s.to_string()));
    args
}

fn refs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

#[test]
fn gnu_parallel_and_index_runs_equal_one_process() {
    let whole = tempfile::tempdir().unwrap();
    ok(&sim_host(&refs(&grid(whole.path().to_str().unwrap(), &[]))));
    let expected = tree(whole.path());
    assert_eq!(expected.len(), 8 * 6, "8 runs of 6 files, no lock or temporary left");

    // One command per run; each alone makes exactly its folder.
    let spread = tempfile::tempdir().unwrap();
    let list = ok(&sim_host(&refs(&grid(spread.path().to_str().unwrap(), &["--list"]))));
    let commands: Vec<&str> = list.lines().collect();
    assert_eq!(commands.len(), 8);
    assert!(commands[0].contains(" learn --task tower --world symbolic --variant none --seeds 1 --generations 6 "));
    assert_eq!(std::fs::read_dir(spread.path()).unwrap().count(), 0, "--list runs nothing");

    // GNU parallel, as the README says: `sim-host learn ... --list | parallel`.
    let has_parallel = Command::new("parallel").arg("--version").output().is_ok_and(|o| o.status.success());
    if has_parallel {
        let mut child = Command::new("parallel")
            .args(["--will-cite", "-j", "3"])
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::io::Write::write_all(&mut child.stdin.take().unwrap(), list.as_bytes()).unwrap();
        let done = child.wait_with_output().unwrap();
        assert!(done.status.success(), "{}", String::from_utf8_lossy(&done.stderr));
        assert_eq!(tree(spread.path()), expected, "GNU parallel");
    } else {
        // CI installs GNU parallel (.ci/run); elsewhere run the commands through sh.
        assert!(std::env::var_os("CI").is_none(), "GNU parallel is missing on CI");
        eprintln!("GNU parallel is not installed: running the listed commands with sh one by one");
        for c in &commands {
            let status = Command::new("sh").args(["-c", c]).stdout(Stdio::null()).status().unwrap();
            assert!(status.success(), "{c}");
        }
        assert_eq!(tree(spread.path()), expected, "listed commands");
    }

    // --index I makes only the I-th run of the same grid.
    let indexed = tempfile::tempdir().unwrap();
    let out = indexed.path().to_str().unwrap();
    for i in 0..8 {
        ok(&sim_host(&refs(&grid(out, &["--index", &i.to_string()]))));
    }
    assert_eq!(tree(indexed.path()), expected, "--index");
    one_line_error(&sim_host(&refs(&grid(out, &["--index", "8"]))), "--index 8: the grid has 8 runs, numbered 0 to 7");
}

#[test]
fn a_run_being_made_elsewhere_is_refused_and_interrupted_ones_are_cleaned() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let run = ["learn", "--task", "tower", "--seeds", "1", "--generations", "4", "--out", out];
    // Another process holds the run's lock.
    let lock = dir.path().join(".tower-baseline-symbolic-seed1.lock");
    let held = OpenOptions::new().create(true).truncate(false).write(true).open(&lock).unwrap();
    held.lock().unwrap();
    one_line_error(&sim_host(&run), "another `sim-host learn` is making this run now");
    assert!(!dir.path().join("tower-baseline-symbolic-seed1").exists());
    held.unlock().unwrap();
    drop(held);

    // What an interrupted run leaves: its temporary folder; the next learn of that run
    // removes it, a temporary of another run stays.
    let mine = dir.path().join(".tower-baseline-symbolic-seed1-a1B2c3");
    let other = dir.path().join(".tower-baseline-symbolic-seed10-x9Y8z7");
    for t in [&mine, &other] {
        std::fs::create_dir(t).unwrap();
        std::fs::write(t.join("run.txt"), "half").unwrap();
    }
    let made = sim_host(&run);
    ok(&made);
    assert!(String::from_utf8_lossy(&made.stderr).contains("removed 1 temporary folder of an interrupted run"));
    assert!(!mine.exists() && other.exists());
    assert!(!lock.exists(), "the lock file goes with the run");
    assert!(dir.path().join("tower-baseline-symbolic-seed1/best.xml").exists());
}

#[test]
fn repeated_entries_and_oversized_grids_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    one_line_error(
        &sim_host(&["learn", "--task", "tower", "--seeds", "1,1,1", "--out", out]),
        "seed `1` is given twice",
    );
    one_line_error(&sim_host(&["learn", "--task", "tower,tower", "--out", out]), "task `tower` is given twice");
    one_line_error(
        &sim_host(&["learn", "--task", "tower", "--variant", "none,none", "--out", out]),
        "variant `none` is given twice",
    );
    one_line_error(
        &sim_host(&["learn", "--task", "tower", "--generations", "4294967295", "--out", out]),
        "over the limit of 100000",
    );
    one_line_error(
        &sim_host(&["learn", "--task", "all", "--variant", "all", "--seeds", "0..9999", "--out", out]),
        "160000 runs, over the limit of 10000",
    );
    one_line_error(&sim_host(&["learn", "--task", "tower", "--islands", "0", "--out", out]), "--islands 0");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing written");
}
