//! `sim-host plan` through the real binary: Example 2 of Colledanchise et al. 2019 with `--expand-at`
//! (Fig. 4, then the tree the firmware runs), the published brick trees with
//! `--goal-sequence`, and trees that do not reach the goal: shown on stderr with the
//! reason, exit code 2, nothing written.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

mod cli_common;
use cli_common::{ok, one_line_error, sim_host};

fn path(rel: &str) -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel).to_str().unwrap().to_string()
}

fn cube(problem: &str) -> [String; 4] {
    [
        "--domain".into(),
        path("planner/domains/cube-sphere/domain.pddl"),
        "--problem".into(),
        path(&format!("planner/domains/cube-sphere/{problem}")),
    ]
}

fn plan(args: &[String], more: &[&str]) -> std::process::Output {
    let mut all: Vec<&str> = vec!["plan"];
    all.extend(args.iter().map(String::as_str));
    all.extend_from_slice(more);
    sim_host(&all)
}

/// The tree at the end of Example 2, which the firmware embeds (pinned node for node,
/// against the paper's notation, in `planner/tests/shipped_trees.rs`).
const EXAMPLE_2_END: &str = "f( at(cube, goal)? s( f( path-free(goal)? s( f( near(sphere)? s( path-free(sphere)? \
    move-to(sphere)! ) ) f( hand-empty? s( holding(cube)? near(goal)? place(cube, goal)! ) s( holding(cube)? \
    drop(cube)! ) ) clear-path(sphere, goal)! ) ) f( holding(cube)? s( f( near(cube)? s( path-free(cube)? \
    move-to(cube)! ) ) hand-empty? pick(cube)! ) ) f( near(goal)? s( path-free(goal)? move-to(goal)! ) ) \
    place(cube, goal)! ) )\n";

#[test]
fn expand_at_runs_example_2_through_fig_4_to_the_firmwares_tree() {
    let state = "holding(cube), not hand-empty, not path-free(goal)";
    let out = plan(&cube("problem.pddl"), &["--format", "tokens", "--expand-at", state]);
    assert_eq!(ok(&out), EXAMPLE_2_END);
    let summary = String::from_utf8(out.stderr).unwrap();
    assert!(summary.contains("planned: 4 expansions, 19 nodes\n"), "{summary}");
    assert!(summary.contains(&format!("at run time from `{state}`: 3 expansions, 37 nodes\n")), "{summary}");
    // The first run-time expansion is Fig. 4: the conflict, then 25 nodes.
    assert!(
        summary.contains(
            "  1. expanded `path-free(goal)` with clear-path(sphere, goal); conflict: `pick(cube)` undoes its \
             precondition `hand-empty`, moved the new subtree up a level; conflict: `pick(cube)` undoes its \
             precondition `hand-empty`, moved the new subtree one place left (25 nodes)\n"
        ),
        "{summary}"
    );
    assert!(
        summary.contains("  3. expanded `hand-empty` with place(cube, goal), drop(cube) (37 nodes)\n"),
        "{summary}"
    );
    assert!(
        summary.contains("the tree reaches the goal in 5 ticks from the initial state and in 8 ticks from --expand-at"),
        "{summary}"
    );

    // The firmware's way: the blocked problem, then the cube put in the hand.
    let out =
        plan(&cube("problem-blocked.pddl"), &["--format", "tokens", "--expand-at", "holding(cube), not hand-empty"]);
    assert_eq!(ok(&out), EXAMPLE_2_END);
    let summary = String::from_utf8(out.stderr).unwrap();
    assert!(summary.contains("planned: 6 expansions, 29 nodes\n"), "{summary}");
    assert!(summary.contains(": 1 expansion, 37 nodes\n"), "{summary}");
}

#[test]
fn help_says_what_expand_at_does_and_that_a_failing_tree_is_never_written() {
    let help = ok(&sim_host(&["plan", "--help"]));
    assert!(
        help.contains(
            "--expand-at STATE goes on as a robot would at run time (Example 2 of Colledanchise et al. 2019)"
        ),
        "{help}"
    );
    assert!(help.contains("A tree that does not reach the goal is never written"), "{help}");
}

#[test]
fn expand_at_names_the_column_of_a_bad_fact() {
    let out = plan(&cube("problem.pddl"), &["--expand-at", "holding(cube), not hand-empy"]);
    one_line_error(
        &out,
        "error: --expand-at `holding(cube), not hand-empy`: column 20: unknown predicate `hand-empy` (declared: at, \
         holding, hand-empty, near, path-free, obstacle)",
    );
    let out = sim_host(&["plan", "--task", "tower", "--expand-at", "picked 0"]);
    one_line_error(&out, "cannot be used with");
}

#[test]
fn goal_sequence_gives_the_published_balance_tree() {
    let out = sim_host(&["plan", "--task", "balance", "--format", "tokens", "--goal-sequence"]);
    assert_eq!(
        ok(&out),
        "s( f( 0 at pos (0.0, 0.0, 0.0192)? s( f( 1 at pos (0.0, 0.0, 0.0)? put 1 at (0.0, 0.0, 0.0)! ) \
         f( 0 on 1? put 0 on 1! ) apply force 0! ) ) )\n"
    );
    let out = sim_host(&["plan", "--task", "balance", "--format", "tokens"]);
    assert!(ok(&out).starts_with("f( 0 at pos "));
}

/// Stderr of a failed run: the tree's lines, then one error line; nothing on stdout.
fn failure(out: &std::process::Output) -> (String, String) {
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stdout));
    assert!(out.stdout.is_empty(), "{}", String::from_utf8_lossy(&out.stdout));
    let err = String::from_utf8(out.stderr.clone()).unwrap();
    let (tree, last) = err.trim_end().rsplit_once('\n').unwrap();
    (tree.to_string(), last.to_string())
}

#[test]
fn a_final_tree_that_does_not_reach_the_goal_is_shown_and_not_written() {
    // Algorithm 1 alone on an IPC blocks instance ends with a tree that fails and that
    // it cannot expand further.
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("never.bt");
    let fixture = "planner/tests/fixtures/ipc/blocks";
    let out = sim_host(&[
        "plan",
        "--domain",
        &path(&format!("{fixture}/domain.pddl")),
        "--problem",
        &path(&format!("{fixture}/probBLOCKS-4-0.pddl")),
        "--method",
        "algorithm-1",
        "--format",
        "image",
        "--out",
        target.to_str().unwrap(),
    ]);
    let (tree, last) = failure(&out);
    assert!(!target.exists());
    assert!(tree.starts_with("the tree ("), "{tree}");
    assert!(tree.contains("nodes), which does not reach the goal:\n    {-} Sequence\n"), "{tree}");
    assert!(tree.contains("--> stack("), "{tree}");
    assert!(
        last.starts_with("error: planning ")
            && last.contains(
                "probBLOCKS-4-0.pddl: the tree does not reach the goal from the initial state: the tree fails, but \
                 every failed condition was expanded before ("
            ),
        "{last}"
    );
}

/// The Sussman anomaly on the shipped blocks domain.
fn sussman(dir: &std::path::Path) -> String {
    let p = dir.join("sussman.pddl");
    std::fs::write(
        &p,
        "(define (problem sussman) (:domain blocks) (:objects a b c - block)
           (:init (on c a) (on-table a) (on-table b) (clear c) (clear b) (hand-empty))
           (:goal (and (on a b) (on b c))))",
    )
    .unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn an_oscillating_tree_is_shown_with_the_actions_it_repeats() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("never.txt");
    let args =
        ["--domain".to_string(), path("planner/domains/blocks/domain.pddl"), "--problem".into(), sussman(dir.path())];
    let out = plan(&args, &["--method", "algorithm-1", "--out", target.to_str().unwrap()]);
    let (tree, last) = failure(&out);
    assert!(!target.exists());
    assert!(tree.starts_with("the tree (265 nodes), which does not reach the goal:\n    {-} Sequence\n"), "{tree}");
    assert!(tree.ends_with("\n        --> on(b, c)"), "{tree}");
    assert!(last.ends_with(": the tree oscillates, repeating put-down(b), pick-up(b)"), "{last}");

    // By default search takes over; the summary still shows what oscillated.
    let text = ok(&plan(&args, &[]));
    assert!(
        text.contains(
            "algorithm-1 gave up: the tree oscillates, repeating put-down(b), pick-up(b)\n  the tree that \
             oscillates (265 nodes):\n    {-} Sequence\n"
        ),
        "{text}"
    );
}

#[test]
fn a_regression_tree_is_closed_over_disturbances_unless_close_nodes_is_0() {
    let files = [
        "--domain".to_string(),
        path("planner/tests/fixtures/ipc/assembly/domain.pddl"),
        "--problem".to_string(),
        path("planner/tests/fixtures/ipc/assembly/prob01.pddl"),
    ];
    // The summary after the tree: `planned: 0 expansions, 615 nodes`.
    let nodes_of = |text: &str| -> usize {
        let line = text.lines().find(|l| l.starts_with("planned:")).unwrap();
        line.rsplit(", ").next().unwrap().trim_end_matches(" nodes").parse().unwrap()
    };
    let closed = ok(&plan(&files, &["--format", "ascii", "--close-nodes", "600"]));
    assert!(closed.contains("made by regression"), "{closed}");
    assert!(closed.contains("closed over disturbances:"), "{closed}");
    let plain = ok(&plan(&files, &["--format", "ascii", "--close-nodes", "0"]));
    assert!(!plain.contains("closed over disturbances"), "{plain}");
    let (big, small) = (nodes_of(&closed), nodes_of(&plain));
    assert!(small < big && big <= 600 + 200, "{small} nodes plain, {big} closed");
}
