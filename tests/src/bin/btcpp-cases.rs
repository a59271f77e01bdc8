//! Writes cases for BehaviorTree.CPP's harness (see `tests/btcpp/README.md`):
//!
//! - `btcpp-cases SEED FROM COUNT`: random cases FROM..FROM+COUNT of the set made from SEED;
//! - `btcpp-cases --scripted SEED FROM COUNT`: the same for random trees with `Script` and
//!   `ScriptCondition` leaves;
//! - `btcpp-cases FILE.spec`: the cases a spec file lists, one per line,
//!   `NAME TICKS SPEC [once] [NODE=SCRIPT ...]` (`#` starts a comment); leaves without a
//!   script return Success.

use std::io::Write;
use std::process::ExitCode;

use integration_tests::btcpp::case::{Case, Script};
use integration_tests::btcpp::generate;
use integration_tests::btcpp::spec::{Kind, Spec};

fn from_line(line: &str) -> Result<Case, String> {
    let mut words = line.split_whitespace();
    let name = words.next().ok_or("no name")?.to_string();
    let ticks = words.next().and_then(|t| t.parse().ok()).ok_or("no tick count")?;
    // The spec is the words up to the scripts (`NODE=STATUSES`) or `once`; its scripted
    // attributes (`{W=6}`) contain `=` too.
    let rest: Vec<&str> = words.collect();
    let script =
        |w: &str| w.split_once('=').is_some_and(|(n, _)| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
    let split = rest.iter().position(|w| script(w) || *w == "once").unwrap_or(rest.len());
    let spec = Spec::parse(&rest[..split].join(" "))?;
    let mut once = false;
    let mut given = vec![];
    for w in &rest[split..] {
        if *w == "once" {
            once = true;
            continue;
        }
        let (node, script) = w.split_once('=').ok_or(format!("bad script `{w}`"))?;
        given.push((node.parse::<usize>().map_err(|_| format!("bad node in `{w}`"))?, script.to_string()));
    }
    let nodes = spec.preorder();
    let scripts = nodes
        .iter()
        .enumerate()
        .filter(|(_, n)| matches!(n.kind, Kind::Condition | Kind::Action))
        .map(|(id, n)| Script {
            node: id,
            action: n.kind == Kind::Action,
            statuses: given.iter().find(|(g, _)| *g == id).map_or("S".to_string(), |(_, s)| s.clone()),
        })
        .collect();
    let period_ms = if nodes.iter().any(|n| n.kind.is_timed()) { generate::PERIOD_MS } else { 0 };
    Ok(Case { name, spec, ticks, period_ms, once, scripts })
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut out = std::io::stdout().lock();
    if let [file] = &args[..] {
        let text = match std::fs::read_to_string(file) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("{file}: {e}");
                return ExitCode::from(2);
            }
        };
        for (i, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            match from_line(line) {
                Ok(case) => {
                    if writeln!(out, "{}end", case.input()).is_err() {
                        return ExitCode::FAILURE;
                    }
                }
                Err(e) => {
                    eprintln!("{file}:{}: {e}", i + 1);
                    return ExitCode::from(2);
                }
            }
        }
        return ExitCode::SUCCESS;
    }
    let scripted = args.first().is_some_and(|a| a == "--scripted");
    let nums: Vec<u64> = args.iter().filter_map(|a| a.parse().ok()).collect();
    let [seed, from, count] = nums[..] else {
        eprintln!("usage: btcpp-cases [--scripted] SEED FROM COUNT | btcpp-cases FILE.spec");
        return ExitCode::from(2);
    };
    for i in from..from + count {
        let case = if scripted { generate::scripted_case(seed, i as u32) } else { generate::case(seed, i as u32) };
        if writeln!(out, "{}end", case.input()).is_err() {
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}
