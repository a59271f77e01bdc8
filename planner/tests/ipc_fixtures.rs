//! IPC benchmark problems kept in `tests/fixtures/ipc` (one of each of a few domain
//! sets), compared with what `tests/fixtures/ipc/record.py` recorded from tools outside
//! the project: every plan our tree executes must be the one VAL validated when it was
//! recorded, and pyperplan's plans (also VAL-validated) must reach the goal in our
//! grounding. A change of plan fails here until it is validated and recorded again.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use planner::coverage;
use planner::ground::Grounding;
use planner::pddl::{parse_domain, parse_problem};
use planner::{Options, PddlCatalog};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ipc")
}

fn plan_file(problem: &Path, suffix: &str) -> Option<Vec<String>> {
    let path = problem.with_extension(suffix);
    let text = std::fs::read_to_string(path).ok()?;
    Some(text.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with(';')).map(str::to_string).collect())
}

#[test]
fn every_fixture_plans_as_recorded_and_validated() {
    let list = coverage::instances(&fixtures()).unwrap();
    assert!(list.len() >= 10, "{list:?}");
    let mut solved = 0;
    let mut pyperplan = 0;
    for i in &list {
        let id = format!("{}/{}", i.domain, i.problem_file.display());
        let dtext = std::fs::read_to_string(&i.domain_file).unwrap();
        let ptext = std::fs::read_to_string(&i.problem_file).unwrap();
        let recorded = plan_file(&i.problem_file, "plan");
        let problem = match parse_domain("domain.pddl", &dtext).and_then(|d| parse_problem("problem.pddl", &ptext, &d))
        {
            Ok(p) => p,
            Err(e) => {
                // Refused: only where nothing was recorded, and with a location.
                assert!(recorded.is_none(), "{id}: refused but a plan was recorded: {e}");
                assert!(e.to_string().contains(".pddl:"), "{id}: {e}");
                continue;
            }
        };
        let g = Arc::new(Grounding::new(&problem).unwrap());
        let c = Arc::new(PddlCatalog::new(&problem));
        // No deadline: with one, the closure over disturbances gets time in proportion
        // to the first tree's, and the tree (its rules can shorten the plan) depends on
        // the machine's speed.
        let plan = planner::plan(g.clone(), c, Options::default());
        match (&plan, &recorded) {
            (Ok(p), Some(want)) => {
                let got: Vec<String> = p.executed.iter().map(|&a| g.action_pddl(a)).collect();
                assert_eq!(&got, want, "{id}: the plan changed; validate and record it again (record.py)");
                solved += 1;
            }
            (Ok(_), None) => panic!("{id}: solved now; record the plan (record.py)"),
            (Err(e), Some(_)) => panic!("{id}: was solved when recorded, now: {e}"),
            (Err(_), None) => {}
        }
        if let Some(theirs) = plan_file(&i.problem_file, "pyperplan.plan") {
            let by_name: HashMap<String, u32> =
                (0..g.actions().len() as u32).map(|a| (g.action_pddl(a).to_ascii_lowercase(), a)).collect();
            let ids: Vec<u32> = theirs
                .iter()
                .map(|n| *by_name.get(&n.to_ascii_lowercase()).unwrap_or_else(|| panic!("{id}: no ground action {n}")))
                .collect();
            let end =
                planner::search::execute(&g, &ids).unwrap_or_else(|| panic!("{id}: pyperplan's plan not applicable"));
            assert!(g.goal_holds(&end), "{id}: pyperplan's plan does not reach the goal in our grounding");
            pyperplan += 1;
        }
    }
    assert!(solved >= 10, "solved {solved}");
    assert!(pyperplan >= 6, "pyperplan plans checked {pyperplan}");
}
