//! `sim-host plot DIR [--out FILE.png]`: learning curves like Figs. 6-11 of seed 003.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};
use gp::Variant;
use plotters::prelude::*;
use plotters::style::FontStyle;
use sim_host::learn::{self, Recorded};
use sim_host::scenario::WorldKind;

use super::output::{self, Content, Target};

pub const LONG_ABOUT: &str = "Reads every run folder under DIR (as written by `sim-host learn`, \
from any number of machines) and draws the learning curves like Figs. 6-11 of seed 003: one \
panel per task and world, one curve per variant, the mean over seeds of the best fitness so \
far with a band of one standard deviation, against episodes (unique simulations), and the \
planner's fitness as a dotted line. Seeds reach episodes at different generations, so each \
curve is read as a step function (the best so far at that episode) on a common grid. Also \
prints a table: seeds, median and mean final best fitness, and how many episodes each \
variant needed to reach the planner's level.";

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The folder holding run folders (searched one level down).
    pub dir: PathBuf,
    /// The PNG to write (default: DIR/curves.png; `-`: stdout, the table then goes to
    /// stderr).
    #[arg(long, value_name = "FILE", value_parser = Target::parse)]
    pub out: Option<Target>,
}

/// The font every label uses, embedded so the picture needs no system fonts.
static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

const COLOURS: [RGBColor; 4] =
    [RGBColor(214, 39, 40), RGBColor(31, 119, 180), RGBColor(44, 160, 44), RGBColor(0, 0, 0)];

fn colour(v: Variant) -> RGBColor {
    // The paper's colours: no baseline red, baseline blue, boost crossover green, boost all black.
    COLOURS[Variant::ALL.iter().position(|&x| x == v).unwrap_or(0) % COLOURS.len()]
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let runs = read_runs(&args.dir)?;
    let mut panels: Vec<(planner::duplo::Task, WorldKind)> = runs.iter().map(|r| (r.task, r.world)).collect();
    panels.sort_by_key(|&(t, w)| (t, w.name()));
    panels.dedup();
    let out = args.out.clone().unwrap_or_else(|| Target::File(args.dir.join("curves.png")));
    let content = Content::Binary("a PNG picture");
    output::check(&out, content)?;
    let table = table(&runs, &panels);
    let png = draw(&runs, &panels)?;
    output::write(&out, &png, content)?;
    match out {
        Target::File(path) => output::stdout(format!("{table}curves: {}\n", path.display()).as_bytes())?,
        Target::Stdout => output::stderr(table.as_bytes())?,
    }
    Ok(())
}

fn read_runs(dir: &Path) -> anyhow::Result<Vec<Recorded>> {
    let entries = std::fs::read_dir(dir).with_context(|| format!("cannot read {}", dir.display()))?;
    let mut runs = Vec::new();
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for path in paths {
        if path.is_dir() && path.join("run.txt").exists() {
            runs.push(learn::read_folder(&path)?);
        }
    }
    if runs.is_empty() {
        bail!("{}: no run folders (folders with a run.txt, as `sim-host learn` writes)", dir.display());
    }
    Ok(runs)
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

fn table(runs: &[Recorded], panels: &[(planner::duplo::Task, WorldKind)]) -> String {
    let mut table = format!(
        "{:<10} {:<9} {:<16} {:>5} {:>10} {:>10} {:>9} {:>22}\n",
        "task", "world", "variant", "seeds", "median", "mean", "planner", "episodes to planner"
    );
    for &(task, world) in panels {
        for v in Variant::ALL {
            let group: Vec<&Recorded> =
                runs.iter().filter(|r| r.task == task && r.world == world && r.variant == v).collect();
            if group.is_empty() {
                continue;
            }
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
                format!("{m:.0} ({}/{} seeds)", reached.len(), group.len())
            };
            table.push_str(&format!(
                "{:<10} {:<9} {:<16} {:>5} {:>10.3} {:>10.3} {:>9.3} {:>22}\n",
                task.name(),
                world.name(),
                v.name(),
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

/// Draws the panels into a PNG (through a temporary file: plotters' encoder writes
/// files) and returns its bytes.
fn draw(runs: &[Recorded], panels: &[(planner::duplo::Task, WorldKind)]) -> anyhow::Result<Vec<u8>> {
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| anyhow::anyhow!("the embedded font cannot be read"))?;
    let cols = if panels.len() > 1 { 2 } else { 1 };
    let rows = panels.len().div_ceil(cols);
    let (w, h) = (700 * cols as u32, 480 * rows as u32);
    let dir = tempfile::tempdir().context("cannot make a temporary folder for the picture")?;
    let path = dir.path().join("curves.png");
    {
        let root = BitMapBackend::new(&path, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow::anyhow!("drawing: {e}"))?;
        let areas = root.split_evenly((rows, cols));
        for (area, &(task, world)) in areas.iter().zip(panels) {
            panel(area, runs, task, world).map_err(|e| anyhow::anyhow!("drawing {}: {e}", task.name()))?;
        }
        root.present().map_err(|e| anyhow::anyhow!("encoding the picture: {e}"))?;
    }
    std::fs::read(&path).context("reading the encoded picture")
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

fn panel(
    area: &Area<'_>,
    runs: &[Recorded],
    task: planner::duplo::Task,
    world: WorldKind,
) -> Result<(), Box<dyn std::error::Error>> {
    let mine: Vec<&Recorded> = runs.iter().filter(|r| r.task == task && r.world == world).collect();
    let max_ep = mine.iter().filter_map(|r| r.curve.last().map(|x| x.episodes)).max().unwrap_or(1) as f64;
    let planner = mine.first().map_or(0.0, |r| r.planner_fitness);
    // The band of interest: from a little below the planner (or the worst mean) to 0.
    let mut series = Vec::new();
    let mut lo = planner.min(-1.0);
    const STEPS: usize = 400;
    for v in Variant::ALL {
        let group: Vec<&&Recorded> = mine.iter().filter(|r| r.variant == v).collect();
        if group.is_empty() {
            continue;
        }
        let mut pts = Vec::with_capacity(STEPS);
        for i in 0..=STEPS {
            let e = max_ep * i as f64 / STEPS as f64;
            let ys: Vec<f64> = group.iter().filter_map(|r| at(&r.curve, e)).collect();
            if ys.len() == group.len() {
                let (m, s) = mean_std(&ys);
                lo = lo.min(m - s);
                pts.push((e, m, s));
            }
        }
        series.push((v, group.len(), pts));
    }
    let lo = (lo * 1.05).max(-1000.0);
    let title = format!("{} ({} world)", task.name(), world.name());
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..max_ep, lo..0.5f64)?;
    chart
        .configure_mesh()
        .x_desc("episodes (unique simulations)")
        .y_desc("best fitness (mean ± 1 sd over seeds)")
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_label_formatter(&|y| format!("{y:.0}"))
        .label_style(("sans-serif", 13))
        .draw()?;
    for (v, n, pts) in &series {
        let c = colour(*v);
        let band: Vec<(f64, f64)> = pts
            .iter()
            .map(|&(e, m, s)| (e, (m + s).min(0.5)))
            .chain(pts.iter().rev().map(|&(e, m, s)| (e, (m - s).max(lo))))
            .collect();
        chart.draw_series(std::iter::once(Polygon::new(band, c.mix(0.15))))?;
        chart
            .draw_series(LineSeries::new(pts.iter().map(|&(e, m, _)| (e, m.max(lo))), c.stroke_width(2)))?
            .label(format!("{} ({})", v.name(), sim_host::text::count(*n, "seed")))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)));
    }
    // The planner's fitness, dotted.
    let dots: Vec<(f64, f64)> = (0..=60).map(|i| (max_ep * f64::from(i) / 60.0, planner)).collect();
    chart
        .draw_series(dots.iter().map(|&p| Circle::new(p, 2, BLACK.filled())))?
        .label(format!("planner ({planner:.1})"))
        .legend(|(x, y)| Circle::new((x + 9, y), 2, BLACK.filled()));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()?;
    Ok(())
}
