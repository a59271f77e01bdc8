//! The built-ins that read, write or compare blackboard entries, compiled into programs
//! of the script machine (`bt_core::script`): `SetBlackboard` (both versions) becomes a
//! `Script` that assigns its `value` to the key its `output_key` names; version 3's
//! `BlackboardCheck*` a `Check` of the comparison of its two values; a count read from
//! a `{key}` (`Repeat`, `RetryUntilSuccessful`) the slot a `Cycles` reads.

use bt_core::script::{leading_double, op};
use bt_core::{Code, PortDirection, PortType, PortValue};

use super::Lowerer;
use super::scripts::{SCRIPT_PORT, script_name};
use crate::error::{Fault, ImportError, Result};
use crate::kinds::{Compared, refuse};
use crate::xml::document::Version;
use crate::xml::flatten::{Inst, Key, Value};
use crate::xml::model::Literal;
use crate::xml::script::{Push, element_program};

/// What a `SetBlackboard`'s `output_key` names: the key its text names.
pub(super) fn set_blackboard_key(l: &Lowerer<'_>, n: &Inst) -> Option<Key> {
    let b = n.ports.iter().find(|b| b.port == "output_key")?;
    match &b.value {
        Value::Literal(text) => Some(l.flat.resolve(n.scope, text)),
        Value::Key(_) => None,
    }
}

impl Lowerer<'_> {
    /// `SetBlackboard`: `output_key` names the key written (as text: a `{key}` there
    /// would name the entry whose name another entry holds at run time, which slots
    /// fixed at import cannot follow), `value` is a string, or a `{key}` whose value is
    /// copied. The program assigns it as a script's `:=` does in version 4; in version 3
    /// as 3.8's blackboard `set` does ([`op::SET`]): a string given to a typed key is
    /// converted by the key's type, anything else stored as it is.
    pub(super) fn set_blackboard(&mut self, n: &Inst) -> Result<Code> {
        let missing = |attribute| ImportError::new(&n.at, Fault::MissingAttribute { element: n.id.clone(), attribute });
        let out = n.ports.iter().find(|b| b.port == "output_key").ok_or_else(|| missing("output_key"))?;
        let value = n.ports.iter().find(|b| b.port == "value").ok_or_else(|| missing("value"))?;
        let Some(key) = set_blackboard_key(self, n) else {
            return Err(refuse(
                &out.at,
                format!("<SetBlackboard output_key=\"{}\">", out.raw),
                "a {key} here names the entry whose name that key holds when the node runs; bt-core's keys are fixed when the tree is imported: write the key's name itself (output_key=\"goal\")",
            ));
        };
        let mut words = match &value.value {
            Value::Key(k) => vec![op::LOAD, self.script_slot(k, n, &value.at)?],
            Value::Literal(text) => vec![op::STR, self.intern(Literal::Str(text.clone()), &value.at)?],
        };
        // Version 3's blackboard `set`; version 4's as a script's `:=`.
        let mode = if self.flat.version == Version::V3 { op::SET } else { 0 };
        let slot = self.script_slot(&key, n, &out.at)?;
        words.extend_from_slice(&[op::STORE, mode, slot, op::DECLARED]);
        let name = |l: &Self, s: u16| script_name(&l.out.slots[usize::from(s)].name).into_owned();
        let shown = match &value.value {
            Value::Key(k) => {
                let s = self.slot_ids.get(k).copied().unwrap_or(slot);
                format!("{{{}}}", name(self, s))
            }
            Value::Literal(text) => text.clone(),
        };
        if let Some(meta) = self.out.meta.last_mut() {
            let out_name = script_name(&self.out.slots[usize::from(slot)].name).into_owned();
            meta.flat = Some(vec![("value".to_string(), shown), ("output_key".to_string(), out_name)]);
        }
        self.place(n, &words)
    }

    /// The slot a count parameter's `{key}` names, when the key does not start at a
    /// literal (which the parameter then reads): typed `int`, read on every tick. The
    /// flattened tree's XML names it as scripts do.
    pub(super) fn count_slot(&mut self, n: &Inst, port: &'static str) -> Result<Option<u16>> {
        let Some(b) = n.ports.iter().find(|b| b.port == port) else { return Ok(None) };
        let Value::Key(k) = &b.value else { return Ok(None) };
        if self.initial_literal(k).is_some() {
            return Ok(None);
        }
        let v = self.slot_value(k, (PortType::Int, PortDirection::Input), Some("int"), &b.at, n, port)?;
        let PortValue::Slot(slot) = PortValue::from_u16(v) else {
            return Err(ImportError::new(&b.at, Fault::TooLarge("no slot for a blackboard key".into())));
        };
        let key = format!("{{{}}}", script_name(&self.out.slots[usize::from(slot)].name));
        if let Some(meta) = self.out.meta.last_mut() {
            let params = meta.params.iter().map(|(p, v)| (p.clone(), if p == port { key.clone() } else { v.clone() }));
            meta.flat = Some(params.collect());
        }
        Ok(Some(slot))
    }

    /// A `BlackboardCheck*`'s program: `value_A` and `value_B` read as 3.8's
    /// `getInput<T>` reads them (a literal converted as `std::stoi`, `std::stod` or its
    /// boolean rule convert it; a `{key}` loaded), compared with `==` (doubles within
    /// `f32`'s epsilon, as 3.8's `IsSame`). A value 3.8 cannot read (a literal that
    /// does not convert, a port left out) never matches: the program is `false`.
    pub(super) fn comparison(&mut self, n: &Inst, ty: Compared) -> Result<Code> {
        let a = self.operand(n, "value_A", ty)?;
        let b = self.operand(n, "value_B", ty)?;
        let eps = f64::from(f32::EPSILON);
        let words = match (a, b) {
            // |a - b| <= eps. Against a number written in the document, as two
            // comparisons with its bounds (which read a string key as a number, as
            // 3.8's `getInput<double>` does); between two keys, with arithmetic.
            (Some(Operand::Number(x)), Some(Operand::Load(k))) | (Some(Operand::Load(k)), Some(Operand::Number(x)))
                if ty == Compared::Double =>
            {
                let bound = |v: f64| element_program(Push::Double(v), None);
                [&k[..], &bound(x - eps), &[op::CMP, GE], &k, &bound(x + eps), &[op::CMP, LE, op::AND]].concat()
            }
            (Some(a), Some(b)) if ty == Compared::Double => {
                let (a, b, eps) = (a.words(), b.words(), element_program(Push::Double(eps), None));
                let mut w = [a.as_slice(), &b, &[op::SUB], &eps, &[op::CMP, LE]].concat();
                w.extend([b.as_slice(), &a, &[op::SUB], &eps, &[op::CMP, LE, op::AND]].concat());
                w
            }
            (Some(a), Some(b)) => [a.words().as_slice(), &b.words(), &[op::CMP, EQ]].concat(),
            _ => element_program(Push::Int(0), None),
        };
        self.place(n, &words)
    }

    /// A `BlackboardCheck*` value, `None` when 3.8 cannot read it.
    fn operand(&mut self, n: &Inst, port: &'static str, ty: Compared) -> Result<Option<Operand>> {
        let Some(b) = n.ports.iter().find(|b| b.port == port) else { return Ok(None) };
        let text = match &b.value {
            Value::Literal(text) => text.clone(),
            Value::Key(k) => match self.initial_literal(k) {
                Some(text) => text,
                None => {
                    let slot = self.script_slot(k, n, &b.at)?;
                    return Ok(Some(Operand::Load(vec![op::LOAD, slot])));
                }
            },
        };
        let push = |p: Push| Operand::Push(element_program(p, None));
        Ok(match ty {
            Compared::Int => stoi(&text).map(|v| push(Push::Int(v))),
            Compared::Double => leading_double(text.trim_start()).map(Operand::Number),
            Compared::Bool => match text.as_str() {
                "1" | "true" | "TRUE" | "True" => Some(push(Push::Int(1))),
                "0" | "false" | "FALSE" | "False" => Some(push(Push::Int(0))),
                _ => None,
            },
            Compared::String => Some(push(Push::Str(self.intern(Literal::Str(text), &b.at)?))),
        })
    }

    /// The slot of `key` as a script names it (typed by the first port that names it).
    fn script_slot(&mut self, key: &Key, n: &Inst, at: &crate::error::Location) -> Result<u16> {
        let v = self.slot_value(key, (PortType::Any, PortDirection::InOut), None, at, n, SCRIPT_PORT)?;
        match PortValue::from_u16(v) {
            PortValue::Slot(s) => Ok(s),
            _ => Err(ImportError::new(at, Fault::TooLarge("no slot for a blackboard key".into()))),
        }
    }
}

/// The comparisons of the `cmp` instruction.
const EQ: u16 = 0;
const LE: u16 = 4;
const GE: u16 = 5;

/// A value a `BlackboardCheck*` compares: a key, a double written in the document, or
/// another literal.
enum Operand {
    Load(Vec<u16>),
    Number(f64),
    Push(Vec<u16>),
}

impl Operand {
    /// The words that push it.
    fn words(self) -> Vec<u16> {
        match self {
            Self::Load(w) | Self::Push(w) => w,
            Self::Number(v) => element_program(Push::Double(v), None),
        }
    }
}

/// An integer as BehaviorTree.CPP 3.8's `convertFromString<int>` reads it (`std::stoi`):
/// the leading integer after white space; `None` without one or out of `int`'s range.
#[must_use]
pub fn stoi(s: &str) -> Option<i64> {
    let t = s.trim_start();
    let (negative, digits) = match t.as_bytes().first() {
        Some(b'-') => (true, &t[1..]),
        Some(b'+') => (false, &t[1..]),
        _ => (false, t),
    };
    let end = digits.bytes().take_while(u8::is_ascii_digit).count();
    let v: i64 = digits.get(..end).filter(|d| !d.is_empty())?.parse().ok()?;
    i32::try_from(if negative { -v } else { v }).ok().map(i64::from)
}
