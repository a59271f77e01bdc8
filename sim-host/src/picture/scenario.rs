//! A scenario run as a picture: a top view of the world over the episode (the path of
//! every body, the goal region, world events marked where they happened, expansions
//! marked on the robot's path) and the tree at chosen moments (the start, after each
//! expansion, the end), each node coloured by its status then.

use std::fmt::Write as _;

use bt_core::Tree;

use super::tree::{LINE, snapshot};
use super::writer::{Boxes, document, esc};
use crate::scenario::Run;
use crate::scenario::driver::DEPTH;

const PALETTE: [&str; 6] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"];
const VIEW: f32 = 520.0;
const MARGIN: f32 = 40.0;

/// The picture of `run`, titled `title`.
#[must_use]
pub fn svg(run: &Run, title: &str) -> String {
    let mut body = String::new();
    let mut y = MARGIN;
    let _ = writeln!(body, r#"<text x="{MARGIN}" y="{y}" font-size="18" font-weight="bold">{}</text>"#, esc(title));
    y += 20.0;
    let has_view = run.record.frames.iter().any(|(_, p)| !p.is_empty());
    let mut width = 900.0f32;
    if has_view {
        top_view(&mut body, run, MARGIN, y);
        y += VIEW + 30.0;
    } else {
        let _ = writeln!(
            body,
            r##"<text x="{MARGIN}" y="{}" font-size="13" fill="#555">a symbolic world has no geometry: events and expansions are listed below</text>"##,
            y + 14.0
        );
        y += 30.0;
    }
    y = timeline(&mut body, run, MARGIN, y);
    // The tree snapshots, side by side in rows.
    let snaps = &run.record.snapshots;
    let mut x = MARGIN;
    let mut row_h = 0.0f32;
    let col_w = 430.0f32;
    for snap in snaps {
        let Ok(tree) = Tree::<'_, DEPTH>::validate(&snap.nodes, run.catalog.as_ref()) else { continue };
        let h = LINE * (tree.len() as f32 + 2.0);
        if x + col_w > 1800.0 {
            x = MARGIN;
            y += row_h + 20.0;
            row_h = 0.0;
        }
        let label = format!("tick {}: {}", snap.tick, snap.label);
        snapshot(&mut body, run.catalog.as_ref(), tree, &snap.states, (x, y), &label);
        row_h = row_h.max(h);
        x += col_w;
        width = width.max(x);
    }
    y += row_h + MARGIN;
    document(f64::from(width), f64::from(y), r#"font-family="sans-serif""#, "", &body)
}

/// Marks closer than this (pixels) share one ring and one label.
const SPOT: f32 = 8.0;

/// Where one or more marks fall in the top view.
struct Spot<'a> {
    x: f32,
    y: f32,
    colour: &'a str,
    numbers: Vec<usize>,
}

/// Paths of every named point, start and end marked, events and expansions annotated.
fn top_view(out: &mut String, run: &Run, x0: f32, y0: f32) {
    let frames = &run.record.frames;
    let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    let mut grow = |p: [f32; 2]| {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    };
    for (_, pts) in frames {
        for (_, p) in pts {
            grow(*p);
        }
    }
    if let Some((corner, size)) = run.goal_region {
        grow(corner);
        grow([corner[0] + size[0], corner[1] + size[1]]);
    }
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-3) * 1.1;
    let (cx, cy) = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
    let map = |p: [f32; 2]| -> (f32, f32) {
        (x0 + (p[0] - cx) / span * VIEW + VIEW / 2.0, y0 + VIEW / 2.0 - (p[1] - cy) / span * VIEW)
    };
    let _ = writeln!(
        out,
        r##"<rect x="{x0}" y="{y0}" width="{VIEW}" height="{VIEW}" fill="#fafafa" stroke="#999"/><text x="{}" y="{}" font-size="12" fill="#555">top view (x right, y up); {:.2} m across</text>"##,
        x0 + 4.0,
        y0 + VIEW + 14.0,
        span
    );
    if let Some((corner, size)) = run.goal_region {
        let (ax, ay) = map([corner[0], corner[1] + size[1]]);
        let (bx, by) = map([corner[0] + size[0], corner[1]]);
        let _ = writeln!(
            out,
            r##"<rect x="{ax:.1}" y="{ay:.1}" width="{:.1}" height="{:.1}" fill="#e8f5e9" stroke="#2e7d32" stroke-dasharray="4 3"/><text x="{ax:.1}" y="{:.1}" font-size="12" fill="#2e7d32">goal region</text>"##,
            bx - ax,
            by - ay,
            ay - 4.0
        );
    }
    let names: Vec<&str> = frames.first().map(|(_, p)| p.iter().map(|(n, _)| *n).collect()).unwrap_or_default();
    for (k, name) in names.iter().enumerate() {
        let colour = PALETTE.get(k % PALETTE.len()).copied().unwrap_or("#000");
        let pts: Vec<(f32, f32)> =
            frames.iter().filter_map(|(_, p)| p.iter().find(|(n, _)| n == name).map(|(_, q)| map(*q))).collect();
        let path: Vec<String> = pts.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
        let _ = writeln!(
            out,
            r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="2" opacity="0.8"/>"#,
            path.join(" ")
        );
        if let (Some(first), Some(last)) = (pts.first(), pts.last()) {
            let _ = writeln!(
                out,
                r#"<circle cx="{:.1}" cy="{:.1}" r="4" fill="white" stroke="{colour}" stroke-width="2"/><circle cx="{:.1}" cy="{:.1}" r="5" fill="{colour}"/>"#,
                first.0, first.1, last.0, last.1
            );
        }
        let _ = writeln!(
            out,
            r#"<rect x="{}" y="{}" width="12" height="4" fill="{colour}"/><text x="{}" y="{}" font-size="12">{} (open dot: start, filled: end)</text>"#,
            x0 + VIEW + 12.0,
            y0 + 10.0 + k as f32 * 16.0,
            x0 + VIEW + 28.0,
            y0 + 15.0 + k as f32 * 16.0,
            esc(name)
        );
    }
    // Events and expansions at the first point's (the robot's) position at their tick.
    let at = |tick: u32| -> Option<(f32, f32)> {
        frames.iter().find(|(t, _)| *t >= tick).and_then(|(_, p)| p.first()).map(|(_, q)| map(*q))
    };
    let mut marks: Vec<(u32, String, &str)> =
        run.record.events.iter().map(|(t, e)| (*t, e.clone(), "#d62728")).collect();
    marks.extend(
        run.record
            .expansions
            .iter()
            .enumerate()
            .map(|(i, (t, e))| (*t, format!("expansion {}: {}", i + 1, e.condition), "#6a1b9a")),
    );
    marks.sort_by_key(|m| m.0);
    // Marks where the robot stood still fall on one spot: one ring there, and their
    // numbers side by side ("1, 2, 5") in one label, placed clear of other labels.
    let mut spots: Vec<Spot<'_>> = Vec::new();
    for (n, (tick, _, colour)) in marks.iter().enumerate() {
        let Some((x, y)) = at(*tick) else { continue };
        match spots.iter_mut().find(|s| (s.x - x).abs() < SPOT && (s.y - y).abs() < SPOT) {
            Some(spot) => spot.numbers.push(n + 1),
            None => spots.push(Spot { x, y, colour, numbers: vec![n + 1] }),
        }
    }
    // Boxes already taken: the rings, the goal region's label.
    let mut taken = Boxes::default();
    for s in &spots {
        taken.take(wide([s.x - 8.0, s.y - 8.0, s.x + 8.0, s.y + 8.0]));
    }
    if let Some((corner, size)) = run.goal_region {
        let (ax, ay) = map([corner[0], corner[1] + size[1]]);
        taken.take(wide([ax, ay - 15.0, ax + 70.0, ay - 2.0]));
    }
    for spot in &spots {
        let text: Vec<String> = spot.numbers.iter().map(ToString::to_string).collect();
        let text = text.join(", ");
        let width = 7.0 * text.len() as f32;
        // A label's box from its text's start and baseline.
        let boxed = |lx: f32, ly: f32| wide([lx, ly - 10.0, lx + width, ly + 2.0]);
        // Right of the ring, above or below; left of it; then further down the right.
        let (x, y) = (spot.x, spot.y);
        let candidates =
            [(x + 9.0, y - 6.0), (x + 9.0, y + 14.0), (x - 9.0 - width, y - 6.0), (x - 9.0 - width, y + 14.0)];
        let (lx, ly) = candidates
            .into_iter()
            .chain((1..40).map(|k| (x + 9.0, y + 14.0 + 12.0 * k as f32)))
            .find(|&(lx, ly)| taken.free(boxed(lx, ly)))
            .unwrap_or((x + 9.0, y - 6.0));
        taken.take(boxed(lx, ly));
        let _ = writeln!(
            out,
            r#"<circle cx="{:.1}" cy="{:.1}" r="7" fill="none" stroke="{}" stroke-width="2"/><text x="{lx:.1}" y="{ly:.1}" font-size="11" font-weight="bold" fill="{}">{text}</text>"#,
            spot.x, spot.y, spot.colour, spot.colour
        );
    }
    for (n, (tick, text, colour)) in marks.iter().enumerate() {
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{}" font-size="12" fill="{colour}">{}. tick {tick}: {}</text>"#,
            x0 + VIEW + 12.0,
            y0 + 30.0 + (names.len() + n) as f32 * 16.0,
            n + 1,
            esc(text)
        );
    }
}

/// Without geometry: the events and expansions as a list.
fn timeline(out: &mut String, run: &Run, x0: f32, mut y: f32) -> f32 {
    if run.record.frames.iter().any(|(_, p)| !p.is_empty()) {
        return y;
    }
    let mut marks: Vec<(u32, String, &str)> =
        run.record.events.iter().map(|(t, e)| (*t, format!("world: {e}"), "#d62728")).collect();
    marks.extend(
        run.record
            .expansions
            .iter()
            .enumerate()
            .map(|(i, (t, e))| (*t, format!("expansion {}: {e}", i + 1), "#6a1b9a")),
    );
    marks.sort_by_key(|m| m.0);
    for (tick, text, colour) in marks {
        let _ = writeln!(
            out,
            r#"<text x="{x0}" y="{y}" font-size="12" fill="{colour}">tick {tick}: {}</text>"#,
            esc(&text)
        );
        y += LINE;
    }
    y + 10.0
}

/// A box in the writer's units (exact: every `f32` is an `f64`).
fn wide(b: [f32; 4]) -> [f64; 4] {
    b.map(f64::from)
}
