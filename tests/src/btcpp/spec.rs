//! The neutral tree spec: one line of text from which both BehaviorTree.CPP's XML and
//! our node array are derived.
//!
//! ```text
//! node     := kind [ "(" param { "," param } ")" ] [ "[" node { " " node } "]" ]
//! ```
//!
//! Kinds carry BehaviorTree.CPP's names and parameters as BehaviorTree.CPP reads them
//! (negative Parallel thresholds, `-1` for "forever"); `C` and `A` are a scripted
//! condition and action, whose scripts the fixture gives per node.

use std::fmt;

/// A node kind of the spec, with BehaviorTree.CPP's parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `Sequence`: BehaviorTree.CPP's sequence that remembers its running child.
    Sequence,
    /// `SequenceWithMemory`: keeps its place after a failure.
    SequenceWithMemory,
    /// `Fallback`: remembers its running child.
    Fallback,
    /// `ReactiveSequence`.
    ReactiveSequence,
    /// `ReactiveFallback`.
    ReactiveFallback,
    /// `Parallel(success_count, failure_count)`, negative counts as BehaviorTree.CPP reads them.
    Parallel { success: i32, failure: i32 },
    /// `ParallelAll(max_failures)`.
    ParallelAll { max_failures: i32 },
    /// `IfThenElse`: 2 or 3 children.
    IfThenElse,
    /// `WhileDoElse`: 2 or 3 children.
    WhileDoElse,
    /// `Inverter`.
    Inverter,
    /// `ForceSuccess`.
    ForceSuccess,
    /// `ForceFailure`.
    ForceFailure,
    /// `Repeat(num_cycles)`, `-1` forever.
    Repeat(i32),
    /// `RetryUntilSuccessful(num_attempts)`, `-1` forever.
    RetryUntilSuccessful(i32),
    /// `KeepRunningUntilFailure`.
    KeepRunningUntilFailure,
    /// `RunOnce(then_skip)`.
    RunOnce { then_skip: bool },
    /// `Timeout(msec)`.
    Timeout(u32),
    /// `Delay(delay_msec)`.
    Delay(u32),
    /// `AlwaysSuccess` leaf.
    AlwaysSuccess,
    /// `AlwaysFailure` leaf.
    AlwaysFailure,
    /// `C`: a scripted condition.
    Condition,
    /// `A`: a scripted action.
    Action,
    /// `Script` running [`SCRIPTS`]`[i]`.
    Script(u8),
    /// `ScriptCondition` running [`SCRIPTS`]`[i]`.
    ScriptCondition(u8),
    /// `Sleep(msec)`.
    Sleep(u32),
    /// `Precondition(if, else)`: `if` is [`SCRIPTS`]`[i]`, `else` a status letter
    /// (`S`, `F`, `R`, `K` for SKIPPED).
    Precondition(u8, char),
    /// `LoopInt` (over `1;2;...`, into `{n}`) or `LoopDouble` (over `0.5;1.5;...`, into
    /// `{m}`) with `count` elements and `if_empty` a status letter.
    Loop {
        /// `LoopDouble` rather than `LoopInt`.
        double: bool,
        /// Elements in its literal queue.
        count: u8,
        /// The `if_empty` status letter.
        if_empty: char,
    },
}

/// The elements of a spec loop's queue, as BehaviorTree.CPP reads them.
#[must_use]
pub fn loop_elements(double: bool, count: u8) -> Vec<String> {
    (1..=count).map(|k| if double { format!("{}.5", k - 1) } else { k.to_string() }).collect()
}

/// The scripts of `Script` and `ScriptCondition` nodes, by index: 0 starts every
/// scripted case; 1 to 5 are for `Script`, 6 and up for `ScriptCondition`. Keys `n`
/// (an integer), `m` (a double), `flag` (a double used as a boolean).
pub const SCRIPTS: &[&str] = &[
    "n := 0; m := 0.0; flag := false",
    "n += 1",
    "m := n * 2",
    "flag := !flag",
    "n := n > 4 ? 0 : n + 1",
    "m += 0.5",
    "n < 3",
    "flag",
    "n >= m",
    "n == 2 || m > 3",
    "m - n > 1 && flag",
    "n & 1",
];

/// BehaviorTree.CPP's name of a status letter (`K`: SKIPPED).
#[must_use]
pub fn status_name(letter: char) -> &'static str {
    match letter {
        'S' => "SUCCESS",
        'F' => "FAILURE",
        'R' => "RUNNING",
        _ => "SKIPPED",
    }
}

/// The first script of [`SCRIPTS`] meant for `ScriptCondition`.
pub const FIRST_CONDITION_SCRIPT: u8 = 6;

impl Kind {
    /// BehaviorTree.CPP's registration name (`C`/`A` for the scripted leaves).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Sequence => "Sequence",
            Self::SequenceWithMemory => "SequenceWithMemory",
            Self::Fallback => "Fallback",
            Self::ReactiveSequence => "ReactiveSequence",
            Self::ReactiveFallback => "ReactiveFallback",
            Self::Parallel { .. } => "Parallel",
            Self::ParallelAll { .. } => "ParallelAll",
            Self::IfThenElse => "IfThenElse",
            Self::WhileDoElse => "WhileDoElse",
            Self::Inverter => "Inverter",
            Self::ForceSuccess => "ForceSuccess",
            Self::ForceFailure => "ForceFailure",
            Self::Repeat(_) => "Repeat",
            Self::RetryUntilSuccessful(_) => "RetryUntilSuccessful",
            Self::KeepRunningUntilFailure => "KeepRunningUntilFailure",
            Self::RunOnce { .. } => "RunOnce",
            Self::Timeout(_) => "Timeout",
            Self::Delay(_) => "Delay",
            Self::AlwaysSuccess => "AlwaysSuccess",
            Self::AlwaysFailure => "AlwaysFailure",
            Self::Script(_) => "Script",
            Self::ScriptCondition(_) => "ScriptCondition",
            Self::Precondition(..) => "Precondition",
            Self::Loop { double: false, .. } => "LoopInt",
            Self::Loop { double: true, .. } => "LoopDouble",
            Self::Sleep(_) => "Sleep",
            Self::Condition => "C",
            Self::Action => "A",
        }
    }

    /// The parameters as `(XML attribute, value)` pairs.
    #[must_use]
    pub fn params(self) -> Vec<(&'static str, String)> {
        match self {
            Self::Parallel { success, failure } => {
                vec![("success_count", success.to_string()), ("failure_count", failure.to_string())]
            }
            Self::ParallelAll { max_failures } => vec![("max_failures", max_failures.to_string())],
            Self::Repeat(n) => vec![("num_cycles", n.to_string())],
            Self::RetryUntilSuccessful(n) => vec![("num_attempts", n.to_string())],
            Self::RunOnce { then_skip } => vec![("then_skip", then_skip.to_string())],
            Self::Timeout(ms) => vec![("msec", ms.to_string())],
            Self::Delay(ms) => vec![("delay_msec", ms.to_string())],
            Self::Sleep(ms) => vec![("msec", ms.to_string())],
            Self::Script(i) | Self::ScriptCondition(i) => vec![("code", i.to_string())],
            Self::Precondition(i, otherwise) => vec![("if", i.to_string()), ("else", otherwise.to_string())],
            Self::Loop { count, if_empty, .. } => {
                vec![("queue", count.to_string()), ("if_empty", if_empty.to_string())]
            }
            _ => vec![],
        }
    }

    /// True for the kinds without children.
    #[must_use]
    pub fn is_leaf(self) -> bool {
        matches!(
            self,
            Self::AlwaysSuccess
                | Self::AlwaysFailure
                | Self::Condition
                | Self::Action
                | Self::Script(_)
                | Self::ScriptCondition(_)
                | Self::Sleep(_)
        )
    }

    /// True for the kinds with exactly one child.
    #[must_use]
    pub fn is_decorator(self) -> bool {
        matches!(
            self,
            Self::Inverter
                | Self::ForceSuccess
                | Self::ForceFailure
                | Self::Repeat(_)
                | Self::RetryUntilSuccessful(_)
                | Self::KeepRunningUntilFailure
                | Self::RunOnce { .. }
                | Self::Timeout(_)
                | Self::Delay(_)
                | Self::Precondition(..)
                | Self::Loop { .. }
        )
    }

    /// True for the kinds whose behavior depends on the clock.
    #[must_use]
    pub fn is_timed(self) -> bool {
        matches!(self, Self::Timeout(_) | Self::Delay(_) | Self::Sleep(_))
    }
}

/// A tree of the spec.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Spec {
    /// What the root is.
    pub kind: Kind,
    /// Its children, in order.
    pub children: Vec<Spec>,
    /// Its scripted attributes: a [`HOOKS`] letter and a [`SCRIPTS`] index each.
    pub hooks: Vec<(char, u8)>,
}

/// The scripted attributes, by their letter in the spec (`{K=6,s=1}`): `F` `_failureIf`,
/// `S` `_successIf`, `K` `_skipIf`, `W` `_while`, `H` `_onHalted`, `f` `_onFailure`,
/// `s` `_onSuccess`, `P` `_post`, in bt-core's hook order.
pub const HOOKS: [(char, &str); 8] = [
    ('F', "_failureIf"),
    ('S', "_successIf"),
    ('K', "_skipIf"),
    ('W', "_while"),
    ('H', "_onHalted"),
    ('f', "_onFailure"),
    ('s', "_onSuccess"),
    ('P', "_post"),
];

impl Spec {
    /// A node with children.
    #[must_use]
    pub fn new(kind: Kind, children: Vec<Spec>) -> Self {
        Self { kind, children, hooks: vec![] }
    }

    /// A leaf.
    #[must_use]
    pub fn leaf(kind: Kind) -> Self {
        Self { kind, children: vec![], hooks: vec![] }
    }

    /// The nodes in pre-order (the node ids both sides use).
    #[must_use]
    pub fn preorder(&self) -> Vec<&Spec> {
        let mut out = vec![];
        let mut stack = vec![self];
        while let Some(n) = stack.pop() {
            out.push(n);
            stack.extend(n.children.iter().rev());
        }
        out
    }

    /// Number of nodes.
    #[must_use]
    pub fn len(&self) -> usize {
        self.preorder().len()
    }

    /// Never true: a spec has a root.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Levels from the root to the deepest leaf, both included.
    #[must_use]
    pub fn depth(&self) -> usize {
        1 + self.children.iter().map(Spec::depth).max().unwrap_or(0)
    }

    /// BehaviorTree.CPP v4 XML on one line; scripted leaves are `<C7/>` and `<A9/>`
    /// after their pre-order node id.
    #[must_use]
    pub fn to_xml(&self) -> String {
        let mut out = String::from(r#"<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main">"#);
        let mut next = 0usize;
        write_xml(self, &mut next, &mut out);
        out.push_str("</BehaviorTree></root>");
        out
    }

    /// Parses the text form.
    ///
    /// # Errors
    /// A message naming the byte offset of the fault.
    pub fn parse(text: &str) -> Result<Spec, String> {
        let mut p = Parser { s: text.as_bytes(), at: 0 };
        let spec = p.node()?;
        if p.at != p.s.len() {
            return Err(format!("unexpected text at byte {}", p.at));
        }
        Ok(spec)
    }
}

fn write_xml(spec: &Spec, next: &mut usize, out: &mut String) {
    let id = *next;
    *next += 1;
    let name = match spec.kind {
        Kind::Condition => format!("C{id}"),
        Kind::Action => format!("A{id}"),
        k => k.name().to_string(),
    };
    out.push('<');
    out.push_str(&name);
    for (attr, value) in spec.kind.params() {
        let value = match (spec.kind, attr) {
            (Kind::Script(i) | Kind::ScriptCondition(i) | Kind::Precondition(i, _), "code" | "if") => {
                SCRIPTS.get(usize::from(i)).copied().unwrap_or("").replace('&', "&amp;").replace('<', "&lt;")
            }
            (Kind::Precondition(_, otherwise), _) => status_name(otherwise).to_string(),
            (Kind::Loop { double, count, .. }, "queue") => loop_elements(double, count).join(";"),
            (Kind::Loop { if_empty, .. }, _) => status_name(if_empty).to_string(),
            _ => value,
        };
        out.push_str(&format!(r#" {attr}="{value}""#));
    }
    if let Kind::Loop { double, .. } = spec.kind {
        out.push_str(if double { r#" value="{m}""# } else { r#" value="{n}""# });
    }
    for (h, i) in &spec.hooks {
        let attr = HOOKS.iter().find(|(c, _)| c == h).map_or("", |(_, a)| a);
        let code = SCRIPTS.get(usize::from(*i)).copied().unwrap_or("").replace('&', "&amp;").replace('<', "&lt;");
        out.push_str(&format!(r#" {attr}="{code}""#));
    }
    if spec.children.is_empty() {
        out.push_str("/>");
        return;
    }
    out.push('>');
    for c in &spec.children {
        write_xml(c, next, out);
    }
    out.push_str(&format!("</{name}>"));
}

impl fmt::Display for Spec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.kind.name())?;
        let params = self.kind.params();
        if !params.is_empty() {
            let values: Vec<_> = params.into_iter().map(|(_, v)| v).collect();
            write!(f, "({})", values.join(","))?;
        }
        if !self.hooks.is_empty() {
            let hooks: Vec<String> = self.hooks.iter().map(|(h, i)| format!("{h}={i}")).collect();
            write!(f, "{{{}}}", hooks.join(","))?;
        }
        if !self.children.is_empty() {
            f.write_str("[")?;
            for (i, c) in self.children.iter().enumerate() {
                if i > 0 {
                    f.write_str(" ")?;
                }
                write!(f, "{c}")?;
            }
            f.write_str("]")?;
        }
        Ok(())
    }
}

struct Parser<'a> {
    s: &'a [u8],
    at: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<u8> {
        self.s.get(self.at).copied()
    }

    fn word(&mut self) -> &str {
        let start = self.at;
        while self.peek().is_some_and(|c| c.is_ascii_alphanumeric() || c == b'-' || c == b'_') {
            self.at += 1;
        }
        std::str::from_utf8(&self.s[start..self.at]).unwrap_or("")
    }

    fn node(&mut self) -> Result<Spec, String> {
        let at = self.at;
        let name = self.word().to_string();
        let mut params = vec![];
        if self.peek() == Some(b'(') {
            self.at += 1;
            loop {
                params.push(self.word().to_string());
                match self.peek() {
                    Some(b',') => self.at += 1,
                    Some(b')') => {
                        self.at += 1;
                        break;
                    }
                    _ => return Err(format!("expected , or ) at byte {}", self.at)),
                }
            }
        }
        let int = |i: usize| -> Result<i32, String> {
            params.get(i).and_then(|p| p.parse().ok()).ok_or(format!("bad parameter {i} of {name} at byte {at}"))
        };
        let kind = match name.as_str() {
            "Sequence" => Kind::Sequence,
            "SequenceWithMemory" => Kind::SequenceWithMemory,
            "Fallback" => Kind::Fallback,
            "ReactiveSequence" => Kind::ReactiveSequence,
            "ReactiveFallback" => Kind::ReactiveFallback,
            "Parallel" => Kind::Parallel { success: int(0)?, failure: int(1)? },
            "ParallelAll" => Kind::ParallelAll { max_failures: int(0)? },
            "IfThenElse" => Kind::IfThenElse,
            "WhileDoElse" => Kind::WhileDoElse,
            "Inverter" => Kind::Inverter,
            "ForceSuccess" => Kind::ForceSuccess,
            "ForceFailure" => Kind::ForceFailure,
            "Repeat" => Kind::Repeat(int(0)?),
            "RetryUntilSuccessful" => Kind::RetryUntilSuccessful(int(0)?),
            "KeepRunningUntilFailure" => Kind::KeepRunningUntilFailure,
            "RunOnce" => Kind::RunOnce { then_skip: params.first().is_some_and(|p| p == "true") },
            "Timeout" => Kind::Timeout(int(0)? as u32),
            "Delay" => Kind::Delay(int(0)? as u32),
            "AlwaysSuccess" => Kind::AlwaysSuccess,
            "AlwaysFailure" => Kind::AlwaysFailure,
            "Script" => Kind::Script(int(0)? as u8),
            "ScriptCondition" => Kind::ScriptCondition(int(0)? as u8),
            "Sleep" => Kind::Sleep(int(0)? as u32),
            "Precondition" => Kind::Precondition(
                int(0)? as u8,
                params.get(1).and_then(|p| p.chars().next()).ok_or(format!("no else status at byte {at}"))?,
            ),
            "LoopInt" | "LoopDouble" => Kind::Loop {
                double: name == "LoopDouble",
                count: int(0)? as u8,
                if_empty: params.get(1).and_then(|p| p.chars().next()).ok_or(format!("no if_empty at byte {at}"))?,
            },
            "C" => Kind::Condition,
            "A" => Kind::Action,
            _ => return Err(format!("unknown kind `{name}` at byte {at}")),
        };
        let mut hooks = vec![];
        if self.peek() == Some(b'{') {
            self.at += 1;
            loop {
                let h = self.peek().map(char::from).ok_or(format!("expected a hook at byte {}", self.at))?;
                if !HOOKS.iter().any(|(c, _)| *c == h) || self.s.get(self.at + 1) != Some(&b'=') {
                    return Err(format!("bad hook at byte {}", self.at));
                }
                self.at += 2;
                let i = self.word().parse().map_err(|_| format!("bad script index at byte {}", self.at))?;
                hooks.push((h, i));
                match self.peek() {
                    Some(b',') => self.at += 1,
                    Some(b'}') => {
                        self.at += 1;
                        break;
                    }
                    _ => return Err(format!("expected , or }} at byte {}", self.at)),
                }
            }
        }
        let mut children = vec![];
        if self.peek() == Some(b'[') {
            self.at += 1;
            loop {
                children.push(self.node()?);
                match self.peek() {
                    Some(b' ') => self.at += 1,
                    Some(b']') => {
                        self.at += 1;
                        break;
                    }
                    _ => return Err(format!("expected a space or ] at byte {}", self.at)),
                }
            }
        }
        Ok(Spec { kind, children, hooks })
    }
}
