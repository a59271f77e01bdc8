//! `sim-host plot` on results folders as they are found in practice: temporaries of
//! runs being written or interrupted, incomplete and copied run folders, damaged
//! curves, and --out targets it must not write.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;
use std::process::Output;

mod cli_common;
use cli_common::{ok, sim_host};

/// As [`cli_common::one_line_error`], and nothing reported as done.
fn one_line_error(out: &Output, part: &str) {
    cli_common::one_line_error(out, part);
    assert!(out.stdout.is_empty(), "nothing reported as done: {}", String::from_utf8_lossy(&out.stdout));
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

/// Two seeds of croissant, baseline, 8 generations.
fn results() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    ok(&sim_host(&["learn", "--task", "croissant", "--seeds", "1..2", "--generations", "8", "--out", out]));
    dir
}

fn seeds_in_table(table: &str) -> &str {
    let row = table.lines().find(|l| l.starts_with("croissant")).unwrap();
    row.split_whitespace().nth(3).unwrap()
}

#[test]
fn temporaries_incomplete_folders_and_copies_are_skipped_and_counted() {
    let dir = results();
    let out = dir.path().to_str().unwrap();
    let seed1 = dir.path().join("croissant-baseline-symbolic-seed1");
    // A run being written (or interrupted): a hidden temporary with a whole record.
    copy_dir(&seed1, &dir.path().join(".croissant-baseline-symbolic-seed3-Ab12Cd"));
    // A run folder that lost a file, and a plain copy of a run under another name.
    let broken = dir.path().join("croissant-baseline-symbolic-seed4");
    copy_dir(&seed1, &broken);
    std::fs::remove_file(broken.join("best.bt")).unwrap();
    copy_dir(&seed1, &dir.path().join("backup-of-seed1"));
    let done = sim_host(&["plot", out]);
    let table = ok(&done);
    assert_eq!(seeds_in_table(&table), "2", "{table}");
    let err = String::from_utf8_lossy(&done.stderr);
    assert!(err.contains("skipping"), "{err}");
    assert!(
        err.contains("skipped 1 hidden temporary folder (")
            && err.contains("1 incomplete run folder,")
            && err.contains("1 copy of a run already read"),
        "{err}"
    );
    // A copy that differs is two results for one run: refused, naming both.
    let record = dir.path().join("backup-of-seed1/run.txt");
    let text = std::fs::read_to_string(&record).unwrap();
    std::fs::write(&record, format!("# edited by hand\n{text}")).unwrap();
    one_line_error(&sim_host(&["plot", out]), "with different results; keep one");
}

#[test]
fn damaged_records_are_refused_with_the_file_and_line() {
    let dir = results();
    let out = dir.path().to_str().unwrap();
    let run = dir.path().join("croissant-baseline-symbolic-seed2");
    let csv = run.join("curve.csv");
    let good = std::fs::read_to_string(&csv).unwrap();
    let row = |i: usize| good.lines().nth(i).unwrap().to_string();
    let with = |line: usize, new: &str| {
        let mut lines: Vec<String> = good.lines().map(String::from).collect();
        lines[line - 1] = new.to_string();
        std::fs::write(&csv, lines.join("\n") + "\n").unwrap();
    };
    let fields = |i: usize| row(i).split(',').map(String::from).collect::<Vec<_>>();
    let f3 = fields(3);
    for (bad, part) in [
        ("NaN", "curve.csv:4: best_fitness `NaN` is not a finite number"),
        ("inf", "curve.csv:4: best_fitness `inf` is not a finite number"),
        ("0.5", "curve.csv:4: best_fitness `0.5` is positive"),
        ("-1e300", "curve.csv:4: best_fitness `-1e300` is below -1e9"),
    ] {
        with(4, &format!("{},{},{bad},{}", f3[0], f3[1], f3[3]));
        one_line_error(&sim_host(&["plot", out]), part);
    }
    with(4, &format!("{},{},-9999,{}", f3[0], f3[1], f3[3]));
    one_line_error(&sim_host(&["plot", out]), "curve.csv:4: the best fitness drops");
    with(4, &format!("7,{},{},{}", f3[1], f3[2], f3[3]));
    one_line_error(&sim_host(&["plot", out]), "curve.csv:4: generation 7 where 2 was expected");
    std::fs::write(&csv, &good).unwrap();

    let run_txt = run.join("run.txt");
    let record = std::fs::read_to_string(&run_txt).unwrap();
    let line = record.lines().position(|l| l.starts_with("task = ")).unwrap() + 1;
    std::fs::write(&run_txt, record.replace("task = croissant", "task = croisant")).unwrap();
    one_line_error(&sim_host(&["plot", out]), &format!("run.txt:{line}: unknown task `croisant`"));
    std::fs::write(&run_txt, record.replace("planner_fitness = ", "planner_fitness = NaN#")).unwrap();
    one_line_error(&sim_host(&["plot", out]), "planner_fitness `NaN#");
}

#[test]
fn the_picture_goes_only_where_a_picture_belongs() {
    let dir = results();
    let out = dir.path().to_str().unwrap();
    let run_txt = dir.path().join("croissant-baseline-symbolic-seed1/run.txt");
    let before = std::fs::read(&run_txt).unwrap();
    one_line_error(&sim_host(&["plot", out, "--out", run_txt.to_str().unwrap()]), "give a name ending in .png or .svg");
    assert_eq!(std::fs::read(&run_txt).unwrap(), before);
    // SVG by name.
    let svg = dir.path().join("c.SVG");
    ok(&sim_host(&["plot", out, "--out", svg.to_str().unwrap()]));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.contains("croissant (symbolic world)"), "{}", &text[..100]);
    // A picture that cannot be written: an error, and no table printed as if done.
    let nowhere = dir.path().join("missing").join("c.png");
    let failed = sim_host(&["plot", out, "--out", nowhere.to_str().unwrap()]);
    one_line_error(&failed, "missing");
}

#[test]
fn fitness_labels_differ_on_small_ranges() {
    // Tower with the baseline: every curve between -3.0 and -2.3, a tenth of a decade.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    ok(&sim_host(&["learn", "--task", "tower", "--seeds", "1", "--generations", "40", "--out", out]));
    let svg = dir.path().join("c.svg");
    ok(&sim_host(&["plot", out, "--out", svg.to_str().unwrap()]));
    let text = std::fs::read_to_string(&svg).unwrap();
    // The axis labels are the <text> elements that read as a fitness.
    let labels: Vec<&str> = text
        .split("<text")
        .filter_map(|t| Some(t.split('>').nth(1)?.split('<').next()?.trim()))
        .filter(|t| t.starts_with('-') && t[1..].parse::<f64>().is_ok())
        .collect();
    assert!(labels.len() >= 3, "{labels:?}");
    let mut unique = labels.clone();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), labels.len(), "repeated labels: {labels:?}");
}

/// The `points` of every `<polyline>` of one stroke colour and width, in drawing order,
/// with the element's position among all polylines.
fn polylines(svg: &str, stroke: &str) -> Vec<(usize, Vec<(i32, i32)>)> {
    svg.split("<polyline")
        .skip(1)
        .enumerate()
        .filter(|(_, p)| p.contains(stroke))
        .map(|(i, p)| {
            let pts = p.split("points=\"").nth(1).unwrap().split('"').next().unwrap();
            let xy = pts
                .split_whitespace()
                .map(|xy| {
                    let (x, y) = xy.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect();
            (i, xy)
        })
        .collect()
}

#[test]
fn curves_are_drawn_over_the_planners_level_and_the_legend_beside_them() {
    // Tower with the baseline starts exactly at the planner's level: its curve lies on
    // the planner's dashed line, and must be drawn after (over) it.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    ok(&sim_host(&["learn", "--task", "tower", "--seeds", "1", "--generations", "8", "--out", out]));
    let svg_path = dir.path().join("c.svg");
    ok(&sim_host(&["plot", out, "--out", svg_path.to_str().unwrap()]));
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    // The legend's labels: the text elements that name a variant and its seeds.
    let legend_x: Vec<i32> = svg
        .split("<text")
        .filter(|t| t.contains("seed)") || t.contains("planner ("))
        .map(|t| t.split("x=\"").nth(1).unwrap().split('"').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(legend_x.len(), 2, "one variant and the planner");
    // The baseline's curve (blue, 2 px), its legend sample (blue, 3 px) and the
    // planner's level (grey, 2 px dashes, in the chart and in the legend).
    let curve = polylines(&svg, "stroke=\"#1F77B4\" stroke-width=\"2\"");
    let sample = polylines(&svg, "stroke=\"#1F77B4\" stroke-width=\"3\"");
    let planner = polylines(&svg, "stroke=\"#5A5A5A\" stroke-width=\"2\"");
    assert_eq!((curve.len(), sample.len()), (1, 1), "one curve, one legend entry");
    let right_of_curve = curve[0].1.iter().map(|&(x, _)| x).max().unwrap();
    let legend_left = sample[0].1.iter().map(|&(x, _)| x).chain(legend_x).min().unwrap();
    assert!(
        legend_left > right_of_curve,
        "the legend ({legend_left}) starts right of every curve point ({right_of_curve})"
    );
    let dashes: Vec<_> = planner.iter().filter(|(_, pts)| pts.iter().all(|&(x, _)| x <= right_of_curve)).collect();
    assert!(!dashes.is_empty(), "the planner's level is drawn in the chart");
    assert!(dashes.iter().all(|(i, _)| *i < curve[0].0), "a dash of the planner's level is drawn over the curve");
    // The curve lies on the planner's level at its start: the test is about overlap.
    assert_eq!(curve[0].1[0].1, dashes[0].1[0].1, "the tower's baseline starts at the planner's level");
}
