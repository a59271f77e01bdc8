//! The size bound: a validity rule that no tree of a run ever breaks, with the
//! baseline and the smallest tree checked up front, and runs as deterministic as
//! unbounded ones.

mod common;

use bt_core::Node;
use common::{Target, tower_baseline};
use gp::islands::{self, IslandParams};
use gp::{Bound, Evaluation, Gp, GpError, Params, Size, Variant};

/// Bigger is better: without a bound, trees grow without end.
fn bigger(tree: &[Node]) -> f64 {
    tree.len() as f64
}

fn params(seed: u64, variant: Variant, spec: &planner::duplo::Spec, bound: Bound) -> Params {
    let baseline = variant.uses_baseline().then(|| tower_baseline(spec));
    Params { generations: 30, bound, ..Params::new(seed, variant, baseline) }
}

fn size(individual: &gp::Individual) -> Size {
    gp::image_size(&individual.tree().unwrap()).unwrap()
}

#[test]
fn no_tree_of_a_bounded_run_is_over_the_bound() {
    let (spec, alphabet, _) = Target::tower();
    let baseline = gp::image_size(&tower_baseline(&spec)).unwrap();
    // Room for the baseline and a few nodes more, in bytes; in nodes, a little more.
    let bound = Bound { bytes: Some(baseline.bytes + 12), nodes: Some(baseline.nodes + 6) };
    let free = gp::run(
        alphabet.clone(),
        &bigger,
        params(5, Variant::Baseline, &spec, Bound::NONE),
        Evaluation::Sequential,
        |_| {},
    )
    .unwrap();
    assert!(!bound.admits(size(&free.best)), "unbounded, the best outgrows the bound: {:?}", size(&free.best));

    let mut gp =
        Gp::new(alphabet, &bigger, params(5, Variant::Baseline, &spec, bound), Evaluation::Sequential).unwrap();
    for generation in 0..40 {
        for i in gp.population() {
            assert!(bound.admits(size(i)), "generation {generation}: {:?} over {bound}", size(i));
        }
        gp.step();
    }
    // The bound is reached, not just respected from afar.
    let best = size(gp.best());
    assert!(best.bytes + 6 > bound.bytes.unwrap() || best.nodes == bound.nodes.unwrap(), "{best:?}");
}

#[test]
fn a_node_bound_below_the_initial_length_draws_smaller_trees() {
    let (spec, alphabet, _) = Target::tower();
    let bound = Bound { bytes: None, nodes: Some(4) };
    let gp = Gp::new(alphabet, &bigger, params(2, Variant::None, &spec, bound), Evaluation::Sequential).unwrap();
    assert!(gp.population().iter().all(|i| i.genome.length() <= 4));
}

#[test]
fn a_baseline_over_the_bound_and_a_bound_below_any_tree_are_refused() {
    let (spec, alphabet, _) = Target::tower();
    let baseline = gp::image_size(&tower_baseline(&spec)).unwrap();
    let bound = Bound { bytes: Some(baseline.bytes - 1), nodes: None };
    let err = Gp::new(alphabet.clone(), &bigger, params(1, Variant::Baseline, &spec, bound), Evaluation::Sequential)
        .unwrap_err();
    assert_eq!(err, GpError::BaselineTooBig { size: baseline, bound });
    assert!(err.to_string().contains(&format!("over the bound of at most {} bytes", baseline.bytes - 1)), "{err}");

    let nothing = Bound { bytes: Some(0), nodes: None };
    let err = Gp::new(alphabet, &bigger, params(1, Variant::None, &spec, nothing), Evaluation::Sequential).unwrap_err();
    assert_eq!(err, GpError::BoundTooSmall { bound: nothing, min_length: 2 });
}

#[test]
fn bounded_runs_are_deterministic_sequential_parallel_and_on_islands() {
    let (spec, alphabet, target) = Target::tower();
    let baseline = gp::image_size(&tower_baseline(&spec)).unwrap();
    let bound = Bound { bytes: Some(baseline.bytes + 20), nodes: None };
    let p = params(9, Variant::BoostAll, &spec, bound);
    let mut par = Gp::new(alphabet.clone(), &target, p.clone(), Evaluation::Parallel).unwrap();
    let mut seq = Gp::new(alphabet.clone(), &target, p.clone(), Evaluation::Sequential).unwrap();
    for generation in 0..30 {
        assert_eq!(par.population(), seq.population(), "generation {generation}");
        assert_eq!(par.step(), seq.step(), "generation {generation}");
    }
    let again = gp::run(alphabet.clone(), &target, p.clone(), Evaluation::Parallel, |_| {}).unwrap();
    assert_eq!(again, gp::run(alphabet.clone(), &target, p.clone(), Evaluation::Parallel, |_| {}).unwrap());

    let setup = IslandParams { islands: 3, migration_interval: 5, stagnation: Some(10), stop_at: None };
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| islands::run(alphabet.clone(), &target, p.clone(), setup, |_| {}).unwrap())
    };
    let one = on(1);
    assert_eq!(one, on(2));
    assert!(bound.admits(size(&one.best)), "{:?}", size(&one.best));
}

#[test]
fn the_bound_is_in_the_record() {
    let (spec, _, _) = Target::tower();
    let p = params(3, Variant::Baseline, &spec, Bound { bytes: Some(300), nodes: Some(40) });
    let record = p.to_record(&spec).unwrap();
    assert!(record.contains("max_bytes = 300\nmax_nodes = 40\n"), "{record}");
    assert_eq!(Params::from_record(&record, &spec).unwrap(), p);
    let plain = params(3, Variant::Baseline, &spec, Bound::NONE);
    let record = plain.to_record(&spec).unwrap();
    assert!(!record.contains("max_"), "{record}");
    assert_eq!(Params::from_record(&record, &spec).unwrap(), plain);
}
