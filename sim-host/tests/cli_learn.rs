//! `sim-host learn` and `sim-host plot` through the real binary: the run folder is the
//! whole record, runs repeat bit for bit, parallel runs equal runs one by one, and bad
//! arguments leave nothing behind.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

mod cli_common;
use cli_common::{ok, one_line_error, sim_host};

fn learn(dir: &Path, extra: &[&str]) -> String {
    let mut args = vec!["learn", "--task", "croissant", "--generations", "12", "--out", dir.to_str().unwrap()];
    args.extend_from_slice(extra);
    ok(&sim_host(&args))
}

#[test]
fn a_run_folder_is_the_whole_record() {
    let dir = tempfile::tempdir().unwrap();
    learn(dir.path(), &["--variant", "baseline", "--seeds", "3"]);
    let run = dir.path().join("croissant-baseline-symbolic-seed3");
    let csv = std::fs::read_to_string(run.join("curve.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("generation,episodes,best_fitness,best_length"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 12);
    assert_eq!(rows[0][0], "0");
    assert_eq!(rows[11][0], "11");
    // Elitism: the best never gets worse; with the baseline, never below the planner's.
    let best: Vec<f64> = rows.iter().map(|r| r[2].parse().unwrap()).collect();
    assert!(best.windows(2).all(|w| w[1] >= w[0]), "{best:?}");
    let record = std::fs::read_to_string(run.join("run.txt")).unwrap();
    let planner: f64 = record.lines().find_map(|l| l.strip_prefix("planner_fitness = ")).unwrap().parse().unwrap();
    assert!(best[0] >= planner, "{} < {planner}", best[0]);
    for key in
        ["task = croissant", "world = symbolic", "seed = 3", "variant = baseline", "generations = 12", "baseline = s("]
    {
        assert!(record.contains(key), "run.txt lacks `{key}`:\n{record}");
    }
    // The best tree: an image that inspect loads, and the same tree as text.
    let inspect = ok(&sim_host(&["inspect", run.join("best.bt").to_str().unwrap()]));
    assert!(inspect.contains("brick task `croissant`"), "{inspect}");
    let tokens = std::fs::read_to_string(run.join("best.tokens")).unwrap();
    let exported = ok(&sim_host(&["export", run.join("best.bt").to_str().unwrap(), "--format", "tokens"]));
    assert_eq!(exported, tokens);
    assert!(std::fs::read_to_string(run.join("best.txt")).unwrap().starts_with('{') || tokens.starts_with("s("));
}

#[test]
fn runs_repeat_and_parallel_runs_equal_single_ones() {
    let together = tempfile::tempdir().unwrap();
    learn(together.path(), &["--variant", "none,boost-all", "--seeds", "1..2"]);
    for variant in ["none", "boost-all"] {
        for seed in ["1", "2"] {
            let alone = tempfile::tempdir().unwrap();
            learn(alone.path(), &["--variant", variant, "--seeds", seed]);
            let name = format!("croissant-{variant}-symbolic-seed{seed}");
            for file in ["curve.csv", "best.tokens", "best.bt"] {
                assert_eq!(
                    std::fs::read(together.path().join(&name).join(file)).unwrap(),
                    std::fs::read(alone.path().join(&name).join(file)).unwrap(),
                    "{name}/{file}"
                );
            }
        }
    }
}

#[test]
fn plot_draws_a_png_and_prints_the_table() {
    let dir = tempfile::tempdir().unwrap();
    learn(dir.path(), &["--variant", "none,baseline", "--seeds", "1..2"]);
    let png = dir.path().join("curves.png");
    let table = ok(&sim_host(&["plot", dir.path().to_str().unwrap(), "--out", png.to_str().unwrap()]));
    assert!(table.contains("croissant  symbolic  baseline"), "{table}");
    assert!(table.contains("croissant  symbolic  none"), "{table}");
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert!(bytes.len() > 10_000, "a real picture, {} bytes", bytes.len());
}

#[test]
fn bad_arguments_are_one_line_and_leave_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    one_line_error(&sim_host(&["learn", "--task", "tower", "--seeds", "5..1", "--out", out]), "empty seed range");
    one_line_error(
        &sim_host(&["learn", "--task", "tower", "--variant", "turbo", "--out", out]),
        "unknown variant `turbo`",
    );
    one_line_error(&sim_host(&["learn", "--task", "towers", "--out", out]), "unknown task `towers`");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing written");

    learn(dir.path(), &["--seeds", "1"]);
    let before = std::fs::read(dir.path().join("croissant-baseline-symbolic-seed1/curve.csv")).unwrap();
    one_line_error(
        &sim_host(&["learn", "--task", "croissant", "--seeds", "1", "--generations", "3", "--out", out]),
        "pass --force",
    );
    assert_eq!(std::fs::read(dir.path().join("croissant-baseline-symbolic-seed1/curve.csv")).unwrap(), before);
    ok(&sim_host(&["learn", "--task", "croissant", "--seeds", "1", "--generations", "3", "--force", "--out", out]));
    let after = std::fs::read_to_string(dir.path().join("croissant-baseline-symbolic-seed1/curve.csv")).unwrap();
    assert_eq!(after.lines().count(), 1 + 3, "--force replaced the run");

    let empty = tempfile::tempdir().unwrap();
    one_line_error(&sim_host(&["plot", empty.path().to_str().unwrap()]), "no finished run folders");
    let nowhere = dir.path().join("missing").join("c.png");
    one_line_error(&sim_host(&["plot", out, "--out", nowhere.to_str().unwrap()]), "missing");
}

#[test]
fn a_physics_run_records_the_worlds_settings() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let args = ["learn", "--task", "tower", "--world", "physics", "--generations", "2", "--seeds", "1", "--out", out];
    ok(&sim_host(&args));
    let record = std::fs::read_to_string(dir.path().join("tower-baseline-physics-seed1/run.txt")).unwrap();
    for key in [
        "world = physics",
        "physics_steps_per_tick = 5",
        "physics_solver_iterations = 4",
        "physics_pgs_iterations = 3",
        "physics_gripper_speed = 0.3",
        "physics_travel_height = 0.09",
    ] {
        assert!(record.contains(key), "run.txt lacks `{key}`:\n{record}");
    }
    // The extra keys do not stop the folder from being read back.
    let table = ok(&sim_host(&["plot", out]));
    let row: Vec<&str> = table.lines().nth(1).unwrap_or_default().split_whitespace().collect();
    assert_eq!(row.get(..3), Some(&["tower", "physics", "baseline"][..]), "{table}");
}

#[test]
fn counts_of_one_are_singular() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let learn = |seeds: &str, threads: &str| {
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_sim-host"))
            .args(["learn", "--task", "croissant", "--generations", "2", "--seeds", seeds, "--force", "--out", out])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        ok(&run)
    };
    let one = learn("1", "1");
    let summary = one.lines().find(|l| l.contains(" in ") && l.contains("episodes/s")).unwrap();
    assert!(summary.starts_with("1 run, ") && summary.ends_with(" on 1 thread"), "{one}");
    let two = learn("1,2", "2");
    let summary = two.lines().find(|l| l.contains(" in ") && l.contains("episodes/s")).unwrap();
    assert!(summary.starts_with("2 runs, ") && summary.ends_with(" on 2 threads"), "{two}");
}
