//! Running a checked program against a blackboard: the value stack, the operators,
//! comparisons and conversions as BehaviorTree.CPP's scripting language defines them.

use super::op::{
    ADD, CMP, CMP_CHAIN, COMPL, CONCAT, DOUBLE, INT, JUMP, JUMP_UNLESS, LOAD, NEG, NOT, POP, SET, STORE, STR,
};
use super::{Blackboard, STACK, ScriptFault, Value, op, operands};
use crate::port::{Constant, PortTable, PortType};

struct Stack {
    values: [Value; STACK],
    len: usize,
}

impl Stack {
    fn push(&mut self, v: Value) -> Result<(), ScriptFault> {
        let slot = self.values.get_mut(self.len).ok_or(ScriptFault::StackOverflow)?;
        *slot = v;
        self.len += 1;
        Ok(())
    }

    fn pop(&mut self, at: usize) -> Result<Value, ScriptFault> {
        self.len = self.len.checked_sub(1).ok_or(ScriptFault::Malformed { at: at as u16 })?;
        self.values.get(self.len).copied().ok_or(ScriptFault::Malformed { at: at as u16 })
    }
}

fn word4(w: &[u16]) -> u64 {
    w.iter().rev().fold(0u64, |acc, &x| acc << 16 | u64::from(x))
}

/// Runs a program: reads and writes `bb`, reads string constants from `ports`; returns
/// the value of the last statement. Never panics; a program [`check`](super::check) did not accept
/// stops with [`ScriptFault::Malformed`].
///
/// # Errors
/// The [`ScriptFault`] that stopped it; slots assigned before it keep their values.
pub fn run<B: Blackboard + ?Sized>(code: &[u16], ports: &PortTable<'_>, bb: &mut B) -> Result<Value, ScriptFault> {
    let mut st = Stack { values: [Value::Int(0); STACK], len: 0 };
    let mut pc = 0usize;
    while let Some(&op) = code.get(pc) {
        let bad = ScriptFault::Malformed { at: pc as u16 };
        let n = operands(op).ok_or(bad)?;
        let args = code.get(pc + 1..pc + 1 + n).ok_or(bad)?;
        let mut next = pc + 1 + n;
        let arg = |i: usize| args.get(i).copied().ok_or(bad);
        match op {
            INT => st.push(Value::Int(word4(args) as i64))?,
            DOUBLE => st.push(Value::Double(f64::from_bits(word4(args))))?,
            STR => st.push(Value::Str(arg(0)?))?,
            LOAD => {
                let slot = arg(0)?;
                st.push(bb.get(slot).ok_or(ScriptFault::Unset { slot })?)?;
            }
            NEG | NOT | COMPL => {
                let v = st.pop(pc)?.number().ok_or(ScriptFault::NotPermitted)?;
                st.push(Value::Double(match op {
                    NEG => -v,
                    NOT => f64::from(u8::from(v == 0.0)),
                    _ => !to_i64(v).ok_or(ScriptFault::NotPermitted)? as f64,
                }))?;
            }
            ADD..=CONCAT => {
                let r = st.pop(pc)?;
                let l = st.pop(pc)?;
                st.push(binary(op, l, r)?)?;
            }
            CMP | CMP_CHAIN => {
                let r = st.pop(pc)?;
                let l = st.pop(pc)?;
                let holds = compare(arg(0)?, l, r, ports)?;
                if op == CMP {
                    st.push(Value::Double(f64::from(u8::from(holds))))?;
                } else if holds {
                    st.push(r)?;
                } else {
                    st.push(Value::Double(0.0))?;
                    next = usize::from(arg(1)?);
                }
            }
            JUMP_UNLESS => {
                let v = st.pop(pc)?;
                // A string holds when it reads as a number other than 0.
                let x = match v {
                    Value::Str(k) => str_of(ports, k).and_then(leading_double),
                    other => other.number(),
                };
                let holds = x.ok_or(ScriptFault::NotPermitted)? != 0.0;
                if !holds {
                    next = usize::from(arg(0)?);
                }
            }
            JUMP => next = usize::from(arg(0)?),
            POP => {
                st.pop(pc)?;
            }
            STORE => {
                let v = st.pop(pc)?;
                let stored = store(bb, ports, arg(0)?, arg(1)?, arg(2)?, v)?;
                st.push(stored)?;
            }
            _ => return Err(bad),
        }
        if next <= pc {
            return Err(bad);
        }
        pc = next;
    }
    if st.len == 1 { st.pop(pc) } else { Err(ScriptFault::Malformed { at: pc as u16 }) }
}

/// A value as a boolean, as BehaviorTree.CPP casts it (for `ScriptCondition`, `&&` and
/// `||`): the integers 0 and 1, doubles from 0 up (those other than 0 hold).
///
/// # Errors
/// [`ScriptFault::NotPermitted`] for other integers, negative numbers and strings.
pub fn truth(v: Value) -> Result<bool, ScriptFault> {
    match v {
        Value::Bool(b) => Ok(b),
        Value::Int(0) => Ok(false),
        Value::Int(1) => Ok(true),
        Value::Double(d) if d >= 0.0 => Ok(d != 0.0),
        _ => Err(ScriptFault::NotPermitted),
    }
}

fn str_of<'a>(ports: &PortTable<'a>, k: u16) -> Option<&'a str> {
    match ports.constant(k) {
        Some(Constant::Str(s)) => Some(s),
        _ => None,
    }
}

/// A double that is an integer within `i64`'s range, as that integer.
fn to_i64(v: f64) -> Option<i64> {
    // 2^63 is exactly representable; every double below it in magnitude that is whole fits.
    if v.is_finite() && v == (v as i64) as f64 && v < 9_223_372_036_854_775_808.0 { Some(v as i64) } else { None }
}

/// BehaviorTree.CPP's integer view of a number (`cast<int64_t>`).
fn int_of(v: Value) -> Option<i64> {
    match v {
        Value::Int(i) => Some(i),
        Value::Bool(b) => Some(i64::from(b)),
        Value::Double(d) => to_i64(d),
        Value::Str(_) => None,
    }
}

fn binary(op: u16, l: Value, r: Value) -> Result<Value, ScriptFault> {
    let (Some(a), Some(b)) = (l.number(), r.number()) else {
        return Err(match (l, r, op) {
            (Value::Str(_), Value::Str(_), ADD) => ScriptFault::StringBuilding,
            (Value::Str(_), _, CONCAT) | (_, Value::Str(_), CONCAT) => ScriptFault::StringBuilding,
            _ => ScriptFault::NotPermitted,
        });
    };
    Ok(Value::Double(match op {
        ADD => a + b,
        op::SUB => a - b,
        op::MUL => a * b,
        op::DIV => a / b,
        op::BIT_AND | op::BIT_OR | op::BIT_XOR => {
            let (Some(x), Some(y)) = (int_of(l), int_of(r)) else {
                return Err(ScriptFault::NotInteger);
            };
            (match op {
                op::BIT_AND => x & y,
                op::BIT_OR => x | y,
                _ => x ^ y,
            }) as f64
        }
        op::AND | op::OR => {
            let (x, y) = (truth(l)?, truth(r)?);
            f64::from(u8::from(if op == op::AND { x && y } else { x || y }))
        }
        // `..` on two numbers: BehaviorTree.CPP refuses it too.
        _ => return Err(ScriptFault::NotPermitted),
    }))
}

/// A number, or a string read as one (`true`, `false`, or a leading number).
fn number_or_str(v: Value, ports: &PortTable<'_>) -> Option<f64> {
    match v {
        Value::Str(k) => {
            let s = str_of(ports, k)?;
            match s {
                "true" => Some(1.0),
                "false" => Some(0.0),
                _ => leading_double(s),
            }
        }
        other => other.number(),
    }
}

/// The double at the start of `s`, as C++'s `std::from_chars` reads it: an optional
/// `-`, digits with an optional fraction and exponent, or `inf`/`infinity`/`nan`.
pub fn leading_double(s: &str) -> Option<f64> {
    let b = s.as_bytes();
    let mut i = usize::from(b.first() == Some(&b'-'));
    let rest = s.get(i..)?;
    for word in ["infinity", "inf", "nan"] {
        if rest.get(..word.len()).is_some_and(|w| w.eq_ignore_ascii_case(word)) {
            let v = if word == "nan" { f64::NAN } else { f64::INFINITY };
            return Some(if i == 1 { -v } else { v });
        }
    }
    let digits = |mut j: usize| {
        while b.get(j).is_some_and(u8::is_ascii_digit) {
            j += 1;
        }
        j
    };
    let int_end = digits(i);
    let mut end = int_end;
    if b.get(end) == Some(&b'.') {
        let frac_end = digits(end + 1);
        if frac_end > end + 1 || int_end > i {
            end = frac_end;
        }
    }
    if end == i || (end == i + 1 && b.get(i) == Some(&b'.')) {
        return None;
    }
    if matches!(b.get(end), Some(b'e' | b'E')) {
        let mut j = end + 1;
        if matches!(b.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        let exp_end = digits(j);
        if exp_end > j {
            end = exp_end;
        }
    }
    i = end;
    s.get(..i)?.parse().ok()
}

fn compare(c: u16, l: Value, r: Value, ports: &PortTable<'_>) -> Result<bool, ScriptFault> {
    use core::cmp::Ordering;
    let order = match (l, r) {
        (Value::Str(a), Value::Str(b)) => {
            let (a, b) = (str_of(ports, a).unwrap_or(""), str_of(ports, b).unwrap_or(""));
            a.as_bytes().cmp(b.as_bytes())
        }
        _ => {
            let a = number_or_str(l, ports).ok_or(ScriptFault::NotPermitted)?;
            let b = number_or_str(r, ports).ok_or(ScriptFault::NotPermitted)?;
            // Equality within float's epsilon, as BehaviorTree.CPP.
            let same = (a - b).abs() <= f64::from(f32::EPSILON);
            return Ok(match c {
                0 => same,
                1 => !same,
                2 => a < b,
                3 => a > b,
                4 => a <= b,
                _ => a >= b,
            });
        }
    };
    Ok(match c {
        0 => order == Ordering::Equal,
        1 => order != Ordering::Equal,
        2 => order == Ordering::Less,
        3 => order == Ordering::Greater,
        4 => order != Ordering::Greater,
        _ => order != Ordering::Less,
    })
}

/// A string converted for a typed slot, as BehaviorTree.CPP's converters read it.
fn convert_str(s: &str, k: u16, ty: PortType) -> Option<Value> {
    Some(match ty {
        PortType::Int => Value::Int(s.parse().ok()?),
        PortType::Double => Value::Double(leading_double(s)?),
        PortType::Bool => Value::Bool(match s {
            "true" | "True" | "TRUE" | "1" => true,
            "false" | "False" | "FALSE" | "0" => false,
            _ => return None,
        }),
        PortType::String | PortType::Other => Value::Str(k),
        PortType::Any => return None,
    })
}

/// A number converted into the kind of value a slot already holds (`Any::copyInto`).
fn into_kind(held: Value, v: Value, slot: u16) -> Result<Value, ScriptFault> {
    let fault = ScriptFault::Conversion { slot };
    Ok(match held {
        Value::Int(_) => Value::Int(int_of(v).ok_or(fault)?),
        Value::Bool(_) => Value::Bool(int_of(v).ok_or(fault)? != 0),
        Value::Double(_) => Value::Double(v.number().ok_or(fault)?),
        Value::Str(_) => return Err(fault),
    })
}

fn store<B: Blackboard + ?Sized>(
    bb: &mut B,
    ports: &PortTable<'_>,
    mode: u16,
    slot: u16,
    flags: u16,
    v: Value,
) -> Result<Value, ScriptFault> {
    let ty = ports.slot(slot).map_or(PortType::Any, |info| info.ty);
    if mode == SET {
        let new = match v {
            Value::Str(k) if ty != PortType::Any => {
                convert_str(str_of(ports, k).ok_or(ScriptFault::Conversion { slot })?, k, ty)
                    .ok_or(ScriptFault::Conversion { slot })?
            }
            _ => v,
        };
        bb.set(slot, new);
        return Ok(new);
    }
    let declared = flags & op::DECLARED != 0;
    let held = bb.get(slot);
    if mode != 0 && held.is_none() && !declared {
        return Err(ScriptFault::NoEntry { slot });
    }
    let fault = ScriptFault::Conversion { slot };
    let new = if mode <= 1 {
        match (held, v) {
            (None, _) if ty == PortType::Any => v,
            (None | Some(Value::Int(_) | Value::Double(_) | Value::Bool(_)), Value::Str(k)) => {
                let s = str_of(ports, k).ok_or(fault)?;
                match convert_str(s, k, ty) {
                    Some(c) => c,
                    // A number slot without a converter takes the string's number.
                    None if held.is_some() => Value::Double(number_or_str(v, ports).ok_or(fault)?),
                    None => return Err(fault),
                }
            }
            (None, _) => v,
            (Some(Value::Str(_)), Value::Str(_)) => v,
            (Some(h), _) => into_kind(h, v, slot)?,
        }
    } else {
        let h = held.ok_or(ScriptFault::Unset { slot })?;
        match v {
            Value::Str(_) => {
                return Err(if mode == 2 { ScriptFault::StringBuilding } else { ScriptFault::NotPermitted });
            }
            _ => {
                let (a, b) = (h.number().ok_or(ScriptFault::NotPermitted)?, v.number().ok_or(fault)?);
                let r = match mode {
                    2 => a + b,
                    3 => a - b,
                    4 => a * b,
                    _ => a / b,
                };
                into_kind(h, Value::Double(r), slot)?
            }
        }
    };
    bb.set(slot, new);
    Ok(new)
}
