//! The differential test against BehaviorTree.CPP 3.8: random version 3 documents
//! (SubTrees remapped by name, `SubTreePlus` with `__autoremap`, `${key}`, literals on
//! output ports, `SetBlackboard`, version 3's `Parallel`, `SequenceStar`, `Repeat` and
//! `RetryUntilSuccessful`, counts from a `{key}`, `BlackboardCheckInt`) whose leaves
//! read and write ports, recorded from BehaviorTree.CPP 3.8 by `tests/btcpp/v3/record.sh`
//! and run here through the importer (`btcpp::xml`) and bt-core's executor.
//!
//! A case is its document and its leaf types' scripts; a fixture is the harness's
//! output (`tests/btcpp/v3/harness.cpp` describes it). Unlike the version 4 cases, the
//! tree is not built from a spec: the document goes through the importer, so that what
//! is compared is what `sim-host import` makes of it.

pub mod generate;
pub mod run;

use std::fmt::Write as _;

use super::case::Tick;

/// A leaf type: every node of the type counts its calls together.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LeafType {
    /// `C3`, `A5`: `C` for a condition, `A` for an action, and its number.
    pub name: String,
    /// The statuses it returns, one per call, cyclically (`S`, `F`, `R`).
    pub script: String,
}

impl LeafType {
    /// Whether it is an action.
    #[must_use]
    pub fn action(&self) -> bool {
        self.name.starts_with('A')
    }

    /// The number in its name.
    #[must_use]
    pub fn number(&self) -> i64 {
        self.name.get(1..).and_then(|n| n.parse().ok()).unwrap_or(0)
    }
}

/// A version 3 document, its leaf types and how to tick it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Case {
    /// Unique within its file.
    pub name: String,
    /// Ticks to run (one `tickRoot()` each).
    pub ticks: u32,
    /// 0, or milliseconds between ticks.
    pub period_ms: u32,
    /// The leaf types the document uses.
    pub types: Vec<LeafType>,
    /// The document, on one line.
    pub xml: String,
}

impl Case {
    /// The harness's input for this case (without `end`).
    #[must_use]
    pub fn input(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "case {}", self.name);
        let _ = writeln!(out, "ticks {}", self.ticks);
        let _ = writeln!(out, "period {}", self.period_ms);
        for t in &self.types {
            let _ = writeln!(out, "leaf {} {} {}", t.name, if t.action() { 'A' } else { 'C' }, t.script);
        }
        let _ = writeln!(out, "xml {}", self.xml);
        out
    }
}

/// A case with what BehaviorTree.CPP 3.8 did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Recorded {
    /// The case.
    pub case: Case,
    /// BehaviorTree.CPP's nodes in pre-order: registration ID (`SubTree` for a SubTree
    /// node) and parent.
    pub nodes: Vec<(String, Option<usize>)>,
    /// One per tick run.
    pub ticks: Vec<Tick>,
    /// Set when BehaviorTree.CPP refused or stopped: its message.
    pub error: Option<String>,
}

/// Parses a fixture file.
///
/// # Errors
/// A message with the line number.
pub fn parse_fixtures(text: &str) -> Result<Vec<Recorded>, String> {
    let mut out = vec![];
    let mut cur: Option<Recorded> = None;
    for (i, line) in text.lines().enumerate() {
        let at = |m: &str| format!("line {}: {m}", i + 1);
        let (key, rest) = line.split_once(' ').unwrap_or((line, ""));
        if key == "case" {
            let case = Case { name: rest.to_string(), ticks: 0, period_ms: 0, types: vec![], xml: String::new() };
            cur = Some(Recorded { case, nodes: vec![], ticks: vec![], error: None });
            continue;
        }
        let Some(c) = cur.as_mut() else {
            if line.trim().is_empty() || line.starts_with('#') {
                continue;
            }
            return Err(at("text outside a case"));
        };
        match key {
            "ticks" => c.case.ticks = rest.parse().map_err(|_| at("bad tick count"))?,
            "period" => c.case.period_ms = rest.parse().map_err(|_| at("bad period"))?,
            "leaf" => {
                let w: Vec<&str> = rest.split(' ').collect();
                let [name, _, script] = w[..] else { return Err(at("bad leaf line")) };
                c.case.types.push(LeafType { name: name.to_string(), script: script.to_string() });
            }
            "xml" => c.case.xml = rest.to_string(),
            "nodes" => {
                for n in rest.split(' ') {
                    let (id, parent) = n.rsplit_once('/').ok_or_else(|| at("bad node"))?;
                    let parent = if parent == "-" { None } else { Some(parent.parse().map_err(|_| at("bad parent"))?) };
                    c.nodes.push((id.to_string(), parent));
                }
            }
            "tick" => c.ticks.push(Tick::parse(rest).map_err(at)?),
            "error" => c.error = Some(rest.to_string()),
            "runaway" => c.error = Some("runaway".to_string()),
            "end" => out.push(cur.take().ok_or_else(|| at("end outside a case"))?),
            _ => return Err(at(&format!("unknown line `{key}`"))),
        }
    }
    Ok(out)
}
