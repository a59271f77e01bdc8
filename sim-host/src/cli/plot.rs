//! `sim-host plot DIR [--out FILE.png|FILE.svg]`: learning curves like Figs. 6-11 of
//! Styrud et al., and a results table.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context as _, anyhow, bail};
use gp::Variant;
use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::prelude::*;
use plotters::style::FontStyle;
use sim_host::learn::{self, Folder, Recorded, Skipped};
use sim_host::text::{count, count_as};

use super::output::{self, Content, Target};

pub const LONG_ABOUT: &str = "Reads every run folder under DIR (as written by `sim-host learn`, \
from any number of machines) and draws the learning curves like Figs. 6-11 of Styrud et al.: one \
panel per task and world, one curve per variant, the mean over seeds of the best fitness so \
far with a band of one standard deviation, against episodes (unique simulations), and the \
planner's fitness as a dashed line. The fitness axis is logarithmic in the cost (-fitness), so \
that curves near the planner's level stay apart from it and from each other. Seeds reach \
episodes at different generations, so each curve is read as a step function (the best so far \
at that episode) on a common grid. Then prints a table: seeds, median and mean final best \
fitness, and how many episodes each variant needed to reach the planner's level.\n\n\
Skipped, and counted on stderr: hidden .<run>-XXXXXX folders (runs being written, or \
interrupted), run folders that lack a file or rows of their curve, and copies of a run already \
read. Refused, with the file and line: values no run writes (NaN, infinities, positive or \
absurd fitness, curves whose best gets worse), and two different folders for the same run.\n\n\
The picture is PNG or SVG, by the name given to --out (default DIR/curves.png).";

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The folder holding run folders (searched one level down).
    pub dir: PathBuf,
    /// The picture to write: a .png or .svg file (default: DIR/curves.png; `-`: a PNG
    /// to stdout, the table then goes to stderr).
    #[arg(long, value_name = "FILE", value_parser = Target::parse)]
    pub out: Option<Target>,
}

/// The font every label uses, embedded so the picture needs no system fonts.
pub(super) static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// The paper's colours first (no baseline red, baseline blue, boost crossover green,
/// boost all black), then more for other series.
pub(super) const COLOURS: [RGBColor; 9] = [
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(0, 0, 0),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// A panel: task (or PDDL problem) and world.
type Panel = (String, String);

/// How a series sorts and is coloured: the variant's place, then islands.
fn series_key(r: &Recorded) -> (usize, String) {
    let v = Variant::EVERY.iter().position(|&x| x == r.variant).unwrap_or(Variant::EVERY.len());
    (v, r.variant_label.clone())
}

fn colour(r: &Recorded) -> RGBColor {
    if r.variant_label == r.variant.name()
        && let Some(i) = Variant::ALL.iter().position(|&x| x == r.variant)
    {
        return COLOURS[i];
    }
    // Other series: by a hash of the label, past the paper's four.
    let h = r.variant_label.bytes().fold(0usize, |h, b| h.wrapping_mul(31).wrapping_add(usize::from(b)));
    COLOURS[4 + h % (COLOURS.len() - 4)]
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Format {
    Png,
    Svg,
}

pub(super) fn format_of(out: &Path) -> anyhow::Result<Format> {
    let ext = out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => Ok(Format::Png),
        Some("svg") => Ok(Format::Svg),
        _ => bail!("--out {}: the picture is written as PNG or SVG; give a name ending in .png or .svg", out.display()),
    }
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let out = args.out.clone().unwrap_or_else(|| Target::File(args.dir.join("curves.png")));
    let format = match &out {
        Target::File(path) => format_of(path)?,
        Target::Stdout => Format::Png,
    };
    let content = match format {
        Format::Png => Content::Binary("a PNG picture"),
        Format::Svg => Content::Text,
    };
    output::check(&out, content)?;
    let (runs, skipped) = read_runs(&args.dir)?;
    let mut panels: Vec<Panel> = runs.iter().map(|r| (r.label.clone(), r.world.clone())).collect();
    panels.sort();
    panels.dedup();
    let picture = match format {
        Format::Png => png(&runs, &panels)?,
        Format::Svg => svg(&runs, &panels)?.into_bytes(),
    };
    // The picture first: if it cannot be written, nothing is reported as done.
    output::write(&out, &picture, content)?;
    let table = table(&runs, &panels);
    match &out {
        Target::File(path) => output::stdout(format!("{table}curves: {}\n", path.display()).as_bytes())?,
        Target::Stdout => output::stderr(table.as_bytes())?,
    }
    report(&skipped)?;
    Ok(())
}

fn report(s: &Skipped) -> anyhow::Result<()> {
    let mut parts = Vec::new();
    if s.temporary > 0 {
        parts.push(format!(
            "{} (runs being written, or interrupted; the next `learn` of that run removes them)",
            count(s.temporary, "hidden temporary folder")
        ));
    }
    if s.incomplete > 0 {
        parts.push(count(s.incomplete, "incomplete run folder"));
    }
    if s.copies > 0 {
        parts.push(format!("{} of a run already read", count_as(s.copies, "copy", "copies")));
    }
    if !parts.is_empty() {
        output::stderr(format!("skipped {}\n", parts.join(", ")).as_bytes())?;
    }
    Ok(())
}

fn read_runs(dir: &Path) -> anyhow::Result<(Vec<Recorded>, Skipped)> {
    let entries = std::fs::read_dir(dir).with_context(|| format!("cannot read {}", dir.display()))?;
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    let mut runs: Vec<Recorded> = Vec::new();
    let mut skipped = Skipped::default();
    // The same run (task, world, variant, seed) seen twice: a copy if identical.
    let mut seen: BTreeMap<(String, String, String, u64), PathBuf> = BTreeMap::new();
    for path in paths {
        if !path.is_dir() {
            continue;
        }
        let hidden = path.file_name().and_then(|n| n.to_str()).is_none_or(|n| n.starts_with('.'));
        if hidden {
            skipped.temporary += 1;
            continue;
        }
        let run = match learn::read_folder(&path)? {
            Folder::Run(r) => r,
            Folder::Incomplete { path, missing } => {
                output::stderr(format!("skipping {}: incomplete (no {missing})\n", path.display()).as_bytes())?;
                skipped.incomplete += 1;
                continue;
            }
            Folder::Other => continue,
        };
        let key = (run.label.clone(), run.world.clone(), run.variant_label.clone(), run.seed);
        if let Some(first) = seen.get(&key) {
            let same = |f: &str| std::fs::read(first.join(f)).ok() == std::fs::read(run.path.join(f)).ok();
            if same("run.txt") && same("curve.csv") {
                skipped.copies += 1;
                continue;
            }
            bail!(
                "{} and {} both hold {} {} {} seed {}, with different results; keep one",
                first.display(),
                run.path.display(),
                key.0,
                key.1,
                key.2,
                key.3
            );
        }
        seen.insert(key, run.path.clone());
        runs.push(run);
    }
    if runs.is_empty() {
        bail!("{}: no finished run folders (folders as `sim-host learn` writes them)", dir.display());
    }
    Ok((runs, skipped))
}

/// Best fitness so far at `episodes`, reading a curve as a step function.
fn at(curve: &[gp::GenerationLog], episodes: f64) -> Option<f64> {
    curve.iter().take_while(|r| r.episodes as f64 <= episodes).last().map(|r| r.best_fitness)
}

fn mean_std(xs: &[f64]) -> (f64, f64) {
    let n = xs.len().max(1) as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
    (mean, var.sqrt())
}

fn median(xs: &mut [f64]) -> f64 {
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 { xs[n / 2] } else { (xs[n / 2 - 1] + xs[n / 2]) / 2.0 }
}

/// The runs of a panel grouped by series, in series order.
fn series_of<'a>(runs: &'a [Recorded], panel: &Panel) -> Vec<Vec<&'a Recorded>> {
    let mut groups: BTreeMap<(usize, String), Vec<&Recorded>> = BTreeMap::new();
    for r in runs.iter().filter(|r| r.label == panel.0 && r.world == panel.1) {
        groups.entry(series_key(r)).or_default().push(r);
    }
    groups.into_values().collect()
}

fn table(runs: &[Recorded], panels: &[Panel]) -> String {
    let tw = panels.iter().map(|p| p.0.len()).max().unwrap_or(0).max(10);
    let ww = panels.iter().map(|p| p.1.len()).max().unwrap_or(0).max(9);
    let vw = runs.iter().map(|r| r.variant_label.len()).max().unwrap_or(0).max(16);
    let mut table = format!(
        "{:<tw$} {:<ww$} {:<vw$} {:>5} {:>10} {:>10} {:>9} {:>22}\n",
        "task", "world", "variant", "seeds", "median", "mean", "planner", "episodes to planner"
    );
    for panel in panels {
        for group in series_of(runs, panel) {
            let mut finals: Vec<f64> = group.iter().filter_map(|r| r.curve.last().map(|x| x.best_fitness)).collect();
            let (mean, _) = mean_std(&finals);
            let planner = group[0].planner_fitness;
            let reached: Vec<u64> = group
                .iter()
                .filter_map(|r| r.curve.iter().find(|x| x.best_fitness >= planner).map(|x| x.episodes))
                .collect();
            let to_planner = if reached.is_empty() {
                "never".to_string()
            } else {
                let m = reached.iter().sum::<u64>() as f64 / reached.len() as f64;
                format!("{m:.0} ({}/{})", reached.len(), count(group.len(), "seed"))
            };
            table.push_str(&format!(
                "{:<tw$} {:<ww$} {:<vw$} {:>5} {:>10.3} {:>10.3} {:>9.3} {:>22}\n",
                panel.0,
                panel.1,
                group[0].variant_label,
                group.len(),
                median(&mut finals),
                mean,
                planner,
                to_planner
            ));
        }
    }
    table
}

const PANEL: (u32, u32) = (900, 460);
const LEGEND: u32 = 230;

fn size(panels: &[Panel]) -> (u32, u32, usize, usize) {
    let cols = if panels.len() > 1 { 2 } else { 1 };
    let rows = panels.len().div_ceil(cols);
    (PANEL.0 * cols as u32, PANEL.1 * rows as u32, rows, cols)
}

/// Draws the panels into a PNG (through a temporary file: plotters' encoder writes
/// files) and returns its bytes.
fn png(runs: &[Recorded], panels: &[Panel]) -> anyhow::Result<Vec<u8>> {
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| anyhow!("the embedded font cannot be read"))?;
    let (w, h, rows, cols) = size(panels);
    let dir = tempfile::tempdir().context("cannot make a temporary folder for the picture")?;
    let path = dir.path().join("curves.png");
    {
        let root = BitMapBackend::new(&path, (w, h)).into_drawing_area();
        draw(&root, runs, panels, rows, cols)?;
        root.present().map_err(|e| anyhow!("encoding the picture: {e}"))?;
    }
    std::fs::read(&path).context("reading the encoded picture")
}

fn svg(runs: &[Recorded], panels: &[Panel]) -> anyhow::Result<String> {
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| anyhow!("the embedded font cannot be read"))?;
    let (w, h, rows, cols) = size(panels);
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, (w, h)).into_drawing_area();
        draw(&root, runs, panels, rows, cols)?;
        root.present().map_err(|e| anyhow!("writing the picture: {e}"))?;
    }
    Ok(text)
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    runs: &[Recorded],
    panels: &[Panel],
    rows: usize,
    cols: usize,
) -> anyhow::Result<()> {
    root.fill(&WHITE).map_err(|e| anyhow!("drawing: {e}"))?;
    let areas = root.split_evenly((rows, cols));
    for (area, p) in areas.iter().zip(panels) {
        panel(area, runs, p).map_err(|e| anyhow!("drawing {} ({}): {e}", p.0, p.1))?;
    }
    Ok(())
}

/// A number of episodes, short: 950, 12k, 1.2M.
fn short(x: f64) -> String {
    if x >= 1e6 {
        format!("{}M", trim(x / 1e6, 1))
    } else if x >= 1e3 {
        format!("{}k", trim(x / 1e3, 1))
    } else {
        format!("{x:.0}")
    }
}

/// `v` with at most `decimals` decimals, trailing zeros dropped.
fn trim(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
}

/// The axis coordinate of a cost: `-log10(cost)`, so that better (a smaller cost) is
/// higher, as in the paper's plots, and small costs near each other stay apart.
fn axis(cost: f64) -> f64 {
    -cost.max(1e-6).log10()
}

/// The fitness axis: linear in [`axis`] of the cost, with its key points (labels and
/// grid lines) at the given values.
struct CostAxis {
    range: std::ops::Range<f64>,
    ticks: Vec<f64>,
}

impl Ranged for CostAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let span = self.range.end - self.range.start;
        let f = if span > 0.0 { (value - self.range.start) / span } else { 0.5 };
        limit.0 + (f * f64::from(limit.1 - limit.0)).round() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() { Vec::new() } else { self.ticks.clone() }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.range.clone()
    }
}

/// Costs to label between `lo` and `hi`: 1-2-5 steps, finer ones when the range is
/// small, and at worst five evenly spaced values.
fn cost_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let decades = (lo.log10().floor() as i32)..=(hi.log10().ceil() as i32);
    for mantissas in [&[1.0, 2.0, 5.0][..], &[1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]] {
        let ticks: Vec<f64> = decades
            .clone()
            .flat_map(|d| mantissas.iter().map(move |m| m * 10f64.powi(d)))
            .filter(|&v| v >= lo && v <= hi)
            .collect();
        if ticks.len() >= 3 {
            return ticks;
        }
    }
    (0..5).map(|i| lo * (hi / lo).powf(f64::from(i) / 4.0)).collect()
}

/// The largest 1-2-5 value at most `v`: the axis then ends on a labelled value (the
/// best end of the fitness axis is the one read most).
fn snap_down(v: f64) -> f64 {
    let d = 10f64.powi(v.log10().floor() as i32);
    [5.0, 2.0, 1.0].iter().map(|m| m * d).find(|&x| x <= v * (1.0 + 1e-12)).unwrap_or(d)
}

/// Fitness labels for costs, with as few decimals as keep neighbours apart (at least
/// two significant digits).
fn fitness_labels(costs: &[f64]) -> Vec<String> {
    for extra in 0..6usize {
        let labels: Vec<String> = costs
            .iter()
            .map(|&c| {
                let decimals = (1 - c.log10().floor() as i32).max(0) as usize + extra;
                format!("-{}", trim(c, decimals))
            })
            .collect();
        if labels.windows(2).all(|w| w[0] != w[1]) {
            return labels;
        }
    }
    costs.iter().map(|c| format!("-{c}")).collect()
}

fn panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, runs: &[Recorded], p: &Panel) -> anyhow::Result<()> {
    let err = |e: &dyn std::fmt::Display| anyhow!("{e}");
    let groups = series_of(runs, p);
    let max_ep =
        groups.iter().flatten().filter_map(|r| r.curve.last().map(|x| x.episodes)).max().unwrap_or(1).max(1) as f64;
    let planner_cost = -groups.first().and_then(|g| g.first()).map_or(0.0, |r| r.planner_fitness);
    const STEPS: usize = 400;
    // (colour, label, points (episodes, mean cost, band low, band high)).
    let mut series = Vec::new();
    let (mut lo, mut hi) = (planner_cost.max(1e-3), planner_cost.max(1e-3));
    for group in &groups {
        let mut pts = Vec::with_capacity(STEPS + 1);
        for i in 0..=STEPS {
            let e = max_ep * i as f64 / STEPS as f64;
            let ys: Vec<f64> = group.iter().filter_map(|r| at(&r.curve, e)).collect();
            if ys.len() == group.len() {
                let (m, s) = mean_std(&ys);
                let cost = -m;
                lo = lo.min(cost);
                hi = hi.max(cost + s);
                pts.push((e, cost, cost - s, cost + s));
            }
        }
        let label =
            format!("{} ({} seed{})", group[0].variant_label, group.len(), if group.len() == 1 { "" } else { "s" });
        series.push((colour(group[0]), label, pts));
    }
    let (lo, hi) = (snap_down((lo * 0.7).max(1e-3)), hi * 1.25);
    // The planner's level is labelled too: curves are read against it.
    let mut ticks = cost_ticks(lo, hi);
    if planner_cost > 0.0 && ticks.iter().all(|t| (t / planner_cost - 1.0).abs() > 0.15) {
        ticks.push(planner_cost);
        ticks.sort_by(f64::total_cmp);
    }
    let labels = fitness_labels(&ticks);
    let key_points: Vec<f64> = ticks.iter().map(|&c| axis(c)).collect();
    let label_of =
        |t: f64| key_points.iter().position(|&k| (k - t).abs() < 1e-9).map_or_else(String::new, |i| labels[i].clone());
    let (chart_area, legend_area) = area.split_horizontally(area.dim_in_pixel().0.saturating_sub(LEGEND));
    let title = format!("{} ({} world)", p.0, p.1);
    let y_range = CostAxis { range: axis(hi)..axis(lo), ticks: key_points.clone() };
    let mut chart = ChartBuilder::on(&chart_area)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..max_ep, y_range)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("episodes (unique simulations)")
        .y_desc("best fitness, mean ± 1 sd (log scale)")
        .x_label_formatter(&|x| short(*x))
        .y_label_formatter(&|y| label_of(*y))
        .label_style(("sans-serif", 13))
        .max_light_lines(0)
        .draw()
        .map_err(|e| err(&e))?;
    // The planner's level first, so every curve is drawn over it.
    let planner_style = RGBColor(90, 90, 90).stroke_width(2);
    if planner_cost > 0.0 {
        chart
            .draw_series(DashedLineSeries::new(
                [(0.0, axis(planner_cost)), (max_ep, axis(planner_cost))],
                8,
                6,
                planner_style,
            ))
            .map_err(|e| err(&e))?;
    }
    for (c, _, pts) in &series {
        let band: Vec<(f64, f64)> = pts
            .iter()
            .map(|&(e, _, _, h)| (e, axis(h.min(hi))))
            .chain(pts.iter().rev().map(|&(e, _, l, _)| (e, axis(l.max(lo)))))
            .collect();
        chart.draw_series(std::iter::once(Polygon::new(band, c.mix(0.12)))).map_err(|e| err(&e))?;
    }
    for (c, _, pts) in &series {
        chart
            .draw_series(LineSeries::new(pts.iter().map(|&(e, m, _, _)| (e, axis(m.max(lo)))), c.stroke_width(2)))
            .map_err(|e| err(&e))?;
    }
    // The legend beside the chart, never over a curve.
    let font = ("sans-serif", 14).into_font();
    let mut y = 56;
    for (c, label, _) in &series {
        legend_area.draw(&PathElement::new(vec![(6, y), (34, y)], c.stroke_width(3))).map_err(|e| err(&e))?;
        legend_area.draw(&Text::new(label.clone(), (42, y - 8), font.clone())).map_err(|e| err(&e))?;
        y += 24;
    }
    if planner_cost > 0.0 {
        for x in [6, 20] {
            legend_area
                .draw(&PathElement::new(vec![(x, y), (x + 9, y)], RGBColor(90, 90, 90).stroke_width(2)))
                .map_err(|e| err(&e))?;
        }
        legend_area
            .draw(&Text::new(format!("planner ({})", fitness_labels(&[planner_cost])[0]), (42, y - 8), font))
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_best_end_of_the_axis_is_a_labelled_value() {
        assert_eq!(snap_down(21.4), 20.0);
        assert_eq!(snap_down(0.7), 0.5);
        assert_eq!(snap_down(2.0), 2.0);
        assert_eq!(snap_down(1.3), 1.0);
        assert!((snap_down(0.0142) - 0.01).abs() < 1e-12);
        assert!(cost_ticks(snap_down(21.4), 400.0).contains(&20.0));
    }
}
