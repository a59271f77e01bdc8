//! A brick episode as a picture:
//!
//! - a top view (x-y) of the table: each brick's start footprint (dotted), its path over
//!   the episode (a line through every place it stood), its final footprint (filled) and
//!   its goal (dashed, with the goal height);
//! - the height (z) of each brick against ticks, with the goal heights;
//! - the tree, one row per node, with each node's status after each chosen tick (all
//!   ticks when there are at most [`MAX_COLUMNS`]; else the first, the last, those where
//!   the root's status changed, then those where an action's did), and what the hand
//!   held.
//!
//! Footprints lie as the physics world lays the bricks: 0.031 m in x, the long side
//! along y.

use std::fmt::Write as _;

use bt_core::Node;
use planner::duplo::{BRICK_2X2, BrickKind, Spec};

use super::tree::{chosen_ticks, tree_panel};
use super::writer::{Boxes, document, esc};
use crate::episode::{Episode, Trace};

/// Most tick columns in the tree panel.
pub const MAX_COLUMNS: usize = 40;

/// One recorded episode, as the picture needs it.
#[derive(Clone, Copy, Debug)]
pub struct Run<'a> {
    /// The task.
    pub spec: &'a Spec,
    /// The tree, in pre-order.
    pub nodes: &'a [Node],
    /// The episode, tick by tick.
    pub trace: &'a Trace,
    /// Its outcome and fitness.
    pub episode: &'a Episode,
    /// Which world ran it ("symbolic", "physics").
    pub world: &'a str,
}

const WIDTH: f64 = 1160.0;
pub(super) const MARGIN: f64 = 24.0;
const PANEL_TOP: f64 = 78.0;
const PANEL_H: f64 = 400.0;
pub(super) const ROW_H: f64 = 17.0;
pub(super) const CELL_W: f64 = 20.0;
const BRICK_COLORS: [&str; 4] = ["#3366cc", "#e08a00", "#8e44ad", "#17a2b8"];

pub(super) fn color(brick: usize) -> &'static str {
    BRICK_COLORS.get(brick % BRICK_COLORS.len()).copied().unwrap_or("#555555")
}

/// Footprint (x, y extents) of a brick kind, metres.
fn footprint(kind: BrickKind) -> (f64, f64) {
    let w = f64::from(BRICK_2X2);
    match kind {
        BrickKind::TwoByTwo => (w, w),
        BrickKind::FourByTwo | BrickKind::FourByTwoWithCone => (w, 2.0 * w),
        BrickKind::LongUnbalanced => (w, 4.0 * w),
    }
}

/// The picture of `run`, as an SVG document.
#[must_use]
pub fn svg(run: &Run<'_>) -> String {
    let columns = chosen_ticks(run.trace);
    let tree_top = PANEL_TOP + PANEL_H + 56.0;
    let rows = run.nodes.len() + 1;
    let height = tree_top + 40.0 + rows as f64 * ROW_H + 50.0;
    let mut defs = String::new();
    for (b, c) in BRICK_COLORS.iter().enumerate() {
        let _ = write!(
            defs,
            r#"<marker id="arrow{b}" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" markerHeight="7" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="{c}"/></marker>"#
        );
    }
    let mut s = String::new();
    header(&mut s, run);
    let half = (WIDTH - 3.0 * MARGIN) / 2.0;
    top_view(&mut s, run, MARGIN, PANEL_TOP, half, PANEL_H);
    heights(&mut s, run, 2.0 * MARGIN + half, PANEL_TOP, half, PANEL_H);
    tree_panel(&mut s, run, &columns, tree_top);
    let font = r#"font-family="DejaVu Sans, Helvetica, Arial, sans-serif" font-size="12""#;
    document(WIDTH, height, font, &defs, &s)
}

fn header(s: &mut String, run: &Run<'_>) {
    let e = run.episode;
    let f = &e.fitness;
    let _ = writeln!(
        s,
        r#"<text x="{MARGIN}" y="30" font-size="20" font-weight="bold">{} task, {} world: {}-node tree</text>"#,
        esc(run.spec.task.name()),
        esc(run.world),
        e.nodes
    );
    let outcome = match e.end {
        crate::episode::End::Success => "root Success twice in a row",
        crate::episode::End::Failure => "root Failure",
        crate::episode::End::Timeout => "timeout",
    };
    let _ = writeln!(
        s,
        r#"<text x="{MARGIN}" y="54" font-size="14">ended by {outcome} after {}{}  ·  fitness {:.3} = −({})</text>"#,
        crate::text::count(e.ticks, "tick"),
        if e.timed_out && e.end != crate::episode::End::Timeout { " (the tick limit)" } else { "" },
        f.value(),
        f.terms_text(" + ")
    );
}

/// Maps metres to pixels with equal scales in x and y.
struct View {
    x0: f64,
    y0: f64,
    scale: f64,
    left: f64,
    bottom: f64,
}

impl View {
    fn px(&self, x: f64, y: f64) -> (f64, f64) {
        (self.left + (x - self.x0) * self.scale, self.bottom - (y - self.y0) * self.scale)
    }
}

fn top_view(s: &mut String, run: &Run<'_>, left: f64, top: f64, w: f64, h: f64) {
    let spec = run.spec;
    let _ = writeln!(
        s,
        r#"<text x="{left}" y="{}" font-size="14" font-weight="bold">Top view of the table (x right, y up; metres)</text>"#,
        top - 8.0
    );
    let _ = writeln!(s, r##"<rect x="{left}" y="{top}" width="{w}" height="{h}" fill="#fbfaf6" stroke="#999"/>"##);
    // Bounds: every position the bricks took, and the goals, with room for footprints.
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    let mut grow = |p: [f32; 3]| {
        for i in 0..2 {
            lo[i] = lo[i].min(f64::from(p[i]));
            hi[i] = hi[i].max(f64::from(p[i]));
        }
    };
    for b in 0..spec.bricks.len() {
        run.trace.path(b).for_each(&mut grow);
    }
    spec.goal.iter().flatten().copied().for_each(&mut grow);
    if lo[0] > hi[0] {
        (lo, hi) = ([-0.1; 2], [0.1; 2]);
    }
    let pad = 0.075;
    let (dx, dy) = (hi[0] - lo[0] + 2.0 * pad, hi[1] - lo[1] + 2.0 * pad);
    let scale = (w / dx).min(h / dy);
    let (cx, cy) = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
    let view = View { x0: cx - w / scale / 2.0, y0: cy - h / scale / 2.0, scale, left, bottom: top + h };
    // Grid every 5 cm.
    let step = 0.05;
    let mut g = (view.x0 / step).ceil() * step;
    while g < view.x0 + w / scale {
        let (x, _) = view.px(g, 0.0);
        let _ = writeln!(s, r##"<line x1="{x:.1}" y1="{top}" x2="{x:.1}" y2="{}" stroke="#e3e0d6"/>"##, top + h);
        if x + 30.0 < left + w {
            let _ = writeln!(
                s,
                r##"<text x="{:.1}" y="{}" font-size="10" fill="#888">{:.2}</text>"##,
                x + 2.0,
                top + h - 4.0,
                tidy(g)
            );
        }
        g += step;
    }
    let mut g = (view.y0 / step).ceil() * step;
    while g < view.y0 + h / scale {
        let (_, y) = view.px(0.0, g);
        let _ = writeln!(
            s,
            r##"<line x1="{left}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#e3e0d6"/><text x="{}" y="{:.1}" font-size="10" fill="#888">{:.2}</text>"##,
            left + w,
            left + 3.0,
            y - 2.0,
            tidy(g)
        );
        g += step;
    }
    let rect = |s: &mut String, b: usize, p: [f32; 3], style: &str| {
        let (fx, fy) = footprint(spec.bricks.get(b).copied().unwrap_or(BrickKind::TwoByTwo));
        let (x, y) = view.px(f64::from(p[0]) - fx / 2.0, f64::from(p[1]) + fy / 2.0);
        let _ = writeln!(
            s,
            r#"<rect x="{x:.1}" y="{y:.1}" width="{:.1}" height="{:.1}" {style}/>"#,
            fx * scale,
            fy * scale
        );
    };
    // Goal labels: above their goal, clear of each other and of the legend (top right).
    let legend_h = 20.0 + 15.0 * spec.bricks.len() as f64;
    let mut taken = Boxes::default();
    taken.take([left + w - 210.0, top, left + w, top + legend_h]);
    for (b, goal) in spec.goal.iter().enumerate() {
        if let Some(g) = *goal {
            let c = color(b);
            rect(s, b, g, &format!(r#"fill="none" stroke="{c}" stroke-width="2" stroke-dasharray="6 3""#));
            let (x, y) = view.px(f64::from(g[0]), f64::from(g[1]));
            let text = format!("goal {b} (z {:.1} mm)", g[2] * 1000.0);
            let (lx, ly) = place_label(&mut taken, x + 2.0, y - 4.0, 5.6 * text.len() as f64, (top, top + h));
            let _ = writeln!(s, r#"<text x="{lx:.1}" y="{ly:.1}" font-size="10" fill="{c}">{text}</text>"#);
        }
    }
    let mut labels = String::new();
    for b in 0..spec.bricks.len() {
        let c = color(b);
        let mut points: Vec<(f64, f64)> = Vec::new();
        for p in run.trace.path(b) {
            let q = view.px(f64::from(p[0]), f64::from(p[1]));
            if points.last() != Some(&q) {
                points.push(q);
            }
        }
        if let Some(first) = run.trace.path(b).next() {
            rect(s, b, first, &format!(r#"fill="none" stroke="{c}" stroke-dasharray="2 2""#));
        }
        if points.len() > 1 {
            let d: Vec<String> = points.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{c}" stroke-width="2" marker-end="url(#arrow{})"/>"#,
                d.join(" "),
                b % BRICK_COLORS.len()
            );
        }
        let last = run.episode.positions().get(b).copied().unwrap_or([0.0; 3]);
        rect(s, b, last, &format!(r#"fill="{c}" fill-opacity="0.55" stroke="{c}""#));
        // Labels go on top of every footprint, side by side when bricks share a spot.
        let (x, y) = view.px(f64::from(last[0]), f64::from(last[1]));
        let x = x - 4.0 + 9.0 * b as f64 - 4.5 * (spec.bricks.len() as f64 - 1.0);
        let _ = writeln!(
            labels,
            r#"<text x="{x:.1}" y="{:.1}" font-size="12" font-weight="bold" fill="white" stroke="{c}" stroke-width="0.6">{b}</text>"#,
            y + 4.0
        );
    }
    s.push_str(&labels);
    // Legend.
    for (b, kind) in spec.bricks.iter().enumerate() {
        let y = top + 16.0 + 15.0 * b as f64;
        let held = if run.episode.held == Some(b as u8) { ", held at the end" } else { "" };
        let _ = writeln!(
            s,
            r#"<rect x="{}" y="{}" width="10" height="10" fill="{}"/><text x="{}" y="{y}">brick {b}: {}{held}</text>"#,
            left + w - 190.0,
            y - 9.0,
            color(b),
            left + w - 175.0,
            kind_name(*kind)
        );
    }
    let y = top + 16.0 + 15.0 * spec.bricks.len() as f64;
    let _ = writeln!(
        s,
        r##"<text x="{}" y="{y}" font-size="10" fill="#555">dotted: start · filled: end · dashed: goal</text>"##,
        left + w - 205.0
    );
}

/// Where a 10-pixel label of `width` wants to start (`x`, baseline `y`): there if that is
/// free of every box in `taken`, else the nearest free baseline 11 pixels further up or
/// down (within `rows`, the panel's top and bottom). Takes the box it returns.
fn place_label(taken: &mut Boxes, x: f64, y: f64, width: f64, rows: (f64, f64)) -> (f64, f64) {
    let boxed = |ly: f64| [x, ly - 9.0, x + width, ly + 2.0];
    let ly = (0..40)
        .flat_map(|k| [y - 11.0 * f64::from(k), y + 11.0 * f64::from(k)])
        .filter(|ly| *ly - 9.0 >= rows.0 && *ly + 2.0 <= rows.1)
        .find(|ly| taken.free(boxed(*ly)))
        .unwrap_or(y);
    taken.take(boxed(ly));
    (x, ly)
}

/// A grid coordinate without rounding noise or a negative zero.
fn tidy(g: f64) -> f64 {
    let r = (g * 1000.0).round() / 1000.0;
    if r == 0.0 { 0.0 } else { r }
}

fn kind_name(kind: BrickKind) -> &'static str {
    match kind {
        BrickKind::TwoByTwo => "2x2",
        BrickKind::FourByTwo => "4x2",
        BrickKind::LongUnbalanced => "8x2, unbalanced",
        BrickKind::FourByTwoWithCone => "4x2 with cone",
    }
}

fn heights(s: &mut String, run: &Run<'_>, left: f64, top: f64, w: f64, h: f64) {
    let spec = run.spec;
    let _ = writeln!(
        s,
        r#"<text x="{left}" y="{}" font-size="14" font-weight="bold">Height z of each brick (mm) against ticks</text>"#,
        top - 8.0
    );
    let (pl, pb) = (46.0, 30.0);
    let (x0, y0, pw, ph) = (left + pl, top + h - pb, w - pl - 10.0, h - pb - 10.0);
    let _ = writeln!(s, r##"<rect x="{left}" y="{top}" width="{w}" height="{h}" fill="white" stroke="#999"/>"##);
    let ticks = run.trace.ticks.len().max(1);
    let mut zmax: f64 = 0.06;
    for b in 0..spec.bricks.len() {
        for p in run.trace.path(b) {
            zmax = zmax.max(f64::from(p[2]));
        }
    }
    zmax = (zmax * 1000.0 / 10.0).ceil() * 10.0 + 10.0; // mm, a round number above
    let px = |t: f64, z_mm: f64| (x0 + t / ticks as f64 * pw, y0 - z_mm / zmax * ph);
    let mut z = 0.0;
    while z <= zmax {
        let (_, y) = px(0.0, z);
        let _ = writeln!(
            s,
            r##"<line x1="{x0}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#eee"/><text x="{}" y="{:.1}" font-size="10" text-anchor="end" fill="#666">{z:.0}</text>"##,
            x0 + pw,
            x0 - 4.0,
            y + 3.0
        );
        z += 10.0;
    }
    let every = (ticks / 15).max(1);
    for t in (0..=ticks).step_by(every) {
        let (x, _) = px(t as f64, 0.0);
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{y0}" x2="{x:.1}" y2="{:.1}" stroke="#999"/><text x="{x:.1}" y="{:.1}" font-size="10" text-anchor="middle" fill="#666">{t}</text>"##,
            y0 + 4.0,
            y0 + 15.0
        );
    }
    let _ = writeln!(
        s,
        r##"<text x="{:.1}" y="{:.1}" font-size="11" text-anchor="middle" fill="#444">tick (0 = start)</text>"##,
        x0 + pw / 2.0,
        y0 + 27.0
    );
    let _ = writeln!(
        s,
        r##"<line x1="{x0}" y1="{y0}" x2="{:.1}" y2="{y0}" stroke="#444"/><line x1="{x0}" y1="{y0}" x2="{x0}" y2="{:.1}" stroke="#444"/>"##,
        x0 + pw,
        y0 - ph
    );
    for (b, goal) in spec.goal.iter().enumerate() {
        if let Some(g) = *goal {
            let (_, y) = px(0.0, f64::from(g[2]) * 1000.0);
            let _ = writeln!(
                s,
                r#"<line x1="{x0}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="{}" stroke-dasharray="6 3"/><text x="{:.1}" y="{:.1}" font-size="10" text-anchor="end" fill="{}">goal {b}</text>"#,
                x0 + pw,
                color(b),
                x0 + pw - 2.0 - 42.0 * b as f64,
                y - 3.0,
                color(b)
            );
        }
    }
    for b in 0..spec.bricks.len() {
        let points: Vec<String> = run
            .trace
            .path(b)
            .enumerate()
            .map(|(t, p)| {
                let (x, y) = px(t as f64, f64::from(p[2]) * 1000.0);
                // Bricks at the same height would hide each other: a hair apart.
                format!("{x:.1},{:.1}", y - 1.5 * b as f64)
            })
            .collect();
        let _ = writeln!(
            s,
            r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="2"/>"#,
            points.join(" "),
            color(b)
        );
        let y = top + 16.0 + 15.0 * b as f64;
        let _ = writeln!(
            s,
            r#"<rect x="{}" y="{}" width="10" height="10" fill="{}"/><text x="{}" y="{y}">brick {b}</text>"#,
            left + w - 80.0,
            y - 9.0,
            color(b),
            left + w - 65.0
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::episode::Runner;
    use crate::symbolic::SymbolicBrickWorld;
    use bt_core::{NodeStatus, Status};
    use planner::duplo::Task;

    #[test]
    fn draws_paths_goals_heights_and_the_tree() {
        let spec = Task::Tower.spec();
        let nodes = bt_formats::tokens::parse("s( pick 1! place on 0! apply force 1! )", &spec).unwrap();
        let tree: bt_core::Tree<'_, 8> = bt_core::Tree::validate(&nodes, &spec).unwrap();
        let mut runner = Runner::new(SymbolicBrickWorld::new(&spec).unwrap()).unwrap();
        let mut trace = Trace::default();
        let episode = runner.run_recorded(tree, &mut trace).unwrap();
        let doc = svg(&Run { spec: &spec, nodes: &nodes, trace: &trace, episode: &episode, world: "symbolic" });
        assert!(doc.starts_with("<svg ") && doc.trim_end().ends_with("</svg>"));
        // One footprint per goal (dashed), per start (dotted) and per end (filled).
        assert_eq!(doc.matches(r#"stroke-dasharray="6 3""#).count(), 3 + 3, "goal footprints and goal heights");
        assert_eq!(doc.matches("fill-opacity=\"0.55\"").count(), 3);
        // Brick 1 moved: one path with an arrow; the others did not.
        assert_eq!(doc.matches("marker-end=").count(), 1);
        // A row per node, a cell per node and tick.
        assert!(doc.contains(">place on 0!</text>"));
        assert_eq!(doc.matches(r#"rx="2""#).count(), nodes.len() * trace.ticks.len());
        assert!(doc.contains("fitness"));
    }

    #[test]
    fn goal_labels_clear_each_other_and_the_legend() {
        // Croissant: goals 0 and 1 share a spot, goal 3's label hit the legend.
        for task in Task::ALL {
            let spec = task.spec();
            let plan = planner::duplo::plan(task).unwrap();
            let tree: bt_core::Tree<'_, 64> = bt_core::Tree::validate(&plan.nodes, &spec).unwrap();
            let mut runner = Runner::new(SymbolicBrickWorld::new(&spec).unwrap()).unwrap();
            let mut trace = Trace::default();
            let episode = runner.run_recorded(tree, &mut trace).unwrap();
            let doc =
                svg(&Run { spec: &spec, nodes: &plan.nodes, trace: &trace, episode: &episode, world: "symbolic" });
            // Boxes of the goal labels and the legend's texts: x, baseline, text.
            let num = |tag: &str, name: &str| -> f64 {
                let from = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
                tag[from..from + tag[from..].find('"').unwrap()].parse().unwrap()
            };
            let boxes: Vec<([f64; 4], String)> = doc
                .split("<text")
                .skip(1)
                .filter_map(|t| {
                    let (tag, rest) = t.split_once('>')?;
                    let text = rest.split_once("</text>")?.0.to_string();
                    let legend = text.starts_with("brick ") || text.starts_with("dotted:");
                    (text.starts_with("goal ") && text.contains("(z") || legend).then(|| {
                        let (x, y) = (num(tag, "x"), num(tag, "y"));
                        ([x, y - 9.0, x + 5.6 * text.chars().count() as f64, y + 2.0], text)
                    })
                })
                .collect();
            assert!(boxes.iter().filter(|b| b.1.starts_with("goal ")).count() >= 1, "{task:?}");
            for (i, (a, an)) in boxes.iter().enumerate() {
                for (b, bn) in boxes.iter().skip(i + 1) {
                    let overlap = a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3];
                    assert!(!overlap, "{task:?}: `{an}` and `{bn}` overlap");
                }
            }
        }
    }

    #[test]
    fn long_episodes_show_chosen_ticks_only() {
        let mut trace = Trace::default();
        for t in 0..200 {
            trace.ticks.push(crate::episode::TickRecord {
                root: if t < 100 { Status::Running } else { Status::Failure },
                nodes: vec![if t % 7 == 0 { NodeStatus::Running } else { NodeStatus::Success }],
                positions: vec![],
                held: None,
            });
        }
        let chosen = chosen_ticks(&trace);
        assert_eq!(chosen.len(), MAX_COLUMNS);
        assert!(chosen.contains(&0) && chosen.contains(&199) && chosen.contains(&100));
        assert!(chosen.windows(2).all(|w| w[0] < w[1]));
    }
}
