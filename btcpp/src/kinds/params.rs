//! How a built-in's parameters map to its kind's fields, both ways: counts with `-1`
//! for no limit, milliseconds, rates and statuses, read as BehaviorTree.CPP and Nav2
//! read them (with this crate's precise errors) and written as they write them.

use bt_core::{Code, NodeKind, Span, Status};

use crate::btlog::replay::status as code;
use crate::error::{Fault, ImportError, Location, Result};
use crate::xml::model::{Literal, convert};

/// A node being lowered, as a table entry's [`Read`](super::Read) sees it. The lowerer
/// implements it; absent parameters read as the entry's port defaults.
pub trait Params {
    /// The node's ID as written (a v3 name as it is).
    fn id(&self) -> &str;
    /// Where the node is.
    fn at(&self) -> &Location;
    /// Its number of children.
    fn children(&self) -> usize;
    /// Attribute `port` as written, and where it is.
    fn attr(&self, port: &str) -> Option<(&str, &Location)>;
    /// The literal text of parameter `port` and where it is: the attribute, the literal
    /// a SubTree-local key starts at, else the port's default (at the node); `None`
    /// when absent without a default.
    ///
    /// # Errors
    /// [`Fault::ParameterFromBlackboard`] for a key without such a literal.
    fn text(&self, port: &str) -> Result<Option<(String, Location)>>;
    /// Script parameter `port` compiled into the tree's value table.
    ///
    /// # Errors
    /// The script's fault, with its place.
    fn script(&mut self, port: &'static str) -> Result<Code>;
    /// `SetBlackboard`'s program, compiled into the tree's value table: its `value`
    /// (a string, or a `{key}` copied) assigned to the key its `output_key` names.
    ///
    /// # Errors
    /// A missing parameter; an `output_key` that is a `{key}`.
    fn set_blackboard(&mut self) -> Result<Code>;
    /// The slot of parameter `port` when it is a `{key}` without a literal to start at
    /// (typed `int`, as a count), else `None`.
    ///
    /// # Errors
    /// A key of another type.
    fn count_slot(&mut self, port: &'static str) -> Result<Option<u16>>;
    /// A `BlackboardCheck*` node's comparison of `value_A` and `value_B` as values of
    /// `ty`, compiled into the tree's value table.
    ///
    /// # Errors
    /// A parameter missing; the value table full.
    fn comparison(&mut self, ty: Compared) -> Result<Code>;

    /// Where attribute `port` is, else where the node is.
    fn at_of(&self, port: &str) -> &Location {
        self.attr(port).map_or_else(|| self.at(), |(_, at)| at)
    }
}

/// The type a `BlackboardCheck*` node compares its values as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compared {
    /// `BlackboardCheckInt`.
    Int,
    /// `BlackboardCheckDouble` (equal within `f32`'s epsilon).
    Double,
    /// `BlackboardCheckString`.
    String,
    /// `BlackboardCheckBool`.
    Bool,
}

/// What a count parameter (`num_cycles`, `num_attempts`) gives: a literal count, or a
/// blackboard slot read on every tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Count {
    /// The count ([`NodeKind::FOREVER`]: no limit).
    Literal(u16),
    /// The slot holding it.
    Slot(u16),
}

/// A count parameter: a `{key}` is read on every tick, as BehaviorTree.CPP reads it;
/// else as [`cycles`].
///
/// # Errors
/// As [`cycles`], or a key of another type than an integer.
pub fn count_of(p: &mut dyn Params, port: &'static str) -> Result<Count> {
    match p.count_slot(port)? {
        Some(slot) => Ok(Count::Slot(slot)),
        None => Ok(Count::Literal(cycles(p, port)?)),
    }
}

/// A construct this importer cannot put on a controller.
#[must_use]
pub fn refuse(at: &Location, construct: String, reason: &str) -> ImportError {
    ImportError::new(at, Fault::Unsupported { construct, reason: reason.into() })
}

fn bad_literal(p: &dyn Params, at: &Location, port: &str, value: String, ty: &str) -> ImportError {
    ImportError::new(at, Fault::BadLiteral { node: p.id().to_string(), port: port.into(), value, ty: ty.into() })
}

/// An integer parameter.
///
/// # Errors
/// [`Fault::MissingAttribute`] when absent without a default, [`Fault::BadLiteral`].
pub fn int(p: &dyn Params, port: &'static str) -> Result<i64> {
    let Some((text, at)) = p.text(port)? else {
        return Err(ImportError::new(p.at(), Fault::MissingAttribute { element: p.id().to_string(), attribute: port }));
    };
    match convert(Some("int"), &text) {
        Some(Literal::Int(v)) => Ok(v),
        _ => Err(bad_literal(p, &at, port, text, "int")),
    }
}

/// A boolean parameter (absent: `false`, unless the port has a default).
///
/// # Errors
/// [`Fault::BadLiteral`].
pub fn boolean(p: &dyn Params, port: &'static str) -> Result<bool> {
    let Some((text, at)) = p.text(port)? else {
        return Ok(false);
    };
    match convert(Some("bool"), &text) {
        Some(Literal::Bool(b)) => Ok(b),
        _ => Err(bad_literal(p, &at, port, text, "bool")),
    }
}

/// The statuses a status parameter names: bt-core's, BehaviorTree.CPP's name, the
/// log's code.
const STATUSES: [(Status, &str, u8); 4] = [
    (Status::Success, "SUCCESS", code::SUCCESS),
    (Status::Failure, "FAILURE", code::FAILURE),
    (Status::Running, "RUNNING", code::RUNNING),
    (Status::Skipped, "SKIPPED", code::SKIPPED),
];

/// A status parameter (`else`, `if_empty`): `SUCCESS`, `FAILURE`, `RUNNING` or
/// `SKIPPED` (absent: Failure, unless the port has a default).
///
/// # Errors
/// [`Fault::BadLiteral`].
pub fn status(p: &dyn Params, port: &'static str) -> Result<Status> {
    let Some((text, at)) = p.text(port)? else {
        return Ok(Status::Failure);
    };
    match STATUSES.iter().find(|(_, name, _)| *name == text.trim()) {
        Some(&(s, _, _)) => Ok(s),
        None => Err(bad_literal(p, &at, port, text, "status (SUCCESS, FAILURE, RUNNING or SKIPPED)")),
    }
}

/// A status as BehaviorTree.CPP names it.
#[must_use]
pub fn status_name(s: Status) -> &'static str {
    status_code(s).1
}

/// A status as the log's replay codes it, and as BehaviorTree.CPP names it.
#[must_use]
pub fn status_code(s: Status) -> (u8, &'static str) {
    STATUSES.iter().find(|(t, _, _)| *t == s).map_or((code::FAILURE, "FAILURE"), |&(_, name, c)| (c, name))
}

/// `num_cycles` / `num_attempts`: -1 is forever ([`NodeKind::FOREVER`]), other negative
/// counts are 0 (the child is not ticked), as BehaviorTree.CPP reads them.
///
/// # Errors
/// As [`int`]; [`Fault::Unsupported`] above 65534.
pub fn cycles(p: &dyn Params, port: &'static str) -> Result<u16> {
    let v = int(p, port)?;
    match v {
        -1 => Ok(NodeKind::FOREVER),
        v if v < 0 => Ok(0),
        v => u16::try_from(v).ok().filter(|&v| v != NodeKind::FOREVER).ok_or_else(|| {
            refuse(
                p.at_of(port),
                format!("<{} {port}=\"{v}\">", p.id()),
                "the count must be -1 (forever) or between 0 and 65534",
            )
        }),
    }
}

/// A count as BehaviorTree.CPP writes it: -1 for no limit.
#[must_use]
pub fn count(n: u16) -> i32 {
    if n == NodeKind::FOREVER { -1 } else { i32::from(n) }
}

/// A span in milliseconds (`msec`, `delay_msec`).
///
/// # Errors
/// As [`int`]; [`Fault::Unsupported`] outside 0 to [`Span::MAX`].
pub fn span(p: &dyn Params, port: &'static str) -> Result<Span> {
    let v = int(p, port)?;
    u32::try_from(v).ok().and_then(Span::new).ok_or_else(|| {
        refuse(
            p.at_of(port),
            format!("<{} {port}=\"{v}\">", p.id()),
            "milliseconds must be between 0 and 16,777,215 (4 h 39 min)",
        )
    })
}

/// Nav2's `RateController` rate (`hz`) as its period in milliseconds, rounded up so
/// the rate is never exceeded (less a hair, so that the rate [`rate`] writes for a
/// period reads back as it). A period longer than `now` counts (2^32 ms, 49.7 days:
/// Nav2's `hz="0.0000001"`, "plan once") never expires: [`Span::NEVER`].
///
/// # Errors
/// [`Fault::BadLiteral`] for a rate that is not a number; [`Fault::Unsupported`] for one
/// of 0 or less, or whose period is longer than [`Span::MAX`] and shorter than 2^32 ms.
pub fn period(p: &dyn Params, port: &'static str) -> Result<Span> {
    let Some((text, at)) = p.text(port)? else {
        return Err(ImportError::new(p.at(), Fault::MissingAttribute { element: p.id().to_string(), attribute: port }));
    };
    let hz = match convert(Some("double"), &text) {
        Some(Literal::Double(v)) => v,
        _ => return Err(bad_literal(p, &at, port, text, "double")),
    };
    let ms = if hz > 0.0 { (1000.0 / hz * (1.0 - 1e-12)).ceil() } else { f64::INFINITY };
    if ms.is_finite() && ms > f64::from(u32::MAX) {
        return Ok(Span::NEVER);
    }
    (ms.is_finite() && ms <= f64::from(Span::MAX)).then(|| Span::new(ms as u32)).flatten().ok_or_else(|| {
        refuse(
            &at,
            format!("<{} {port}=\"{text}\">", p.id()),
            if hz > 0.0 {
                "its period is longer than 16,777,215 ms (4 h 39 min), the longest a controller's 24-bit start time measures, and shorter than 2^32 ms (49.7 days), beyond which it is read as never expiring"
            } else {
                "the rate must be above 0"
            },
        )
    })
}

/// The rate that gives a period back, as written (Nav2's "plan once" rate for
/// [`Span::NEVER`]).
#[must_use]
pub fn rate(period: Span) -> String {
    if period == Span::NEVER {
        return "0.0000001".to_string();
    }
    (1000.0 / f64::from(period.get())).to_string()
}
