//! Compares fixture files recorded from BehaviorTree.CPP with our executor and prints
//! every disagreement: `btcpp-check tests/btcpp/fixtures/*.txt`. The test
//! `tests/tests/btcpp.rs` does the same and fails on the first.
//!
//! `btcpp-check --restarted FILES` prints only the names of the cases compared up to a
//! tick where halt before start restarted a branch (`record.sh` keeps their `.btlog`).

use std::process::ExitCode;

use integration_tests::btcpp::{case, compare, run};

fn main() -> ExitCode {
    let mut bad = 0usize;
    let mut total = compare::Totals::default();
    let mut cases = 0usize;
    let mut refused = 0usize;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names_only = args.first().is_some_and(|a| a == "--restarted");
    for path in args.iter().skip(usize::from(names_only)) {
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("{path}: {e}");
                return ExitCode::from(2);
            }
        };
        let recorded = match case::parse_fixtures(&text) {
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
                .map_err(|e| format!("{}: {e}\n  spec      {}", rec.case.name, rec.case.spec))
                .and_then(|ours| compare::compare(rec, &ours))
            {
                Ok(c) => {
                    total.add(&c);
                    if c.restarted_at.is_some() && names_only {
                        println!("{}", rec.case.name);
                    }
                }
                Err(e) => {
                    bad += 1;
                    if names_only {
                        eprintln!("{e}");
                    } else {
                        println!("{e}");
                    }
                }
            }
        }
    }
    if names_only {
        return if bad == 0 { ExitCode::SUCCESS } else { ExitCode::FAILURE };
    }
    println!("{cases} cases ({refused} refused by BehaviorTree.CPP not counted), {bad} disagree; {total}");
    if bad == 0 { ExitCode::SUCCESS } else { ExitCode::FAILURE }
}
