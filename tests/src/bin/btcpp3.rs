//! The version 3 differential test's tool (see `tests/btcpp/README.md`):
//!
//! - `btcpp3 cases SEED FROM COUNT`: random cases FROM..FROM+COUNT of the set made from
//!   SEED, for the harness (`tests/btcpp/v3/harness.cpp`);
//! - `btcpp3 cases FILE.cases`: the hand-made cases of a cases file, likewise;
//! - `btcpp3 check FILES`: compares fixture files recorded from BehaviorTree.CPP 3.8 with
//!   our importer and executor and prints every disagreement (the test
//!   `tests/tests/btcpp3.rs` does the same and fails on the first).

use std::io::Write;
use std::process::ExitCode;

use integration_tests::btcpp::compare::Totals;
use integration_tests::btcpp::v3::{generate, parse_fixtures, run};

fn cases(args: &[String]) -> ExitCode {
    let cases = if let [file] = args {
        match std::fs::read_to_string(file).map_err(|e| e.to_string()).and_then(|t| generate::from_file(&t)) {
            Ok(c) => c,
            Err(e) => {
                eprintln!("{file}: {e}");
                return ExitCode::from(2);
            }
        }
    } else {
        let nums: Vec<u64> = args.iter().filter_map(|a| a.parse().ok()).collect();
        let [seed, from, count] = nums[..] else {
            eprintln!("usage: btcpp3 cases SEED FROM COUNT | btcpp3 cases FILE.cases");
            return ExitCode::from(2);
        };
        (from..from + count).map(|i| generate::case(seed, i as u32)).collect()
    };
    let mut out = std::io::stdout().lock();
    for case in cases {
        if writeln!(out, "{}end", case.input()).is_err() {
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}

fn check(files: &[String]) -> ExitCode {
    let (mut cases, mut refused, mut bad) = (0usize, 0usize, 0usize);
    let mut total = Totals::default();
    for path in files {
        let recorded = match std::fs::read_to_string(path).map_err(|e| e.to_string()).and_then(|t| parse_fixtures(&t)) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("{path}: {e}");
                return ExitCode::from(2);
            }
        };
        for rec in &recorded {
            if rec.error.is_some() {
                refused += 1;
                continue;
            }
            cases += 1;
            match run::run(&rec.case)
                .map_err(|e| format!("{}: {e}\n  xml       {}", rec.case.name, rec.case.xml))
                .and_then(|ours| run::compare(rec, &ours))
            {
                Ok(c) => {
                    total.add(&c);
                }
                Err(e) => {
                    bad += 1;
                    println!("{e}");
                }
            }
        }
    }
    println!("{cases} cases ({refused} refused by BehaviorTree.CPP 3.8 not counted), {bad} disagree; {total}");
    if bad == 0 { ExitCode::SUCCESS } else { ExitCode::FAILURE }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.split_first() {
        Some((cmd, rest)) if cmd == "cases" => cases(rest),
        Some((cmd, rest)) if cmd == "check" => check(rest),
        _ => {
            eprintln!("usage: btcpp3 cases SEED FROM COUNT | btcpp3 check FILES");
            ExitCode::from(2)
        }
    }
}
