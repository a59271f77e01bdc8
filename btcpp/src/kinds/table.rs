//! The table: every node type of BehaviorTree.CPP 4.10, and Nav2's control nodes.

use bt_core::NodeKind;
use bt_core::PortType::{Any, Bool, Double, Int, String as Str};
use bt_core::script::Element;

use super::Origin::{BehaviorTreeCpp, Nav2};
use super::Shape::{AnyNumber, Control, Decorator, Leaf, Two, TwoOrThree};
use super::params::{Count, boolean, count, count_of, int, period, rate, refuse, span, status, status_code};
use super::v3::write_cycles;
use super::{Attrs, Entry, LOOP_LOG_DEFAULTS, LOOP_PORTS, Map, Port, Shape, Written};
use crate::btlog::tree::Kind;

const SWITCH: &str = "it compares blackboard strings at run time; write the cases as a Fallback of Sequences, each a condition and its branch";
const UNSET: &str = "it removes a blackboard entry at run time, and a controller's slots stay; give an output port of an Action the value instead";
const UPDATED: &str = "it watches blackboard sequence numbers, which a controller's slots do not keep";
const NO_KIND: &str = "bt-core has no node kind with its semantics";

pub(super) const fn port(name: &'static str, ty: bt_core::PortType, default: Option<&'static str>) -> Port {
    Port { name, ty, default }
}

/// An entry without aliases, log defaults or log model, of version 4 only.
pub(super) const fn entry(id: &'static str, shape: Shape, ports: &'static [Port], map: Map) -> Entry {
    Entry {
        id,
        aliases: &[],
        origin: BehaviorTreeCpp,
        shape,
        ports,
        map,
        log_defaults: &[],
        log_model: None,
        v3: false,
    }
}

/// An entry BehaviorTree.CPP 3.8 shares (see [`Entry::v3`]).
const fn both(e: Entry) -> Entry {
    Entry { v3: true, ..e }
}

/// A node type that is always the same kind.
pub(super) const fn plain(id: &'static str, shape: Shape, kind: NodeKind, log: Kind) -> Entry {
    entry(id, shape, &[], Map::Plain(kind, log))
}

/// A node type that is refused.
pub(super) const fn refused(id: &'static str, shape: Shape, ports: &'static [Port], why: &'static str) -> Entry {
    entry(id, shape, ports, Map::Refused(why))
}

/// A node type whose parameters `read` and `write` map.
pub(super) const fn params(
    id: &'static str,
    shape: Shape,
    ports: &'static [Port],
    read: super::Read,
    write: super::Write,
) -> Entry {
    entry(id, shape, ports, Map::Params { read, write, attrs: Attrs::Document })
}

/// A built-in loop.
const fn looping(id: &'static str, element: Element) -> Entry {
    Entry { log_defaults: LOOP_LOG_DEFAULTS, ..entry(id, Decorator, &LOOP_PORTS, Map::Loop(element)) }
}

const fn with_defaults(e: Entry, log_defaults: &'static [(&'static str, &'static str)]) -> Entry {
    Entry { log_defaults, ..e }
}

const fn with_attrs(e: Entry, attrs: Attrs) -> Entry {
    match e.map {
        Map::Params { read, write, .. } => Entry { map: Map::Params { read, write, attrs }, ..e },
        _ => e,
    }
}

/// Nav2's: its humble release (BehaviorTree.CPP 3.8) runs them as its later ones do.
const fn nav2(e: Entry, log_model: &'static str) -> Entry {
    Entry { origin: Nav2, log_model: Some(log_model), v3: true, ..e }
}

pub(super) fn written(params: Vec<(&'static str, String)>, log: Kind) -> Option<Written> {
    Some(Written { params, log })
}

/// A span as written: whole milliseconds.
pub(super) fn ms(s: bt_core::Span) -> String {
    s.get().to_string()
}

/// Every node type: BehaviorTree.CPP 4.10's built-ins in the order of its factory, then
/// Nav2's control nodes and `RateController`.
pub const TABLE: &[Entry] = &[
    // Reactive and with-memory sequences and fallbacks. BehaviorTree.CPP's `Sequence`
    // resumes at the running child; its `SequenceWithMemory` also keeps its place after
    // a failure (bt-core's `SequenceStar`).
    both(plain("Sequence", Control, NodeKind::SequenceWithMemory, Kind::Sequence)),
    both(plain("Fallback", Control, NodeKind::FallbackWithMemory, Kind::Fallback)),
    Entry {
        aliases: &["SequenceStar"],
        ..plain("SequenceWithMemory", Control, NodeKind::SequenceStar, Kind::SequenceWithMemory)
    },
    both(plain("ReactiveSequence", Control, NodeKind::Sequence, Kind::ReactiveSequence)),
    both(plain("ReactiveFallback", Control, NodeKind::Fallback, Kind::ReactiveFallback)),
    // A negative count is counted from the number of children; a success count that
    // counts skipped children was negative in the XML.
    with_defaults(
        params(
            "Parallel",
            Control,
            &[port("success_count", Int, Some("-1")), port("failure_count", Int, Some("1"))],
            |p| {
                let children = p.children();
                let s = int(p, "success_count")?;
                let f = int(p, "failure_count")?;
                let resolve = |t: i64| if t < 0 { (children as i64 + t + 1).max(0) } else { t };
                let (rs, rf) = (resolve(s), resolve(f));
                for (port, v) in [("success_count", rs), ("failure_count", rf)] {
                    if v < 1 || v > children as i64 {
                        return Err(refuse(
                            p.at(),
                            format!("<Parallel {port}> of {v} with {children} children"),
                            "the threshold must be between 1 and the number of children",
                        ));
                    }
                }
                Ok(NodeKind::Parallel {
                    success_threshold: rs as u16,
                    failure_threshold: rf as u16,
                    count_skipped: s < 0,
                })
            },
            |k, children| {
                let NodeKind::Parallel { success_threshold, failure_threshold, count_skipped } = *k else {
                    return None;
                };
                let success = if count_skipped {
                    i64::from(success_threshold) - i64::try_from(children).unwrap_or(i64::MAX) - 1
                } else {
                    i64::from(success_threshold)
                };
                written(
                    vec![("success_count", success.to_string()), ("failure_count", failure_threshold.to_string())],
                    Kind::Parallel {
                        success: i32::try_from(success).unwrap_or(i32::MIN),
                        failure: i32::from(failure_threshold),
                    },
                )
            },
        ),
        &[("failure_count", "1"), ("success_count", "-1")],
    ),
    with_defaults(
        params(
            "ParallelAll",
            Control,
            &[port("max_failures", Int, Some("1"))],
            |p| {
                let children = p.children();
                let m = int(p, "max_failures")?;
                let resolved = if m < 0 { (children as i64 + m + 1).max(0) } else { m };
                if resolved > children as i64 {
                    return Err(refuse(
                        p.at(),
                        format!("<ParallelAll max_failures=\"{m}\"> with {children} children"),
                        "it could never fail (BehaviorTree.CPP refuses it when ticked)",
                    ));
                }
                Ok(NodeKind::ParallelAll { max_failures: resolved as u16 })
            },
            |k, _| {
                let NodeKind::ParallelAll { max_failures } = *k else { return None };
                written(
                    vec![("max_failures", max_failures.to_string())],
                    Kind::ParallelAll { max_failures: i32::from(max_failures) },
                )
            },
        ),
        &[("max_failures", "1")],
    ),
    both(plain("IfThenElse", TwoOrThree, NodeKind::IfThenElse, Kind::IfThenElse)),
    plain("WhileDoElse", TwoOrThree, NodeKind::WhileDoElse, Kind::WhileDoElse),
    both(plain("Inverter", Decorator, NodeKind::Inverter, Kind::Inverter)),
    both(plain("ForceSuccess", Decorator, NodeKind::ForceSuccess, Kind::ForceSuccess)),
    both(plain("ForceFailure", Decorator, NodeKind::ForceFailure, Kind::ForceFailure)),
    // A `{key}` count is read on every tick (a `Cycles`).
    params(
        "Repeat",
        Decorator,
        &[port("num_cycles", Int, None)],
        |p| {
            Ok(match count_of(p, "num_cycles")? {
                Count::Literal(n) => NodeKind::RepeatCycles(n),
                Count::Slot(s) => NodeKind::Cycles { count: s, from_slot: true, retry: false, v3: false },
            })
        },
        |k, _| match *k {
            NodeKind::RepeatCycles(n) => written(vec![("num_cycles", count(n).to_string())], Kind::Repeat(count(n))),
            _ => write_cycles(k, false, false),
        },
    ),
    params(
        "RetryUntilSuccessful",
        Decorator,
        &[port("num_attempts", Int, None)],
        |p| {
            Ok(match count_of(p, "num_attempts")? {
                Count::Literal(n) => NodeKind::RetryUntilSuccessful(n),
                Count::Slot(s) => NodeKind::Cycles { count: s, from_slot: true, retry: true, v3: false },
            })
        },
        |k, _| match *k {
            NodeKind::RetryUntilSuccessful(n) => {
                written(vec![("num_attempts", count(n).to_string())], Kind::Retry(count(n)))
            }
            _ => write_cycles(k, true, false),
        },
    ),
    both(plain("KeepRunningUntilFailure", Decorator, NodeKind::KeepRunningUntilFailure, Kind::KeepRunningUntilFailure)),
    with_defaults(
        params(
            "RunOnce",
            Decorator,
            &[port("then_skip", Bool, Some("true"))],
            |p| Ok(NodeKind::RunOnce { then_skip: boolean(p, "then_skip")? }),
            |k, _| {
                let NodeKind::RunOnce { then_skip } = *k else { return None };
                written(vec![("then_skip", then_skip.to_string())], Kind::RunOnce { then_skip })
            },
        ),
        &[("then_skip", "true")],
    ),
    params(
        "Timeout",
        Decorator,
        &[port("msec", Int, None)],
        |p| Ok(NodeKind::TimeLimit(span(p, "msec")?)),
        |k, _| {
            let NodeKind::TimeLimit(s) = *k else { return None };
            written(vec![("msec", ms(s))], Kind::Timeout(s.get()))
        },
    ),
    both(params(
        "Delay",
        Decorator,
        &[port("delay_msec", Int, None)],
        |p| Ok(NodeKind::Delay(span(p, "delay_msec")?)),
        |k, _| {
            let NodeKind::Delay(s) = *k else { return None };
            written(vec![("delay_msec", ms(s))], Kind::Delay(s.get()))
        },
    )),
    both(plain("AlwaysSuccess", Leaf, NodeKind::AlwaysSuccess, Kind::AlwaysSuccess)),
    both(plain("AlwaysFailure", Leaf, NodeKind::AlwaysFailure, Kind::AlwaysFailure)),
    refused("AsyncSequence", Control, &[], NO_KIND),
    refused("AsyncFallback", Control, &[], NO_KIND),
    refused("TryCatch", Control, &[port("catch_on_halt", Bool, Some("false"))], NO_KIND),
    // In BT.CPP 4.10's sources, though neither built into its library nor registered by
    // its factory; its ex03 example's tree uses it. The choice comes from the behavior
    // set here (bt_core::BehaviorSet::select), not from a terminal. Any number of
    // children: BT.CPP's node asks for a status when it has none. A program that loads
    // a tree with one registers it, and its log then lists the model (written from the
    // node's `providedPorts()`).
    Entry {
        log_defaults: &[("repeat_last_selection", "false")],
        log_model: Some(
            "        <Control ID=\"ManualSelector\">\n            <input_port name=\"repeat_last_selection\" type=\"bool\" default=\"false\">If true, execute again the same child that was selected the last time</input_port>\n        </Control>\n",
        ),
        ..params(
            "ManualSelector",
            AnyNumber,
            &[port("repeat_last_selection", Bool, Some("false"))],
            |p| {
                let children = p.children();
                if children > usize::from(u8::MAX) {
                    return Err(refuse(
                        p.at(),
                        format!("<ManualSelector> with {children} children"),
                        "the behavior set chooses a child by a number from 0 to 254: at most 255 children",
                    ));
                }
                Ok(NodeKind::ManualSelector { repeat_last: boolean(p, "repeat_last_selection")? })
            },
            |k, _| {
                let NodeKind::ManualSelector { repeat_last } = *k else { return None };
                written(vec![("repeat_last_selection", repeat_last.to_string())], Kind::ManualSelector { repeat_last })
            },
        )
    },
    // Scripts: their programs go into the image's value table; the text is written
    // only as the document wrote it.
    with_attrs(
        params(
            "Script",
            Leaf,
            &[port("code", Str, None)],
            |p| Ok(NodeKind::Script(p.script("code")?)),
            |k, _| matches!(k, NodeKind::Script(_)).then(|| Written { params: Vec::new(), log: Kind::Script }),
        ),
        Attrs::Script,
    ),
    with_attrs(
        params(
            "ScriptCondition",
            Leaf,
            &[port("code", Any, None)],
            |p| Ok(NodeKind::ScriptCondition(p.script("code")?)),
            |k, _| {
                matches!(k, NodeKind::ScriptCondition(_))
                    .then(|| Written { params: Vec::new(), log: Kind::ScriptCondition })
            },
        ),
        Attrs::Script,
    ),
    with_defaults(
        with_attrs(
            params(
                "Precondition",
                Decorator,
                &[port("if", Str, None), port("else", Any, Some("FAILURE"))],
                |p| Ok(NodeKind::Precondition { code: p.script("if")?, otherwise: status(p, "else")? }),
                |k, _| {
                    let NodeKind::Precondition { otherwise, .. } = *k else { return None };
                    let (code, name) = status_code(otherwise);
                    written(vec![("else", name.to_string())], Kind::Precondition(code))
                },
            ),
            Attrs::Script,
        ),
        &[("else", "FAILURE")],
    ),
    // A `Script` assigning `value` to the key `output_key` names; written back as it.
    both(with_attrs(
        params(
            "SetBlackboard",
            Leaf,
            &[port("value", Any, None), port("output_key", Any, None)],
            |p| Ok(NodeKind::Script(p.set_blackboard()?)),
            |k, _| matches!(k, NodeKind::Script(_)).then(|| Written { params: Vec::new(), log: Kind::Script }),
        ),
        Attrs::Script,
    )),
    refused("UnsetBlackboard", Leaf, &[port("key", Str, None)], UNSET),
    // Written from the kind: a `msec` a SubTree's literal gave is written as its value.
    with_attrs(
        params(
            "Sleep",
            Leaf,
            &[port("msec", Int, None)],
            |p| Ok(NodeKind::Sleep(span(p, "msec")?)),
            |k, _| {
                let NodeKind::Sleep(s) = *k else { return None };
                written(vec![("msec", ms(s))], Kind::Sleep(s.get()))
            },
        ),
        Attrs::Kind,
    ),
    both(refused("Switch2", Control, &[], SWITCH)),
    both(refused("Switch3", Control, &[], SWITCH)),
    both(refused("Switch4", Control, &[], SWITCH)),
    both(refused("Switch5", Control, &[], SWITCH)),
    both(refused("Switch6", Control, &[], SWITCH)),
    looping("LoopInt", Element::Int),
    looping("LoopBool", Element::Bool),
    looping("LoopDouble", Element::Double),
    looping("LoopString", Element::String),
    refused("WasEntryUpdated", Leaf, &[port("entry", Any, None)], UPDATED),
    refused("SkipUnlessUpdated", Decorator, &[port("entry", Any, None)], UPDATED),
    refused("WaitValueUpdate", Decorator, &[port("entry", Any, None)], UPDATED),
    // Nav2's, with their ports and log models as Nav2 jazzy declares them (as
    // BehaviorTree.CPP 4.10.0 writes them).
    nav2(
        plain("PipelineSequence", Control, NodeKind::PipelineSequence, Kind::PipelineSequence),
        "        <Control ID=\"PipelineSequence\"/>\n",
    ),
    nav2(
        with_defaults(
            params(
                "RecoveryNode",
                Two,
                &[port("number_of_retries", Int, Some("1"))],
                |p| {
                    let r = int(p, "number_of_retries")?;
                    let retries = u16::try_from(r).map_err(|_| {
                        refuse(
                            p.at(),
                            format!("<RecoveryNode number_of_retries=\"{r}\">"),
                            "the number of retries must be between 0 and 65535",
                        )
                    })?;
                    Ok(NodeKind::Recovery { retries })
                },
                |k, _| {
                    let NodeKind::Recovery { retries } = *k else { return None };
                    written(vec![("number_of_retries", retries.to_string())], Kind::Recovery(i32::from(retries)))
                },
            ),
            &[("number_of_retries", "1")],
        ),
        "        <Control ID=\"RecoveryNode\">\n            <input_port name=\"number_of_retries\" type=\"int\" default=\"1\">Number of retries</input_port>\n        </Control>\n",
    ),
    // bt-core's is Nav2 jazzy's classic one, which has no `wrap_around`.
    nav2(
        params(
            "RoundRobin",
            Control,
            &[port("wrap_around", Bool, None)],
            |p| {
                if let Some((raw, at)) = p.attr("wrap_around") {
                    return Err(refuse(
                        at,
                        format!("<RoundRobin wrap_around=\"{raw}\">"),
                        "bt-core's RoundRobin is Nav2's classic one (Nav2 jazzy): it fails once every child has failed in turn and goes on from the first; leave wrap_around out",
                    ));
                }
                Ok(NodeKind::RoundRobin)
            },
            |k, _| matches!(k, NodeKind::RoundRobin).then(|| Written { params: Vec::new(), log: Kind::RoundRobin }),
        ),
        "        <Control ID=\"RoundRobin\"/>\n",
    ),
    // The rate is read as a period in whole milliseconds, and written as the rate that
    // gives it back.
    nav2(
        with_defaults(
            params(
                "RateController",
                Decorator,
                &[port("hz", Double, Some("10.0"))],
                |p| Ok(NodeKind::RateController(period(p, "hz")?)),
                |k, _| {
                    let NodeKind::RateController(s) = *k else { return None };
                    written(vec![("hz", rate(s))], Kind::RateController(s.get()))
                },
            ),
            &[("hz", "10.000000")],
        ),
        "        <Decorator ID=\"RateController\">\n            <input_port name=\"hz\" type=\"double\" default=\"10.000000\">Rate</input_port>\n        </Decorator>\n",
    ),
];
