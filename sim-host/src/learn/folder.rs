//! The run folder: a run's whole record, written by `sim-host learn` and read by
//! `sim-host plot`.
//!
//! `<task>-<variant>-<world>-seed<N>/` (a PDDL run uses the problem's name as task and
//! `strips` or `strips-disturb<RATE>` as world; an island run's variant reads
//! `baseline-islands8`) holds:
//! - `run.txt`: `key = value` lines — what was learned (task, or the PDDL domain and
//!   problem names and files), the world, the crate version, the planner's fitness
//!   there, the best fitness, episodes, generations run, the world's and the fitness's
//!   settings, the islands' settings, and every GP setting
//!   ([`gp::Params::to_record`]: seed, variant, generations, baseline, Table I);
//! - `curve.csv`: `generation,episodes,best_fitness,best_length`, one row per
//!   generation;
//! - the best tree as `best.bt` (image), `best.txt` (ASCII), `best.tokens` (GP's
//!   token notation) and `best.xml` (BehaviorTree.CPP v4);
//! - for a PDDL run, `domain.pddl` and `problem.pddl` as they were read.
//!
//! Nothing in it depends on the machine or the number of threads: the same run gives
//! the same bytes anywhere (times go to the terminal, not the folder).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail};
use bt_core::Catalog as _;
use bt_formats::{Names, ascii, image::Image};
use btcpp::xml::to_xml;
use gp::{GenerationLog, Variant};
use planner::duplo::Task;

use super::{RunOutcome, Subject, bricks, strips::StripsFitnessParams};
use crate::text::count;

/// The files every finished run folder holds (folders of earlier versions have no
/// `best.xml`; they still count as finished).
pub const FILES: [&str; 5] = ["run.txt", "curve.csv", "best.bt", "best.txt", "best.tokens"];

/// Fitness values a run can record: the cost is never negative, and no task's cost
/// comes near a billion.
const WORST: f64 = -1e9;

/// The files of a run's folder, by name.
///
/// # Errors
/// A best tree that cannot be encoded.
pub fn folder_files(run: &RunOutcome) -> anyhow::Result<Vec<(&'static str, Vec<u8>)>> {
    let spec = &run.spec;
    let best = run.best.tree()?;
    let mut record = String::new();
    let mut line = |k: &str, v: &dyn std::fmt::Display| {
        let _ = writeln!(record, "{k} = {v}");
    };
    let mut files: Vec<(&'static str, Vec<u8>)> = Vec::new();
    match &spec.subject {
        Subject::Brick { task, .. } => {
            line("task", &task.name());
        }
        Subject::Strips { problem, .. } => {
            line("problem", &problem.name());
            line("domain", &problem.domain_name());
            line("domain_file", &"domain.pddl");
            line("problem_file", &"problem.pddl");
        }
    }
    line("world", &spec.subject.world_name());
    line("sim_host_version", &env!("CARGO_PKG_VERSION"));
    line("planner_fitness", &format!("{:?}", run.planner_fitness));
    line("best_fitness", &format!("{:?}", run.best.fitness));
    line("episodes", &run.episodes);
    line("generations_run", &run.log.len());
    line("goal_sequence", &spec.goal_sequence);
    let catalog = spec.subject.catalog();
    let mut tokens = bt_formats::tokens::to_string(&best, catalog.as_ref())?;
    tokens.push('\n');
    match &spec.subject {
        Subject::Brick { task, world } => {
            let mut text = String::new();
            if *world == worlds::WorldKind::Physics {
                // The world's own settings: the episodes of a physics run depend on them.
                text.push_str(&bricks::physics_record());
            }
            record.push_str(&text);
            let spec = task.spec();
            files.push(("best.bt", Image::new(&best).encode(spec.fingerprint())?));
            files.push(("best.txt", ascii::to_ascii(&best, &spec)?.into_bytes()));
            files.push(("best.xml", to_xml(&best, &spec)?.into_bytes()));
        }
        Subject::Strips { problem, tick_limit, disturbance } => {
            let f = StripsFitnessParams::default();
            let _ = writeln!(record, "tick_limit = {tick_limit}");
            if !spec.bound.is_none() {
                // What the bound did to the planner's tree (its closure cut or left out).
                let _ = writeln!(record, "planner_fit = {}", problem.planner_fit());
            }
            match disturbance {
                Some(d) => {
                    let _ = writeln!(
                        record,
                        "disturb_rate = {}\ndisturb_seed = {}\ndisturb_episodes = {}",
                        d.rate, d.seed, d.episodes
                    );
                }
                None => record.push_str("disturb_rate = 0\n"),
            }
            let _ = writeln!(
                record,
                "fitness_unmet_goal = {}\nfitness_length = {}\nfitness_tick = {}\nfitness_failure = {}\nfitness_timeout = {}",
                f.unmet_goal, f.length, f.tick, f.failure, f.timeout
            );
            let nodes = problem.to_pddl(&best)?;
            let pddl = problem.pddl_catalog();
            // The problem's own names travel with the image (another problem of the
            // same domain has the same fingerprint but other objects).
            let title = format!("PDDL problem `{}` of domain `{}`", problem.name(), problem.domain_name());
            let names = Names::of(&title, pddl, pddl.objects());
            files.push(("best.bt", Image::new(&nodes).names(&names).encode(pddl.fingerprint())?));
            files.push(("best.txt", ascii::to_ascii(&nodes, pddl)?.into_bytes()));
            files.push(("best.xml", to_xml(&nodes, pddl)?.into_bytes()));
            files.push(("domain.pddl", problem.domain_text.clone().into_bytes()));
            files.push(("problem.pddl", problem.problem_text.clone().into_bytes()));
        }
    }
    if let Some(setup) = spec.islands {
        record.push_str(&setup.to_record());
        let _ = writeln!(record, "restarts = {}", run.restarts);
        let reached = run.reached.map_or("none".to_string(), |r| r.generation.to_string());
        let _ = writeln!(record, "reached_generation = {reached}");
    }
    record.push_str(&spec.params()?.to_record(catalog.as_ref())?);
    let mut out = vec![
        ("run.txt", format!("# sim-host learn: one GP run (Styrud et al.)\n{record}").into_bytes()),
        ("curve.csv", gp::to_csv(&run.log).into_bytes()),
        ("best.tokens", tokens.into_bytes()),
    ];
    out.extend(files);
    Ok(out)
}

/// A run folder read back: what `plot` needs.
#[derive(Clone, Debug)]
pub struct Recorded {
    /// The folder.
    pub path: PathBuf,
    /// The brick task's name, or the PDDL problem's.
    pub label: String,
    /// `symbolic`, `physics`, `strips`, `strips-disturb<RATE>`.
    pub world: String,
    /// Variant.
    pub variant: Variant,
    /// Variant as named in folders: `baseline`, `baseline-islands8`.
    pub variant_label: String,
    /// Seed.
    pub seed: u64,
    /// The planner's fitness in that world.
    pub planner_fitness: f64,
    /// The learning curve.
    pub curve: Vec<GenerationLog>,
}

/// What a folder under a results folder is.
#[derive(Clone, Debug)]
pub enum Folder {
    /// A finished run.
    Run(Recorded),
    /// A run folder that lacks something a finished run has (a file, rows of its
    /// curve): copied while being written, or left by an older version.
    Incomplete {
        /// The folder.
        path: PathBuf,
        /// What it lacks.
        missing: String,
    },
    /// Not a run folder (none of the files a run writes).
    Other,
}

/// Skipped while reading a results folder.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Skipped {
    /// Hidden `.<run>-XXXXXX` folders: runs being written, or interrupted.
    pub temporary: usize,
    /// Incomplete run folders.
    pub incomplete: usize,
    /// Copies of a run already read (same run, same record and curve).
    pub copies: usize,
}

/// Reads a folder.
///
/// # Errors
/// A malformed `run.txt` or `curve.csv`, naming the file and line: unknown names,
/// numbers that do not parse, fitness that is not finite, positive or absurd, a curve
/// whose generations do not count up or whose best gets worse.
pub fn read_folder(path: &Path) -> anyhow::Result<Folder> {
    let present: Vec<&str> = FILES.iter().copied().filter(|f| path.join(f).is_file()).collect();
    if present.is_empty() {
        return Ok(Folder::Other);
    }
    if present.len() < FILES.len() {
        let missing: Vec<&str> = FILES.iter().copied().filter(|f| !present.contains(f)).collect();
        return Ok(Folder::Incomplete { path: path.to_path_buf(), missing: missing.join(", ") });
    }
    let run_txt = path.join("run.txt");
    let text = std::fs::read_to_string(&run_txt).map_err(|e| anyhow!("cannot read {}: {e}", run_txt.display()))?;
    let entries = gp::parse_record(&text).map_err(|e| anyhow!("{}: {e}", run_txt.display()))?;
    let at = |line: usize| format!("{}:{line}", run_txt.display());
    let get = |key: &str| -> anyhow::Result<(usize, &str)> {
        entries
            .iter()
            .find(|e| e.key == key)
            .map(|e| (e.line, e.value))
            .ok_or_else(|| anyhow!("{}: no `{key} = ...` line", run_txt.display()))
    };
    let label = match get("task") {
        Ok((line, name)) => {
            Task::from_name(name).ok_or_else(|| {
                let names: Vec<&str> = Task::ALL.iter().map(|t| t.name()).collect();
                anyhow!("{}: unknown task `{name}` (tasks: {})", at(line), names.join(", "))
            })?;
            name.to_string()
        }
        Err(_) => get("problem")
            .map_err(|_| anyhow!("{}: no `task = ...` or `problem = ...` line", run_txt.display()))?
            .1
            .to_string(),
    };
    let (line, world) = get("world")?;
    let known_world = matches!(world, "symbolic" | "physics" | "strips")
        || world
            .strip_prefix("strips-disturb")
            .is_some_and(|r| r.parse::<f64>().is_ok_and(|r| (0.0..=1.0).contains(&r)));
    if !known_world {
        bail!("{}: unknown world `{world}` (symbolic, physics, strips, strips-disturb<RATE>)", at(line));
    }
    let (line, v) = get("variant")?;
    let variant: Variant = v.parse().map_err(|e| anyhow!("{}: {e}", at(line)))?;
    let (line, s) = get("seed")?;
    let seed: u64 = s.parse().map_err(|_| anyhow!("{}: seed `{s}` is not a whole number", at(line)))?;
    let islands = match get("islands") {
        Ok((line, k)) => {
            Some(k.parse::<usize>().map_err(|_| anyhow!("{}: islands `{k}` is not a whole number", at(line)))?)
        }
        Err(_) => None,
    };
    let variant_label = match islands {
        Some(k) => format!("{}-islands{k}", variant.name()),
        None => variant.name().to_string(),
    };
    let (line, p) = get("planner_fitness")?;
    let planner_fitness = fitness_value(p).map_err(|why| anyhow!("{}: planner_fitness `{p}` {why}", at(line)))?;
    let (line, g) = get("generations_run").or_else(|_| get("generations"))?;
    let rows: usize = g.parse().map_err(|_| anyhow!("{}: `{g}` is not a number of generations", at(line)))?;

    let csv = path.join("curve.csv");
    let curve_text = std::fs::read_to_string(&csv).map_err(|e| anyhow!("cannot read {}: {e}", csv.display()))?;
    let curve = gp::read_csv(&curve_text).map_err(|e| anyhow!("{}: {e}", csv.display()))?;
    check_curve(&csv, &curve)?;
    if curve.len() < rows {
        let missing = format!("curve.csv rows: {} of the {} run", curve.len(), count(rows, "generation"));
        return Ok(Folder::Incomplete { path: path.to_path_buf(), missing });
    }
    if curve.len() > rows {
        bail!(
            "{}: {}, but run.txt records {} run",
            csv.display(),
            count(curve.len(), "row"),
            count(rows, "generation")
        );
    }
    Ok(Folder::Run(Recorded {
        path: path.to_path_buf(),
        label,
        world: world.to_string(),
        variant,
        variant_label,
        seed,
        planner_fitness,
        curve,
    }))
}

/// A fitness as a run records it: finite, at most 0, not absurdly low.
fn fitness_value(text: &str) -> Result<f64, &'static str> {
    let v: f64 = text.parse().map_err(|_| "is not a number")?;
    check_fitness(v).map(|()| v)
}

fn check_fitness(v: f64) -> Result<(), &'static str> {
    if !v.is_finite() {
        return Err("is not a finite number");
    }
    if v > 0.0 {
        return Err("is positive; fitness is minus a cost, at most 0");
    }
    if v < WORST {
        return Err("is below -1e9, beyond any cost a run can have");
    }
    Ok(())
}

fn check_curve(csv: &Path, curve: &[GenerationLog]) -> anyhow::Result<()> {
    let mut last: Option<&GenerationLog> = None;
    for (i, row) in curve.iter().enumerate() {
        // Line numbers: the header is line 1 and read_csv skips no line before rows.
        let at = format!("{}:{}", csv.display(), i + 2);
        if row.generation as usize != i {
            bail!("{at}: generation {} where {i} was expected (rows count generations from 0)", row.generation);
        }
        let best = row.best_fitness;
        check_fitness(best).map_err(|why| anyhow!("{at}: best_fitness `{best:?}` {why}"))?;
        if row.best_length == 0 || row.best_length > usize::from(u16::MAX) {
            bail!("{at}: best_length {} is not a tree's length (1 to 65535 nodes)", row.best_length);
        }
        if row.episodes > 1 << 40 {
            bail!("{at}: {} is beyond any run", count(row.episodes, "episode"));
        }
        if let Some(prev) = last {
            if row.episodes < prev.episodes {
                bail!("{at}: episodes go down from {} to {}", prev.episodes, row.episodes);
            }
            if best < prev.best_fitness {
                bail!(
                    "{at}: the best fitness drops from {} to {best}; a run's best never gets worse",
                    prev.best_fitness
                );
            }
        }
        last = Some(row);
    }
    if curve.is_empty() {
        bail!("{}: no rows", csv.display());
    }
    Ok(())
}
