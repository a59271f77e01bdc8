//! Cases and fixtures: what the harness is given and what it answers, in one text form.
//!
//! A fixture file is the harness's output: each case echoes its input lines, then one
//! `tick` line per tick, then `end`. See `tests/btcpp/README.md`.

use std::fmt::Write as _;

use super::spec::Spec;

/// The statuses a scripted leaf returns, one per call, cyclically.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Script {
    /// The leaf's pre-order node id.
    pub node: usize,
    /// An action (else a condition).
    pub action: bool,
    /// `S`, `F`, `R`, one per call.
    pub statuses: String,
}

/// A tree, its scripts and how to tick it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Case {
    /// Unique within its file.
    pub name: String,
    /// The tree.
    pub spec: Spec,
    /// Ticks to run.
    pub ticks: u32,
    /// 0, or milliseconds between ticks (tick `k` runs at `k * period_ms`).
    pub period_ms: u32,
    /// Ticked with BehaviorTree.CPP's `tickOnce()` (ticks again while a node asks for a
    /// wake-up), else with `tickExactlyOnce()`.
    pub once: bool,
    /// One per scripted leaf.
    pub scripts: Vec<Script>,
}

impl Case {
    /// The harness's input for this case (without `end`).
    #[must_use]
    pub fn input(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "case {}", self.name);
        let _ = writeln!(out, "spec {}", self.spec);
        let _ = writeln!(out, "ticks {}", self.ticks);
        let _ = writeln!(out, "period {}", self.period_ms);
        if self.once {
            let _ = writeln!(out, "mode once");
        }
        for s in &self.scripts {
            let _ = writeln!(out, "leaf {} {} {}", s.node, if s.action { 'A' } else { 'C' }, s.statuses);
        }
        let _ = writeln!(out, "xml {}", self.spec.to_xml());
        out
    }
}

/// One recorded tick.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tick {
    /// `S`, `F`, `R` or `K` (skipped).
    pub root: char,
    /// Leaf calls and halts, in order (see the harness).
    pub events: Vec<String>,
    /// One status letter per node, pre-order.
    pub statuses: String,
}

impl Tick {
    /// A harness's `tick` line after the word: `N ROOT | EVENTS | STATUSES`.
    ///
    /// # Errors
    /// What is missing.
    pub fn parse(rest: &str) -> Result<Self, &'static str> {
        let parts: Vec<&str> = rest.splitn(3, " | ").collect();
        let [head, events, statuses] = parts[..] else { return Err("bad tick line") };
        let root = head.split(' ').nth(1).and_then(|s| s.chars().next()).ok_or("no root status")?;
        Ok(Self {
            root,
            events: events.split(' ').filter(|e| !e.is_empty()).map(str::to_string).collect(),
            statuses: statuses.to_string(),
        })
    }
}

/// A case with what BehaviorTree.CPP did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Recorded {
    /// The case.
    pub case: Case,
    /// The XML BehaviorTree.CPP was given.
    pub xml: String,
    /// One per tick run.
    pub ticks: Vec<Tick>,
    /// Set when BehaviorTree.CPP refused or stopped: its message.
    pub error: Option<String>,
}

/// A case being read.
#[derive(Default)]
struct Partial {
    name: String,
    spec: Option<Spec>,
    ticks: u32,
    period_ms: u32,
    once: bool,
    scripts: Vec<Script>,
    xml: String,
    recorded: Vec<Tick>,
    error: Option<String>,
}

/// Parses a fixture file.
///
/// # Errors
/// A message with the line number.
pub fn parse_fixtures(text: &str) -> Result<Vec<Recorded>, String> {
    let mut out = vec![];
    let mut cur: Option<Partial> = None;
    for (i, line) in text.lines().enumerate() {
        let at = |m: &str| format!("line {}: {m}", i + 1);
        let (key, rest) = line.split_once(' ').unwrap_or((line, ""));
        if key == "case" {
            cur = Some(Partial { name: rest.to_string(), ..Partial::default() });
            continue;
        }
        let Some(c) = cur.as_mut() else {
            if line.trim().is_empty() || line.starts_with('#') {
                continue;
            }
            return Err(at("text outside a case"));
        };
        match key {
            "spec" => c.spec = Some(Spec::parse(rest).map_err(|e| at(&e))?),
            "ticks" => c.ticks = rest.parse().map_err(|_| at("bad tick count"))?,
            "period" => c.period_ms = rest.parse().map_err(|_| at("bad period"))?,
            "mode" => c.once = rest == "once",
            "leaf" => {
                let w: Vec<&str> = rest.split(' ').collect();
                let [node, kind, statuses] = w[..] else { return Err(at("bad leaf line")) };
                c.scripts.push(Script {
                    node: node.parse().map_err(|_| at("bad node id"))?,
                    action: kind == "A",
                    statuses: statuses.to_string(),
                });
            }
            "xml" => c.xml = rest.to_string(),
            "tick" => c.recorded.push(Tick::parse(rest).map_err(at)?),
            "error" => c.error = Some(rest.to_string()),
            "runaway" => c.error = Some("runaway".to_string()),
            "end" => {
                let Some(p) = cur.take() else { return Err(at("end outside a case")) };
                let spec = p.spec.ok_or_else(|| at("case without spec"))?;
                out.push(Recorded {
                    case: Case {
                        name: p.name,
                        spec,
                        ticks: p.ticks,
                        period_ms: p.period_ms,
                        once: p.once,
                        scripts: p.scripts,
                    },
                    xml: p.xml,
                    ticks: p.recorded,
                    error: p.error,
                });
            }
            _ => return Err(at(&format!("unknown line `{key}`"))),
        }
    }
    Ok(out)
}
