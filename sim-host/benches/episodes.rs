//! Symbolic episodes per second on one core: the planner's tree of each task (it solves
//! the tower; the other three fail as in the paper), through `Runner::run` exactly as
//! GP's fitness calls it, and the cost of recording a trace for pictures.
//!
//! `cargo bench -p sim-host --bench episodes`; the throughput line is episodes/s.
#![allow(clippy::unwrap_used, missing_docs)]

use std::hint::black_box;

use bt_core::{Node, Tree};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use planner::duplo::Task;
use random_trees::{Stream, random_tree};
use sim_host::episode::{Runner, Trace};
use sim_host::symbolic::SymbolicBrickWorld;

#[path = "../tests/fixtures/planner_trees.rs"]
mod planner_trees;
#[path = "../tests/fixtures/random_trees.rs"]
mod random_trees;

fn episodes(c: &mut Criterion) {
    let mut group = c.benchmark_group("symbolic_episode");
    group.throughput(Throughput::Elements(1));
    for task in Task::ALL {
        let spec = task.spec();
        let nodes = bt_formats::tokens::parse(planner_trees::planner_tree(task), &spec).unwrap();
        let tree: Tree<'_, 64> = Tree::validate(&nodes, &spec).unwrap();
        let mut runner = Runner::new(SymbolicBrickWorld::new(&spec).unwrap()).unwrap();
        let e = runner.run(tree).unwrap();
        eprintln!(
            "{}: {} nodes, {} ticks, {:?}, fitness {:.3}",
            task.name(),
            e.nodes,
            e.ticks,
            e.end,
            e.fitness.value()
        );
        group.bench_function(task.name(), |b| b.iter(|| black_box(runner.run(black_box(tree)).unwrap())));
    }
    // Validation included, as a caller holding only nodes pays it.
    let spec = Task::Tower.spec();
    let nodes = bt_formats::tokens::parse(planner_trees::TOWER, &spec).unwrap();
    let mut runner = Runner::new(SymbolicBrickWorld::new(&spec).unwrap()).unwrap();
    group.bench_function("tower_validate_and_run", |b| {
        b.iter(|| black_box(runner.run_nodes(black_box(&nodes)).unwrap()));
    });
    let tree: Tree<'_, 64> = Tree::validate(&nodes, &spec).unwrap();
    let mut trace = Trace::default();
    group.bench_function("tower_with_trace", |b| {
        b.iter(|| black_box(runner.run_recorded(black_box(tree), &mut trace).unwrap()));
    });
    group.finish();
}

/// GP's workload: many different trees, each validated and run once.
fn random_trees(c: &mut Criterion) {
    const TREES: usize = 1000;
    let mut group = c.benchmark_group("symbolic_random_trees");
    group.throughput(Throughput::Elements(TREES as u64));
    for task in Task::ALL {
        let spec = task.spec();
        let mut rng = Stream(0x5eed ^ task as u64);
        let trees: Vec<Vec<Node>> = (0..TREES).map(|_| random_tree(&spec, &mut rng, 3)).collect();
        let mut runner = Runner::new(SymbolicBrickWorld::new(&spec).unwrap()).unwrap();
        let (nodes, ticks): (usize, u32) = trees.iter().fold((0, 0), |(n, t), tree| {
            let e = runner.run_nodes(tree).unwrap();
            (n + e.nodes, t + e.ticks)
        });
        eprintln!(
            "{}: {TREES} random trees, {:.1} nodes and {:.1} ticks per episode on average",
            task.name(),
            nodes as f64 / TREES as f64,
            f64::from(ticks) / TREES as f64
        );
        group.bench_function(task.name(), |b| {
            b.iter(|| {
                for t in &trees {
                    black_box(runner.run_nodes(black_box(t)).unwrap());
                }
            });
        });
    }
    group.finish();
}

criterion_group!(benches, episodes, random_trees);
criterion_main!(benches);
