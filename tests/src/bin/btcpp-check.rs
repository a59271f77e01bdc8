//! Compares fixture files recorded from BehaviorTree.CPP with our executor and prints
//! every disagreement: `btcpp-check tests/btcpp/fixtures/*.txt`. The test
//! `tests/tests/btcpp.rs` does the same and fails on the first.

use std::process::ExitCode;

use integration_tests::btcpp::{case, run};

fn main() -> ExitCode {
    let mut bad = 0usize;
    let mut total = run::Comparison::default();
    let mut cases = 0usize;
    let mut refused = 0usize;
    let mut restarted = 0usize;
    for path in std::env::args().skip(1) {
        let text = match std::fs::read_to_string(&path) {
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
                .and_then(|ours| run::compare(rec, &ours))
            {
                Ok(c) => {
                    total.ticks += c.ticks;
                    total.halts_moved_earlier += c.halts_moved_earlier;
                    if c.restarted_at.is_some() {
                        restarted += 1;
                    }
                    total.ticks_with_other_statuses += c.ticks_with_other_statuses;
                }
                Err(e) => {
                    bad += 1;
                    println!("{e}");
                }
            }
        }
    }
    println!(
        "{cases} cases ({refused} refused by BehaviorTree.CPP not counted), {} ticks compared: {bad} disagree; \
         {} halts earlier (halt before start); {restarted} cases compared up to a branch restarted by halt \
         before start; {} ticks with other statuses as BehaviorTree.CPP shows them",
        total.ticks, total.halts_moved_earlier, total.ticks_with_other_statuses
    );
    if bad == 0 { ExitCode::SUCCESS } else { ExitCode::FAILURE }
}
