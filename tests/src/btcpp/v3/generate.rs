//! Random version 3 documents, from a seed: the cases `tests/btcpp/v3/record.sh` gives
//! BehaviorTree.CPP 3.8.
//!
//! A document has a main tree and up to two subtrees (`S1` may call `S2`, never the
//! other way), called by `<SubTree>` remapping by name (or sharing the blackboard) and by
//! `<SubTreePlus>` (`{key}` and `${key}` remapped, literals, `__autoremap`). Leaves are
//! scripted conditions `C0`..`C2` and actions `A3`..`A5` with an input port `in` and an
//! output port `out` (both `int`), given `{key}`, `${key}`, literals, and on `out` a
//! key's name (which version 3 writes), `SetBlackboard`, `AlwaysSuccess` and
//! `AlwaysFailure`. Keys: `a`, `b`, `c` in the main tree, which sets them first; `a`,
//! `b`, `x`, `y` in subtrees. Decorators: version 3's `Repeat` and
//! `RetryUntilSuccessful` (counts from a `{key}` too), `BlackboardCheckInt`, and the
//! others BehaviorTree.CPP 3.8 has.

use std::fmt::Write as _;

use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{Case, LeafType};

/// Ticks every case runs.
pub const TICKS: u32 = 20;
/// Milliseconds between ticks in cases with `Timeout` or `Delay` (their spans are odd
/// multiples of half of it, as in the version 4 cases).
pub const PERIOD_MS: u32 = 100;
/// Deepest nesting within one tree, its root included.
const MAX_DEPTH: usize = 5;

/// The leaf types: conditions `C0`..`C2`, actions `A3`..`A5`.
const TYPES: [&str; 6] = ["C0", "C1", "C2", "A3", "A4", "A5"];

struct Gen {
    rng: ChaCha8Rng,
    timed: bool,
    budget: usize,
}

fn pick<T: Copy>(rng: &mut impl Rng, items: &[T]) -> T {
    items[rng.random_range(0..items.len())]
}

impl Gen {
    fn keys(tree: usize) -> &'static [&'static str] {
        if tree == 0 { &["a", "b", "c"] } else { &["a", "b", "x", "y"] }
    }

    fn key(&mut self, tree: usize) -> &'static str {
        pick(&mut self.rng, Self::keys(tree))
    }

    /// A value for an input port: a key (both syntaxes) or a literal.
    fn input(&mut self, tree: usize) -> String {
        let k = self.key(tree);
        match self.rng.random_range(0..5) {
            0 | 1 => format!("{{{k}}}"),
            2 => format!("${{{k}}}"),
            3 => pick(&mut self.rng, &["2", "5", "-1"]).to_string(),
            _ => format!("{{{k}}}"),
        }
    }

    fn count(&mut self, tree: usize) -> String {
        if self.rng.random_bool(0.2) {
            format!("{{{}}}", self.key(tree))
        } else {
            pick(&mut self.rng, &["-1", "0", "1", "2", "3"]).to_string()
        }
    }

    fn leaf(&mut self, tree: usize, subtrees: usize, out: &mut String) {
        let callable: Vec<usize> = (tree + 1..=subtrees).collect();
        let roll = self.rng.random_range(0..100);
        if roll < 20 && !callable.is_empty() {
            let s = pick(&mut self.rng, &callable);
            let a = self.key(tree);
            let b = self.key(tree);
            match self.rng.random_range(0..4) {
                0 => {
                    let _ = write!(out, r#"<SubTree ID="S{s}" __shared_blackboard="true"/>"#);
                }
                1 => {
                    let y = if self.rng.random_bool(0.5) { "3".to_string() } else { format!("${{{b}}}") };
                    let auto = pick(&mut self.rng, &["true", "false", "1"]);
                    let _ = write!(out, r#"<SubTreePlus ID="S{s}" x="{{{a}}}" y="{y}" __autoremap="{auto}"/>"#);
                }
                _ => {
                    let _ = write!(out, r#"<SubTree ID="S{s}" x="{a}" y="{b}"/>"#);
                }
            }
        } else if roll < 35 {
            let k = self.key(tree);
            // A copy only in the main tree, whose keys its prologue sets: copying an entry
            // never written is a documented difference.
            let value = match self.rng.random_range(0..4) {
                0 => "7".to_string(),
                1 => "12".to_string(),
                2 if tree == 0 => format!("{{{}}}", self.key(tree)),
                _ => "1".to_string(),
            };
            let _ = write!(out, r#"<SetBlackboard output_key="{k}" value="{value}"/>"#);
        } else if roll < 42 {
            out.push_str(pick(&mut self.rng, &["<AlwaysSuccess/>", "<AlwaysFailure/>"]));
        } else {
            let t = pick(&mut self.rng, &TYPES);
            let _ = write!(out, "<{t}");
            if self.rng.random_bool(0.7) {
                let v = self.input(tree);
                let _ = write!(out, r#" in="{v}""#);
            }
            if self.rng.random_bool(0.5) {
                let k = self.key(tree);
                let v = if self.rng.random_bool(0.5) { format!("{{{k}}}") } else { k.to_string() };
                let _ = write!(out, r#" out="{v}""#);
            }
            out.push_str("/>");
        }
    }

    fn node(&mut self, depth: usize, tree: usize, subtrees: usize, out: &mut String) {
        self.budget = self.budget.saturating_sub(1);
        let leaf_chance = if depth >= MAX_DEPTH || self.budget < 3 { 1.0 } else { 0.15 + 0.12 * depth as f64 };
        if self.rng.random_bool(leaf_chance.min(1.0)) {
            self.leaf(tree, subtrees, out);
            return;
        }
        if self.rng.random_bool(0.35) {
            let half = PERIOD_MS / 2;
            let mut kinds: Vec<String> = vec![
                "Inverter".into(),
                "ForceSuccess".into(),
                "ForceFailure".into(),
                format!(r#"Repeat num_cycles="{}""#, self.count(tree)),
                format!(r#"RetryUntilSuccessful num_attempts="{}""#, self.count(tree)),
                "KeepRunningUntilFailure".into(),
                format!(
                    r#"BlackboardCheckInt value_A="{{{}}}" value_B="{}" return_on_mismatch="{}""#,
                    self.key(tree),
                    pick(&mut self.rng, &["7", "12", "1"]),
                    pick(&mut self.rng, &["SUCCESS", "FAILURE", "RUNNING"])
                ),
            ];
            if self.timed {
                let ms = pick(&mut self.rng, &[half, 3 * half, 5 * half]);
                kinds.push(format!(r#"Timeout msec="{ms}""#));
                kinds.push(format!(r#"Delay delay_msec="{ms}""#));
            }
            let open = pick(&mut self.rng, &kinds.iter().map(String::as_str).collect::<Vec<_>>()).to_string();
            let tag = open.split(' ').next().unwrap_or("").to_string();
            let _ = write!(out, "<{open}>");
            self.node(depth + 1, tree, subtrees, out);
            let _ = write!(out, "</{tag}>");
            return;
        }
        let shape = self.rng.random_range(0..9);
        let n = match shape {
            7 => self.rng.random_range(2..=3),
            8 => 3,
            _ => self.rng.random_range(1..=4),
        };
        let mut children = String::new();
        let mut count = 0;
        for _ in 0..n {
            if self.budget == 0 && count > 0 {
                break;
            }
            self.node(depth + 1, tree, subtrees, &mut children);
            count += 1;
        }
        if matches!(shape, 7 | 8) {
            while count < if shape == 8 { 3 } else { 2 } {
                self.leaf(tree, subtrees, &mut children);
                count += 1;
            }
        }
        let threshold = |rng: &mut ChaCha8Rng| {
            let t = rng.random_range(1..=count);
            if rng.random_bool(0.3) { t - count - 1 } else { t }
        };
        let open = match shape {
            0 => "Sequence".to_string(),
            1 => "SequenceStar".to_string(),
            2 => "Fallback".to_string(),
            3 => "ReactiveSequence".to_string(),
            4 => "ReactiveFallback".to_string(),
            5 => {
                let s = threshold(&mut self.rng);
                let f = threshold(&mut self.rng);
                if self.rng.random_bool(0.2) {
                    format!(r#"Parallel success_threshold="{s}""#)
                } else {
                    format!(r#"Parallel success_threshold="{s}" failure_threshold="{f}""#)
                }
            }
            6 => "Fallback".to_string(),
            7 => "IfThenElse".to_string(),
            _ => "WhileDoElse".to_string(),
        };
        let tag = open.split(' ').next().unwrap_or("").to_string();
        let _ = write!(out, "<{open}>{children}</{tag}>");
    }
}

/// The models of the leaf types, which the importer reads (BehaviorTree.CPP 3.8 ignores
/// `<TreeNodesModel>`): a case's document is given to the importer with them.
#[must_use]
pub fn models() -> String {
    let mut m = String::from("<TreeNodesModel>");
    for t in TYPES {
        let tag = if t.starts_with('C') { "Condition" } else { "Action" };
        let _ = write!(
            m,
            r#"<{tag} ID="{t}"><input_port name="in" type="int"/><output_port name="out" type="int"/></{tag}>"#
        );
    }
    m.push_str("</TreeNodesModel>");
    m
}

/// The random case `index` of the set made from `seed`.
#[must_use]
pub fn case(seed: u64, index: u32) -> Case {
    let rng = ChaCha8Rng::seed_from_u64(seed ^ (u64::from(index) << 20) ^ 0x0003_b7c0);
    let mut g = Gen { rng, timed: false, budget: 0 };
    g.timed = g.rng.random_bool(0.2);
    let subtrees = g.rng.random_range(0..=2);
    let mut xml = String::from(r#"<root main_tree_to_execute="Main">"#);
    for tree in 0..=subtrees {
        let id = if tree == 0 { "Main".to_string() } else { format!("S{tree}") };
        let _ = write!(xml, r#"<BehaviorTree ID="{id}">"#);
        // The main tree first sets its keys.
        if tree == 0 {
            xml.push_str(r#"<Sequence><SetBlackboard output_key="a" value="1"/><SetBlackboard output_key="b" value="2"/><SetBlackboard output_key="c" value="3"/>"#);
        }
        loop {
            g.budget = if tree == 0 { 24 } else { 10 };
            let mut body = String::new();
            g.node(1, tree, subtrees, &mut body);
            // A root with children, for something to happen.
            if tree > 0 || body.matches('<').count() >= 4 {
                xml.push_str(&body);
                break;
            }
        }
        if tree == 0 {
            xml.push_str("</Sequence>");
        }
        xml.push_str("</BehaviorTree>");
    }
    xml.push_str("</root>");
    let types = TYPES
        .iter()
        .map(|t| {
            let alphabet: &[u8] = if t.starts_with('C') { b"SF" } else { b"SFRRR" };
            let len = g.rng.random_range(1..=6);
            let script = (0..len).map(|_| char::from(alphabet[g.rng.random_range(0..alphabet.len())])).collect();
            LeafType { name: (*t).to_string(), script }
        })
        .collect();
    let period_ms = if xml.contains("<Timeout") || xml.contains("<Delay") { PERIOD_MS } else { 0 };
    Case { name: format!("v{index:04}"), ticks: TICKS, period_ms, types, xml }
}

/// The cases of a cases file (`tests/btcpp/v3/cases/*.cases`): for each, a line `NAME
/// TICKS [TYPE=STATUSES ...]` (`#` starts a comment), then a line of its
/// `<BehaviorTree>`s, wrapped here with the root and the leaf models. Types without a
/// script always succeed.
///
/// # Errors
/// A message with the line number.
pub fn from_file(text: &str) -> Result<Vec<Case>, String> {
    let mut out = vec![];
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
    while let Some((i, head)) = lines.next() {
        let at = |m: &str| format!("line {}: {m}", i + 1);
        let mut words = head.split_whitespace();
        let name = words.next().ok_or_else(|| at("no name"))?.to_string();
        let ticks = words.next().and_then(|t| t.parse().ok()).ok_or_else(|| at("no tick count"))?;
        let given: Vec<(&str, &str)> = words
            .map(|w| w.split_once('=').ok_or_else(|| at(&format!("bad script `{w}`"))))
            .collect::<Result<_, _>>()?;
        let (_, trees) = lines.next().ok_or_else(|| at("no trees after it"))?;
        let xml = format!(r#"<root main_tree_to_execute="Main">{}</root>"#, trees.trim());
        let types = TYPES
            .iter()
            .map(|t| LeafType {
                name: (*t).to_string(),
                script: given.iter().find(|(g, _)| g == t).map_or("S", |(_, s)| s).to_string(),
            })
            .collect();
        let period_ms = if xml.contains("<Timeout") || xml.contains("<Delay") { PERIOD_MS } else { 0 };
        out.push(Case { name, ticks, period_ms, types, xml });
    }
    Ok(out)
}
