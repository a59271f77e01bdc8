//! Planning time (offline, Algorithm 1 against the symbolic world) and tree size.
//! `cargo bench -p planner`. Tree sizes are printed once per problem.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use planner::duplo::{self, Task};
use planner::ground::Grounding;
use planner::{Options, PddlCatalog, domains, plan};

fn pddl_case(c: &mut Criterion, name: &str, g: Grounding) {
    let g = Arc::new(g);
    let cat = Arc::new(PddlCatalog::new(g.problem()));
    let p = plan(g.clone(), cat.clone(), Options::default()).expect("plans");
    println!("{name}: {} nodes, {} expansions, goal in {:?} ticks", p.nodes.len(), p.expansions.len(), p.goal_ticks);
    c.bench_function(name, |b| b.iter(|| black_box(plan(g.clone(), cat.clone(), Options::default()).expect("plans"))));
}

fn blocks(c: &mut Criterion) {
    for n in [5, 10, 20, 40] {
        pddl_case(c, &format!("blocks world {n}"), domains::blocks_world(n).expect("built-in"));
    }
}

fn cube_sphere(c: &mut Criterion) {
    pddl_case(c, "cube-sphere blocked (Fig. 4)", domains::cube_sphere_blocked().expect("built-in"));
    pddl_case(c, "cellphone assembly", domains::cellphone().expect("built-in"));
}

fn bricks(c: &mut Criterion) {
    for t in Task::ALL {
        let p = duplo::plan(t).expect("plans");
        println!("brick {}: {} nodes, {} expansions", t.name(), p.nodes.len(), p.expansions.len());
        c.bench_function(&format!("brick {}", t.name()), |b| {
            b.iter(|| black_box(duplo::plan(black_box(t)).expect("plans")))
        });
    }
}

criterion_group!(benches, blocks, cube_sphere, bricks);
criterion_main!(benches);
