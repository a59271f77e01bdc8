//! `sim-host bench-pddl DIR`: planner coverage on a folder of PDDL benchmark domains,
//! side by side with pyperplan, every plan checked by an independent validator.
//!
//! Each instance runs in a child process of this binary (the same command with the
//! hidden `--child`), killed at the timeout; the child reads, grounds and plans with
//! [`planner::coverage::run`] and prints its result as `key<TAB>value` lines. The
//! parent then checks the executed plan with the validator, runs pyperplan on a copy
//! of the files with the same timeout, and sums up per domain.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context as _, bail};
use planner::coverage::{self, Disturbed, Instance, Outcome, Run, Settings};
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
    --pyperplan, pyperplan (greedy best-first search with h_FF) runs on the same instance with the \
    same timeout, and its plan is validated the same way.\n\n\
    Prints a line per instance (with the tree and the repeating actions when Algorithm 1 \
    oscillated), then a table per domain: instances, parsed, solved, median planning time, median \
    tree size and plan cost, plans found valid, disturbed episodes that reached the goal (of all, and \
    of those where a plan remained: a disturbance that search proves leaves no plan to the goal, \
    such as a peg jumped out of turn in peg solitaire, is a dead end no tree recovers from), and \
    pyperplan's solved count and median time. Times are wall-clock: ours from reading the files to \
    the checked tree, pyperplan's for its whole process.";

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

/// One instance's results on both sides.
struct Row {
    instance: Instance,
    ours: Run,
    valid: Option<bool>,
    pyperplan: Option<PyperplanRun>,
    /// Why pyperplan ended without a plan before the timeout.
    pyperplan_why: Option<String>,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let settings = Settings {
        timeout: Duration::from_secs(args.timeout),
        episodes: args.episodes,
        seed: args.seed,
        failures: args.failures,
        close_backchained: args.close_backchained,
        close_nodes: args.close_nodes,
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
            (Some(v), true) => Some(validate(v, &instance, &ours.plan.join("\n"))?),
            _ => None,
        };
        let (pyperplan, pyperplan_why) = match &args.pyperplan {
            Some(p) => {
                let (r, why) = pyperplan(p, &instance, args)?;
                (Some(r), why)
            }
            None => (None, None),
        };
        let row = Row { instance, ours, valid, pyperplan, pyperplan_why };
        writeln!(out, "{}", line(&row))?;
        if !row.ours.variables.is_empty() {
            writeln!(out, "  {}", planner::variables_line(&row.ours.variables))?;
        }
        if row.ours.covered > 0 {
            writeln!(out, "  {}", planner::covered_line(row.ours.covered))?;
        }
        if let Some(c) = &row.ours.closed {
            writeln!(out, "  {c}")?;
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
    let table = table(&rows, args);
    writeln!(out, "\n{table}")?;
    super::output::stdout(&out)?;
    if let Some(path) = &args.out {
        super::output::write_whole(path, table.as_bytes())?;
    }
    Ok(())
}

fn name(p: &Path) -> String {
    p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()
}

/// Runs `cmd` with a time limit; returns its output, or `None` when it was killed.
fn timed(mut cmd: Command, limit: Duration) -> anyhow::Result<(Option<std::process::Output>, f64)> {
    let start = Instant::now();
    let mut child = cmd.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn()?;
    // Read the pipes on threads so a chatty child never blocks on a full pipe.
    let mut so = child.stdout.take();
    let mut se = child.stderr.take();
    let t_out = std::thread::spawn(move || {
        let mut b = Vec::new();
        if let Some(s) = so.as_mut() {
            let _ = std::io::Read::read_to_end(s, &mut b);
        }
        b
    });
    let t_err = std::thread::spawn(move || {
        let mut b = Vec::new();
        if let Some(s) = se.as_mut() {
            let _ = std::io::Read::read_to_end(s, &mut b);
        }
        b
    });
    let status = loop {
        if let Some(s) = child.try_wait()? {
            break Some(s);
        }
        if start.elapsed() >= limit {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let secs = start.elapsed().as_secs_f64();
    let stdout = t_out.join().unwrap_or_default();
    let stderr = t_err.join().unwrap_or_default();
    Ok((status.map(|status| std::process::Output { status, stdout, stderr }), secs))
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

/// Checks a plan with the validator: true when it exits with status 0.
fn validate(program: &Path, instance: &Instance, plan: &str) -> anyhow::Result<bool> {
    let mut file = tempfile::NamedTempFile::new()?;
    file.write_all(plan.as_bytes())?;
    file.write_all(b"\n")?;
    let mut cmd = Command::new(program);
    cmd.arg(&instance.domain_file).arg(&instance.problem_file).arg(file.path());
    let (out, _) = timed(cmd, Duration::from_secs(300)).with_context(|| format!("cannot run {}", program.display()))?;
    Ok(out.is_some_and(|o| o.status.success()))
}

/// pyperplan's result: solved, seconds, plan valid (`None`: not validated).
type PyperplanRun = (bool, f64, Option<bool>);

/// pyperplan on a copy of the files: (solved, seconds, plan valid), and when it ended
/// by itself without a plan, its exit status and last line of output (why).
fn pyperplan(program: &Path, instance: &Instance, args: &Args) -> anyhow::Result<(PyperplanRun, Option<String>)> {
    let dir = tempfile::tempdir()?;
    let d = dir.path().join("domain.pddl");
    let p = dir.path().join("problem.pddl");
    std::fs::copy(&instance.domain_file, &d)?;
    std::fs::copy(&instance.problem_file, &p)?;
    let mut cmd = Command::new(program);
    cmd.args(["-H", "hff", "-s", "gbf"]).arg(&d).arg(&p).current_dir(dir.path());
    let (out, secs) =
        timed(cmd, Duration::from_secs(args.timeout)).with_context(|| format!("cannot run {}", program.display()))?;
    let soln = dir.path().join("problem.pddl.soln");
    let solved = out.is_some() && soln.is_file();
    let why = out.as_ref().filter(|_| !solved).map(|o| {
        let last_of = |b: &[u8]| {
            String::from_utf8_lossy(b).lines().rev().find(|l| !l.trim().is_empty()).map(|l| l.trim().to_string())
        };
        let last = last_of(&o.stderr).or_else(|| last_of(&o.stdout)).unwrap_or_default();
        let last: String = last.chars().filter(|c| !c.is_control()).take(120).collect();
        format!("{}: {last}", o.status)
    });
    let valid = match (&args.validate, solved) {
        (Some(v), true) => {
            let plan = std::fs::read_to_string(&soln)?;
            Some(validate(v, instance, &plan)?)
        }
        _ => None,
    };
    Ok(((solved, secs, valid), why))
}

fn yes(b: Option<bool>) -> &'static str {
    match b {
        Some(true) => "valid",
        Some(false) => "INVALID",
        None => "not validated",
    }
}

fn line(r: &Row) -> String {
    let id = format!("{}/{}", r.instance.domain, name(&r.instance.problem_file));
    let o = &r.ours;
    let ours = match &o.outcome {
        Outcome::Solved => format!(
            "solved {:.2}s {} {}, plan {} cost {} {}, disturbed {}",
            o.seconds,
            o.method.map_or("?", planner::Made::name),
            count(o.nodes, "node"),
            o.plan.len(),
            o.cost,
            yes(r.valid),
            o.disturbed
        ),
        Outcome::Refused(e) => format!("refused: {e}"),
        Outcome::Failed(e) => format!("failed: {e}"),
        Outcome::Timeout => "timeout".to_string(),
    };
    let py = match &r.pyperplan {
        Some((true, s, v)) => format!(" | pyperplan solved {s:.2}s {}", yes(*v)),
        Some((false, s, _)) => match &r.pyperplan_why {
            Some(why) => format!(" | pyperplan unsolved ({s:.0}s, {why})"),
            None => format!(" | pyperplan unsolved ({s:.0}s)"),
        },
        None => String::new(),
    };
    format!("{id}: {ours}{py}")
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 { v[n / 2] } else { (v[n / 2 - 1] + v[n / 2]) / 2.0 })
}

fn fmt(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "–".into(), |x| format!("{x:.digits$}"))
}

fn table(rows: &[Row], args: &Args) -> String {
    let mut domains: Vec<&str> = rows.iter().map(|r| r.instance.domain.as_str()).collect();
    domains.dedup();
    let mut s = String::from(
        "| domain | instances | parsed | solved | median s | median nodes | median cost | valid | disturbed reached | reached where a plan remained | methods (A1/guided/regr) | pyperplan solved | pyperplan valid | pyperplan median s |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|\n",
    );
    let mut all: Vec<&Row> = Vec::new();
    let summary = |name: &str, rs: &[&Row], s: &mut String| {
        let solved: Vec<&&Row> = rs.iter().filter(|r| r.ours.solved()).collect();
        let dist = solved.iter().fold(Disturbed::default(), |a, r| a.plus(r.ours.disturbed));
        let by = |m: planner::Made| solved.iter().filter(|r| r.ours.method == Some(m)).count();
        let valid = solved.iter().filter(|r| r.valid == Some(true)).count();
        let py_solved: Vec<&&Row> = rs.iter().filter(|r| r.pyperplan.is_some_and(|p| p.0)).collect();
        let py_valid = py_solved.iter().filter(|r| r.pyperplan.is_some_and(|p| p.2 == Some(true))).count();
        let pct = |of: u32| {
            if of == 0 {
                "–".to_string()
            } else {
                format!("{:.1} %", 100.0 * f64::from(dist.reached) / f64::from(of))
            }
        };
        let (pct, kept) = (pct(dist.episodes), pct(dist.recoverable()));
        let _ = writeln!(
            s,
            "| {name} | {} | {} | {} | {} | {} | {} | {} | {pct} | {kept} | {}/{}/{} | {} | {} | {} |",
            rs.len(),
            rs.iter().filter(|r| r.ours.parsed()).count(),
            solved.len(),
            fmt(median(solved.iter().map(|r| r.ours.seconds).collect()), 2),
            fmt(median(solved.iter().map(|r| r.ours.nodes as f64).collect()), 0),
            fmt(median(solved.iter().map(|r| r.ours.cost as f64).collect()), 0),
            if args.validate.is_some() { valid.to_string() } else { "–".into() },
            by(planner::Made::Algorithm1),
            by(planner::Made::SearchGuided),
            by(planner::Made::Regression),
            if args.pyperplan.is_some() { py_solved.len().to_string() } else { "–".into() },
            if args.pyperplan.is_some() && args.validate.is_some() { py_valid.to_string() } else { "–".into() },
            fmt(median(py_solved.iter().filter_map(|r| r.pyperplan.map(|p| p.1)).collect()), 2),
        );
    };
    use std::fmt::Write as _;
    for d in domains {
        let rs: Vec<&Row> = rows.iter().filter(|r| r.instance.domain == d).collect();
        summary(d, &rs, &mut s);
        all.extend(rs);
    }
    summary("**all**", &all, &mut s);
    s
}
