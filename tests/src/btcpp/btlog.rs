//! Our Groot2 replay log of a fixture case against the one BehaviorTree.CPP's
//! `FileLogger2` wrote for it (`tests/btcpp/fixtures/btlog/`): the same header, the same
//! tree XML and the same transitions (uid, new status), timestamps aside.
//!
//! Our log is made the way `sim-host run --btlog` makes one: the case runs on bt-core
//! ([`run::run`]), and the leaf results of each tick are replayed through
//! [`btcpp::btlog::RunLog`]. The tree XML is that of the case's XML imported
//! ([`btcpp::btlog::LogTree::of_imported`]), and, where bt-core's nodes keep the
//! parameters as written, that of the bt-core tree itself ([`LogTree::new`], what a log
//! of an image shows).

use std::fmt::Write as _;
use std::path::Path;

use bt_core::{BehaviorId, BehaviorInfo, Catalog};
use btcpp::btlog::{Log, LogTree, RunLog, Ticking, replay::status};
use btcpp::xml::{ImportOptions, import_text};

use super::case::{Recorded, Tick};
use super::compare::Comparison;
use super::run;
use super::spec::Kind;

/// How a log compared.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Header, XML and every transition equal.
    Exact,
    /// The differential test compares this case only up to tick `tick` (halt before
    /// start restarted a branch BehaviorTree.CPP went on running): the transitions of
    /// the ticks before it are equal; from it on the runs differ by design.
    UpToTick {
        /// The first tick not compared.
        tick: usize,
        /// Transitions compared (ours, all equal to BehaviorTree.CPP's first ones).
        compared: usize,
        /// How the logs go on: the tick where the replay could not follow our run, or
        /// the first record that differs.
        after: String,
    },
}

/// What one log comparison found besides its outcome.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Compared {
    /// The outcome.
    pub outcome: Outcome,
    /// Transitions in BehaviorTree.CPP's log.
    pub transitions: usize,
    /// Whether the XML of the bt-core tree ([`LogTree::new`], as a log of an image
    /// has it) was compared too: it is whenever the case's parameters are as bt-core
    /// writes them back.
    pub image_xml_compared: bool,
}

/// The case's scripted leaves as the harness registers them: only those, named `C7`,
/// `A9`, with the fixtures' behavior ids ([`run::catalog`]).
struct CaseLeaves {
    all: Vec<BehaviorInfo<'static>>,
    used: Vec<bool>,
}

impl CaseLeaves {
    fn new(rec: &Recorded) -> Self {
        let all = run::catalog();
        let mut used = vec![false; all.len()];
        for s in &rec.case.scripts {
            let b = if s.action { usize::from(run::LEAVES) + s.node } else { s.node };
            if let Some(u) = used.get_mut(b) {
                *u = true;
            }
        }
        Self { all, used }
    }
}

impl Catalog for CaseLeaves {
    fn len(&self) -> usize {
        self.all.len()
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        let i = usize::from(id);
        if self.used.get(i).copied().unwrap_or(false) { self.all.get(i).copied() } else { None }
    }
}

/// The case's XML with a model for each scripted leaf, as the harness registers them.
fn with_models(rec: &Recorded) -> String {
    let models: String = rec
        .case
        .scripts
        .iter()
        .map(|s| {
            let (tag, letter) = if s.action { ("Action", 'A') } else { ("Condition", 'C') };
            format!("<{tag} ID=\"{letter}{}\"/>", s.node)
        })
        .collect();
    rec.xml.replace("</root>", &format!("<TreeNodesModel>{models}</TreeNodesModel></root>"))
}

/// The log tree of the case's XML, imported; its bt-core nodes must be the spec's.
///
/// # Errors
/// A message when the import fails or gives other nodes.
pub fn imported_tree(rec: &Recorded) -> Result<LogTree, String> {
    let imported = import_text(Path::new(&rec.case.name), &with_models(rec), &ImportOptions::default())
        .map_err(|e| format!("{}: import: {e}", rec.case.name))?;
    let built = run::build_full(&rec.case.spec)?;
    let same = imported.nodes.len() == built.nodes.len()
        && imported.nodes.iter().zip(&built.nodes).enumerate().all(|(i, (a, b))| {
            a.size() == b.size()
                && match (a.kind(), b.kind()) {
                    // Leaves are named by their spec node (`C7`).
                    (bt_core::NodeKind::Condition(_), bt_core::NodeKind::Condition(_))
                    | (bt_core::NodeKind::Action(_), bt_core::NodeKind::Action(_)) => {
                        imported.meta[i].id.get(1..) == Some(built.to_spec[i].to_string().as_str())
                    }
                    (x, y) => x == y,
                }
        });
    if !same {
        return Err(format!("{}: the imported XML is not the spec's tree", rec.case.name));
    }
    LogTree::of_imported(&imported).map_err(|e| format!("{}: {e}", rec.case.name))
}

/// Whether every parameter of the spec is written as bt-core gives it back (negative
/// counts other than `num_cycles="-1"` and `success_count` are resolved by the import).
fn canonical(rec: &Recorded) -> bool {
    rec.case.spec.preorder().iter().all(|n| match n.kind {
        Kind::Parallel { failure, .. } => failure >= 0,
        Kind::ParallelAll { max_failures } => max_failures >= 0,
        Kind::Repeat(c) | Kind::RetryUntilSuccessful(c) => c >= -1,
        // An image keeps a script's program, not its text (nor a guard's, nor a loop's
        // queue).
        Kind::Script(_) | Kind::ScriptCondition(_) | Kind::Precondition(..) | Kind::Loop { .. } => false,
        _ if !n.hooks.is_empty() => false,
        _ => true,
    })
}

fn has_scripts(rec: &Recorded) -> bool {
    rec.case.spec.preorder().iter().any(|n| {
        !n.hooks.is_empty()
            || matches!(n.kind, Kind::Script(_) | Kind::ScriptCondition(_) | Kind::Precondition(..) | Kind::Loop { .. })
    })
}

/// The leaf calls of a tick, from the harness's events: `(bt-core node, status)`;
/// `to_core` gives the bt-core node of each spec node's leaf.
fn calls(tick: &Tick, to_core: &[usize]) -> Vec<(usize, u8)> {
    tick.events
        .iter()
        .filter(|e| !e.starts_with(['H', 'h']))
        .filter_map(|e| {
            // `$`: a script's run (ours only, named by its bt-core node), answered to the
            // replay as a leaf's.
            let (e, core) = match e.strip_prefix('$') {
                Some(e) => (e, true),
                None => (e.as_str(), false),
            };
            let (node, s) = e.split_at(e.len().checked_sub(1)?);
            let s = match s.to_ascii_uppercase().as_str() {
                "S" => status::SUCCESS,
                "F" => status::FAILURE,
                "R" => status::RUNNING,
                _ => status::SKIPPED,
            };
            let node: usize = node.parse().ok()?;
            Some((if core { node } else { *to_core.get(node)? }, s))
        })
        .collect()
}

/// Microseconds between ticks in our logs: the tick of a transition is its time
/// divided by this.
const TICK_USEC: i64 = 1000;

/// Our log of the run `ours` (one [`Tick`] per tick, from [`run::run`]) and, if the
/// replay stopped because BehaviorTree.CPP's model would tick other leaves than the
/// run did, the tick and why.
///
/// # Errors
/// None yet; a message for a tree the log cannot hold.
pub fn our_log(rec: &Recorded, tree: &LogTree, ours: &[Tick]) -> Result<(Log, Option<(usize, String)>), String> {
    let ticking = if rec.case.once { Ticking::Once } else { Ticking::ExactlyOnce };
    let mut log = RunLog::new(tree, 0).ticked(ticking);
    // The bt-core node of each spec node: its own, which comes after its guard.
    let built = run::build_full(&rec.case.spec)?;
    let mut to_core = vec![0; rec.case.spec.len()];
    for (core, &spec) in built.to_spec.iter().enumerate() {
        if let Some(c) = to_core.get_mut(spec) {
            *c = core;
        }
    }
    let mut stopped = None;
    for (k, t) in ours.iter().enumerate() {
        let k32 = u32::try_from(k).unwrap_or(u32::MAX);
        if let Err(e) = log.tick(k32, i64::from(k32) * TICK_USEC, run::now(&rec.case, k32), &calls(t, &to_core)) {
            stopped = Some((k, e.to_string()));
            break;
        }
    }
    let log = Log::parse(&log.into_bytes()).map_err(|e| format!("{}: our log: {e}", rec.case.name))?;
    Ok((log, stopped))
}

/// Node names by uid, for messages.
fn who(tree: &LogTree, uid: u16) -> String {
    tree.nodes.iter().find(|n| n.uid == uid).map_or_else(|| format!("uid {uid}"), |n| format!("{uid} {}", n.name))
}

fn status_name(s: u8) -> &'static str {
    match s {
        status::IDLE => "Idle",
        status::RUNNING => "Running",
        status::SUCCESS => "Success",
        status::FAILURE => "Failure",
        _ => "?",
    }
}

/// A readable account of the first difference between two transition lists, at
/// record `at`: a few records either side, both columns, with our tick.
fn transition_diff(tree: &LogTree, theirs: &Log, ours: &Log, at: usize) -> String {
    let mut m = String::new();
    let _ = writeln!(m, "  record  {:<28} {:<28} our tick", "BehaviorTree.CPP", "ours");
    let row = |l: &Log, r: usize| {
        l.transitions
            .get(r)
            .map_or_else(|| "-".to_string(), |&(_, uid, s)| format!("{} -> {}", who(tree, uid), status_name(s)))
    };
    for r in at.saturating_sub(4)..(at + 4).min(theirs.transitions.len().max(ours.transitions.len())) {
        let tick = ours.transitions.get(r).map_or_else(String::new, |t| (t.0 as i64 / TICK_USEC).to_string());
        let mark = if r == at { ">" } else { " " };
        let _ = writeln!(m, "{mark} {r:<6} {:<28} {:<28} {tick}", row(theirs, r), row(ours, r));
    }
    m
}

/// The `_uid` attributes of a document, in order.
#[must_use]
pub fn uids(xml: &str) -> Vec<u16> {
    xml.split(" _uid=\"").skip(1).filter_map(|r| r.split('"').next()?.parse().ok()).collect()
}

fn first_line_diff(a: &str, b: &str) -> String {
    let (al, bl): (Vec<&str>, Vec<&str>) = (a.lines().collect(), b.lines().collect());
    let n = al.iter().zip(&bl).position(|(x, y)| x != y).unwrap_or(al.len().min(bl.len()));
    format!(
        "line {}:\n  BehaviorTree.CPP {}\n  ours             {}",
        n + 1,
        al.get(n).unwrap_or(&"(end)"),
        bl.get(n).unwrap_or(&"(end)")
    )
}

/// Compares our log of the case with BehaviorTree.CPP's (`theirs`, the bytes of its
/// `.btlog`); `diff` is what the differential test found for the case.
///
/// # Errors
/// Every difference the differential test does not allow, readably: the case, the
/// record, both sides.
pub fn compare(rec: &Recorded, theirs: &[u8], diff: &Comparison) -> Result<Compared, String> {
    let name = &rec.case.name;
    let theirs = Log::parse(theirs).map_err(|e| format!("{name}: BehaviorTree.CPP's log: {e}"))?;
    let tree = imported_tree(rec)?;
    // The header: magic, protocol and XML (its length follows).
    if tree.xml() != theirs.xml {
        return Err(format!("{name}: the tree XML differs at {}", first_line_diff(&theirs.xml, &tree.xml())));
    }
    let nodes = run::build(&rec.case.spec)?;
    let image_xml_compared = canonical(rec);
    if image_xml_compared {
        let mut image = LogTree::new(&nodes, &CaseLeaves::new(rec)).map_err(|e| format!("{name}: {e}"))?;
        // An image does not keep the tree's ID (its logs say `MainTree`).
        image.main.clone_from(&tree.main);
        if image.xml() != theirs.xml {
            return Err(format!(
                "{name}: the XML of the bt-core tree differs at {}",
                first_line_diff(&theirs.xml, &image.xml())
            ));
        }
    }
    // What `sim-host export` writes for the same nodes numbers them as BehaviorTree.CPP
    // numbered the case's XML in its log.
    let exported = if !has_scripts(rec) {
        btcpp::xml::to_xml(&nodes, run::catalog().as_slice()).map_err(|e| format!("{name}: {e}"))?
    } else {
        // Not exported from an image: the scripts' text is not in it.
        theirs.xml.clone()
    };
    if uids(&exported) != uids(&theirs.xml) {
        return Err(format!(
            "{name}: the export numbers the nodes {:?}, BehaviorTree.CPP {:?}",
            uids(&exported),
            uids(&theirs.xml)
        ));
    }
    let ran = run::run(&rec.case)?;
    let (ours, stopped) = our_log(rec, &tree, &ran)?;
    let pairs = |l: &Log| l.transitions.iter().map(|&(_, uid, s)| (uid, s)).collect::<Vec<_>>();
    let (want, got) = (pairs(&theirs), pairs(&ours));
    let transitions = want.len();
    match (diff.restarted_at, stopped) {
        (None, None) => {
            if let Some(at) = (0..want.len().max(got.len())).find(|&r| want.get(r) != got.get(r)) {
                return Err(format!(
                    "{name}: transition record {at} differs ({} in BehaviorTree.CPP's log, {} in ours)\n  spec {}\n{}",
                    want.len(),
                    got.len(),
                    rec.case.spec,
                    transition_diff(&tree, &theirs, &ours, at)
                ));
            }
            Ok(Compared { outcome: Outcome::Exact, transitions, image_xml_compared })
        }
        (None, Some((k, why))) => {
            Err(format!("{name}: tick {k}: the replay cannot follow the run: {why}\n  spec {}", rec.case.spec))
        }
        (Some(tick), stopped) => {
            if let Some((k, why)) = stopped.as_ref().filter(|(k, _)| *k < tick) {
                return Err(format!(
                    "{name}: tick {k}, before the restart at tick {tick}: the replay cannot follow the run: {why}"
                ));
            }
            // Our transitions of the ticks before the restart, BehaviorTree.CPP's first.
            let before = ours.transitions.iter().take_while(|t| (t.0 as i64 / TICK_USEC) < tick as i64).count();
            if let Some(at) = (0..before).find(|&r| want.get(r) != got.get(r)) {
                return Err(format!(
                    "{name}: transition record {at} (before the restart at tick {tick}) differs\n  spec {}\n{}",
                    rec.case.spec,
                    transition_diff(&tree, &theirs, &ours, at)
                ));
            }
            if stopped.is_none() && got == want {
                return Ok(Compared { outcome: Outcome::Exact, transitions, image_xml_compared });
            }
            let after = match stopped {
                Some((k, _)) => format!("the replay stops at tick {k}"),
                None => {
                    let at = (0..want.len().max(got.len())).find(|&r| want.get(r) != got.get(r)).unwrap_or(0);
                    let tick = ours.transitions.get(at).map_or(-1, |t| t.0 as i64 / TICK_USEC);
                    format!("record {at} (tick {tick}) differs")
                }
            };
            Ok(Compared {
                outcome: Outcome::UpToTick { tick, compared: before, after },
                transitions,
                image_xml_compared,
            })
        }
    }
}
