//! `bench-pddl`'s tables: one row per domain and one for all, then ours against Fast
//! Downward on the instances both solve.

use std::fmt::Write as _;

use planner::coverage::Disturbed;

use super::peers::Peer;
use super::{Args, Row};

/// The median of `v` (`None` when empty).
pub fn median(mut v: Vec<f64>) -> Option<f64> {
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

fn pct(part: usize, of: usize) -> String {
    if of == 0 { "–".to_string() } else { format!("{:.1} %", 100.0 * part as f64 / of as f64) }
}

/// The per-domain table, then the comparison with Fast Downward when it ran.
pub fn table(rows: &[Row], args: &Args) -> String {
    let peers = args.peers();
    let mut domains: Vec<&str> = rows.iter().map(|r| r.instance.domain.as_str()).collect();
    domains.dedup();
    let mut s = String::from(
        "| domain | instances | parsed | solved | median s | median s to a first tree | median nodes | median bytes | fit | median cost | valid | disturbed reached | reached where a plan remained | methods (A1/guided/regr) |",
    );
    let mut rule = String::from("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|");
    for (peer, _) in &peers {
        let n = peer.name();
        let _ = write!(s, " {n} solved | {n} valid | {n} median s |");
        rule.push_str("---:|---:|---:|");
    }
    let _ = writeln!(s, "\n{rule}");
    let fit = args.fit();
    let summary = |name: &str, rs: &[&Row], s: &mut String| {
        let solved: Vec<&&Row> = rs.iter().filter(|r| r.ours.solved()).collect();
        let dist = solved.iter().fold(Disturbed::default(), |a, r| a.plus(r.ours.disturbed));
        let by = |m: planner::Made| solved.iter().filter(|r| r.ours.method == Some(m)).count();
        let valid = solved.iter().filter(|r| r.valid == Some(true)).count();
        let fits = solved.iter().filter(|r| r.ours.bytes <= fit.bytes && r.ours.nodes <= fit.nodes).count();
        let _ = write!(
            s,
            "| {name} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {}/{}/{} |",
            rs.len(),
            rs.iter().filter(|r| r.ours.parsed()).count(),
            solved.len(),
            fmt(median(solved.iter().map(|r| r.ours.seconds).collect()), 2),
            fmt(median(solved.iter().map(|r| r.ours.first).collect()), 2),
            fmt(median(solved.iter().map(|r| r.ours.nodes as f64).collect()), 0),
            fmt(median(solved.iter().map(|r| r.ours.bytes as f64).collect()), 0),
            fits,
            fmt(median(solved.iter().map(|r| r.ours.cost as f64).collect()), 0),
            if args.validate.is_some() { valid.to_string() } else { "–".into() },
            pct(dist.reached as usize, dist.episodes as usize),
            pct(dist.reached as usize, dist.recoverable() as usize),
            by(planner::Made::Algorithm1),
            by(planner::Made::SearchGuided),
            by(planner::Made::Regression),
        );
        for k in 0..peers.len() {
            let solved: Vec<f64> =
                rs.iter().filter_map(|r| r.peers.get(k)).filter(|p| p.solved).map(|p| p.seconds).collect();
            let valid = rs.iter().filter_map(|r| r.peers.get(k)).filter(|p| p.solved && p.valid == Some(true)).count();
            let valid = if args.validate.is_some() { valid.to_string() } else { "–".into() };
            let _ = write!(s, " {} | {valid} | {} |", solved.len(), fmt(median(solved), 2));
        }
        s.push('\n');
    };
    let mut all: Vec<&Row> = Vec::new();
    for d in domains {
        let rs: Vec<&Row> = rows.iter().filter(|r| r.instance.domain == d).collect();
        summary(d, &rs, &mut s);
        all.extend(rs);
    }
    summary("**all**", &all, &mut s);
    if let Some(k) = peers.iter().position(|(p, _)| *p == Peer::FastDownward) {
        s.push('\n');
        s.push_str(&against(rows, k, args.timeout));
    }
    s
}

/// Our seconds to the first tree that reaches the goal, or to the closed tree.
#[derive(Clone, Copy)]
enum Until {
    First,
    Closed,
}

impl Until {
    fn of(self, r: &Row) -> f64 {
        match self {
            Self::First => r.ours.first,
            Self::Closed => r.ours.seconds,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Self::First => "time to the first tree (before its closure over disturbances)",
            Self::Closed => "time to the closed tree",
        }
    }
}

/// Ours against the peer at `k` (Fast Downward): coverage within the time limit, and
/// on the instances both solve, for our time to the first tree and to the closed tree,
/// the share where ours took at most twice its time and half a second, the ratios'
/// median, 90th percentile and worst, and the instances over ten times.
fn against(rows: &[Row], k: usize, timeout: u64) -> String {
    let peer = |r: &Row| r.peers.get(k).filter(|p| p.solved).map(|p| p.seconds);
    let ours_only = rows.iter().filter(|r| r.ours.solved() && peer(r).is_none()).count();
    let theirs_only = rows.iter().filter(|r| !r.ours.solved() && peer(r).is_some()).count();
    let both: Vec<(&Row, f64)> =
        rows.iter().filter(|r| r.ours.solved()).filter_map(|r| peer(r).map(|t| (r, t))).collect();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Against Fast Downward lama-first (timeout {timeout} s): solved by ours alone {ours_only}, by it alone {theirs_only}, by both {}; its median time on those {} s.",
        both.len(),
        fmt(median(both.iter().map(|x| x.1).collect()), 2),
    );
    for until in [Until::First, Until::Closed] {
        let within = both.iter().filter(|(r, t)| until.of(r) <= 2.0 * t + 0.5).count();
        let mut ratios: Vec<(f64, &Row)> = both.iter().map(|(r, t)| (until.of(r) / t.max(1e-3), *r)).collect();
        ratios.sort_by(|a, b| a.0.total_cmp(&b.0));
        let at = |q: f64| ratios.get(((ratios.len() as f64 - 1.0) * q).round() as usize).map(|x| x.0);
        let _ = writeln!(
            s,
            "- {}: at most 2x its time + 0.5 s on {within} ({}); median {} s; ratio ours/its median {}, 90th percentile {}, worst {}.",
            until.name(),
            pct(within, both.len()),
            fmt(median(both.iter().map(|(r, _)| until.of(r)).collect()), 2),
            fmt(at(0.5), 2),
            fmt(at(0.9), 2),
            fmt(ratios.last().map(|x| x.0), 1),
        );
        let over: Vec<String> = ratios
            .iter()
            .rev()
            .filter(|(q, _)| *q > 10.0)
            .map(|(q, r)| format!("{}/{} {q:.1}x", r.instance.domain, super::name(&r.instance.problem_file)))
            .collect();
        if !over.is_empty() {
            let _ = writeln!(s, "  over 10x: {}.", over.join(", "));
        }
    }
    s
}
