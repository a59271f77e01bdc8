//! Trees in pictures: the panel of a brick episode (one row per node, its status after
//! each chosen tick) and a scenario's snapshot (the tree at one moment, each node
//! coloured by its status then).

use std::fmt::Write as _;

use bt_core::{Catalog, NodeKind, NodeState, NodeStatus, Status, Tree};
use planner::duplo::Spec;

use super::bricks::{CELL_W, MARGIN, MAX_COLUMNS, ROW_H, Run, color};
use super::writer::{control_label, esc, status_style};
use crate::episode::Trace;
use crate::scenario::driver::{DEPTH, leaf_name};

/// The ticks (0-based indices into the trace) the tree panel shows: all of them when
/// they fit; else the first and the last, the ticks where the root's status changed,
/// then ticks where any node's did, each group thinned evenly to what still fits.
pub(super) fn chosen_ticks(trace: &Trace) -> Vec<usize> {
    let n = trace.ticks.len();
    if n <= MAX_COLUMNS {
        return (0..n).collect();
    }
    let root = |t: usize| trace.ticks.get(t).map(|r| r.root);
    let nodes = |t: usize| trace.ticks.get(t).map(|r| &r.nodes);
    let mut chosen: Vec<usize> = vec![0, n - 1];
    let root_changes: Vec<usize> = (1..n - 1).filter(|&t| root(t - 1) != root(t)).collect();
    let node_changes: Vec<usize> = (1..n - 1).filter(|&t| root(t - 1) == root(t) && nodes(t - 1) != nodes(t)).collect();
    for group in [root_changes, node_changes] {
        let room = MAX_COLUMNS.saturating_sub(chosen.len());
        if group.len() <= room {
            chosen.extend(group);
        } else if room > 0 {
            chosen.extend((0..room).filter_map(|k| group.get(k * group.len() / room)));
        }
    }
    chosen.sort_unstable();
    chosen.dedup();
    chosen
}

fn node_label(spec: &Spec, kind: &NodeKind) -> String {
    match kind {
        NodeKind::Condition(l) | NodeKind::Action(l) => {
            spec.names.get(usize::from(l.behavior())).cloned().unwrap_or_else(|| format!("#{}", l.behavior()))
        }
        other => control_label(other).unwrap_or_default(),
    }
}

pub(super) fn tree_panel(s: &mut String, run: &Run<'_>, columns: &[usize], top: f64) {
    let _ = writeln!(
        s,
        r#"<text x="{MARGIN}" y="{}" font-size="14" font-weight="bold">The tree: each node's status after each tick</text>"#,
        top - 26.0
    );
    let legend = [
        (NodeStatus::Success, "Success"),
        (NodeStatus::Failure, "Failure"),
        (NodeStatus::Running, "Running"),
        (NodeStatus::Idle, "not ticked / halted"),
    ];
    for (i, (st, name)) in legend.iter().enumerate() {
        let (fill, glyph) = status_style(*st);
        let x = MARGIN + 400.0 + 110.0 * i as f64;
        let _ = writeln!(
            s,
            r##"<rect x="{x}" y="{}" width="14" height="13" fill="{fill}"/><text x="{}" y="{}" font-size="10" fill="white">{glyph}</text><text x="{}" y="{}">{name}</text>"##,
            top - 37.0,
            x + 2.5,
            top - 27.0,
            x + 18.0,
            top - 27.0
        );
    }
    let label_w = 470.0;
    let grid_x = MARGIN + label_w;
    let _ = writeln!(s, r##"<text x="{MARGIN}" y="{}" fill="#555">tick →</text>"##, top + 12.0);
    for (c, &t) in columns.iter().enumerate() {
        let x = grid_x + c as f64 * CELL_W + CELL_W / 2.0;
        let changed = t == 0 || run.trace.ticks.get(t - 1).map(|r| r.root) != run.trace.ticks.get(t).map(|r| r.root);
        let weight = if changed { "bold" } else { "normal" };
        let _ = writeln!(
            s,
            r#"<text x="{x:.1}" y="{}" font-size="10" text-anchor="middle" font-weight="{weight}">{}</text>"#,
            top + 12.0,
            t + 1
        );
    }
    let mut ends: Vec<usize> = Vec::new();
    let y_of = |i: usize| top + 20.0 + i as f64 * ROW_H;
    for (i, node) in run.nodes.iter().enumerate() {
        while ends.last().is_some_and(|&e| e <= i) {
            ends.pop();
        }
        let depth = ends.len() as f64;
        let y = y_of(i);
        if i % 2 == 0 {
            let _ = writeln!(
                s,
                r##"<rect x="{MARGIN}" y="{y:.1}" width="{:.1}" height="{ROW_H}" fill="#f6f6f6"/>"##,
                label_w + columns.len() as f64 * CELL_W
            );
        }
        let x = MARGIN + 6.0 + depth * 16.0;
        if depth > 0.0 {
            let _ = writeln!(
                s,
                r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#aaa"/>"##,
                x - 12.0,
                y + ROW_H / 2.0,
                x - 3.0,
                y + ROW_H / 2.0
            );
        }
        let size = usize::from(node.size());
        if size > 1 {
            // A guide from this control node down to its last child.
            let last_child = {
                let mut c = i + 1;
                let mut last = c;
                while c < i + size {
                    last = c;
                    c += run.nodes.get(c).map_or(1, |n| usize::from(n.size()).max(1));
                }
                last
            };
            let _ = writeln!(
                s,
                r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#aaa"/>"##,
                x + 4.0,
                y + ROW_H - 2.0,
                x + 4.0,
                y_of(last_child) + ROW_H / 2.0
            );
            ends.push(i + size);
        }
        let weight = if size > 1 { "bold" } else { "normal" };
        let _ = writeln!(
            s,
            r#"<text x="{x:.1}" y="{:.1}" font-weight="{weight}">{}</text>"#,
            y + 12.5,
            esc(&node_label(run.spec, node.kind()))
        );
        for (c, &t) in columns.iter().enumerate() {
            let st = run.trace.ticks.get(t).and_then(|r| r.nodes.get(i)).copied().unwrap_or(NodeStatus::Idle);
            cell(s, grid_x + c as f64 * CELL_W, y, st);
        }
    }
    // What the hand held after each chosen tick.
    let y = y_of(run.nodes.len());
    let _ = writeln!(
        s,
        r##"<text x="{MARGIN}" y="{:.1}" fill="#555" font-style="italic">brick held after the tick</text>"##,
        y + 12.5
    );
    for (c, &t) in columns.iter().enumerate() {
        if let Some(b) = run.trace.ticks.get(t).and_then(|r| r.held) {
            let x = grid_x + c as f64 * CELL_W;
            let _ = writeln!(
                s,
                r#"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="{}" rx="3"/><text x="{:.1}" y="{:.1}" font-size="10" fill="white" text-anchor="middle">{b}</text>"#,
                x + 1.0,
                y + 1.0,
                CELL_W - 2.0,
                ROW_H - 2.0,
                color(usize::from(b)),
                x + CELL_W / 2.0,
                y + 12.0
            );
        }
    }
    if run.trace.ticks.len() > columns.len() {
        let _ = writeln!(
            s,
            r##"<text x="{MARGIN}" y="{:.1}" font-size="10" fill="#555">{} of {} shown: the first, the last, those where the root's status changed (bold), then those where a node's did.</text>"##,
            y + 32.0,
            columns.len(),
            crate::text::count(run.trace.ticks.len(), "tick")
        );
    }
    let root_line = run.trace.ticks.iter().map(|r| match r.root {
        Status::Success => 'S',
        Status::Failure => 'F',
        Status::Running => 'R',
        Status::Skipped => 'K',
    });
    let _ = writeln!(
        s,
        r##"<text x="{MARGIN}" y="{:.1}" font-size="10" fill="#555" font-family="DejaVu Sans Mono, monospace">root by tick: {}</text>"##,
        y + 46.0,
        root_line.collect::<String>()
    );
}

fn cell(s: &mut String, x: f64, y: f64, st: NodeStatus) {
    let (fill, glyph) = status_style(st);
    let _ = write!(
        s,
        r#"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="{fill}" rx="2"/>"#,
        x + 1.0,
        y + 1.0,
        CELL_W - 2.0,
        ROW_H - 2.0
    );
    if !glyph.is_empty() {
        let _ = write!(
            s,
            r#"<text x="{:.1}" y="{:.1}" font-size="10" fill="white" text-anchor="middle">{glyph}</text>"#,
            x + CELL_W / 2.0,
            y + 12.0
        );
    }
    s.push('\n');
}

/// Line height of a snapshot, pixels.
pub(super) const LINE: f32 = 15.0;

/// The tree at one moment, titled `label`, from (`x0`, `y0`): one line per node,
/// indented by depth, coloured by its status in `states` (none: all grey).
pub(super) fn snapshot<C: Catalog + ?Sized>(
    out: &mut String,
    catalog: &C,
    tree: Tree<'_, DEPTH>,
    states: &[NodeState],
    (x0, y0): (f32, f32),
    label: &str,
) {
    let _ = writeln!(out, r#"<text x="{x0}" y="{y0}" font-size="13" font-weight="bold">{}</text>"#, esc(label));
    let mut ends: Vec<usize> = Vec::new();
    for (i, node) in tree.nodes().iter().enumerate() {
        while ends.last().is_some_and(|&e| e <= i) {
            ends.pop();
        }
        let depth = ends.len() as f32;
        let (fill, mark) = match states.get(i).map(NodeState::status) {
            None | Some(NodeStatus::Idle) => ("#333", String::new()),
            Some(s) => {
                let (fill, glyph) = status_style(s);
                (fill, format!(" {glyph}"))
            }
        };
        let text = match node.kind() {
            NodeKind::Condition(l) => format!("({})", leaf_name(catalog, l)),
            NodeKind::Action(l) => format!("[{}]", leaf_name(catalog, l)),
            other => control_label(other).unwrap_or_default(),
        };
        let _ = writeln!(
            out,
            r#"<text x="{:.1}" y="{:.1}" font-size="12" fill="{fill}">{}{mark}</text>"#,
            x0 + 14.0 * depth,
            y0 + LINE * (i as f32 + 1.2),
            esc(&text)
        );
        if node.kind().arity() != bt_core::Arity::Leaf {
            ends.push(i + usize::from(node.size()));
        }
    }
}
