//! The physics world against the published experiments of Styrud et al.: the trees that the
//! reference implementation's experiment script lists as solving each task, with the
//! fitness each scored in its AGX Dynamics simulation, score the same here.
//!
//! Source: `duplo_simulation/main.py`, `paper_run()`, of the reference implementation
//! (github.com/jstyrud/planning-and-learning), where each tree is kept next to the
//! fitness it scored. A solved task costs only the tree's length (0.1 per node) and the
//! AGX bricks' residual error beyond the allowed 0.4 mm, which is 0.011 at most there;
//! so each tree here must score its published value within 0.02.
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[path = "fixtures/planner_trees.rs"]
mod planner_trees;

use planner::duplo::Task;
use sim_host::episode::{End, Runner};
use sim_host::physics::PhysicsBrickWorld;

/// (task, tree in the token notation of Styrud et al., fitness published for it in AGX).
const SOLVED: [(Task, &str, f64); 9] = [
    // Tower: the planner's tree, and two smaller ones GP found.
    (Task::Tower, planner_trees::TOWER, -3.0109),
    (
        Task::Tower,
        "s( f( 0 at pos (0.0, 0.05, 0.0)? s( pick 0! place at (0.0, 0.05, 0.0)! ) ) \
         f( 1 at pos (0.0, 0.05, 0.0192)? s( f( 1 on 0? s( pick 1! place on 0! ) ) apply force 1! ) ) \
         f( 2 at pos (0.0, 0.05, 0.0384)? s( f( 2 on 1? s( pick 2! place on 1! ) ) apply force 2! ) ) )",
        -2.4110,
    ),
    (
        Task::Tower,
        "s( f( 0 at pos (0.0, 0.05, 0.0)? s( pick 0! place at (0.0, 0.05, 0.0)! ) ) \
         f( 1 on 0? s( pick 1! place on 0! ) ) f( 1 at pos (0.0, 0.05, 0.0192)? apply force 1! ) \
         f( 2 on 1? s( pick 2! place on 1! ) ) f( 2 at pos (0.0, 0.05, 0.0384)? apply force 2! ) )",
        -2.2110,
    ),
    // Croissant: the side bricks before the long one.
    (
        Task::Croissant,
        "s( f( 0 at pos (0.0, 0.0, 0.0)? s( pick 0! place at (0.0, 0.0, 0.0)! ) ) \
         f( 2 at pos (0.016, -0.032, 0.0)? s( pick 2! place at (0.016, -0.032, 0.0)! ) ) \
         f( 3 at pos (0.016, 0.032, 0.0)? s( pick 3! place at (0.016, 0.032, 0.0)! ) ) \
         f( 1 at pos (0.0, 0.0, 0.0192)? s( f( 1 on 0? s( pick 1! place on 0! ) ) apply force 1! ) ) )",
        -2.5,
    ),
    (
        Task::Croissant,
        "s( f( 0 at pos (0.0, 0.0, 0.0)? s( pick 0! place at (0.0, 0.0, 0.0)! ) ) \
         f( 3 at pos (0.016, 0.032, 0.0)? s( pick 3! place at (0.016, 0.032, 0.0)! ) ) \
         f( 2 at pos (0.016, -0.032, 0.0)? s( pick 2! place at (0.016, -0.032, 0.0)! ) ) \
         f( 1 on 0? s( pick 1! place on 0! ) ) f( 1 at pos (0.0, 0.0, 0.0192)? apply force 1! ) )",
        -2.4,
    ),
    (
        Task::Croissant,
        "s( f( 0 at pos (0.0, 0.0, 0.0)? s( pick 0! place at (0.0, 0.0, 0.0)! ) ) \
         f( 1 at pos (0.0, 0.0, 0.0192)? s( f( 1 on 0? s( f( 2 at pos (0.016, -0.032, 0.0)? \
         s( 3 at pos (0.016, 0.032, 0.0)? pick 2! place at (0.016, -0.032, 0.0)! ) \
         place at (0.016, 0.032, 0.0)! ) pick 1! place on 0! ) ) apply force 1! ) pick 3! ) )",
        -2.3,
    ),
    // Balance: the long brick on the wide brick 2, not on the narrow brick 1.
    (
        Task::Balance,
        "f( 0 at pos (0.0, 0.0, 0.0192)? s( put 2 at (0.0, 0.0, 0.0)! put 0 on 2! apply force 0! ) )",
        -0.6,
    ),
    // Blocking: 1 rides on 0 from D to A once brick 2 is out of the way at B.
    (
        Task::Blocking,
        "s( put 1 on 0! f( 0 at pos (-0.1, 0.0, 0.0)? put 2 at (0.0, 0.05, 0.0)! ) put 0 at (-0.1, 0.0, 0.0)! \
         f( 1 at pos (-0.1, 0.0, 0.0192)? apply force 1! ) put 2 at (0.0, 0.0, 0.0)! )",
        -1.0,
    ),
    (
        Task::Blocking,
        "s( f( 1 at pos (-0.1, 0.0, 0.0192)? s( put 1 on 0! put 2 at (0.0, 0.05, 0.0)! \
         put 0 at (-0.1, 0.0, 0.0)! apply force 1! ) ) put 2 at (0.0, 0.0, 0.0)! )",
        -0.9,
    ),
];

#[test]
fn the_published_solutions_score_their_published_fitness() {
    let mut failures = Vec::new();
    for (task, text, published) in SOLVED {
        let spec = task.spec();
        let nodes = bt_formats::tokens::parse(text, &spec).unwrap_or_else(|e| panic!("{text}: {e}"));
        let mut runner = Runner::new(PhysicsBrickWorld::new(&spec).unwrap()).unwrap();
        let episode = runner.run_nodes(&nodes).unwrap();
        let fitness = episode.fitness.value();
        if episode.end != End::Success || (fitness - published).abs() > 0.02 {
            failures.push(format!("{task:?}: {fitness:.3} ({:?}), published {published}: {text}", episode.end));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
