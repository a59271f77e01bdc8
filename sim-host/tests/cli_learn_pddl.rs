//! `sim-host learn` on PDDL problems and with islands, through the real binary: the
//! run folder of a PDDL run, disturbances, `run` on a learned tree, island runs that do
//! not depend on threads, nokeep and the reference's baseline form.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

mod cli_common;
use cli_common::{ok, one_line_error, sim_host, sim_host_threads};

const DOMAIN: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../planner/domains/cube-sphere/domain.pddl");
const BLOCKED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../planner/domains/cube-sphere/problem-blocked.pddl");

fn record(dir: &Path, key: &str) -> String {
    let text = std::fs::read_to_string(dir.join("run.txt")).unwrap();
    text.lines().find_map(|l| l.strip_prefix(&format!("{key} = "))).unwrap_or_else(|| panic!("no {key}: {text}")).into()
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .map(|e| (e.file_name().to_string_lossy().into_owned(), std::fs::read(e.path()).unwrap()))
        .collect();
    out.sort();
    out
}

#[test]
fn a_pddl_run_learns_from_the_planners_tree_and_keeps_its_problem() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let args = ["learn", "--domain", DOMAIN, "--problem", BLOCKED, "--seeds", "1", "--generations", "30", "--out", out];
    ok(&sim_host(&args));
    let run = dir.path().join("cube-to-goal-blocked-baseline-strips-seed1");
    let names: Vec<String> = files(&run).into_iter().map(|f| f.0).collect();
    assert_eq!(
        names,
        ["best.bt", "best.tokens", "best.txt", "best.xml", "curve.csv", "domain.pddl", "problem.pddl", "run.txt"]
    );
    assert_eq!(std::fs::read(run.join("domain.pddl")).unwrap(), std::fs::read(DOMAIN).unwrap());
    assert_eq!(record(&run, "problem"), "cube-to-goal-blocked");
    assert_eq!(record(&run, "domain"), "cube-sphere");
    assert_eq!(record(&run, "world"), "strips");
    // The baseline is the planner's tree (Fig. 4 of Colledanchise et al. 2019), in grounded leaves.
    let baseline = record(&run, "baseline");
    assert!(baseline.starts_with("f( at(cube, goal)? s( f( path-free(goal)? "), "{baseline}");
    // GP starts at the planner's level and improves on it (a shorter tree).
    let planner: f64 = record(&run, "planner_fitness").parse().unwrap();
    let best: f64 = record(&run, "best_fitness").parse().unwrap();
    assert!(best > planner, "{best} <= {planner}");
    // The best tree: an image of the PDDL leaf contract that inspect reads with the
    // problem's names, and that `run` plays to the goal.
    let inspect = ok(&sim_host(&["inspect", run.join("best.bt").to_str().unwrap()]));
    assert!(inspect.contains("at(cube, goal)"), "{inspect}");
    let tokens = std::fs::read_to_string(run.join("best.tokens")).unwrap();
    assert!(tokens.contains("place(cube, goal)!"), "{tokens}");
    for tree in ["best.bt", "best.tokens"] {
        let played = ok(&sim_host(&[
            "run",
            "--domain",
            DOMAIN,
            "--problem",
            BLOCKED,
            "--tree",
            run.join(tree).to_str().unwrap(),
        ]));
        assert!(played.contains("goal     reached in 1 of 1 episode"), "{played}");
        assert!(played.contains(&format!("fitness  {best:.3}")), "{tree}: {played} vs {best}");
    }
}

#[test]
fn disturbed_runs_score_the_same_seeded_episodes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let args = [
        "learn",
        "--domain",
        DOMAIN,
        "--problem",
        BLOCKED,
        "--variant",
        "boost-all",
        "--seeds",
        "2",
        "--generations",
        "12",
        "--disturb",
        "0.1",
        "--disturb-seed",
        "7",
        "--disturb-episodes",
        "10",
        "--out",
        out,
    ];
    ok(&sim_host(&args));
    let run = dir.path().join("cube-to-goal-blocked-boost-all-strips-disturb0.1-seed2");
    assert_eq!(record(&run, "disturb_rate"), "0.1");
    assert_eq!(record(&run, "disturb_seed"), "7");
    assert_eq!(record(&run, "disturb_episodes"), "10");
    // `run` with the same agents gives the planner's recorded fitness: the episodes
    // are a function of the seed.
    let planner: f64 = record(&run, "planner_fitness").parse().unwrap();
    let played = ok(&sim_host(&[
        "run",
        "--domain",
        DOMAIN,
        "--problem",
        BLOCKED,
        "--disturb",
        "0.1",
        "--disturb-seed",
        "7",
        "--episodes",
        "10",
    ]));
    assert!(played.contains(&format!("fitness  {planner:.3} (mean)")), "{played} vs {planner}");
    assert!(played.contains("episodes 10, agents act"), "{played}");
    // Other agents, another score.
    let other = ok(&sim_host(&[
        "run",
        "--domain",
        DOMAIN,
        "--problem",
        BLOCKED,
        "--disturb",
        "0.3",
        "--disturb-seed",
        "8",
        "--episodes",
        "10",
    ]));
    assert!(!other.contains(&format!("fitness  {planner:.3} (mean)")), "{other}");
}

#[test]
fn island_runs_do_not_depend_on_threads() {
    let one = tempfile::tempdir().unwrap();
    let two = tempfile::tempdir().unwrap();
    for (threads, dir) in [("1", &one), ("2", &two)] {
        let out = dir.path().to_str().unwrap();
        let args = [
            "learn",
            "--task",
            "blocking",
            "--islands",
            "3",
            "--migration-interval",
            "4",
            "--stagnation",
            "6",
            "--generations",
            "20",
            "--seeds",
            "4",
            "--out",
            out,
        ];
        ok(&sim_host_threads(threads, &args));
    }
    let name = "blocking-baseline-islands3-symbolic-seed4";
    let a = files(&one.path().join(name));
    assert_eq!(a, files(&two.path().join(name)));
    let run = one.path().join(name);
    assert_eq!(record(&run, "islands"), "3");
    assert_eq!(record(&run, "generations_run"), "20");
    let csv = std::fs::read_to_string(run.join("curve.csv")).unwrap();
    // Three islands' initial populations in the first row.
    assert!(csv.lines().nth(1).unwrap().starts_with("0,48,"), "{csv}");
}

#[test]
fn islands_stop_at_the_level_asked() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    // The planner's tower scores -3.0; a smaller tree beats it within a few generations.
    let args = ["learn", "--task", "tower", "--islands", "2", "--stop-at", "-2.95", "--seeds", "1", "--out", out];
    ok(&sim_host(&args));
    let run = dir.path().join("tower-baseline-islands2-symbolic-seed1");
    let reached: u32 = record(&run, "reached_generation").parse().unwrap();
    let rows: u32 = record(&run, "generations_run").parse().unwrap();
    assert!(rows < 200 && reached < rows, "{reached} {rows}");
    assert!(record(&run, "best_fitness").parse::<f64>().unwrap() >= -2.95);
}

#[test]
fn nokeep_and_the_reference_baseline_form() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let args =
        ["learn", "--task", "balance", "--variant", "nokeep", "--goal-sequence", "--generations", "5", "--seeds", "1"];
    ok(&sim_host(&[&args[..], &["--out", out]].concat()));
    let run = dir.path().join("balance-nokeep-symbolic-seed1");
    assert_eq!(record(&run, "variant"), "nokeep");
    assert_eq!(record(&run, "goal_sequence"), "true");
    // The reference planner's balance tree: the goal Sequence kept, 11 nodes.
    assert_eq!(
        record(&run, "baseline"),
        "s( f( 0 at pos (0.0, 0.0, 0.0192)? s( f( 1 at pos (0.0, 0.0, 0.0)? put 1 at (0.0, 0.0, 0.0)! ) \
         f( 0 on 1? put 0 on 1! ) apply force 0! ) ) )"
    );
}

#[test]
fn pddl_arguments_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let pddl = ["learn", "--domain", DOMAIN, "--problem", BLOCKED, "--out", out];
    one_line_error(&sim_host(&[&pddl[..], &["--disturb", "1.5"]].concat()), "--disturb 1.5");
    one_line_error(&sim_host(&[&pddl[..], &["--world", "physics"]].concat()), "symbolic STRIPS world");
    one_line_error(&sim_host(&["learn", "--task", "tower", "--disturb", "0.1", "--out", out]), "--domain");
    let missing = dir.path().join("nope.pddl");
    one_line_error(
        &sim_host(&["learn", "--domain", DOMAIN, "--problem", missing.to_str().unwrap(), "--out", out]),
        "nope.pddl",
    );
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing written");
}
