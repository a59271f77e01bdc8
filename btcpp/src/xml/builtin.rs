//! BehaviorTree.CPP's built-in node types (release 4.10, and the v3 names it still
//! reads): their shape, their ports, and whether this importer can put them on a
//! controller.

use bt_core::PortType;

/// How many children a node type takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// No children.
    Leaf,
    /// Exactly one.
    Decorator,
    /// One or more.
    Control,
    /// Exactly two (Nav2's `RecoveryNode`).
    Two,
    /// Two or three (`IfThenElse`, `WhileDoElse`).
    TwoOrThree,
    /// Any number, none included (`ManualSelector`).
    AnyNumber,
}

impl Shape {
    /// The rule in words, for errors.
    #[must_use]
    pub const fn rule(self) -> &'static str {
        match self {
            Self::Leaf => "takes no children",
            Self::Decorator => "takes exactly one child",
            Self::Control => "takes one or more children",
            Self::Two => "takes exactly two children",
            Self::TwoOrThree => "takes two or three children",
            Self::AnyNumber => "takes any number of children",
        }
    }

    /// Whether `n` children fit.
    #[must_use]
    pub const fn fits(self, n: usize) -> bool {
        match self {
            Self::Leaf => n == 0,
            Self::Decorator => n == 1,
            Self::Control => n >= 1,
            Self::Two => n == 2,
            Self::TwoOrThree => n == 2 || n == 3,
            Self::AnyNumber => true,
        }
    }

    /// The shape of a bt-core kind.
    #[must_use]
    pub const fn of(kind: &bt_core::NodeKind) -> Self {
        match kind.arity() {
            bt_core::Arity::Leaf => Self::Leaf,
            bt_core::Arity::One => Self::Decorator,
            bt_core::Arity::AtLeastOne => Self::Control,
            bt_core::Arity::Two => Self::Two,
            bt_core::Arity::TwoOrThree => Self::TwoOrThree,
            bt_core::Arity::Any => Self::AnyNumber,
        }
    }
}

/// A port of a built-in node: name, type, default.
pub type BuiltinPort = (&'static str, PortType, Option<&'static str>);

/// One built-in node type.
#[derive(Clone, Copy, Debug)]
pub struct Builtin {
    /// Its registration ID in BehaviorTree.CPP 4 (a v3 name maps to it).
    pub id: &'static str,
    /// Children it takes.
    pub shape: Shape,
    /// Its ports.
    pub ports: &'static [BuiltinPort],
    /// `None` when it can be imported; else why not.
    pub refused: Option<&'static str>,
}

const SWITCH: &str = "it compares blackboard strings at run time; write the cases as a Fallback of Sequences, each a condition and its branch";
const BLACKBOARD: &str = "it writes or removes blackboard entries of any type at run time; give the value to an output port of an Action instead";
const UPDATED: &str = "it watches blackboard sequence numbers, which a controller's slots do not keep";
const NO_KIND: &str = "bt-core has no node kind with its semantics";

/// A loop's ports (the `value` port's type is its element's, see [`loop_element`]).
pub const LOOP_PORTS: [BuiltinPort; 3] =
    [("queue", Any, None), ("if_empty", Any, Some("SUCCESS")), ("value", Any, None)];

/// The element type of a built-in loop (`LoopInt`, ...).
#[must_use]
pub fn loop_element(id: &str) -> Option<bt_core::script::Element> {
    use bt_core::script::Element;
    Some(match id {
        "LoopInt" => Element::Int,
        "LoopBool" => Element::Bool,
        "LoopDouble" => Element::Double,
        "LoopString" => Element::String,
        _ => return None,
    })
}

const fn b(id: &'static str, shape: Shape, ports: &'static [BuiltinPort]) -> Builtin {
    Builtin { id, shape, ports, refused: None }
}

const fn r(id: &'static str, shape: Shape, ports: &'static [BuiltinPort], why: &'static str) -> Builtin {
    Builtin { id, shape, ports, refused: Some(why) }
}

use PortType::{Any, Bool, Int, String as Str};
use Shape::{AnyNumber, Control, Decorator, Leaf, Two, TwoOrThree};

/// Every built-in node type of BehaviorTree.CPP 4.10.
pub const BUILTINS: &[Builtin] = &[
    b("Sequence", Control, &[]),
    b("Fallback", Control, &[]),
    b("SequenceWithMemory", Control, &[]),
    b("ReactiveSequence", Control, &[]),
    b("ReactiveFallback", Control, &[]),
    b("Parallel", Control, &[("success_count", Int, Some("-1")), ("failure_count", Int, Some("1"))]),
    b("ParallelAll", Control, &[("max_failures", Int, Some("1"))]),
    b("IfThenElse", TwoOrThree, &[]),
    b("WhileDoElse", TwoOrThree, &[]),
    b("Inverter", Decorator, &[]),
    b("ForceSuccess", Decorator, &[]),
    b("ForceFailure", Decorator, &[]),
    b("Repeat", Decorator, &[("num_cycles", Int, None)]),
    b("RetryUntilSuccessful", Decorator, &[("num_attempts", Int, None)]),
    b("KeepRunningUntilFailure", Decorator, &[]),
    b("RunOnce", Decorator, &[("then_skip", Bool, Some("true"))]),
    b("Timeout", Decorator, &[("msec", Int, None)]),
    b("Delay", Decorator, &[("delay_msec", Int, None)]),
    b("AlwaysSuccess", Leaf, &[]),
    b("AlwaysFailure", Leaf, &[]),
    r("AsyncSequence", Control, &[], NO_KIND),
    r("AsyncFallback", Control, &[], NO_KIND),
    r("TryCatch", Control, &[("catch_on_halt", Bool, Some("false"))], NO_KIND),
    // In BT.CPP 4.10's sources, though neither built into its library nor registered by
    // its factory; its ex03 example's tree uses it. The choice comes from the behavior
    // set here (bt_core::BehaviorSet::select), not from a terminal. Any number of
    // children: BT.CPP's node asks for a status when it has none.
    b("ManualSelector", AnyNumber, &[("repeat_last_selection", Bool, Some("false"))]),
    b("Script", Leaf, &[("code", Str, None)]),
    b("ScriptCondition", Leaf, &[("code", Any, None)]),
    b("Precondition", Decorator, &[("if", Str, None), ("else", Any, Some("FAILURE"))]),
    r("SetBlackboard", Leaf, &[("value", Any, None), ("output_key", Any, None)], BLACKBOARD),
    r("UnsetBlackboard", Leaf, &[("key", Str, None)], BLACKBOARD),
    b("Sleep", Leaf, &[("msec", Int, None)]),
    r("Switch2", Control, &[], SWITCH),
    r("Switch3", Control, &[], SWITCH),
    r("Switch4", Control, &[], SWITCH),
    r("Switch5", Control, &[], SWITCH),
    r("Switch6", Control, &[], SWITCH),
    b("LoopInt", Decorator, &LOOP_PORTS),
    b("LoopBool", Decorator, &LOOP_PORTS),
    b("LoopDouble", Decorator, &LOOP_PORTS),
    b("LoopString", Decorator, &LOOP_PORTS),
    r("WasEntryUpdated", Leaf, &[("entry", Any, None)], UPDATED),
    r("SkipUnlessUpdated", Decorator, &[("entry", Any, None)], UPDATED),
    r("WaitValueUpdate", Decorator, &[("entry", Any, None)], UPDATED),
];

/// Nav2's control and decorator nodes that bt-core has kinds for, with their ports
/// (they are plugins: Nav2's `nav2_tree_nodes.xml` declares them, but they are read
/// whether or not a model is given).
pub const NAV2: &[Builtin] = &[
    b("PipelineSequence", Control, &[]),
    b("RecoveryNode", Two, &[("number_of_retries", Int, Some("1"))]),
    b("RoundRobin", Control, &[("wrap_around", Bool, None)]),
    b("RateController", Decorator, &[("hz", PortType::Double, Some("10.0"))]),
];

/// The Nav2 node with this ID.
#[must_use]
pub fn nav2(id: &str) -> Option<&'static Builtin> {
    NAV2.iter().find(|b| b.id == id)
}

/// The built-in with this ID, reading the v3 names (`SequenceStar`,
/// `RetryUntilSuccesful`) as their v4 successors.
#[must_use]
pub fn builtin(id: &str) -> Option<&'static Builtin> {
    let id = match id {
        "SequenceStar" => "SequenceWithMemory",
        "RetryUntilSuccesful" => "RetryUntilSuccessful",
        other => other,
    };
    BUILTINS.iter().find(|b| b.id == id)
}

/// The attributes BehaviorTree.CPP reserves for scripted pre- and post-conditions, in
/// the order of [`bt_core::script::Hook`] (a guard's table).
pub const SCRIPT_ATTRIBUTES: [&str; 8] =
    ["_failureIf", "_successIf", "_skipIf", "_while", "_onHalted", "_onFailure", "_onSuccess", "_post"];

/// Whether an attribute name is one BehaviorTree.CPP takes as a port: it starts with a
/// letter and is not `name` or `ID` (attributes starting with `_` are metadata such as
/// `_uid`, `_fullpath`, `_description`, ignored as BehaviorTree.CPP ignores them, or
/// the scripted conditions above).
#[must_use]
pub fn is_port_name(name: &str) -> bool {
    name.starts_with(|c: char| c.is_alphabetic()) && name != "name" && name != "ID"
}
