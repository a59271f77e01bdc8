//! The differential test against BehaviorTree.CPP 3.8: every case recorded by
//! `tests/btcpp/v3/record.sh` (random version 3 documents, and the hand-made ones of
//! `tests/btcpp/v3/cases/`) is imported as `sim-host import` imports it and run on
//! bt-core with the same leaf scripts, and must agree on every tick: the same leaf
//! calls with the same values read, the same halts (earlier only by halt before start),
//! root status, nodes Running and statuses as BehaviorTree.CPP shows them (see
//! `integration_tests::btcpp::v3::run::compare` and `docs/behaviortree-cpp.md`).

use integration_tests::btcpp::compare::Totals;
use integration_tests::btcpp::v3::{Recorded, parse_fixtures, run};

fn fixtures() -> Vec<(String, Recorded)> {
    integration_tests::btcpp::fixtures("btcpp/v3/fixtures", parse_fixtures)
}

#[test]
fn version_3_documents_run_as_behaviortree_cpp_3_8_runs_them() {
    let all = fixtures();
    let (mut random, mut handmade) = (0usize, 0usize);
    let mut total = Totals::default();
    let mut failures = vec![];
    for (file, rec) in &all {
        if file.starts_with("random-") {
            random += 1;
            assert!(rec.error.is_none(), "{file}: {}: a case BehaviorTree.CPP refused was kept", rec.case.name);
        } else {
            handmade += 1;
            assert!(rec.error.is_none(), "{file}: {}: BehaviorTree.CPP 3.8 refused it: {:?}", rec.case.name, rec.error);
        }
        match run::run(&rec.case).and_then(|ours| run::compare(rec, &ours)) {
            Ok(c) => {
                total.add(&c);
            }
            Err(e) => failures.push(format!("{file}: {e}")),
        }
    }
    eprintln!("{} cases ({random} random, {handmade} hand-made), {total}", all.len());
    assert!(failures.is_empty(), "{} of {} cases disagree:\n{}", failures.len(), all.len(), failures.join("\n"));
    assert!(random >= 500, "only {random} random cases recorded");
    assert!(handmade >= 20, "only {handmade} hand-made cases recorded");
}
