//! The brick tasks planned with the reference's templates.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use planner::duplo::{self, Task};
use planner::tokens;

fn tree(task: Task) -> String {
    let p = duplo::plan(task).unwrap();
    tokens::to_string(&p.nodes, p.catalog.as_ref()).unwrap()
}

#[test]
fn print_all() {
    for t in Task::ALL {
        println!("{}: {}", t.name(), tree(t));
    }
}
