//! The planners `bench-pddl` runs side by side with ours (pyperplan, Fast Downward),
//! each in its own process with the same time limit, and the plan validator.

use std::io::Write as _;
use std::os::unix::process::CommandExt as _;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::Context as _;
use planner::coverage::Instance;

/// A planner run beside ours.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Peer {
    /// pyperplan, greedy best-first search with h_FF: `PROGRAM -H hff -s gbf DOMAIN
    /// PROBLEM`, its plan in `PROBLEM.soln`.
    Pyperplan,
    /// Fast Downward with LAMA's first iteration: `PROGRAM --alias lama-first
    /// --plan-file PLAN DOMAIN PROBLEM`.
    FastDownward,
}

impl Peer {
    /// Its name in lines and tables.
    pub fn name(self) -> &'static str {
        match self {
            Self::Pyperplan => "pyperplan",
            Self::FastDownward => "FD lama-first",
        }
    }
}

/// A peer's result on one instance.
#[derive(Clone, Debug, PartialEq)]
pub struct PeerRun {
    /// Whether it wrote a plan within the time limit.
    pub solved: bool,
    /// Seconds for its whole process (Fast Downward: translator and search).
    pub seconds: f64,
    /// Whether the plan is valid (`None`: not validated).
    pub valid: Option<bool>,
    /// When it ended by itself without a plan: its exit status and last line of output.
    pub why: Option<String>,
}

/// Runs `cmd` in a process group of its own with a time limit; returns its output, or
/// `None` when it was killed (with the whole group: Fast Downward's driver starts the
/// search as a child process), and the seconds it ran.
pub fn timed(mut cmd: Command, limit: Duration) -> anyhow::Result<(Option<std::process::Output>, f64)> {
    let start = Instant::now();
    cmd.process_group(0);
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
            // The group's id is the child's (process_group(0)).
            let group = format!("-{}", child.id());
            let _ = Command::new("kill").args(["-KILL", "--", &group]).stderr(Stdio::null()).status();
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let secs = start.elapsed().as_secs_f64();
    let stdout = t_out.join().unwrap_or_default();
    let stderr = t_err.join().unwrap_or_default();
    Ok((status.map(|status| std::process::Output { status, stdout, stderr }), secs))
}

/// Checks a plan with the validator: true when it exits with status 0.
pub fn validate(program: &Path, instance: &Instance, plan: &str) -> anyhow::Result<bool> {
    let mut file = tempfile::NamedTempFile::new()?;
    file.write_all(plan.as_bytes())?;
    file.write_all(b"\n")?;
    let mut cmd = Command::new(program);
    cmd.arg(&instance.domain_file).arg(&instance.problem_file).arg(file.path());
    let (out, _) = timed(cmd, Duration::from_secs(300)).with_context(|| format!("cannot run {}", program.display()))?;
    Ok(out.is_some_and(|o| o.status.success()))
}

/// Runs `peer` (`program`) on a copy of the instance's files in a folder of its own,
/// for at most `limit`, and validates its plan with `validator` when given.
pub fn run(
    peer: Peer,
    program: &Path,
    instance: &Instance,
    limit: Duration,
    validator: Option<&Path>,
) -> anyhow::Result<PeerRun> {
    let dir = tempfile::tempdir()?;
    let d = dir.path().join("domain.pddl");
    let p = dir.path().join("problem.pddl");
    std::fs::copy(&instance.domain_file, &d)?;
    std::fs::copy(&instance.problem_file, &p)?;
    let mut cmd = Command::new(program);
    let plan_file = match peer {
        Peer::Pyperplan => {
            cmd.args(["-H", "hff", "-s", "gbf"]);
            dir.path().join("problem.pddl.soln")
        }
        Peer::FastDownward => {
            let plan = dir.path().join("sas_plan");
            cmd.args(["--alias", "lama-first", "--plan-file"]).arg(&plan);
            plan
        }
    };
    cmd.arg(&d).arg(&p).current_dir(dir.path());
    let (out, seconds) = timed(cmd, limit).with_context(|| format!("cannot run {}", program.display()))?;
    let solved = out.is_some() && plan_file.is_file();
    let why = out.as_ref().filter(|_| !solved).map(|o| {
        let last_of = |b: &[u8]| {
            String::from_utf8_lossy(b).lines().rev().find(|l| !l.trim().is_empty()).map(|l| l.trim().to_string())
        };
        let last = last_of(&o.stderr).or_else(|| last_of(&o.stdout)).unwrap_or_default();
        let last: String = last.chars().filter(|c| !c.is_control()).take(120).collect();
        format!("{}: {last}", o.status)
    });
    let valid = match (validator, solved) {
        (Some(v), true) => {
            let plan = std::fs::read_to_string(&plan_file)?;
            Some(validate(v, instance, &plan)?)
        }
        _ => None,
    };
    Ok(PeerRun { solved, seconds, valid, why })
}
