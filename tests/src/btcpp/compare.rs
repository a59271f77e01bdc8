//! Comparing our ticks with what BehaviorTree.CPP did: events in order (halts that our
//! executor does earlier are allowed where they change nothing an action sees), and
//! node statuses as BehaviorTree.CPP shows them.

use std::fmt::Write as _;

use super::case::{Recorded, Tick};
use super::spec::{Kind, Spec};

/// What a comparison found.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Comparison {
    /// Ticks compared.
    pub ticks: usize,
    /// Halts that came earlier in our tick than in BehaviorTree.CPP's, before an action
    /// started in place of the halted one (halt before start).
    pub halts_moved_earlier: usize,
    /// Set when halt before start halted a branch that BehaviorTree.CPP went on running
    /// (the action that preempted it finished at once): the tick where it happened.
    /// From there on the two runs differ by design and are not compared.
    pub restarted_at: Option<usize>,
    /// Ticks where the statuses after the tick, seen as BehaviorTree.CPP shows them
    /// ([`btcpp_view`]), differ: only in finished statuses BehaviorTree.CPP leaves
    /// behind under a node it has reset.
    pub ticks_with_other_statuses: usize,
}

/// Comparisons of many cases added up, for the differential tests' summary lines.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Totals {
    /// Ticks compared.
    pub ticks: usize,
    /// Halts that came earlier by halt before start.
    pub halts_moved_earlier: usize,
    /// Cases compared only up to a branch that halt before start restarted.
    pub restarted: usize,
    /// Ticks whose statuses, as BehaviorTree.CPP shows them, differ in finished statuses
    /// it leaves behind.
    pub ticks_with_other_statuses: usize,
}

impl Totals {
    /// Adds one case's comparison.
    pub fn add(&mut self, c: &Comparison) {
        self.ticks += c.ticks;
        self.halts_moved_earlier += c.halts_moved_earlier;
        self.restarted += usize::from(c.restarted_at.is_some());
        self.ticks_with_other_statuses += c.ticks_with_other_statuses;
    }
}

impl std::fmt::Display for Totals {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} ticks compared; {} halts earlier (halt before start); {} cases compared up to a branch restarted \
             by halt before start; {} ticks with other statuses as BehaviorTree.CPP shows them",
            self.ticks, self.halts_moved_earlier, self.restarted, self.ticks_with_other_statuses
        )
    }
}

fn is_halt(e: &str) -> bool {
    e.starts_with('H') || e.starts_with('h')
}

/// Our node statuses as BehaviorTree.CPP would show them: it resets a finished node's
/// children to Idle, and a reactive node's or a decorator's children that are not
/// Running; bt-core keeps what they returned. The kinds that stand for
/// BehaviorTree.CPP-only nodes keep statuses exactly as it does.
#[must_use]
pub fn btcpp_view(spec: &Spec, ours: &str) -> String {
    let nodes = spec.preorder();
    let ours: Vec<char> = ours.chars().collect();
    let mut view = vec!['I'; nodes.len()];
    // (node, end) of the open ancestors.
    let mut open: Vec<(usize, usize)> = vec![];
    for (i, n) in nodes.iter().enumerate() {
        while open.last().is_some_and(|&(_, end)| end <= i) {
            open.pop();
        }
        let s = ours.get(i).copied().unwrap_or('I');
        view[i] = match open.last() {
            None => {
                if s == 'R' {
                    'R'
                } else {
                    'I'
                }
            }
            Some(&(p, _)) => {
                let pv = view[p];
                match nodes[p].kind {
                    Kind::ReactiveSequence
                    | Kind::ReactiveFallback
                    | Kind::Inverter
                    | Kind::ForceSuccess
                    | Kind::ForceFailure => {
                        if pv == 'R' && s == 'R' {
                            'R'
                        } else {
                            'I'
                        }
                    }
                    Kind::Sequence | Kind::Fallback | Kind::Parallel { .. } => {
                        if pv == 'R' {
                            s
                        } else {
                            'I'
                        }
                    }
                    _ => s,
                }
            }
        };
        open.push((i, i + n.len()));
    }
    view.into_iter().collect()
}

/// Compares our run with BehaviorTree.CPP's recording.
///
/// # Errors
/// The first disagreement, with the tick and both sides.
pub fn compare(rec: &Recorded, ours: &[Tick]) -> Result<Comparison, String> {
    let mut cmp = Comparison::default();
    for (k, (want, got)) in rec.ticks.iter().zip(ours).enumerate() {
        let fail = |what: &str| {
            let mut m = format!("{}: tick {k}: {what}\n", rec.case.name);
            let _ = writeln!(m, "  spec      {}", rec.case.spec);
            let _ = writeln!(m, "  BT.CPP    {} | {} | {}", want.root, want.events.join(" "), want.statuses);
            let _ = writeln!(m, "  bt-core   {} | {} | {}", got.root, got.events.join(" "), got.statuses);
            let _ = writeln!(m, "  as BT.CPP shows it            {}", btcpp_view(&rec.case.spec, &got.statuses));
            m
        };
        if want.events.iter().any(|e| e.starts_with('h')) {
            return Err(fail("BehaviorTree.CPP halted an action that was not Running"));
        }
        let view = btcpp_view(&rec.case.spec, &got.statuses);
        let parents = parents(&rec.case.spec);
        let ours = Ours { tick: got, running: &got.statuses, view: &view };
        match compare_tick(want, &ours, &|n| parents.get(n).copied().flatten(), &|call| is_action(rec, call), &mut cmp)
        {
            Ok(Walked::Same) => {}
            Ok(Walked::Restarted) => {
                cmp.restarted_at = Some(k);
                return Ok(cmp);
            }
            Err(what) => return Err(fail(&what)),
        }
    }
    if rec.ticks.len() != ours.len() {
        return Err(format!("{}: {} ticks recorded, {} run", rec.case.name, rec.ticks.len(), ours.len()));
    }
    Ok(cmp)
}

/// Our tick, for [`compare_tick`]: the tick, the statuses whose Running nodes must be
/// BehaviorTree.CPP's, and the statuses as BehaviorTree.CPP shows them.
#[derive(Debug)]
pub struct Ours<'a> {
    /// Our tick.
    pub tick: &'a Tick,
    /// Statuses per recorded node, for the Running ones.
    pub running: &'a str,
    /// Statuses as BehaviorTree.CPP shows them.
    pub view: &'a str,
}

/// Compares one tick of ours with BehaviorTree.CPP's `want`: the same leaf calls and
/// halts ([`walk_events`]), root status and nodes Running, and the same statuses as
/// BehaviorTree.CPP shows them but for a finished status it left behind under a node it
/// had reset (it resets a node, not its subtree), where bt-core's node is Idle (counted
/// in `cmp`). `parent` gives each recorded node's parent.
///
/// # Errors
/// What differs.
pub fn compare_tick(
    want: &Tick,
    ours: &Ours<'_>,
    parent: &dyn Fn(usize) -> Option<usize>,
    is_action: &dyn Fn(&str) -> bool,
    cmp: &mut Comparison,
) -> Result<Walked, String> {
    if walk_events(&want.events, &ours.tick.events, is_action, cmp)? == Walked::Restarted {
        return Ok(Walked::Restarted);
    }
    if want.root != ours.tick.root {
        return Err("root status differs".into());
    }
    let running = |s: &str| s.chars().map(|c| c == 'R').collect::<Vec<_>>();
    if running(&want.statuses) != running(ours.running) {
        return Err("different nodes Running after the tick".into());
    }
    if want.statuses != ours.view {
        let theirs: Vec<char> = want.statuses.chars().collect();
        for (n, (w, g)) in theirs.iter().zip(ours.view.chars()).enumerate() {
            let stale = g == 'I' && matches!(w, 'S' | 'F') && parent(n).is_some_and(|p| theirs[p] != 'R');
            if *w != g && !stale {
                return Err(format!("node {n} shows {w} in BehaviorTree.CPP, {g} here"));
            }
        }
        cmp.ticks_with_other_statuses += 1;
    }
    cmp.ticks += 1;
    Ok(Walked::Same)
}

/// How the events of one tick compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Walked {
    /// The same, but for halts moved earlier by halt before start.
    Same,
    /// Halt before start halted a branch that BehaviorTree.CPP went on running: the runs
    /// differ by design from here.
    Restarted,
}

/// Walks the events of one tick, BehaviorTree.CPP's (`want`) and ours (`got`, with our
/// script runs, `$...`, left out). Where we halt and BehaviorTree.CPP does not, the
/// halts must be followed by an action starting in both (halt before start,
/// `starts_action` tells a call that does); each such halt must come later in
/// BehaviorTree.CPP's tick, or the run has diverged by design. Consecutive halts at the
/// start of a tick (timers) may come in any order. Counts the halts moved earlier.
///
/// # Errors
/// What differs, in words.
pub fn walk_events(
    want: &[String],
    got: &[String],
    starts_action: &dyn Fn(&str) -> bool,
    cmp: &mut Comparison,
) -> Result<Walked, &'static str> {
    if want.iter().any(|e| e.starts_with('h')) {
        return Err("BehaviorTree.CPP halted an action that was not Running");
    }
    let mut theirs: Vec<&String> = want.iter().collect();
    let mine: Vec<&String> = got.iter().filter(|e| !e.starts_with('$')).collect();
    let (mut i, mut j) = (0usize, 0usize);
    if mine.first().is_some_and(|e| is_halt(e)) {
        let lead = |v: &[&String]| v.iter().take_while(|e| is_halt(e)).map(|e| e.to_string()).collect::<Vec<_>>();
        let (mut a, mut b) = (lead(&theirs), lead(&mine));
        a.sort();
        b.sort();
        if a == b {
            i = a.len();
            j = b.len();
        }
    }
    while j < mine.len() {
        if i < theirs.len() && theirs[i] == mine[j] {
            i += 1;
            j += 1;
            continue;
        }
        if !is_halt(mine[j]) {
            return Err("different events");
        }
        let run_end = (j..mine.len()).find(|&t| !is_halt(mine[t])).unwrap_or(mine.len());
        let start = mine.get(run_end);
        if !start.is_some_and(|c| starts_action(c)) || theirs.get(i) != start {
            return Err("a halt that is not before a start");
        }
        for h in &mine[j..run_end] {
            // BehaviorTree.CPP halts it later in the tick, without ticking it in
            // between: only the order differs. Otherwise it went on running it.
            let node = &h[1..];
            let continued =
                |e: &&String| e.strip_prefix(node).is_some_and(|s| s.starts_with(['S', 'F', 'R', 's', 'f', 'r']));
            match theirs[i..].iter().position(|e| e == h) {
                Some(p) if !theirs[i..i + p].iter().any(continued) => {
                    theirs.remove(i + p);
                    cmp.halts_moved_earlier += 1;
                }
                _ => return Ok(Walked::Restarted),
            }
        }
        j = run_end;
    }
    if i != theirs.len() {
        return Err("BehaviorTree.CPP did more");
    }
    Ok(Walked::Same)
}

/// Each node's parent, pre-order.
fn parents(spec: &Spec) -> Vec<Option<usize>> {
    let nodes = spec.preorder();
    let mut out = vec![None; nodes.len()];
    let mut open: Vec<(usize, usize)> = vec![];
    for (i, n) in nodes.iter().enumerate() {
        while open.last().is_some_and(|&(_, end)| end <= i) {
            open.pop();
        }
        out[i] = open.last().map(|&(p, _)| p);
        open.push((i, i + n.len()));
    }
    out
}

/// Whether `call` starts an action of the case (a call whose letter is upper case).
fn is_action(rec: &Recorded, call: &str) -> bool {
    if !call.ends_with(['S', 'F', 'R']) {
        return false;
    }
    let node: usize = call.trim_end_matches(|c: char| c.is_ascii_alphabetic()).parse().unwrap_or(usize::MAX);
    rec.case.scripts.iter().any(|s| s.node == node && s.action)
}
