//! Coverage on benchmark collections: one instance read, grounded, planned and its
//! tree run undisturbed and with disturbances; instances found in a folder; results
//! summed up per domain. `sim-host bench-pddl` drives it, one process per instance.
//!
//! **Disturbances** are the external agents of Problem 1 in Colledanchise et al. 2019, acting at random
//! ticks (seeded): one *undoes* the robot's last completed action, the other *helps* by
//! doing an action the tree contains ([`crate::strips::disturb`], the model learning
//! uses too). The tree is run as planned, without expanding it at run time, and ticked
//! on after a root Failure as a robot would: an episode ends at the goal, at
//! [`Settings::failures`] Failures in a row (2 by default), or at its tick budget
//! ([`episode_ticks`]).
//!
//! Some domains have actions that cannot be undone (a peg jumped in peg solitaire, a
//! tile painted in floortile, fuel burnt in nomystery): a disturbance there can leave
//! the world where no plan reaches the goal, and no tree could recover. A failed
//! episode is counted as such a *dead end* only when it is proven: from the state just
//! before some disturbance a plan exists (the tree, run undisturbed from there, reaches
//! the goal, or search finds a plan), and from the state just after it a search
//! expanded every reachable state without reaching the goal ([`Disturbed::dead_ends`]).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use bt_core::{Catalog, Node};

use crate::ground::{Grounding, Limits};
use crate::state::State;
use crate::strips::disturb::{Disturbance, tree_actions};
use crate::strips::{self, StripsWorld};
use crate::{Made, Options, PddlCatalog, PlanError, pddl};

/// One problem of a collection with its domain file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Instance {
    /// The folder it is in (the domain's name in tables).
    pub domain: String,
    /// The domain file.
    pub domain_file: PathBuf,
    /// The problem file.
    pub problem_file: PathBuf,
}

/// The domain file of a problem file in its folder, by the naming conventions of the
/// IPC collections: `domain_P`, `domain-P`, the first three characters of `P` and
/// `-domain.pddl`, then `domain.pddl`.
#[must_use]
pub fn domain_file_of(problem: &Path) -> Option<PathBuf> {
    let dir = problem.parent()?;
    let name = problem.file_name()?.to_str()?;
    let prefix: String = name.chars().take(3).collect();
    [format!("domain_{name}"), format!("domain-{name}"), format!("{prefix}-domain.pddl"), "domain.pddl".into()]
        .into_iter()
        .map(|c| dir.join(c))
        .find(|p| p.is_file())
}

/// The instances under `dir`: its `.pddl` files whose name does not contain
/// `domain`, in each sub-folder (or in `dir` itself), sorted by folder then name.
///
/// # Errors
/// When a folder cannot be read.
pub fn instances(dir: &Path) -> std::io::Result<Vec<Instance>> {
    let mut folders: Vec<PathBuf> = vec![dir.to_path_buf()];
    for e in std::fs::read_dir(dir)? {
        let p = e?.path();
        if p.is_dir() {
            folders.push(p);
        }
    }
    folders.sort();
    let mut out = Vec::new();
    for f in folders {
        let mut files: Vec<PathBuf> = std::fs::read_dir(&f)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.extension().is_some_and(|x| x == "pddl")
                    && p.file_name().and_then(|n| n.to_str()).is_some_and(|n| !n.contains("domain"))
            })
            .collect();
        files.sort();
        for problem_file in files {
            let Some(domain_file) = domain_file_of(&problem_file) else { continue };
            let domain = f.file_name().and_then(|n| n.to_str()).unwrap_or(".").to_string();
            out.push(Instance { domain, domain_file, problem_file });
        }
    }
    Ok(out)
}

/// How an instance is run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Time for reading, grounding and planning.
    pub timeout: Duration,
    /// Disturbed episodes per solved instance.
    pub episodes: u32,
    /// Seed of the disturbances.
    pub seed: u64,
    /// Chance of a disturbance at each tick.
    pub rate: f64,
    /// Most disturbances in one episode.
    pub max_disturbances: u32,
    /// Root Failures in a row that end a disturbed episode: 2 by default, as a robot
    /// ticks on after a failed tick (an action whose preconditions an agent changed
    /// while it ran fails) and as Styrud et al.'s episodes end on a status twice in a row;
    /// 1 ends it at the first.
    pub failures: u32,
    /// Plan with [`Options::close_backchained`].
    pub close_backchained: bool,
    /// Plan with this [`Options::close_nodes`].
    pub close_nodes: usize,
    /// Plan with this [`Options::fit`].
    pub fit: crate::Fit,
    /// Plan with this [`Options::deferred`].
    pub deferred: bool,
    /// Plan with this [`Options::landmarks`].
    pub landmarks: bool,
}

impl Settings {
    /// The agents of the disturbed episodes.
    #[must_use]
    pub fn disturbance(&self) -> Disturbance {
        Disturbance { rate: self.rate, max: self.max_disturbances, seed: self.seed }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            timeout: Duration::from_secs(60),
            episodes: 20,
            seed: 1,
            rate: 0.2,
            max_disturbances: 3,
            failures: 2,
            close_backchained: false,
            close_nodes: Options::default().close_nodes,
            fit: crate::Fit::DEFAULT,
            deferred: true,
            landmarks: true,
        }
    }
}

/// What happened to an instance.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// A tree that reaches the goal.
    Solved,
    /// The reader refused the files (one line, file:line:column).
    Refused(String),
    /// Read, but no tree: the error.
    Failed(String),
    /// Out of time.
    Timeout,
}

/// The result of one instance.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// What happened.
    pub outcome: Outcome,
    /// Seconds from reading the files to the checked tree.
    pub seconds: f64,
    /// Seconds from reading the files to the first tree that reaches the goal, before
    /// its closure over disturbances ([`crate::Plan::first`]).
    pub first: f64,
    /// The method that made the tree.
    pub method: Option<Made>,
    /// Tree nodes.
    pub nodes: usize,
    /// Bytes of its image as a controller holds it ([`crate::Plan::fit`]).
    pub bytes: usize,
    /// How it was made to fit, in a line ([`crate::Fitted`]'s display).
    pub fit: Option<String>,
    /// The actions the tree executes undisturbed, as a plan file writes them.
    pub plan: Vec<String>,
    /// Their cost (sum of action costs, or their number without costs).
    pub cost: u64,
    /// The disturbed episodes.
    pub disturbed: Disturbed,
    /// Methods given up on the way, one line each.
    pub gave_up: Vec<String>,
    /// For an oscillation met on the way: the tree (ASCII) and the repeating actions.
    pub oscillation: Option<(String, Vec<String>)>,
    /// How the tree was closed over disturbances, in a line.
    pub closed: Option<String>,
    /// Conditions the backchained tree only checked that were given the plan's step
    /// that made them true ([`crate::Plan::covered`]).
    pub covered: usize,
    /// The state variables guided backchaining did not pin ([`crate::Plan::variables`]).
    pub variables: Vec<String>,
}

impl Run {
    /// A run that ended with `outcome` after `seconds`, nothing else known.
    #[must_use]
    pub fn new(outcome: Outcome, seconds: f64) -> Self {
        Self {
            outcome,
            seconds,
            first: seconds,
            method: None,
            nodes: 0,
            bytes: 0,
            fit: None,
            plan: Vec::new(),
            cost: 0,
            disturbed: Disturbed::default(),
            gave_up: Vec::new(),
            oscillation: None,
            closed: None,
            covered: 0,
            variables: Vec::new(),
        }
    }

    /// Whether a tree was made.
    #[must_use]
    pub fn solved(&self) -> bool {
        self.outcome == Outcome::Solved
    }

    /// Whether the files were read.
    #[must_use]
    pub fn parsed(&self) -> bool {
        !matches!(self.outcome, Outcome::Refused(_))
    }
}

fn clean(s: &str) -> String {
    s.chars().map(|c| if c.is_control() { ' ' } else { c }).collect()
}

/// Reads, grounds and plans one instance within `settings.timeout`, then runs the
/// tree undisturbed and in `settings.episodes` disturbed episodes.
#[must_use]
pub fn run(instance: &Instance, settings: &Settings) -> Run {
    let start = Instant::now();
    let deadline = start + settings.timeout;
    let read = |p: &Path| std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()));
    let secs = || start.elapsed().as_secs_f64();
    let (dtext, ptext) = match (read(&instance.domain_file), read(&instance.problem_file)) {
        (Ok(d), Ok(p)) => (d, p),
        (Err(e), _) | (_, Err(e)) => return Run::new(Outcome::Refused(e), secs()),
    };
    let dname = instance.domain_file.display().to_string();
    let pname = instance.problem_file.display().to_string();
    let problem = match pddl::parse_domain(&dname, &dtext).and_then(|d| pddl::parse_problem(&pname, &ptext, &d)) {
        Ok(p) => p,
        Err(e) => return Run::new(Outcome::Refused(clean(&e.to_string())), secs()),
    };
    let failed = |e: PlanError, s: f64| match e {
        PlanError::Timeout { .. } => Run::new(Outcome::Timeout, s),
        e => Run::new(Outcome::Failed(clean(&e.to_string())), s),
    };
    let limits = Limits { deadline: Some(deadline), ..Limits::default() };
    let g = match Grounding::with_limits(&problem, &limits) {
        Ok(g) => Arc::new(g),
        Err(e) => return failed(e, secs()),
    };
    let catalog = Arc::new(PddlCatalog::new(&problem));
    let options = Options {
        deadline: Some(deadline),
        close_backchained: settings.close_backchained,
        close_nodes: settings.close_nodes,
        fit: settings.fit,
        deferred: settings.deferred,
        landmarks: settings.landmarks,
        ..Options::default()
    };
    let plan = match crate::plan(g.clone(), catalog.clone(), options) {
        Ok(p) => p,
        Err(e) => return failed(e, secs()),
    };
    let seconds = secs();
    // A tree finished after the timeout (its last check ran past the deadline) does not
    // count as solved within it.
    if seconds > settings.timeout.as_secs_f64() {
        return Run::new(Outcome::Timeout, seconds);
    }
    let mut out = Run::new(Outcome::Solved, seconds);
    out.first = plan.first.saturating_duration_since(start).as_secs_f64();
    out.method = Some(plan.method);
    out.closed = plan.closed.map(|c| c.to_string());
    out.covered = plan.covered;
    out.variables.clone_from(&plan.variables);
    out.nodes = plan.nodes.len();
    out.bytes = plan.fit.size.bytes;
    out.fit = Some(plan.fit.to_string());
    out.plan = plan.executed.iter().map(|&a| g.action_pddl(a)).collect();
    out.cost = if g.unit_cost() { plan.executed.len() as u64 } else { g.cost_of(&plan.executed) };
    for gu in &plan.gave_up {
        out.gave_up.push(clean(&format!("{}: {}", gu.method.name(), gu.error)));
        if let PlanError::Oscillates { actions, nodes, values } = &gu.error
            && out.oscillation.is_none()
        {
            let tree = bt_formats::ascii::to_ascii_with(nodes, values, catalog.as_ref()).unwrap_or_default();
            out.oscillation = Some((tree, actions.clone()));
        }
    }
    let ticks = plan.goal_ticks.unwrap_or(0);
    out.disturbed = disturbed(&plan.nodes, &plan.values, catalog.as_ref(), &g, ticks, settings)
        .unwrap_or(Disturbed { episodes: settings.episodes, ..Disturbed::default() });
    out
}

/// What the disturbed episodes of a tree came to.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Disturbed {
    /// Episodes run.
    pub episodes: u32,
    /// Episodes that reached the goal.
    pub reached: u32,
    /// Episodes that failed after a disturbance took the world from a state with a plan
    /// to one from which search proved no plan exists (see the module docs).
    pub dead_ends: u32,
}

impl Disturbed {
    /// Episodes after which a plan to the goal still existed (all but the dead ends).
    #[must_use]
    pub fn recoverable(&self) -> u32 {
        self.episodes.saturating_sub(self.dead_ends)
    }

    /// Adds another instance's episodes.
    #[must_use]
    pub fn plus(self, o: Self) -> Self {
        Self {
            episodes: self.episodes + o.episodes,
            reached: self.reached + o.reached,
            dead_ends: self.dead_ends + o.dead_ends,
        }
    }
}

impl std::fmt::Display for Disturbed {
    /// `17/20` or `17/20 (2 dead ends)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.reached, self.episodes)?;
        if self.dead_ends > 0 {
            write!(f, " ({})", crate::wording::count(self.dead_ends as usize, "dead end"))?;
        }
        Ok(())
    }
}

/// Most time a search may take to show that a disturbed state is a dead end.
const DEAD_END_SEARCH: Duration = Duration::from_secs(2);
/// Most bytes of states that search may store.
const DEAD_END_MEMORY: usize = 256 << 20;

/// Most time all the searches of one instance's episodes may take to tell dead ends
/// apart: past it, failed episodes count as failed, not as dead ends, so that a hard
/// instance's episodes end well within the process's time limit.
const DEAD_END_TOTAL: Duration = Duration::from_secs(20);

/// Whether search finds a plan from a state (`Some(true)`), proves there is none
/// (`Some(false)`), or gives up (`None`): each state searched once, all of them within
/// [`DEAD_END_TOTAL`].
struct Solvable<'g> {
    g: &'g Grounding,
    known: std::collections::HashMap<State, Option<bool>>,
    until: Instant,
}

impl<'g> Solvable<'g> {
    fn new(g: &'g Grounding) -> Self {
        Self { g, known: std::collections::HashMap::new(), until: Instant::now() + DEAD_END_TOTAL }
    }

    fn from(&mut self, s: &State) -> Option<bool> {
        if let Some(&v) = self.known.get(s) {
            return v;
        }
        let now = Instant::now();
        if now >= self.until {
            return None;
        }
        let options = crate::search::SearchOptions {
            deadline: Some((now + DEAD_END_SEARCH).min(self.until)),
            memory: DEAD_END_MEMORY,
            ..crate::search::SearchOptions::default()
        };
        let v = match crate::search::gbfs_from(self.g, s, &options) {
            Ok(_) => Some(true),
            Err(PlanError::NoPlan(_)) => Some(false),
            Err(_) => None,
        };
        self.known.insert(s.clone(), v);
        v
    }
}

/// Most ticks of a disturbed episode of a tree that takes `undisturbed` ticks to the
/// goal (the closure runs its trees from disturbed states as long).
#[must_use]
pub fn episode_ticks(undisturbed: u32) -> u32 {
    undisturbed.saturating_mul(4).saturating_add(200)
}

/// Runs `settings.episodes` disturbed episodes of the tree (see the module docs).
///
/// # Errors
/// As [`strips::run_to_goal`].
pub fn disturbed<C: Catalog + ?Sized>(
    nodes: &[Node],
    values: &[u16],
    catalog: &C,
    g: &Arc<Grounding>,
    undisturbed_ticks: u32,
    settings: &Settings,
) -> Result<Disturbed, PlanError> {
    let budget = episode_ticks(undisturbed_ticks);
    let mut out = Disturbed { episodes: settings.episodes, ..Disturbed::default() };
    let mut states = Vec::new();
    let mut solvable = Solvable::new(g);
    for (reached, changes) in episodes((nodes, values), catalog, g, undisturbed_ticks, settings)? {
        if reached {
            out.reached += 1;
            continue;
        }
        // A plan existed before the disturbance if the tree, run undisturbed from
        // there, reaches the goal (where search for one may take longer than it is
        // given here), or if search finds one.
        let mut tree_reaches = |s: &State| -> Result<bool, PlanError> {
            let mut w = StripsWorld::new(g.clone());
            w.set_state(s.clone());
            let ends = strips::Ends { on_loop: false, failures: settings.failures };
            Ok(strips::run_to_goal((nodes, values), catalog, &mut w, budget, ends, (), &mut states)?.reached())
        };
        for (before, after) in &changes {
            if solvable.from(after) == Some(false) && (tree_reaches(before)? || solvable.from(before) == Some(true)) {
                out.dead_ends += 1;
                break;
            }
        }
    }
    Ok(out)
}

/// One disturbed episode: whether it reached the goal, and the state before and after
/// each disturbance in it.
pub(crate) type Episode = (bool, Vec<(State, State)>);

/// The disturbed episodes of the tree ([`Episode`]).
///
/// # Errors
/// As [`strips::run_to_goal`].
pub(crate) fn episodes<C: Catalog + ?Sized>(
    (nodes, values): (&[Node], &[u16]),
    catalog: &C,
    g: &Arc<Grounding>,
    undisturbed_ticks: u32,
    settings: &Settings,
) -> Result<Vec<Episode>, PlanError> {
    let helpers = tree_actions(nodes, values, g);
    let budget = episode_ticks(undisturbed_ticks);
    let agents = settings.disturbance();
    let mut out = Vec::new();
    let mut states = Vec::new();
    for e in 0..settings.episodes {
        let mut world = StripsWorld::new(g.clone());
        let mut agents = agents.agents(helpers.clone(), e);
        let verdict = strips::run_to_goal(
            (nodes, values),
            catalog,
            &mut world,
            budget,
            strips::Ends { on_loop: false, failures: settings.failures },
            &mut agents,
            &mut states,
        )?;
        out.push((verdict.reached(), agents.into_changes()));
    }
    Ok(out)
}

const SEP: char = '\t';

impl Run {
    /// The run as lines `key<TAB>value`, for passing it between processes.
    #[must_use]
    pub fn encode(&self) -> String {
        let mut s = String::new();
        let (kind, text) = match &self.outcome {
            Outcome::Solved => ("solved", String::new()),
            Outcome::Refused(e) => ("refused", e.clone()),
            Outcome::Failed(e) => ("failed", e.clone()),
            Outcome::Timeout => ("timeout", String::new()),
        };
        let mut line = |k: &str, v: &str| {
            s.push_str(k);
            s.push(SEP);
            s.push_str(&clean(v));
            s.push('\n');
        };
        line("outcome", kind);
        line("message", &text);
        line("seconds", &format!("{:.3}", self.seconds));
        line("first", &format!("{:.3}", self.first));
        line("method", self.method.map_or("", Made::name));
        line("nodes", &self.nodes.to_string());
        line("bytes", &self.bytes.to_string());
        if let Some(f) = &self.fit {
            line("fit", f);
        }
        line("cost", &self.cost.to_string());
        let d = &self.disturbed;
        line("disturbed", &format!("{} {} {}", d.reached, d.episodes, d.dead_ends));
        for p in &self.plan {
            line("plan", p);
        }
        for g in &self.gave_up {
            line("gave-up", g);
        }
        if let Some(c) = &self.closed {
            line("closed", c);
        }
        if self.covered > 0 {
            line("covered", &self.covered.to_string());
        }
        if !self.variables.is_empty() {
            line("variables", &self.variables.join(" "));
        }
        if let Some((tree, actions)) = &self.oscillation {
            for t in tree.lines() {
                line("tree", t);
            }
            line("repeats", &actions.join(", "));
        }
        s
    }

    /// Reads [`Run::encode`]'s lines (other lines are skipped); `None` without an
    /// outcome line.
    #[must_use]
    pub fn decode(text: &str) -> Option<Self> {
        let mut r = Run::new(Outcome::Timeout, 0.0);
        let mut kind = None;
        let mut message = String::new();
        let mut tree = String::new();
        let mut repeats = None;
        for l in text.lines() {
            let Some((k, v)) = l.split_once(SEP) else { continue };
            match k {
                "outcome" => kind = Some(v.to_string()),
                "message" => message = v.to_string(),
                "seconds" => r.seconds = v.parse().unwrap_or(0.0),
                "first" => r.first = v.parse().unwrap_or(0.0),
                "method" => {
                    r.method =
                        [Made::Algorithm1, Made::SearchGuided, Made::Regression].into_iter().find(|m| m.name() == v);
                }
                "nodes" => r.nodes = v.parse().unwrap_or(0),
                "bytes" => r.bytes = v.parse().unwrap_or(0),
                "fit" => r.fit = Some(v.to_string()),
                "cost" => r.cost = v.parse().unwrap_or(0),
                "disturbed" => {
                    let mut it = v.split(' ').map(|x| x.parse().unwrap_or(0));
                    let mut next = || it.next().unwrap_or(0);
                    r.disturbed = Disturbed { reached: next(), episodes: next(), dead_ends: next() };
                }
                "plan" => r.plan.push(v.to_string()),
                "gave-up" => r.gave_up.push(v.to_string()),
                "closed" => r.closed = Some(v.to_string()),
                "covered" => r.covered = v.parse().unwrap_or(0),
                "variables" => r.variables = v.split(' ').filter(|x| !x.is_empty()).map(str::to_string).collect(),
                "tree" => {
                    tree.push_str(v);
                    tree.push('\n');
                }
                "repeats" => repeats = Some(v.split(", ").map(str::to_string).collect()),
                _ => {}
            }
        }
        r.outcome = match kind?.as_str() {
            "solved" => Outcome::Solved,
            "refused" => Outcome::Refused(message),
            "failed" => Outcome::Failed(message),
            _ => Outcome::Timeout,
        };
        if let Some(rep) = repeats {
            r.oscillation = Some((tree, rep));
        }
        Some(r)
    }
}
