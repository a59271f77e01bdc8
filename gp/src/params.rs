//! The parameters of a run (Table I of Styrud et al.), the four variants, and the run
//! record: a plain `key = value` text that is the whole of a run's GP settings.

use std::fmt;
use std::str::FromStr;

use bt_core::{Catalog, Node};

use crate::bound::Bound;
use crate::operators::MutationRates;

/// How the planner's tree takes part (Styrud et al., Section III-C).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Variant {
    /// Plain GP from random trees: no baseline.
    None,
    /// The baseline replaces the first random individual and is put back into the
    /// population whenever it drops out.
    Baseline,
    /// As `Baseline`, and while crossover parents are selected the baseline's fitness
    /// is raised to the population's maximum.
    BoostCrossover,
    /// As `BoostCrossover`, for mutation parents too.
    BoostAll,
    /// The baseline replaces the first random individual of the initial population
    /// only; once it drops out it is gone (the reference implementation's `nokeep`).
    NoKeep,
}

impl Variant {
    /// The paper's four, in its order (what `all` means on the command line).
    pub const ALL: [Variant; 4] = [Variant::None, Variant::Baseline, Variant::BoostCrossover, Variant::BoostAll];

    /// Every variant: the paper's four, then the reference implementation's `nokeep`.
    pub const EVERY: [Variant; 5] =
        [Variant::None, Variant::Baseline, Variant::BoostCrossover, Variant::BoostAll, Variant::NoKeep];

    /// The name on the command line and in records: `none`, `baseline`,
    /// `boost-crossover`, `boost-all`, `nokeep`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Baseline => "baseline",
            Self::BoostCrossover => "boost-crossover",
            Self::BoostAll => "boost-all",
            Self::NoKeep => "nokeep",
        }
    }

    /// The variant with that name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::EVERY.into_iter().find(|v| v.name() == name)
    }

    /// Whether the variant inserts the baseline into the initial population.
    #[must_use]
    pub const fn uses_baseline(self) -> bool {
        !matches!(self, Self::None)
    }

    /// Whether the variant puts the baseline back whenever it drops out.
    #[must_use]
    pub const fn keeps_baseline(self) -> bool {
        !matches!(self, Self::None | Self::NoKeep)
    }

    /// Whether the baseline is boosted while crossover parents are selected.
    #[must_use]
    pub const fn boosts_crossover(self) -> bool {
        matches!(self, Self::BoostCrossover | Self::BoostAll)
    }

    /// Whether the baseline is boosted while mutation parents are selected.
    #[must_use]
    pub const fn boosts_mutation(self) -> bool {
        matches!(self, Self::BoostAll)
    }
}

impl fmt::Display for Variant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A variant name that is none of the four.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown variant `{0}` (expected none, baseline, boost-crossover, boost-all or nokeep)")]
pub struct UnknownVariant(pub String);

impl FromStr for Variant {
    type Err = UnknownVariant;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::from_name(s).ok_or_else(|| UnknownVariant(s.to_string()))
    }
}

/// Everything that decides a run, with Table I's values as defaults.
///
/// Counts are explicit where the reference has fractions of the population size: its
/// "best 10 % of the old population" and "10 % elites" are `round(0.1 * 16)` = 2.
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    /// Individuals in the population (16).
    pub population_size: usize,
    /// Length of the initial random trees, in nodes (8).
    pub initial_length: usize,
    /// Parents selected for crossover (8); even, they are paired up.
    pub crossover_parents: usize,
    /// Crossover rounds (2): each round pairs the crossover parents anew and every
    /// pair gives two children, so each parent has this many offspring.
    pub crossover_rounds: usize,
    /// Parents selected for mutation (8), from the population.
    pub mutation_parents: usize,
    /// Mutation offspring per mutation parent (2).
    pub mutation_offspring: usize,
    /// Probabilities of add, delete and change (40 %, 30 %, 30 %).
    pub mutation: MutationRates,
    /// How many of the best of the old population compete with the offspring for
    /// survival (the reference's best 10 %: 2).
    pub survivor_parents: usize,
    /// The best individuals always kept (2).
    pub elites: usize,
    /// Offspring smaller than this many nodes are refused (2).
    pub min_length: usize,
    /// Generations in the run, the initial one included: a run logs generations
    /// `0..generations` and breeds `generations - 1` times (the reference's count:
    /// 200 for the tower).
    pub generations: u32,
    /// Seed of the run's one random generator.
    pub seed: u64,
    /// How the planner's tree takes part.
    pub variant: Variant,
    /// The planner's tree: required by every variant but `None`, refused by `None`.
    pub baseline: Option<Vec<Node>>,
    /// The most a tree may take on the controller (none by default): a validity rule
    /// like Styrud et al.'s, applied to random trees and offspring alike.
    pub bound: Bound,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            population_size: 16,
            initial_length: 8,
            crossover_parents: 8,
            crossover_rounds: 2,
            mutation_parents: 8,
            mutation_offspring: 2,
            mutation: MutationRates::default(),
            survivor_parents: 2,
            elites: 2,
            min_length: 2,
            generations: 200,
            seed: 0,
            variant: Variant::None,
            baseline: None,
            bound: Bound::NONE,
        }
    }
}

/// A parameter set that cannot run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ParamsError {
    /// A count that must be at least 1.
    #[error("{0} must be at least 1")]
    Zero(&'static str),
    /// A count larger than the population.
    #[error("{field} = {value} exceeds population_size = {population}")]
    OverPopulation {
        /// The parameter.
        field: &'static str,
        /// Its value.
        value: usize,
        /// The population size.
        population: usize,
    },
    /// Crossover pairs its parents up.
    #[error("crossover_parents = {0} must be even (parents are paired)")]
    OddCrossoverParents(usize),
    /// Mutation probabilities that are not a distribution.
    #[error("mutation probabilities add {add}, delete {delete}, change {change} must be >= 0 and sum to 1")]
    Rates {
        /// Add.
        add: f64,
        /// Delete.
        delete: f64,
        /// Change.
        change: f64,
    },
    /// A baseline variant without a baseline tree.
    #[error("variant {0} needs the planner's tree as baseline")]
    MissingBaseline(Variant),
    /// A baseline tree given to the `none` variant.
    #[error("variant none takes no baseline tree")]
    UnexpectedBaseline,
}

impl Params {
    /// Table I's parameters with a seed, a variant and its baseline.
    #[must_use]
    pub fn new(seed: u64, variant: Variant, baseline: Option<Vec<Node>>) -> Self {
        Self { seed, variant, baseline, ..Self::default() }
    }

    /// Checks that the parameters can run.
    ///
    /// # Errors
    /// The first [`ParamsError`] found.
    pub fn check(&self) -> Result<(), ParamsError> {
        for (field, value) in [
            ("population_size", self.population_size),
            ("initial_length", self.initial_length),
            ("min_length", self.min_length),
            ("generations", self.generations as usize),
        ] {
            if value == 0 {
                return Err(ParamsError::Zero(field));
            }
        }
        for (field, value) in [
            ("crossover_parents", self.crossover_parents),
            ("mutation_parents", self.mutation_parents),
            ("survivor_parents", self.survivor_parents),
            ("elites", self.elites),
        ] {
            if value > self.population_size {
                return Err(ParamsError::OverPopulation { field, value, population: self.population_size });
            }
        }
        if !self.crossover_parents.is_multiple_of(2) {
            return Err(ParamsError::OddCrossoverParents(self.crossover_parents));
        }
        let MutationRates { add, delete, change } = self.mutation;
        let rates = [add, delete, change];
        if rates.iter().any(|r| !r.is_finite() || *r < 0.0) || (add + delete + change - 1.0).abs() > 1e-9 {
            return Err(ParamsError::Rates { add, delete, change });
        }
        match (self.variant.uses_baseline(), &self.baseline) {
            (true, None) => Err(ParamsError::MissingBaseline(self.variant)),
            (false, Some(_)) => Err(ParamsError::UnexpectedBaseline),
            _ => Ok(()),
        }
    }

    /// The parameters as a run record: one `key = value` line each, the baseline in
    /// the token notation with leaves named by `catalog`. [`Params::from_record`] reads
    /// it back exactly (floats are written in their shortest exact form).
    ///
    /// # Errors
    /// If the baseline cannot be written as tokens.
    pub fn to_record<C: Catalog + ?Sized>(&self, catalog: &C) -> Result<String, bt_formats::tokens::TokenError> {
        let mut s = String::new();
        let mut line = |k: &str, v: &dyn fmt::Display| s.push_str(&format!("{k} = {v}\n"));
        line("gp_version", &env!("CARGO_PKG_VERSION"));
        line("population_size", &self.population_size);
        line("initial_length", &self.initial_length);
        line("crossover_parents", &self.crossover_parents);
        line("crossover_rounds", &self.crossover_rounds);
        line("mutation_parents", &self.mutation_parents);
        line("mutation_offspring", &self.mutation_offspring);
        line("mutation_add", &self.mutation.add);
        line("mutation_delete", &self.mutation.delete);
        line("mutation_change", &self.mutation.change);
        line("survivor_parents", &self.survivor_parents);
        line("elites", &self.elites);
        line("min_length", &self.min_length);
        line("generations", &self.generations);
        line("seed", &self.seed);
        line("variant", &self.variant);
        if let Some(tree) = &self.baseline {
            line("baseline", &bt_formats::tokens::to_string(tree, catalog)?);
        }
        // Only when given: a record without a bound reads as it always did.
        if let Some(b) = self.bound.bytes {
            line("max_bytes", &b);
        }
        if let Some(n) = self.bound.nodes {
            line("max_nodes", &n);
        }
        Ok(s)
    }

    /// Reads the parameters from a record written by [`Params::to_record`], leaves of
    /// the baseline resolved by `catalog`. Keys it does not know (the caller's: task,
    /// world, ...) are left alone; `gp_version` is informative.
    ///
    /// # Errors
    /// A [`RecordError`] naming the line or the missing key.
    pub fn from_record<C: Catalog + ?Sized>(text: &str, catalog: &C) -> Result<Self, RecordError> {
        let entries = parse_record(text)?;
        let get = |key: &'static str| entries.iter().find(|e| e.key == key);
        fn value<T: FromStr>(e: Option<&Entry<'_>>, key: &'static str) -> Result<T, RecordError> {
            let e = e.ok_or(RecordError::Missing { key })?;
            e.value.parse().map_err(|_| RecordError::Value { line: e.line, key, value: e.value.to_string() })
        }
        let baseline = match get("baseline") {
            Some(e) => Some(
                bt_formats::tokens::parse(e.value, catalog)
                    .map_err(|source| RecordError::Baseline { line: e.line, source })?,
            ),
            None => None,
        };
        Ok(Self {
            population_size: value(get("population_size"), "population_size")?,
            initial_length: value(get("initial_length"), "initial_length")?,
            crossover_parents: value(get("crossover_parents"), "crossover_parents")?,
            crossover_rounds: value(get("crossover_rounds"), "crossover_rounds")?,
            mutation_parents: value(get("mutation_parents"), "mutation_parents")?,
            mutation_offspring: value(get("mutation_offspring"), "mutation_offspring")?,
            mutation: MutationRates {
                add: value(get("mutation_add"), "mutation_add")?,
                delete: value(get("mutation_delete"), "mutation_delete")?,
                change: value(get("mutation_change"), "mutation_change")?,
            },
            survivor_parents: value(get("survivor_parents"), "survivor_parents")?,
            elites: value(get("elites"), "elites")?,
            min_length: value(get("min_length"), "min_length")?,
            generations: value(get("generations"), "generations")?,
            seed: value(get("seed"), "seed")?,
            variant: value(get("variant"), "variant")?,
            baseline,
            bound: Bound {
                bytes: get("max_bytes").map(|e| value(Some(e), "max_bytes")).transpose()?,
                nodes: get("max_nodes").map(|e| value(Some(e), "max_nodes")).transpose()?,
            },
        })
    }
}

/// One `key = value` line of a record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Entry<'a> {
    /// 1-based line number.
    pub line: usize,
    /// The key, trimmed.
    pub key: &'a str,
    /// The value, trimmed.
    pub value: &'a str,
}

/// A record that cannot be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RecordError {
    /// A line that is not blank, a `#` comment, or `key = value`.
    #[error("line {line}: expected `key = value`, found `{text}`")]
    Syntax {
        /// 1-based line.
        line: usize,
        /// The line.
        text: String,
    },
    /// A key given twice.
    #[error("line {line}: `{key}` given a second time (first on line {first})")]
    Duplicate {
        /// 1-based line of the second.
        line: usize,
        /// First line.
        first: usize,
        /// The key.
        key: String,
    },
    /// A value that does not parse for its key.
    #[error("line {line}: `{value}` is not a valid {key}")]
    Value {
        /// 1-based line.
        line: usize,
        /// The key.
        key: &'static str,
        /// The value.
        value: String,
    },
    /// A required key that is absent.
    #[error("`{key}` missing from the record")]
    Missing {
        /// The key.
        key: &'static str,
    },
    /// The baseline tree does not parse.
    #[error("line {line}: baseline: {source}")]
    Baseline {
        /// 1-based line.
        line: usize,
        /// Why.
        source: bt_formats::tokens::TokenError,
    },
}

/// Splits a record into its `key = value` entries (blank lines and `#` comments
/// skipped), for the caller's own keys as well as GP's.
///
/// # Errors
/// [`RecordError::Syntax`] for a line without `=` or with an empty key;
/// [`RecordError::Duplicate`] for a key given twice.
pub fn parse_record(text: &str) -> Result<Vec<Entry<'_>>, RecordError> {
    let mut entries: Vec<Entry<'_>> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let trimmed = raw.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let Some((key, value)) = trimmed.split_once('=') else {
            return Err(RecordError::Syntax { line, text: trimmed.to_string() });
        };
        let (key, value) = (key.trim(), value.trim());
        if key.is_empty() {
            return Err(RecordError::Syntax { line, text: trimmed.to_string() });
        }
        if let Some(first) = entries.iter().find(|e| e.key == key) {
            return Err(RecordError::Duplicate { line, first: first.line, key: key.to_string() });
        }
        entries.push(Entry { line, key, value });
    }
    Ok(entries)
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner::duplo::Task;

    #[test]
    fn defaults_are_table_one() {
        let p = Params::default();
        assert_eq!((p.population_size, p.initial_length), (16, 8));
        assert_eq!((p.crossover_parents, p.crossover_rounds, p.mutation_parents, p.mutation_offspring), (8, 2, 8, 2));
        assert_eq!(p.mutation, MutationRates { add: 0.4, delete: 0.3, change: 0.3 });
        assert_eq!((p.elites, p.survivor_parents, p.min_length), (2, 2, 2));
        assert_eq!(p.check(), Ok(()));
    }

    #[test]
    fn checks_name_the_parameter() {
        let p = |f: fn(&mut Params)| {
            let mut p = Params::default();
            f(&mut p);
            p.check()
        };
        assert_eq!(p(|p| p.population_size = 0), Err(ParamsError::Zero("population_size")));
        assert_eq!(p(|p| p.generations = 0), Err(ParamsError::Zero("generations")));
        assert_eq!(
            p(|p| p.elites = 17),
            Err(ParamsError::OverPopulation { field: "elites", value: 17, population: 16 })
        );
        assert_eq!(p(|p| p.crossover_parents = 7), Err(ParamsError::OddCrossoverParents(7)));
        assert!(matches!(p(|p| p.mutation.add = 0.5), Err(ParamsError::Rates { .. })));
        assert_eq!(p(|p| p.variant = Variant::BoostAll), Err(ParamsError::MissingBaseline(Variant::BoostAll)));
        assert_eq!(p(|p| p.baseline = Some(Vec::new())), Err(ParamsError::UnexpectedBaseline));
    }

    #[test]
    fn variants_by_name() {
        for v in Variant::EVERY {
            assert_eq!(v.name().parse::<Variant>(), Ok(v));
        }
        assert!("boost".parse::<Variant>().is_err());
        assert!(!Variant::Baseline.boosts_crossover() && Variant::BoostCrossover.boosts_crossover());
        assert!(!Variant::BoostCrossover.boosts_mutation() && Variant::BoostAll.boosts_mutation());
        assert!(Variant::NoKeep.uses_baseline() && !Variant::NoKeep.keeps_baseline());
        assert!(!Variant::NoKeep.boosts_crossover() && Variant::Baseline.keeps_baseline());
    }

    #[test]
    fn record_round_trips() {
        let spec = Task::Tower.spec();
        let tree = bt_formats::tokens::parse("s( f( picked 0? pick 0! ) apply force 0! )", &spec).unwrap();
        let mut p = Params::new(3, Variant::BoostCrossover, Some(tree));
        p.mutation = MutationRates { add: 0.1, delete: 0.2, change: 0.7 };
        p.generations = 1000;
        let text = format!("task = tower\n# a comment\n\n{}", p.to_record(&spec).unwrap());
        assert!(text.contains("variant = boost-crossover\n"));
        assert!(text.contains("baseline = s( f( picked 0? pick 0! ) apply force 0! )\n"));
        assert_eq!(Params::from_record(&text, &spec), Ok(p));
    }

    #[test]
    fn record_errors_name_the_line() {
        let spec = Task::Tower.spec();
        let good = Params::default().to_record(&spec).unwrap();
        assert_eq!(
            Params::from_record(&good.replace("seed = 0", "seed = x"), &spec),
            Err(RecordError::Value { line: 15, key: "seed", value: "x".into() })
        );
        assert_eq!(
            Params::from_record(&good.replace("elites = 2\n", ""), &spec),
            Err(RecordError::Missing { key: "elites" })
        );
        assert!(matches!(
            Params::from_record(&format!("{good}elites = 3\n"), &spec),
            Err(RecordError::Duplicate { first: 12, .. })
        ));
        assert!(matches!(Params::from_record("no equals sign", &spec), Err(RecordError::Syntax { line: 1, .. })));
        assert!(matches!(
            Params::from_record(&format!("{good}baseline = s( nope! )\n"), &spec),
            Err(RecordError::Baseline { line: 17, .. })
        ));
    }
}
