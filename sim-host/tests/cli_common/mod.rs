//! Helpers shared by the CLI tests, which run the real `sim-host` binary.
#![allow(dead_code, clippy::unwrap_used)]

use std::process::{Command, Output};

/// Runs `sim-host` with `args` and waits for it.
pub fn sim_host(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sim-host")).args(args).output().unwrap()
}

/// Runs `sim-host` with `args` on a rayon pool of `threads` threads.
pub fn sim_host_threads(threads: &str, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sim-host")).env("RAYON_NUM_THREADS", threads).args(args).output().unwrap()
}

/// The standard output of a run that must succeed.
pub fn ok(out: &Output) -> String {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// A run that must fail with exit 2 and a one-line error containing `part`.
pub fn one_line_error(out: &Output, part: &str) {
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stdout));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(part), "{err} lacks {part}");
}
