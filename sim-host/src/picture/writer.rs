//! The one SVG writer every picture goes through: the document, text escaping, boxes
//! that labels keep clear of, and how a node's status and kind are shown.

use std::fmt::Write as _;

use bt_core::{NodeKind, NodeStatus};

/// `s` as SVG text or attribute value.
pub(super) fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// A whole document of `width` by `height` pixels on white: `font` holds the root's
/// font attributes, `defs` what goes in `<defs>` (none if empty), `body` the drawing.
pub(super) fn document(width: f64, height: f64, font: &str, defs: &str, body: &str) -> String {
    let mut doc = String::new();
    let _ = writeln!(
        doc,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" {font}>"#
    );
    if !defs.is_empty() {
        let _ = writeln!(doc, "<defs>{defs}</defs>");
    }
    let _ = writeln!(doc, r#"<rect width="100%" height="100%" fill="white"/>"#);
    doc.push_str(body);
    doc.push_str("</svg>\n");
    doc
}

/// Boxes already drawn (left, top, right, bottom), that labels must not cover.
#[derive(Debug, Default)]
pub(super) struct Boxes(Vec<[f64; 4]>);

impl Boxes {
    /// Whether `b` overlaps none of the boxes.
    pub(super) fn free(&self, b: [f64; 4]) -> bool {
        !self.0.iter().any(|t| b[0] < t[2] && t[0] < b[2] && b[1] < t[3] && t[1] < b[3])
    }

    /// Marks `b` as drawn.
    pub(super) fn take(&mut self, b: [f64; 4]) {
        self.0.push(b);
    }
}

/// A node's status as a colour and a mark: green ✓, red ✕, amber ▶, grey for a node
/// not ticked in this activation (or halted).
pub(super) const fn status_style(s: NodeStatus) -> (&'static str, &'static str) {
    match s {
        NodeStatus::Idle => ("#eeeeee", ""),
        NodeStatus::Success => ("#2e9e44", "✓"),
        NodeStatus::Failure => ("#d62828", "✕"),
        NodeStatus::Running => ("#f4b400", "▶"),
    }
}

/// How a control node is named in a picture, `None` for leaves.
pub(super) fn control_label(kind: &NodeKind) -> Option<String> {
    match kind {
        NodeKind::Sequence => Some("→ Sequence".into()),
        NodeKind::Fallback => Some("? Fallback".into()),
        NodeKind::Inverter => Some("¬ Inverter".into()),
        NodeKind::Condition(_) | NodeKind::Action(_) => None,
        other => Some(other.name().into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_document_escapes_nothing_it_is_given_and_closes() {
        let doc = document(10.0, 20.5, r#"font-family="x""#, "", "<g/>\n");
        assert!(doc.starts_with(r#"<svg xmlns="http://www.w3.org/2000/svg" width="10" height="20""#));
        assert!(doc.ends_with("<g/>\n</svg>\n") && !doc.contains("<defs>"));
        assert_eq!(esc(r#"a<b & "c">"#), "a&lt;b &amp; &quot;c&quot;&gt;");
    }

    #[test]
    fn boxes_that_touch_do_not_overlap() {
        let mut b = Boxes::default();
        b.take([0.0, 0.0, 10.0, 10.0]);
        assert!(b.free([10.0, 0.0, 20.0, 10.0]));
        assert!(!b.free([9.0, 9.0, 20.0, 20.0]));
    }
}
