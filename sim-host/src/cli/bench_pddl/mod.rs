//! `sim-host bench-pddl DIR`: planner coverage on a folder of PDDL benchmark domains,
//! side by side with pyperplan and Fast Downward, every plan checked by an independent
//! validator.
//!
//! Each instance runs in a child process of this binary (the same command with the
//! hidden `--child`), killed at the timeout; the child reads, grounds and plans with
//! [`planner::coverage::run`] and prints its result as `key<TAB>value` lines. The
//! parent then checks the executed plan with the validator, runs the peers on a copy
//! of the files with the same timeout ([`peers`]), sums up per domain ([`table`]) and
//! draws coverage against time ([`plot`]).

mod peers;
mod plot;
mod table;

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use anyhow::{Context as _, bail};
use peers::{Peer, PeerRun, timed};
use planner::coverage::{self, Instance, Outcome, Run, Settings};
use sim_host::text::count;

pub const LONG_ABOUT: &str = "Measures the planner on a folder of PDDL benchmarks: one sub-folder per \
    domain, each problem with its domain file (`domain.pddl`, or `domain_P.pddl`, `domain-P.pddl`, \
    `pNN-domain.pddl` for problem P, as the IPC collections name them).\n\n\
    For every instance, in a child process killed at --timeout: read, ground and plan (Algorithm 1, \
    search-guided backchaining when it cannot finish); run the tree from the initial state in the \
    symbolic world (the actions it executes are the plan); run it again in --episodes episodes with \
    seeded external disturbances (an agent undoes the robot's last action, or does one of the tree's \
    actions for it) and count the episodes that reach the goal. With --validate, every executed plan \
    is checked by that program (VAL's `Validate DOMAIN PROBLEM PLAN`, exit status 0 = valid); with \
    --pyperplan, pyperplan (greedy best-first search with h_FF), and with --fast-downward, Fast \
    Downward with LAMA's first iteration (`--alias lama-first`), run on the same instance with the \
    same timeout, one process at a time, and their plans are validated the same way.\n\n\
    Prints a line per instance (with the tree and the repeating actions when Algorithm 1 \
    oscillated), then a table per domain: instances, parsed, solved, median planning time, median \
    tree size and plan cost, plans found valid, disturbed episodes that reached the goal (of all, and \
    of those where a plan remained: a disturbance that search proves leaves no plan to the goal, \
    such as a peg jumped out of turn in peg solitaire, is a dead end no tree recovers from), and \
    each peer's solved count and median time; then, against Fast Downward, the instances both \
    solve, how many of ours took at most twice its time and half a second, the worst ratio, and \
    how many of our trees fit --max-bytes. Times are wall-clock: ours from reading the files to \
    the checked tree (the disturbed episodes come after), each peer's for its whole process \
    (Fast Downward's translator included). With --plot, a picture of the instances solved \
    against time, one line per planner, as planning papers draw coverage.";

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The folder of domains (sub-folders) or of one domain's files.
    pub dir: PathBuf,
    /// Seconds per instance (and per pyperplan run).
    #[arg(long, default_value_t = 60)]
    pub timeout: u64,
    /// Disturbed episodes per solved instance.
    #[arg(long, default_value_t = 20)]
    pub episodes: u32,
    /// Seed of the disturbances.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Root Failures in a row that end a disturbed episode: 2 (a robot ticks on after
    /// one failed tick, such as an action whose preconditions the agent changed while
    /// it ran) or 1 (the first Failure ends it).
    #[arg(long, value_name = "N", default_value_t = Settings::default().failures,
          value_parser = clap::value_parser!(u32).range(1..))]
    pub failures: u32,
    /// The plan validator: called as `PROGRAM DOMAIN PROBLEM PLAN`, exit status 0 when
    /// the plan is valid (e.g. VAL's `Validate`).
    #[arg(long, value_name = "PROGRAM")]
    pub validate: Option<PathBuf>,
    /// pyperplan's command, run as `PROGRAM -H hff -s gbf DOMAIN PROBLEM`.
    #[arg(long, value_name = "PROGRAM")]
    pub pyperplan: Option<PathBuf>,
    /// Fast Downward's driver, run as `PROGRAM --alias lama-first --plan-file PLAN
    /// DOMAIN PROBLEM` (`pip install up-fast-downward` ships it as
    /// `up_fast_downward/downward/fast-downward.py`).
    #[arg(long, value_name = "PROGRAM")]
    pub fast_downward: Option<PathBuf>,
    /// The most image bytes a tree may have, as `plan --max-bytes` (default: 16 KiB
    /// where the tree without its closure fits; 0: no bound).
    #[arg(long, value_name = "BYTES")]
    pub max_bytes: Option<usize>,
    /// The most bt-core nodes a tree may have, as `plan --max-nodes`.
    #[arg(long, value_name = "NODES")]
    pub max_nodes: Option<usize>,
    /// How the search that guides the tree evaluates states, as `plan --search`.
    #[arg(long, value_enum, default_value_t = super::plan::SearchArg::Landmarks)]
    pub search: super::plan::SearchArg,
    /// Draw the instances solved against time, ours and the peers', to this PNG or SVG
    /// file.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Only instances whose `domain/problem` path contains this text.
    #[arg(long)]
    pub only: Option<String>,
    /// Write the table (Markdown) here too.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Close the trees of Algorithm 1 over disturbances too, as `plan
    /// --close-backchained` does (guided and regression trees are always closed).
    #[arg(long)]
    pub close_backchained: bool,
    /// The most nodes a tree may grow to while it is closed over disturbances, as
    /// `plan --close-nodes` (0: no closure).
    #[arg(long, value_name = "NODES", default_value_t = planner::Options::default().close_nodes)]
    pub close_nodes: usize,
    /// Child mode: run one instance (domain file, problem file) and print the result.
    #[arg(long, num_args = 2, value_names = ["DOMAIN", "PROBLEM"], hide = true)]
    pub child: Option<Vec<PathBuf>>,
}

/// One instance's results on every side.
struct Row {
    instance: Instance,
    ours: Run,
    valid: Option<bool>,
    /// The peers' runs, in the order of [`Args::peers`].
    peers: Vec<PeerRun>,
}

impl Args {
    /// The peers asked for, with their programs.
    fn peers(&self) -> Vec<(Peer, &Path)> {
        let mut out = Vec::new();
        if let Some(p) = &self.fast_downward {
            out.push((Peer::FastDownward, p.as_path()));
        }
        if let Some(p) = &self.pyperplan {
            out.push((Peer::Pyperplan, p.as_path()));
        }
        out
    }

    /// The size trees must fit (`--max-bytes 0`: no bound).
    fn fit(&self) -> planner::Fit {
        match self.max_bytes {
            Some(0) if self.max_nodes.is_none() => planner::Fit::NONE,
            b => super::plan::fit(b.filter(|&b| b > 0), self.max_nodes),
        }
    }
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let settings = Settings {
        timeout: Duration::from_secs(args.timeout),
        episodes: args.episodes,
        seed: args.seed,
        failures: args.failures,
        close_backchained: args.close_backchained,
        close_nodes: args.close_nodes,
        fit: args.fit(),
        deferred: args.search.options().0,
        landmarks: args.search.options().1,
        ..Settings::default()
    };
    if let Some(files) = &args.child {
        let [domain_file, problem_file] = &files[..] else { bail!("--child takes a domain and a problem file") };
        let instance =
            Instance { domain: String::new(), domain_file: domain_file.clone(), problem_file: problem_file.clone() };
        let r = coverage::run(&instance, &settings);
        super::output::stdout(r.encode().as_bytes())?;
        return Ok(());
    }
    if args.timeout == 0 {
        bail!("--timeout must be at least 1 second");
    }
    if let Some(path) = &args.plot {
        plot::check(path)?;
    }
    let mut list = coverage::instances(&args.dir).with_context(|| format!("cannot read {}", args.dir.display()))?;
    if let Some(only) = &args.only {
        list.retain(|i| format!("{}/{}", i.domain, name(&i.problem_file)).contains(only.as_str()));
    }
    if list.is_empty() {
        bail!("no PDDL problems with a domain file under {}", args.dir.display());
    }
    let exe = std::env::current_exe().context("cannot find this program's path")?;
    // Gathered here, written through `output` row by row (a closed pipe ends quietly).
    let mut out: Vec<u8> = Vec::new();
    writeln!(
        out,
        "{}, timeout {} s, {} each (seed {})",
        count(list.len(), "instance"),
        args.timeout,
        count(args.episodes, "disturbed episode"),
        args.seed
    )?;
    super::output::stdout(&out)?;
    out.clear();
    let mut rows = Vec::with_capacity(list.len());
    for instance in list {
        let ours = child(&exe, &instance, args)?;
        let valid = match (&args.validate, ours.solved()) {
            (Some(v), true) => Some(peers::validate(v, &instance, &ours.plan.join("\n"))?),
            _ => None,
        };
        let mut peer_runs = Vec::new();
        for (peer, program) in args.peers() {
            let limit = Duration::from_secs(args.timeout);
            peer_runs.push(peers::run(peer, program, &instance, limit, args.validate.as_deref())?);
        }
        let row = Row { instance, ours, valid, peers: peer_runs };
        writeln!(out, "{}", line(&row, args))?;
        if !row.ours.variables.is_empty() {
            writeln!(out, "  {}", planner::variables_line(&row.ours.variables))?;
        }
        if row.ours.covered > 0 {
            writeln!(out, "  {}", planner::covered_line(row.ours.covered))?;
        }
        if let Some(c) = &row.ours.closed {
            writeln!(out, "  {c}")?;
        }
        if let Some(f) = &row.ours.fit {
            writeln!(out, "  {f}")?;
        }
        if let Some((tree, actions)) = &row.ours.oscillation {
            writeln!(out, "  Algorithm 1 oscillated, repeating: {}", actions.join(", "))?;
            for l in tree.lines() {
                writeln!(out, "    {l}")?;
            }
        }
        super::output::stdout(&out)?;
        out.clear();
        rows.push(row);
    }
    let table = table::table(&rows, args);
    writeln!(out, "\n{table}")?;
    super::output::stdout(&out)?;
    if let Some(path) = &args.out {
        super::output::write_whole(path, table.as_bytes())?;
    }
    if let Some(path) = &args.plot {
        plot::write(path, &rows, args)?;
        super::output::stdout(format!("coverage against time: {}\n", path.display()).as_bytes())?;
    }
    Ok(())
}

fn name(p: &Path) -> String {
    p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()
}

fn child(exe: &Path, instance: &Instance, args: &Args) -> anyhow::Result<Run> {
    let mut cmd = Command::new(exe);
    cmd.arg("bench-pddl").arg(&args.dir).arg("--child").arg(&instance.domain_file).arg(&instance.problem_file);
    cmd.args(["--timeout", &args.timeout.to_string(), "--episodes", &args.episodes.to_string()]);
    if args.close_backchained {
        cmd.arg("--close-backchained");
    }
    cmd.args(["--close-nodes", &args.close_nodes.to_string()]);
    cmd.args(["--seed", &args.seed.to_string()]);
    cmd.args(["--failures", &args.failures.to_string()]);
    if let Some(v) = clap::ValueEnum::to_possible_value(&args.search) {
        cmd.args(["--search", v.get_name()]);
    }
    if let Some(b) = args.max_bytes {
        cmd.args(["--max-bytes", &b.to_string()]);
    }
    if let Some(n) = args.max_nodes {
        cmd.args(["--max-nodes", &n.to_string()]);
    }
    // Planning stops itself at the timeout; the disturbed episodes come after it.
    let limit = Duration::from_secs(args.timeout.saturating_mul(2).saturating_add(30));
    let (output, secs) = timed(cmd, limit)?;
    Ok(match output {
        None => Run::new(Outcome::Timeout, secs),
        Some(o) => Run::decode(&String::from_utf8_lossy(&o.stdout)).unwrap_or_else(|| {
            let err = String::from_utf8_lossy(&o.stderr);
            let first = err.lines().next().unwrap_or("no result");
            Run::new(Outcome::Failed(format!("the planner process ended with {}: {first}", o.status)), secs)
        }),
    })
}

fn yes(b: Option<bool>) -> &'static str {
    match b {
        Some(true) => "valid",
        Some(false) => "INVALID",
        None => "not validated",
    }
}

fn line(r: &Row, args: &Args) -> String {
    use std::fmt::Write as _;
    let id = format!("{}/{}", r.instance.domain, name(&r.instance.problem_file));
    let o = &r.ours;
    let ours = match &o.outcome {
        Outcome::Solved => format!(
            "solved {:.2}s (first tree {:.2}s) {} {} {}, plan {} cost {} {}, disturbed {}",
            o.seconds,
            o.first,
            o.method.map_or("?", planner::Made::name),
            count(o.nodes, "node"),
            count(o.bytes, "byte"),
            o.plan.len(),
            o.cost,
            yes(r.valid),
            o.disturbed
        ),
        Outcome::Refused(e) => format!("refused: {e}"),
        Outcome::Failed(e) => format!("failed: {e}"),
        Outcome::Timeout => "timeout".to_string(),
    };
    let mut s = format!("{id}: {ours}");
    for ((peer, _), p) in args.peers().into_iter().zip(&r.peers) {
        let name = peer.name();
        let _ = match (p.solved, &p.why) {
            (true, _) => write!(s, " | {name} solved {:.2}s {}", p.seconds, yes(p.valid)),
            (false, Some(why)) => write!(s, " | {name} unsolved ({:.0}s, {why})", p.seconds),
            (false, None) => write!(s, " | {name} unsolved ({:.0}s)", p.seconds),
        };
    }
    s
}
