//! The GP's own cost, with fitness functions that cost (almost) nothing.
//!
//! `cargo bench -p gp`. Groups:
//! - `operators`: one random tree of 8 nodes, one mutation, one crossover (tower
//!   alphabet, trees from a warmed-up run);
//! - `generation`: one whole generation (breeding, cache, survivors) with a trivial
//!   fitness, evaluated sequentially; throughput in offspring slots (32 per
//!   generation, Table I);
//! - `run`: 200 generations of the tower with the baseline, trivial fitness and a
//!   ~5 µs busy fitness (`fitness/busy`, a stand-in for a symbolic episode),
//!   sequential and parallel; episodes per run are printed, so episodes per second
//!   follow.

use std::hint::black_box;
use std::time::Duration;

use bt_core::Node;
use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use gp::operators::{crossover, mutate, random_tree};
use gp::{Alphabet, Evaluation, Gp, MutationRates, Params, Variant};
use planner::duplo::{Spec, Task};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

type FitnessFn = fn(&[Node]) -> f64;

fn trivial(tree: &[Node]) -> f64 {
    -0.1 * tree.len() as f64 - f64::from(tree[0].size() % 7)
}

/// About 5 µs of arithmetic that depends on the tree (measured in `fitness/busy`).
fn busy(tree: &[Node]) -> f64 {
    let mut x = tree.len() as u64 | 1;
    for _ in 0..4_400 {
        x = black_box(x).wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    }
    trivial(tree) - (x >> 60) as f64 * 1e-9
}

fn baseline(spec: &Spec) -> Vec<Node> {
    bt_formats::tokens::parse(
        "s( f( 0 at pos (0.0, 0.05, 0.0)? s( pick 0! place at (0.0, 0.05, 0.0)! ) ) \
         f( 1 on 0? s( pick 1! place on 0! ) ) f( 2 on 1? s( pick 2! place on 1! ) ) )",
        spec,
    )
    .unwrap()
}

fn params(spec: &Spec, generations: u32) -> Params {
    Params { generations, ..Params::new(1, Variant::Baseline, Some(baseline(spec))) }
}

fn operators(c: &mut Criterion) {
    let spec = Task::Tower.spec();
    let alphabet = Alphabet::from_catalog(&spec).unwrap();
    let fitness = trivial;
    let mut gp = Gp::new(alphabet.clone(), &fitness, params(&spec, 30), Evaluation::Sequential).unwrap();
    for _ in 0..30 {
        gp.step();
    }
    let trees: Vec<_> = gp.population().iter().map(|i| i.genome.clone()).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let rates = MutationRates::default();
    let tree = baseline(&spec);
    c.bench_function("fitness/busy", |b| b.iter(|| busy(black_box(&tree))));
    let mut g = c.benchmark_group("operators");
    g.bench_function("random_tree_8", |b| b.iter(|| random_tree(8, &alphabet, &mut rng)));
    let mut k = 0;
    g.bench_function("mutate", |b| {
        b.iter(|| {
            k = (k + 1) % trees.len();
            mutate(&trees[k], &alphabet, &rates, &mut rng)
        })
    });
    g.bench_function("crossover", |b| {
        b.iter(|| {
            k = (k + 1) % trees.len();
            crossover(&trees[k], &trees[(k + 5) % trees.len()], &alphabet, &mut rng)
        })
    });
    g.finish();
}

fn generation(c: &mut Criterion) {
    let spec = Task::Tower.spec();
    let alphabet = Alphabet::from_catalog(&spec).unwrap();
    let fitness = trivial;
    let mut g = c.benchmark_group("generation");
    g.throughput(Throughput::Elements(32));
    for warm in [1, 50] {
        let mut gp = Gp::new(alphabet.clone(), &fitness, params(&spec, 500), Evaluation::Sequential).unwrap();
        for _ in 0..warm {
            gp.step();
        }
        g.bench_function(format!("trivial_fitness_after_{warm}"), |b| {
            b.iter_batched(|| gp.clone(), |mut gp| black_box(gp.step()), BatchSize::SmallInput)
        });
    }
    g.finish();
}

fn run(c: &mut Criterion) {
    let spec = Task::Tower.spec();
    let alphabet = Alphabet::from_catalog(&spec).unwrap();
    let mut g = c.benchmark_group("run");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    let cases: [(&str, FitnessFn, Evaluation); 3] = [
        ("tower_200_trivial_sequential", trivial, Evaluation::Sequential),
        ("tower_200_busy5us_sequential", busy, Evaluation::Sequential),
        ("tower_200_busy5us_parallel", busy, Evaluation::Parallel),
    ];
    for (name, fitness, evaluation) in cases {
        let result = gp::run(alphabet.clone(), &fitness, params(&spec, 200), evaluation, |_| {}).unwrap();
        eprintln!("{name}: {} episodes per run", result.episodes);
        g.bench_function(name, |b| {
            b.iter(|| gp::run(alphabet.clone(), &fitness, params(&spec, 200), evaluation, |_| {}).unwrap().episodes)
        });
    }
    g.finish();
}

criterion_group!(benches, operators, generation, run);
criterion_main!(benches);
