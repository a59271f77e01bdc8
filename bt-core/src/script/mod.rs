//! BehaviorTree.CPP's script language, compiled on the host and run here with no heap:
//! the `Script` and `ScriptCondition` nodes ([`NodeKind::Script`](crate::NodeKind::Script),
//! [`NodeKind::ScriptCondition`](crate::NodeKind::ScriptCondition)).
//!
//! The host (`btcpp::xml`) parses a script and writes it as a small stack program of
//! `u16` words into the tree's value table; a script node names its range. The behavior
//! set, which owns the blackboard and the image's [`PortTable`], runs it when the
//! executor asks ([`BehaviorSet::script`](crate::BehaviorSet::script)), usually with one
//! call to [`run`].
//!
//! # Values
//!
//! A [`Value`] is what a blackboard slot holds: an integer, a double, a boolean or a
//! string constant of the ports section. As in BehaviorTree.CPP, arithmetic is done in
//! doubles, booleans are numbers, a slot keeps the kind of value it first received
//! (numbers converted into it, refused where they would be truncated), a string given to
//! a typed slot is converted by the slot's type, and a comparison of a string with a
//! number reads the string as a number. Strings are never built at run time: `..` and
//! `+` on strings stop the script with [`ScriptFault::StringBuilding`], since they need
//! a heap.
//!
//! # Program layout
//!
//! A program is a sequence of instructions, each an opcode word followed by its operand
//! words. Jumps go forward only, so every program ends; the stack holds at most
//! [`STACK`] values.
//!
//! | opcode | instruction | operands | effect |
//! |---:|---|---|---|
//! | 1 | `int` | 4 words, an `i64` little-endian | push the integer |
//! | 2 | `double` | 4 words, an `f64`'s bits little-endian | push the double |
//! | 3 | `str` | constant id | push the string constant |
//! | 4 | `load` | slot | push the slot's value (unset: [`ScriptFault::Unset`]) |
//! | 5, 6, 7 | `neg`, `not`, `compl` | — | unary `-`, `!`, `~` |
//! | 8 ..= 17 | `+ - * / & \| ^ && \|\| ..` | — | pop right, left; push the result |
//! | 18 | `cmp` | comparison (0 `==`, 1 `!=`, 2 `<`, 3 `>`, 4 `<=`, 5 `>=`) | pop right, left; push 1.0 or 0.0 |
//! | 19 | `cmp-chain` | comparison, target | pop right, left; if false push 0.0 and jump, else push right |
//! | 20 | `jump-unless` | target | pop; jump if it is false |
//! | 21 | `jump` | target | jump |
//! | 22 | `pop` | — | drop the top value |
//! | 23 | `store` | assignment (0 `:=`, 1 `=`, 2 `+=`, 3 `-=`, 4 `*=`, 5 `/=`, 6 set), slot, flags | pop, assign, push the slot's new value |
//!
//! A `store`'s flags are 1 when a port of the tree declares the slot (such a slot exists
//! before any script assigns it, so `=` may assign it), else 0; the slot's type comes
//! from the ports section. Assignment 6, *set*, is BehaviorTree.CPP 3's blackboard
//! `set` (its `SetBlackboard`; programs of image format version 4): a string given to a
//! slot whose ports declare a type is converted by it, any other value is put in the
//! slot as it is, whatever the slot held. A program leaves one value, the last
//! statement's.

use crate::port::{Constant, PortTable};

mod run;

pub use run::{leading_double, run, truth};

/// Most values a script's stack holds.
pub const STACK: usize = 16;

/// A blackboard value a script reads or writes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// An integer.
    Int(i64),
    /// A double.
    Double(f64),
    /// A boolean (a number to scripts, as in BehaviorTree.CPP).
    Bool(bool),
    /// A string constant of the image's ports section.
    Str(u16),
}

impl Value {
    /// The value as a double, for numbers.
    #[must_use]
    pub fn number(self) -> Option<f64> {
        match self {
            Self::Int(i) => Some(i as f64),
            Self::Double(d) => Some(d),
            Self::Bool(b) => Some(if b { 1.0 } else { 0.0 }),
            Self::Str(_) => None,
        }
    }
}

/// The slots a script reads and writes: the behavior set's blackboard.
pub trait Blackboard {
    /// The value of `slot`, `None` while unset.
    fn get(&self, slot: u16) -> Option<Value>;
    /// Sets `slot`.
    fn set(&mut self, slot: u16, value: Value);
}

impl Blackboard for [Option<Value>] {
    fn get(&self, slot: u16) -> Option<Value> {
        <[Option<Value>]>::get(self, usize::from(slot)).copied().flatten()
    }

    fn set(&mut self, slot: u16, value: Value) {
        if let Some(s) = self.get_mut(usize::from(slot)) {
            *s = Some(value);
        }
    }
}

impl<const N: usize> Blackboard for [Option<Value>; N] {
    fn get(&self, slot: u16) -> Option<Value> {
        Blackboard::get(self.as_slice(), slot)
    }

    fn set(&mut self, slot: u16, value: Value) {
        Blackboard::set(self.as_mut_slice(), slot, value);
    }
}

/// Why a script stopped. As in BehaviorTree.CPP, where these throw, the tick ends with
/// the error.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ScriptFault {
    /// The program is malformed at this word (refused when the image loads).
    #[error("the script is malformed at word {at}")]
    Malformed {
        /// The word.
        at: u16,
    },
    /// The behavior set does not run scripts.
    #[error("this behavior set does not run scripts")]
    Unsupported,
    /// The behavior set keeps no blackboard queues ([`BehaviorSet::pop`](crate::BehaviorSet::pop)
    /// is not implemented) and a `Loop` over a `{key}` asked it for an element.
    #[error("this behavior set keeps no blackboard queues (BehaviorSet::pop), which a loop over a {{key}} needs")]
    NoQueues,
    /// The behavior set gives no selections ([`BehaviorSet::select`](crate::BehaviorSet::select)
    /// is not implemented) and a `ManualSelector` asked it what to do.
    #[error(
        "this behavior set gives no selections (BehaviorSet::select), which a ManualSelector needs: \
         the operator's choice of a child or a status"
    )]
    NoSelections,
    /// A slot read before anything was assigned to it.
    #[error("blackboard slot {slot} is read before it is set")]
    Unset {
        /// The slot.
        slot: u16,
    },
    /// `=` (or `+=`, ...) on an entry that does not exist yet; `:=` creates it.
    #[error("blackboard slot {slot} does not exist yet; `:=` creates it")]
    NoEntry {
        /// The slot.
        slot: u16,
    },
    /// An operator applied to values it does not take (a string where a number is
    /// needed, a boolean cast of a negative integer, ...).
    #[error("operator not permitted on these operands")]
    NotPermitted,
    /// A bitwise operator on a number that is not an integer.
    #[error("bitwise operators need integers")]
    NotInteger,
    /// A value that does not fit the slot it is assigned to (a truncated double in an
    /// integer slot, a string that does not read as the slot's type, a number in a
    /// string slot).
    #[error("the value does not convert to blackboard slot {slot}'s type")]
    Conversion {
        /// The slot.
        slot: u16,
    },
    /// `..` or `+` on strings: building strings needs a heap.
    #[error("building strings (`..`, `+` on strings) is not supported without a heap")]
    StringBuilding,
    /// More than [`STACK`] values at once.
    #[error("the script needs more than {STACK} stack values")]
    StackOverflow,
}

/// The instructions (the layout table above), for the host's compiler.
#[allow(missing_docs)]
pub mod op {
    pub const INT: u16 = 1;
    pub const DOUBLE: u16 = 2;
    pub const STR: u16 = 3;
    pub const LOAD: u16 = 4;
    pub const NEG: u16 = 5;
    pub const NOT: u16 = 6;
    pub const COMPL: u16 = 7;
    pub const ADD: u16 = 8;
    pub const SUB: u16 = 9;
    pub const MUL: u16 = 10;
    pub const DIV: u16 = 11;
    pub const BIT_AND: u16 = 12;
    pub const BIT_OR: u16 = 13;
    pub const BIT_XOR: u16 = 14;
    pub const AND: u16 = 15;
    pub const OR: u16 = 16;
    pub const CONCAT: u16 = 17;
    pub const CMP: u16 = 18;
    pub const CMP_CHAIN: u16 = 19;
    pub const JUMP_UNLESS: u16 = 20;
    pub const JUMP: u16 = 21;
    pub const POP: u16 = 22;
    pub const STORE: u16 = 23;
    /// `store`'s flag: a port declares the slot.
    pub const DECLARED: u16 = 1;
    /// `store`'s set: BehaviorTree.CPP 3's blackboard `set`.
    pub const SET: u16 = 6;
}

use op::{ADD, CMP, CMP_CHAIN, COMPL, CONCAT, DOUBLE, INT, JUMP, JUMP_UNLESS, LOAD, NEG, NOT, POP, SET, STORE, STR};

/// Operand words of each opcode (`None`: not an opcode).
const fn operands(op: u16) -> Option<usize> {
    Some(match op {
        INT | DOUBLE => 4,
        STR | LOAD | CMP | JUMP_UNLESS | JUMP => 1,
        CMP_CHAIN => 2,
        STORE => 3,
        NEG..=CONCAT | POP => 0,
        _ => return None,
    })
}

/// Jumps a program may have pending at once (forward jumps not yet reached; jumps to one
/// place count once).
pub const MAX_PENDING_JUMPS: usize = 16;

/// How many values an instruction takes from the stack and puts back.
const fn effect(op: u16) -> (usize, usize) {
    match op {
        INT | DOUBLE | STR | LOAD => (0, 1),
        NEG | NOT | COMPL | STORE => (1, 1),
        ADD..=CONCAT | CMP | CMP_CHAIN => (2, 1),
        JUMP_UNLESS | POP => (1, 0),
        _ => (0, 0),
    }
}

/// Checks that a program uses its stack soundly on every path: it never takes from an
/// empty stack, never holds more than [`STACK`] values, reaches every instruction with
/// one height whichever way it comes, has no unreachable code, and ends with exactly
/// one value. Opcodes and operands must be well formed ([`check`] does both).
///
/// # Errors
/// [`ScriptFault::Malformed`] at the first word where that fails, or
/// [`ScriptFault::StackOverflow`].
pub fn check_stack(code: &[u16]) -> Result<(), ScriptFault> {
    let mut pending = [(0u16, 0u8); MAX_PENDING_JUMPS];
    let mut n = 0usize;
    let mut height = Some(0usize);
    let mut pc = 0usize;
    loop {
        let bad = ScriptFault::Malformed { at: pc as u16 };
        // Paths that jump here.
        let mut k = 0;
        while k < n {
            let (target, h) = pending.get(k).copied().ok_or(bad)?;
            if usize::from(target) == pc {
                match height {
                    None => height = Some(usize::from(h)),
                    Some(cur) if cur != usize::from(h) => return Err(bad),
                    Some(_) => {}
                }
                n -= 1;
                let last = pending.get(n).copied().ok_or(bad)?;
                if let Some(slot) = pending.get_mut(k) {
                    *slot = last;
                }
            } else {
                k += 1;
            }
        }
        let Some(&op) = code.get(pc) else {
            return if pc == code.len() && n == 0 && height == Some(1) { Ok(()) } else { Err(bad) };
        };
        let cur = height.ok_or(bad)?;
        let args = code.get(pc + 1..pc + 1 + operands(op).ok_or(bad)?).ok_or(bad)?;
        let (pops, pushes) = effect(op);
        let after = cur.checked_sub(pops).ok_or(bad)? + pushes;
        if after > STACK {
            return Err(ScriptFault::StackOverflow);
        }
        let target = match op {
            JUMP | JUMP_UNLESS => args.first().copied(),
            CMP_CHAIN => args.get(1).copied(),
            _ => None,
        };
        if let Some(t) = target {
            if usize::from(t) <= pc {
                return Err(bad);
            }
            match pending.get(..n).and_then(|p| p.iter().find(|(pt, _)| *pt == t)) {
                Some(&(_, h)) if usize::from(h) != after => return Err(bad),
                Some(_) => {}
                None => {
                    let slot = pending.get_mut(n).ok_or(bad)?;
                    *slot = (t, after as u8);
                    n += 1;
                }
            }
        }
        height = if op == JUMP { None } else { Some(after) };
        pc += 1 + args.len();
    }
}

/// Checks a program against the image's ports table before it can run: every opcode
/// known with its operands, jumps forward within the program, string constants that
/// are strings, slots within the table, comparison and assignment codes valid, and the
/// stack used soundly ([`check_stack`]). A program that passes runs without a
/// [`ScriptFault::Malformed`].
///
/// # Errors
/// [`ScriptFault::Malformed`] at the first bad word, or [`ScriptFault::StackOverflow`].
pub fn check(code: &[u16], ports: &PortTable<'_>) -> Result<(), ScriptFault> {
    let mut pc = 0usize;
    if code.is_empty() {
        return Err(ScriptFault::Malformed { at: 0 });
    }
    while let Some(&op) = code.get(pc) {
        let bad = ScriptFault::Malformed { at: pc as u16 };
        let n = operands(op).ok_or(bad)?;
        let args = code.get(pc + 1..pc + 1 + n).ok_or(bad)?;
        let next = pc + 1 + n;
        let target_ok = |t: u16| usize::from(t) >= next && usize::from(t) <= code.len();
        let ok = match (op, args) {
            (STR, &[k]) => matches!(ports.constant(k), Some(Constant::Str(_))),
            (LOAD, &[s]) => s < ports.slot_count(),
            (CMP, &[c]) => c <= 5,
            (CMP_CHAIN, &[c, t]) => c <= 5 && target_ok(t),
            (JUMP_UNLESS | JUMP, &[t]) => target_ok(t),
            (STORE, &[mode, s, flags]) => mode <= SET && s < ports.slot_count() && flags <= 1,
            _ => true,
        };
        if !ok {
            return Err(bad);
        }
        pc = next;
    }
    check_stack(code)
}

/// The scripts a [`NodeKind::Guard`](crate::NodeKind::Guard) may carry, in the order of
/// their bits in its table (BehaviorTree.CPP's `_failureIf`, `_successIf`, `_skipIf`,
/// `_while`, `_onHalted`, `_onFailure`, `_onSuccess`, `_post`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Hook {
    /// `_failureIf`: fail without ticking when it holds (checked when starting).
    FailureIf = 0,
    /// `_successIf`: succeed without ticking when it holds (checked when starting).
    SuccessIf = 1,
    /// `_skipIf`: skip when it holds (checked when starting).
    SkipIf = 2,
    /// `_while`: skip when it does not hold when starting; halt and skip when it stops
    /// holding while Running.
    While = 3,
    /// `_onHalted`: run after the node is halted while Running.
    OnHalted = 4,
    /// `_onFailure`: run when the node fails.
    OnFailure = 5,
    /// `_onSuccess`: run when the node succeeds.
    OnSuccess = 6,
    /// `_post`: run when the node succeeds or fails, after the two above.
    Post = 7,
}

/// The program of hook `hook` in a guard's table, if the table has one.
///
/// A guard's table is a mask word (bit `h` set: hook `h` present), then for each hook
/// present, in bit order, its length in words and its program.
#[must_use]
pub fn hook(table: &[u16], hook: Hook) -> Option<&[u16]> {
    let (&mask, rest) = table.split_first()?;
    let h = hook as u16;
    if mask & (1 << h) == 0 {
        return None;
    }
    // The programs of the hooks present before it come first.
    nth_program(rest, (mask & ((1 << h) - 1)).count_ones() as usize)
}

/// The first of a run of programs each preceded by its length (a guard's hooks, a
/// literal queue's elements), and the words after it.
fn split_program(words: &[u16]) -> Option<(&[u16], &[u16])> {
    let (&len, tail) = words.split_first()?;
    tail.split_at_checked(usize::from(len))
}

/// Program `k` (0-based) of a run of length-prefixed programs.
fn nth_program(mut words: &[u16], k: usize) -> Option<&[u16]> {
    for _ in 0..k {
        words = split_program(words)?.1;
    }
    split_program(words).map(|(program, _)| program)
}

/// Checks that `rest`, the end of `table`, is exactly `count` length-prefixed programs,
/// each [`check`]ed.
fn check_programs(table: &[u16], mut rest: &[u16], count: usize, ports: &PortTable<'_>) -> Result<(), ScriptFault> {
    let bad = |rest: &[u16]| ScriptFault::Malformed { at: (table.len() - rest.len()) as u16 };
    for _ in 0..count {
        let (program, after) = split_program(rest).ok_or(bad(rest))?;
        check(program, ports)?;
        rest = after;
    }
    if rest.is_empty() { Ok(()) } else { Err(bad(rest)) }
}

/// Checks a guard's table: a mask of the eight hooks, each program present whole and
/// [`check`]ed, nothing after the last.
///
/// # Errors
/// The first fault, as [`check`] finds it ([`ScriptFault::Malformed`] at the table's
/// word for the framing).
pub fn check_guard(table: &[u16], ports: &PortTable<'_>) -> Result<(), ScriptFault> {
    let bad = ScriptFault::Malformed { at: 0 };
    let (&mask, rest) = table.split_first().ok_or(bad)?;
    if mask == 0 || mask > 0xFF {
        return Err(bad);
    }
    check_programs(table, rest, mask.count_ones() as usize, ports)
}

/// What a [`NodeKind::Loop`](crate::NodeKind::Loop)'s elements are: the `T` of
/// BehaviorTree.CPP's `LoopNode<T>`, which names the node (`LoopInt`, ...).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Element {
    /// A type the C++ program registers its own `LoopNode<T>` for; the table names the
    /// node.
    Registered = 0,
    /// `LoopInt`.
    Int = 1,
    /// `LoopBool`.
    Bool = 2,
    /// `LoopDouble`.
    Double = 3,
    /// `LoopString`.
    String = 4,
}

/// The queue of a [`NodeKind::Loop`](crate::NodeKind::Loop), as its table holds it.
///
/// The table starts with a header word (the [`Element`] type in the low byte, bit 8 set
/// for a blackboard queue) and the string constant naming the node for
/// [`Element::Registered`] (`0xFFFF` otherwise). A literal queue (`queue="1;2;3"`)
/// follows with its element count, then each element's length in words and its
/// program, an assignment of the element to the `value` slot, run through
/// [`BehaviorSet::script`](crate::BehaviorSet::script). A blackboard queue
/// (`queue="{key}"`) follows with the queue's slot and the `value` slot, for
/// [`BehaviorSet::pop`](crate::BehaviorSet::pop).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Queue<'t> {
    /// The literal queue's element programs, count first (the table past the name).
    Literal(&'t [u16]),
    /// A blackboard queue.
    Key {
        /// The slot holding the queue.
        queue: u16,
        /// The slot each element goes to.
        value: u16,
    },
}

/// Bit 8 of a loop table's header: a blackboard queue.
pub const QUEUE_KEY: u16 = 0x100;

/// A loop table's element type and the constant naming it (`None` for the built-in
/// types), or `None` when the header is not one.
#[must_use]
pub fn queue_element(table: &[u16]) -> Option<(Element, Option<u16>)> {
    let (&header, rest) = table.split_first()?;
    let element = match header & !QUEUE_KEY {
        0 => Element::Registered,
        1 => Element::Int,
        2 => Element::Bool,
        3 => Element::Double,
        4 => Element::String,
        _ => return None,
    };
    let name = rest.first().copied().filter(|&n| n != u16::MAX);
    Some((element, name))
}

/// A loop table's queue, or `None` when it is malformed ([`check_queue`] rules that out).
#[must_use]
pub fn queue(table: &[u16]) -> Option<Queue<'_>> {
    let (&header, rest) = table.split_first()?;
    let rest = rest.get(1..)?;
    if header & QUEUE_KEY != 0 {
        match *rest {
            [queue, value] => Some(Queue::Key { queue, value }),
            _ => None,
        }
    } else {
        Some(Queue::Literal(rest))
    }
}

/// The program of element `k` (0-based) of a literal queue, `None` past its end.
#[must_use]
pub fn element(literal: &[u16], k: u16) -> Option<&[u16]> {
    let (&count, rest) = literal.split_first()?;
    if k >= count {
        return None;
    }
    nth_program(rest, usize::from(k))
}

/// Checks a loop table: a known header, the name a string constant when given (and
/// given for [`Element::Registered`]), a blackboard queue's two slots within the ports
/// table, or a literal queue's programs each present whole and [`check`]ed, nothing
/// after the last.
///
/// # Errors
/// The first fault, [`ScriptFault::Malformed`] at the table's word for the framing.
pub fn check_queue(table: &[u16], ports: &PortTable<'_>) -> Result<(), ScriptFault> {
    let bad = |at: usize| ScriptFault::Malformed { at: at as u16 };
    let (element, name) = queue_element(table).ok_or(bad(0))?;
    match name {
        Some(k) if !matches!(ports.constant(k), Some(Constant::Str(_))) => return Err(bad(1)),
        None if element == Element::Registered => return Err(bad(1)),
        _ => {}
    }
    match queue(table).ok_or(bad(0))? {
        Queue::Key { queue, value } => {
            if queue >= ports.slot_count() {
                return Err(bad(2));
            }
            if value >= ports.slot_count() {
                return Err(bad(3));
            }
            Ok(())
        }
        Queue::Literal(literal) => {
            let (&count, rest) = literal.split_first().ok_or(bad(2))?;
            check_programs(table, rest, usize::from(count), ports)
        }
    }
}
