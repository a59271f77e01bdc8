//! The node types BehaviorTree.CPP 3.8 has with other ports or semantics than 4.10's:
//! read in version 3 documents instead of [`TABLE`](super::TABLE)'s, each becoming a
//! kind of bt-core that follows 3.8's node (tick rule 14 of `bt_core::exec`).

use bt_core::PortType::{Any, Int};
use bt_core::{NodeKind, Status};

use super::Shape::{Control, Decorator, TwoOrThree};
use super::params::{Compared, Count, Params, count, count_of, int, refuse, span, status_code};
use super::table::{entry, params, port, written};
use super::{Entry, Map, Written};
use crate::btlog::tree::Kind;
use crate::error::Result;

/// Every node type BehaviorTree.CPP 3.8's factory registers differently from 4.10's.
pub const TABLE_V3: &[Entry] = &[
    // 3.8's SequenceStar: no wake-up between children; a halt sends it back to its first
    // child.
    v3(entry("SequenceStar", Control, &[], Map::Plain(NodeKind::SequenceStarV3, Kind::SequenceStarV3))),
    // 3.8's thresholds: `success_threshold` has no default (3.8 throws when it ticks a
    // Parallel without one), `failure_threshold` defaults to 1; negative counts are
    // counted from the number of children.
    v3(params(
        "Parallel",
        Control,
        &[port("success_threshold", Int, None), port("failure_threshold", Int, Some("1"))],
        |p| {
            let children = p.children();
            let s = int(p, "success_threshold")?;
            let f = int(p, "failure_threshold")?;
            let resolve = |t: i64| if t < 0 { (children as i64 + t + 1).max(0) } else { t };
            let (rs, rf) = (resolve(s), resolve(f));
            for (port, v) in [("success_threshold", rs), ("failure_threshold", rf)] {
                if v < 1 || v > children as i64 {
                    return Err(refuse(
                        p.at(),
                        format!("<Parallel {port}> of {v} with {children} children"),
                        "the threshold must be between 1 and the number of children (BehaviorTree.CPP 3.8 throws when it ticks it)",
                    ));
                }
            }
            Ok(NodeKind::ParallelV3 { success_threshold: rs as u16, failure_threshold: rf as u16 })
        },
        |k, _| {
            let NodeKind::ParallelV3 { success_threshold, failure_threshold } = *k else { return None };
            let (success, failure) = (i32::from(success_threshold), i32::from(failure_threshold));
            written(
                vec![("success_threshold", success.to_string()), ("failure_threshold", failure.to_string())],
                Kind::ParallelV3 { success, failure },
            )
        },
    )),
    v3(params(
        "Repeat",
        Decorator,
        &[port("num_cycles", Int, None)],
        |p| cycles_v3(p, "num_cycles", false),
        |k, _| write_cycles(k, false, true),
    )),
    // 3.5 and 3.6 registered the misspelt name too.
    Entry {
        aliases: &["RetryUntilSuccesful"],
        ..v3(params(
            "RetryUntilSuccessful",
            Decorator,
            &[port("num_attempts", Int, None)],
            |p| cycles_v3(p, "num_attempts", true),
            |k, _| write_cycles(k, true, true),
        ))
    },
    // 3.8's Timeout is read as 4.10's (see the differences in the guide).
    v3(params(
        "Timeout",
        Decorator,
        &[port("msec", Int, None)],
        |p| Ok(NodeKind::TimeLimit(span(p, "msec")?)),
        |_, _| None,
    )),
    // 3.8's needs its three children.
    v3(params(
        "WhileDoElse",
        TwoOrThree,
        &[],
        |p| {
            if p.children() != 3 {
                return Err(refuse(
                    p.at(),
                    format!("<WhileDoElse> with {} children", p.children()),
                    "BehaviorTree.CPP 3.8's WhileDoElse needs three (it throws when ticked with two)",
                ));
            }
            Ok(NodeKind::WhileDoElse)
        },
        |_, _| None,
    )),
    check("BlackboardCheckInt", Compared::Int),
    check("BlackboardCheckDouble", Compared::Double),
    check("BlackboardCheckString", Compared::String),
    check("BlackboardCheckBool", Compared::Bool),
];

const fn v3(e: Entry) -> Entry {
    Entry { v3: true, ..e }
}

/// The ports of the `BlackboardCheck*` nodes.
const CHECK_PORTS: [super::Port; 3] =
    [port("value_A", Any, None), port("value_B", Any, None), port("return_on_mismatch", Any, Some("FAILURE"))];

/// A `BlackboardCheck*` node: a [`NodeKind::Check`] of its comparison.
const fn check(id: &'static str, ty: Compared) -> Entry {
    let read: super::Read = match ty {
        Compared::Int => |p| check_kind(p, Compared::Int),
        Compared::Double => |p| check_kind(p, Compared::Double),
        Compared::String => |p| check_kind(p, Compared::String),
        Compared::Bool => |p| check_kind(p, Compared::Bool),
    };
    v3(params(id, Decorator, &CHECK_PORTS, read, |k, _| {
        let NodeKind::Check { otherwise, .. } = *k else { return None };
        let (code, name) = status_code(otherwise);
        written(vec![("return_on_mismatch", name.to_string())], Kind::Check(code))
    }))
}

fn check_kind(p: &mut dyn Params, ty: Compared) -> Result<NodeKind> {
    // 3.8 ignores whether `getInput` read it: text it does not read as a status leaves
    // FAILURE; IDLE would make its parent throw.
    let otherwise = match p.text("return_on_mismatch")? {
        Some((text, _)) if text == "SUCCESS" => Status::Success,
        Some((text, _)) if text == "RUNNING" => Status::Running,
        Some((text, at)) if text == "IDLE" => {
            return Err(refuse(
                &at,
                format!("<{} return_on_mismatch=\"IDLE\">", p.id()),
                "a node that returns IDLE makes its parent throw in BehaviorTree.CPP 3.8",
            ));
        }
        _ => Status::Failure,
    };
    Ok(NodeKind::Check { code: p.comparison(ty)?, otherwise })
}

/// 3.8's `Repeat` (`retry` false) or `RetryUntilSuccessful`.
fn cycles_v3(p: &mut dyn Params, port: &'static str, retry: bool) -> Result<NodeKind> {
    let (count, from_slot) = match count_of(p, port)? {
        Count::Literal(n) => (n, false),
        Count::Slot(s) => (s, true),
    };
    Ok(NodeKind::Cycles { count, from_slot, retry, v3: true })
}

/// The parameter and log kind of a [`NodeKind::Cycles`] of that `retry` and `v3`.
pub(super) fn write_cycles(k: &NodeKind, retry: bool, v3: bool) -> Option<Written> {
    let NodeKind::Cycles { count: n, from_slot, retry: r, v3: v } = *k else { return None };
    if (r, v) != (retry, v3) {
        return None;
    }
    let port = if retry { "num_attempts" } else { "num_cycles" };
    // A slot is written as the document names its key (an imported tree's attributes).
    let text = if from_slot { format!("{{slot {n}}}") } else { count(n).to_string() };
    written(vec![(port, text)], Kind::Cycles { count: (!from_slot).then(|| count(n)), retry, v3 })
}
