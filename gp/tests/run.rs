//! The generation loop: determinism, parallel == sequential, the cache, elitism, the
//! baseline and boosting, on a synthetic fitness.

mod common;

use common::{Target, tower_baseline};
use gp::{Evaluation, Genome, Gp, GpError, Params, ParamsError, Variant};

fn params(seed: u64, variant: Variant, spec: &planner::duplo::Spec, generations: u32) -> Params {
    let baseline = variant.uses_baseline().then(|| tower_baseline(spec));
    Params { generations, ..Params::new(seed, variant, baseline) }
}

#[test]
fn same_seed_same_run_other_seed_other_run() {
    let (spec, alphabet, target) = Target::tower();
    let run = |seed| {
        gp::run(alphabet.clone(), &target, params(seed, Variant::BoostAll, &spec, 25), Evaluation::Parallel, |_| {})
            .unwrap()
    };
    let (a, b, c) = (run(1), run(1), run(2));
    assert_eq!(a, b);
    assert_ne!(a.population, c.population);
}

#[test]
fn parallel_equals_sequential_generation_by_generation() {
    let (spec, alphabet, target) = Target::tower();
    for variant in Variant::EVERY {
        let p = params(7, variant, &spec, 40);
        let mut par = Gp::new(alphabet.clone(), &target, p.clone(), Evaluation::Parallel).unwrap();
        let mut seq = Gp::new(alphabet.clone(), &target, p, Evaluation::Sequential).unwrap();
        for generation in 0..40 {
            assert_eq!(par.population(), seq.population(), "{variant} generation {generation}");
            assert_eq!(par.episodes(), seq.episodes(), "{variant} generation {generation}");
            assert_eq!(par.log(), seq.log(), "{variant} generation {generation}");
            assert_eq!(par.step(), seq.step(), "{variant} generation {generation}");
        }
    }
}

#[test]
fn episodes_are_unique_simulations() {
    let (spec, alphabet, target) = Target::tower();
    let mut gp = Gp::new(alphabet, &target, params(3, Variant::Baseline, &spec, 1), Evaluation::Parallel).unwrap();
    assert_eq!(gp.episodes(), 16);
    assert_eq!(target.calls(), 16);
    let mut last = gp.episodes();
    for _ in 0..60 {
        let row = gp.step();
        // At most 32 offspring per generation (Section V), each simulated at most once.
        assert!(row.episodes <= last + 32, "{row:?}");
        assert_eq!(target.calls(), row.episodes);
        last = row.episodes;
    }
    // Survivors and the baseline put back are never simulated again.
    let pop: Vec<Genome> = gp.population().iter().map(|i| i.genome.clone()).collect();
    let before = target.calls();
    for g in &pop {
        assert!(gp.cache().contains(g));
    }
    gp.step();
    assert!(target.calls() - before <= 32);
    // The paper: almost every offspring is new.
    assert!(gp.episodes() > 61 * 32 * 7 / 10, "{}", gp.episodes());
}

#[test]
fn elites_are_kept_and_the_best_never_gets_worse() {
    let (spec, alphabet, target) = Target::tower();
    for variant in [Variant::None, Variant::BoostCrossover] {
        let mut gp = Gp::new(alphabet.clone(), &target, params(5, variant, &spec, 1), Evaluation::Parallel).unwrap();
        for _ in 0..50 {
            let mut old: Vec<f64> = gp.population().iter().map(|i| i.fitness).collect();
            old.sort_by(|a, b| b.total_cmp(a));
            gp.step();
            let new: Vec<f64> = gp.population().iter().map(|i| i.fitness).collect();
            // Elites first, best first; they are at least as good as the old two best.
            assert!(new[0] >= new[1] && new[1..].iter().all(|f| *f <= new[0]));
            assert!(new[0] >= old[0] && new[1] >= old[1], "{old:?} -> {new:?}");
        }
        let log = gp.log();
        assert!(log.windows(2).all(|w| w[1].best_fitness >= w[0].best_fitness));
        // The synthetic fitness is learnable: GP improves on the initial population.
        assert!(log[50].best_fitness > log[0].best_fitness + 1.0, "{variant}: {:?} {:?}", log[0], log[50]);
    }
}

#[test]
fn the_baseline_stays_in_the_population_and_its_fitness_is_its_own() {
    let (spec, alphabet, target) = Target::tower();
    let baseline_nodes = tower_baseline(&spec);
    let baseline_fitness = target.score(&baseline_nodes);
    for variant in [Variant::Baseline, Variant::BoostCrossover, Variant::BoostAll] {
        let mut gp = Gp::new(alphabet.clone(), &target, params(2, variant, &spec, 1), Evaluation::Parallel).unwrap();
        let baseline = gp.baseline().unwrap().clone();
        assert_eq!(baseline.to_nodes().unwrap(), baseline_nodes);
        assert_eq!(gp.population()[0].genome, baseline);
        let mut dropped_out = 0;
        for _ in 0..80 {
            gp.step();
            let pop = gp.population();
            let at = pop.iter().position(|i| i.genome == baseline).expect("baseline kept");
            // Boosting never leaks: the baseline keeps its own fitness.
            assert_eq!(pop[at].fitness, baseline_fitness);
            assert!(pop.len() == 16 || (pop.len() == 17 && at == 16));
            dropped_out += usize::from(pop.len() == 17);
            for i in pop {
                assert_eq!(i.fitness, target.score(&i.tree().unwrap()));
            }
        }
        // The baseline is far from the best here, so it drops out and comes back.
        assert!(dropped_out > 0, "{variant}");
    }
    let mut none = Gp::new(alphabet, &target, params(2, Variant::None, &spec, 1), Evaluation::Parallel).unwrap();
    assert!(none.baseline().is_none());
    none.step();
    assert_eq!(none.population().len(), 16);
}

#[test]
fn nokeep_inserts_the_baseline_once_and_lets_it_go() {
    let (spec, alphabet, target) = Target::tower();
    let mut gp = Gp::new(alphabet, &target, params(2, Variant::NoKeep, &spec, 1), Evaluation::Parallel).unwrap();
    let baseline = gp.baseline().unwrap().clone();
    assert_eq!(gp.population()[0].genome, baseline);
    let mut gone_at = None;
    for generation in 1..=80 {
        gp.step();
        let pop = gp.population();
        assert_eq!(pop.len(), 16, "never put back, so never a 17th member");
        let present = pop.iter().any(|i| i.genome == baseline);
        match gone_at {
            None if !present => gone_at = Some(generation),
            Some(g) => assert!(!present, "the baseline came back at generation {generation} after leaving at {g}"),
            None => {}
        }
    }
    // The baseline is far from the best here: it drops out, as with `baseline`, but stays out.
    assert!(gone_at.is_some());
}

#[test]
fn a_good_baseline_starts_the_curve_at_its_level() {
    let (spec, alphabet, target) = Target::tower();
    let baseline_fitness = target.score(&tower_baseline(&spec));
    let with = gp::run(alphabet.clone(), &target, params(4, Variant::Baseline, &spec, 2), Evaluation::Parallel, |_| {})
        .unwrap();
    assert!(with.log[0].best_fitness >= baseline_fitness);
    let without = gp::run(alphabet, &target, params(4, Variant::None, &spec, 2), Evaluation::Parallel, |_| {}).unwrap();
    assert!(without.log[0].best_fitness < baseline_fitness);
}

#[test]
fn run_reports_every_generation_once_in_order() {
    let (spec, alphabet, target) = Target::tower();
    let mut seen = Vec::new();
    let result =
        gp::run(alphabet, &target, params(9, Variant::None, &spec, 12), Evaluation::Sequential, |row| seen.push(*row))
            .unwrap();
    assert_eq!(seen, result.log);
    assert_eq!(seen.iter().map(|r| r.generation).collect::<Vec<_>>(), (0..12).collect::<Vec<_>>());
    assert!(seen.windows(2).all(|w| w[1].episodes >= w[0].episodes));
    assert_eq!(result.episodes, seen[11].episodes);
    assert_eq!(result.best.fitness, seen[11].best_fitness);
    assert_eq!(result.best.genome.length(), seen[11].best_length);
    assert_eq!(result.best.tree().unwrap().len(), seen[11].best_length);
    assert_eq!(gp::read_csv(&gp::to_csv(&result.log)).unwrap(), result.log);
}

#[test]
fn bad_setups_are_refused_with_the_reason() {
    let (spec, alphabet, target) = Target::tower();
    let mut p = params(1, Variant::Baseline, &spec, 3);
    p.baseline = None;
    assert_eq!(
        Gp::new(alphabet.clone(), &target, p, Evaluation::Parallel).unwrap_err(),
        GpError::Params(ParamsError::MissingBaseline(Variant::Baseline))
    );
    // A baseline from another task: its leaves are not all in the tower's alphabet.
    let blocking = planner::duplo::Task::Blocking.spec();
    let foreign = bt_formats::tokens::parse("s( put 2 at (-0.1, 0.0, 0.0)! put 0 on 1! )", &blocking).unwrap();
    let p = Params::new(1, Variant::Baseline, Some(foreign));
    assert!(matches!(Gp::new(alphabet.clone(), &target, p, Evaluation::Parallel), Err(GpError::Baseline(_))));
    let mut p = params(1, Variant::None, &spec, 3);
    p.initial_length = 40;
    assert_eq!(Gp::new(alphabet, &target, p, Evaluation::Parallel).unwrap_err(), GpError::NoRandomTree(40));
}

#[test]
fn every_brick_task_evolves_valid_trees() {
    for task in planner::duplo::Task::ALL {
        let spec = task.spec();
        let alphabet = gp::Alphabet::from_catalog(&spec).unwrap();
        // Score: fewer nodes is better, odd sizes worse; enough to drive selection.
        let fitness = |t: &[bt_core::Node]| -(t.len() as f64) - f64::from(u8::from(t.len() % 2 == 1)) * 0.5;
        let mut gp =
            Gp::new(alphabet.clone(), &fitness, Params::new(1, Variant::None, None), Evaluation::Sequential).unwrap();
        for _ in 0..25 {
            gp.step();
            assert_eq!(gp.population().len(), 16, "{task:?}");
            for i in gp.population() {
                assert_eq!(i.genome.check(&alphabet), Ok(()), "{task:?}");
                assert!(i.genome.length() >= 2);
                assert_eq!(i.fitness, fitness(&i.tree().unwrap()));
            }
        }
        assert!(gp.log().last().unwrap().best_fitness >= -3.0, "{task:?}: {:?}", gp.log().last());
    }
}
