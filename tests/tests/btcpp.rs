//! The differential test against BehaviorTree.CPP 4.10.0: every case recorded by
//! `tests/btcpp/record.sh` (random trees of every built-in kind, random trees with
//! `Script` and `ScriptCondition` leaves, and trees from BehaviorTree.CPP's own tests) is run on bt-core with the same leaf scripts, and must
//! agree on every tick (see `integration_tests::btcpp::compare::compare` and
//! `docs/behaviortree-cpp.md`).

use integration_tests::btcpp::{btlog, case, compare, run};

fn fixtures() -> Vec<(String, case::Recorded)> {
    integration_tests::btcpp::fixtures("btcpp/fixtures", case::parse_fixtures)
}

#[test]
fn bt_core_does_what_behaviortree_cpp_does() {
    let all = fixtures();
    let mut random = 0usize;
    let mut scripted = 0usize;
    let mut total = compare::Totals::default();
    let mut failures = vec![];
    for (file, rec) in &all {
        if rec.error.is_some() {
            continue;
        }
        if file.starts_with("random-") || file.starts_with("scripted-") {
            if file.starts_with("random-") {
                random += 1;
            } else {
                scripted += 1;
            }
            // The XML BehaviorTree.CPP ran (scripts included) is the one the spec gives today.
            assert_eq!(rec.xml, rec.case.spec.to_xml(), "{file}: {}: the XML is no longer the spec's", rec.case.name);
        }
        // Hook for the importer (issue 17): importing `rec.xml` with the fixtures'
        // catalog (`run::catalog()`) must give exactly `run::build(&rec.case.spec)`.
        match run::run(&rec.case).and_then(|ours| compare::compare(rec, &ours)) {
            Ok(c) => {
                total.add(&c);
            }
            Err(e) => failures.push(format!("{file}: {e}")),
        }
    }
    eprintln!("{} cases ({random} random, {scripted} with scripts), {total}", all.len());
    assert!(failures.is_empty(), "{} of {} cases disagree:\n{}", failures.len(), all.len(), failures.join("\n"));
    assert!(random >= 1000, "only {random} random cases recorded");
    assert!(scripted >= 300, "only {scripted} cases with scripts recorded");
}

/// Our Groot2 replay logs against BehaviorTree.CPP's `FileLogger2` logs of the same
/// runs (`btcpp/fixtures/btlog/`, every tenth random case): byte for byte but the
/// timestamps, except where the differential test itself compares a case only up to a
/// tick (see `integration_tests::btcpp::btlog::compare`).
#[test]
fn our_btlogs_are_behaviortree_cpps_but_for_timestamps() {
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("btcpp/fixtures/btlog");
    let files = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(Result::ok)
        .filter(|e| e.path().extension().is_some_and(|x| x == "btlog"))
        .count();
    let (mut logs, mut exact, mut transitions, mut image_xml) = (0usize, 0usize, 0usize, 0usize);
    let (mut up_to, mut up_to_compared) = (vec![], 0usize);
    let (mut exact_with_halts_moved, mut exact_with_stale, mut exact_with_restart) = (0usize, 0usize, 0usize);
    let mut failures = vec![];
    for (file, rec) in &fixtures() {
        let path = dir.join(format!("{}.btlog", rec.case.name));
        if !path.exists() {
            continue;
        }
        logs += 1;
        let theirs = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let result = run::run(&rec.case)
            .and_then(|ours| compare::compare(rec, &ours))
            .and_then(|diff| btlog::compare(rec, &theirs, &diff).map(|c| (diff, c)));
        match result {
            Ok((diff, c)) => {
                transitions += c.transitions;
                image_xml += usize::from(c.image_xml_compared);
                match c.outcome {
                    btlog::Outcome::Exact => {
                        exact += 1;
                        exact_with_halts_moved += usize::from(diff.halts_moved_earlier > 0);
                        exact_with_stale += usize::from(diff.ticks_with_other_statuses > 0);
                        exact_with_restart += usize::from(diff.restarted_at.is_some());
                    }
                    btlog::Outcome::UpToTick { tick, compared, after } => {
                        up_to.push(format!("{} up to tick {tick}, then {after}", rec.case.name));
                        up_to_compared += compared;
                    }
                }
            }
            Err(e) => failures.push(format!("{file}: {e}")),
        }
    }
    eprintln!(
        "{logs} BehaviorTree.CPP logs ({transitions} transitions): {exact} equal ours but for timestamps \
         (of them, {exact_with_halts_moved} cases with halts moved earlier by halt before start, \
         {exact_with_stale} with ticks of stale statuses, {exact_with_restart} that the differential test \
         compares only up to a restart); {} equal up to the tick where halt before start restarted a branch \
         ({up_to_compared} transitions compared): {}; the XML of the bt-core tree itself compared in {image_xml}",
        up_to.len(),
        up_to.join("; ")
    );
    assert!(failures.is_empty(), "{} of {logs} logs differ:\n{}", failures.len(), failures.join("\n"));
    assert_eq!(logs, files, "a .btlog without its case");
    assert!(logs >= 90, "only {logs} logs recorded");
}
