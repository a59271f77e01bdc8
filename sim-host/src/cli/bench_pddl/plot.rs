//! `bench-pddl --plot FILE`: the instances each planner solved against time, the way
//! planning papers draw coverage (a logarithmic time axis, one step line per planner).

use std::path::Path;

use anyhow::{Context as _, anyhow};
use plotters::prelude::*;
use plotters::style::FontStyle;

use super::super::plot::{COLOURS, FONT, Format, format_of};
use super::{Args, Row};

/// Fails early on a name that is neither .png nor .svg.
pub fn check(path: &Path) -> anyhow::Result<()> {
    format_of(path).map(|_| ()).map_err(|_| {
        anyhow!("--plot {}: the picture is written as PNG or SVG; give a name ending in .png or .svg", path.display())
    })
}

/// One line: its label and the seconds of every instance it solved, sorted (ours to
/// the closed tree, ours to the first tree, then each peer).
type Series = (String, Vec<f64>);

fn series(rows: &[Row], args: &Args) -> Vec<Series> {
    let sorted = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v
    };
    let mut out = vec![
        (
            "ours (sim-host plan)".to_string(),
            sorted(rows.iter().filter(|r| r.ours.solved()).map(|r| r.ours.seconds).collect()),
        ),
        (
            "ours, first tree (before its closure)".to_string(),
            sorted(rows.iter().filter(|r| r.ours.solved()).map(|r| r.ours.first).collect()),
        ),
    ];
    for (k, (peer, _)) in args.peers().into_iter().enumerate() {
        let secs = rows.iter().filter_map(|r| r.peers.get(k)).filter(|p| p.solved).map(|p| p.seconds).collect();
        out.push((peer.name().to_string(), sorted(secs)));
    }
    out
}

/// Writes the picture (PNG or SVG by the file's name) whole, or nothing.
pub fn write(path: &Path, rows: &[Row], args: &Args) -> anyhow::Result<()> {
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| anyhow!("the embedded font cannot be read"))?;
    let lines = series(rows, args);
    let title = format!("{}, {} s per instance", sim_host::text::count(rows.len(), "instance"), args.timeout);
    let top = args.timeout as f64;
    let size = (800, 520);
    let bytes = match format_of(path)? {
        Format::Svg => {
            let mut text = String::new();
            {
                let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
                draw(&root, &lines, &title, top, rows.len())?;
                root.present().map_err(|e| anyhow!("writing the picture: {e}"))?;
            }
            text.into_bytes()
        }
        Format::Png => {
            let dir = tempfile::tempdir().context("cannot make a temporary folder for the picture")?;
            let tmp = dir.path().join("coverage.png");
            {
                let root = BitMapBackend::new(&tmp, size).into_drawing_area();
                draw(&root, &lines, &title, top, rows.len())?;
                root.present().map_err(|e| anyhow!("encoding the picture: {e}"))?;
            }
            std::fs::read(&tmp).context("reading the encoded picture")?
        }
    };
    super::super::output::write_whole(path, &bytes)?;
    Ok(())
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    lines: &[Series],
    title: &str,
    top: f64,
    instances: usize,
) -> anyhow::Result<()> {
    let err = |e: &dyn std::fmt::Display| anyhow!("drawing: {e}");
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let low = 0.01;
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 20))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(56)
        .build_cartesian_2d((low..top.max(low * 10.0)).log_scale(), 0.0..(instances.max(1) as f64 * 1.02))
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("time per instance, s (log scale)")
        .y_desc("instances solved within that time")
        .y_label_formatter(&|y| format!("{y:.0}"))
        .label_style(("sans-serif", 13))
        .max_light_lines(0)
        .draw()
        .map_err(|e| err(&e))?;
    for (i, (label, secs)) in lines.iter().enumerate() {
        // The first-tree line in the colour of ours, lighter.
        let colour = if i == 1 { COLOURS[0].mix(0.45).to_rgba() } else { COLOURS[i % COLOURS.len()].to_rgba() };
        // A step line: at each solved instance's time the count rises by one.
        let mut pts = vec![(low, 0.0)];
        for (n, &t) in secs.iter().enumerate() {
            let t = t.max(low);
            pts.push((t, n as f64));
            pts.push((t, n as f64 + 1.0));
        }
        pts.push((top, secs.len() as f64));
        chart
            .draw_series(LineSeries::new(pts, colour.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label(format!("{label}: {}", secs.len()))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(|e| err(&e))?;
    Ok(())
}
