//! BehaviorTree.CPP's script language (`Script`, `ScriptCondition`): parsed here as
//! BehaviorTree.CPP 4.10 parses it (the same tokens, operator precedence and chained
//! comparisons) and compiled to the stack program [`bt_core::script`] runs.
//!
//! Identifiers are blackboard keys (BehaviorTree.CPP's enums are registered in C++ and
//! unknown here); the caller maps each to a slot and each string literal to a constant.

use bt_core::script::{STACK, op};

/// Where a script goes wrong: the byte offset in its text and what.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScriptError {
    /// Byte offset in the script text.
    pub offset: usize,
    /// What is wrong.
    pub message: String,
}

fn err<T>(offset: usize, message: impl Into<String>) -> Result<T, ScriptError> {
    Err(ScriptError { offset, message: message.into() })
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Int(i64),
    Real(f64),
    Bool(bool),
    Str(String),
    Ident(String),
    Op(&'static str),
    End,
}

const TWO: [&str; 12] = ["..", "&&", "||", "==", "!=", "<=", ">=", ":=", "+=", "-=", "*=", "/="];
const ONE: &str = "+-*/&|^~!<>=?:();";

fn tokenize(src: &str) -> Result<Vec<(Tok, usize)>, ScriptError> {
    let b = src.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let ident_start = |c: u8| c.is_ascii_alphabetic() || c == b'_' || c == b'@';
    let ident_char = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    while i < b.len() {
        let c = b[i];
        let start = i;
        if matches!(c, b' ' | b'\t' | b'\n' | b'\r') {
            i += 1;
            continue;
        }
        if c == b'\'' {
            let Some(end) = src[i + 1..].find('\'') else {
                return err(start, "a string without its closing quote");
            };
            out.push((Tok::Str(src[i + 1..i + 1 + end].to_string()), start));
            i += end + 2;
            continue;
        }
        if c.is_ascii_digit() {
            if c == b'0' && matches!(b.get(i + 1), Some(b'x' | b'X')) {
                i += 2;
                let digits = i;
                while b.get(i).is_some_and(u8::is_ascii_hexdigit) {
                    i += 1;
                }
                if i == digits || b.get(i).is_some_and(|&c| c == b'.' || ident_char(c)) {
                    return err(start, "a malformed hexadecimal number");
                }
                let v = i64::from_str_radix(&src[digits..i], 16);
                out.push((Tok::Int(v.or_else(|_| err(start, "a number out of range"))?), start));
                continue;
            }
            let mut real = false;
            while b.get(i).is_some_and(u8::is_ascii_digit) {
                i += 1;
            }
            if b.get(i) == Some(&b'.') && b.get(i + 1) != Some(&b'.') {
                if !b.get(i + 1).is_some_and(u8::is_ascii_digit) {
                    return err(start, "a malformed number");
                }
                real = true;
                i += 1;
                while b.get(i).is_some_and(u8::is_ascii_digit) {
                    i += 1;
                }
            }
            if matches!(b.get(i), Some(b'e' | b'E')) {
                real = true;
                i += 1;
                if matches!(b.get(i), Some(b'+' | b'-')) {
                    i += 1;
                }
                if !b.get(i).is_some_and(u8::is_ascii_digit) {
                    return err(start, "a malformed number");
                }
                while b.get(i).is_some_and(u8::is_ascii_digit) {
                    i += 1;
                }
            }
            if b.get(i).is_some_and(|&c| ident_start(c)) {
                return err(start, "a malformed number");
            }
            let text = &src[start..i];
            let tok = if real {
                Tok::Real(text.parse().or_else(|_| err(start, "a malformed number"))?)
            } else {
                Tok::Int(text.parse().or_else(|_| err(start, "a number out of range"))?)
            };
            out.push((tok, start));
            continue;
        }
        if ident_start(c) {
            i += 1;
            while b.get(i).is_some_and(|&c| ident_char(c)) {
                i += 1;
            }
            let word = &src[start..i];
            out.push((
                match word {
                    "true" => Tok::Bool(true),
                    "false" => Tok::Bool(false),
                    _ => Tok::Ident(word.to_string()),
                },
                start,
            ));
            continue;
        }
        if let Some(two) = src.get(i..i + 2).and_then(|t| TWO.iter().find(|&&o| o == t)) {
            out.push((Tok::Op(two), start));
            i += 2;
            continue;
        }
        if let Some(k) = ONE.find(c as char).filter(|_| c.is_ascii()) {
            out.push((Tok::Op(&ONE[k..=k]), start));
            i += 1;
            continue;
        }
        let ch = src[i..].chars().next().unwrap_or('?');
        return err(start, format!("an unexpected character `{}`", ch.escape_default()));
    }
    out.push((Tok::End, b.len()));
    Ok(out)
}

#[derive(Clone, Debug, PartialEq)]
enum Expr {
    Int(i64),
    Real(f64),
    Str(String),
    Name(String, usize),
    Unary(u16, Box<Expr>),
    Binary(u16, Box<Expr>, Box<Expr>),
    Compare(Vec<u16>, Vec<Expr>),
    If(Box<Expr>, Box<Expr>, Box<Expr>),
    Assign(u16, String, usize, Box<Expr>),
}

/// Deepest nesting of the parser (the host's stack, not the controller's).
const MAX_NESTING: usize = 64;

struct Parser {
    toks: Vec<(Tok, usize)>,
    at: usize,
    depth: usize,
}

fn infix(t: &Tok) -> Option<i32> {
    let Tok::Op(o) = t else { return None };
    Some(match *o {
        ":=" | "=" | "+=" | "-=" | "*=" | "/=" => 2,
        "?" => 4,
        "||" => 6,
        "&&" => 8,
        "==" | "!=" | "<" | ">" | "<=" | ">=" => 10,
        "|" | "^" => 12,
        "&" => 14,
        "+" | "-" | ".." => 16,
        "*" | "/" => 18,
        _ => return None,
    })
}

fn comparison(o: &str) -> Option<u16> {
    ["==", "!=", "<", ">", "<=", ">="].iter().position(|&c| c == o).map(|p| p as u16)
}

impl Parser {
    fn peek(&self) -> &(Tok, usize) {
        self.toks.get(self.at).unwrap_or(&(Tok::End, 0))
    }

    fn next(&mut self) -> (Tok, usize) {
        let t = self.peek().clone();
        if t.0 != Tok::End {
            self.at += 1;
        }
        t
    }

    fn expect(&mut self, o: &str) -> Result<(), ScriptError> {
        let (t, at) = self.next();
        if t == Tok::Op(leak(o)) { Ok(()) } else { err(at, format!("expected `{o}`")) }
    }

    fn prefix(&mut self) -> Result<Expr, ScriptError> {
        let (t, at) = self.next();
        Ok(match t {
            Tok::Op("-") => Expr::Unary(op::NEG, Box::new(self.expr(20)?)),
            Tok::Op("~") => Expr::Unary(op::COMPL, Box::new(self.expr(20)?)),
            Tok::Op("!") => Expr::Unary(op::NOT, Box::new(self.expr(20)?)),
            Tok::Op("(") => {
                let e = self.expr(0)?;
                self.expect(")")?;
                e
            }
            Tok::Bool(b) => Expr::Real(if b { 1.0 } else { 0.0 }),
            Tok::Int(i) => Expr::Int(i),
            Tok::Real(r) => Expr::Real(r),
            Tok::Str(s) => Expr::Str(s),
            Tok::Ident(name) => Expr::Name(name, at),
            Tok::End => return err(at, "an operand is missing at the end"),
            Tok::Op(o) => return err(at, format!("expected an operand, found `{o}`")),
        })
    }

    fn expr(&mut self, min: i32) -> Result<Expr, ScriptError> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return err(self.peek().1, format!("nested more than {MAX_NESTING} deep"));
        }
        let mut left = self.prefix()?;
        loop {
            let (t, at) = self.peek().clone();
            let Some(bp) = infix(&t).filter(|&bp| bp >= min) else { break };
            let Tok::Op(o) = t else { break };
            if bp == 2 {
                self.next();
                let Expr::Name(name, name_at) = left else {
                    return err(at, "the left side of an assignment must be a blackboard key");
                };
                let mode = [":=", "=", "+=", "-=", "*=", "/="].iter().position(|&m| m == o).unwrap_or(0) as u16;
                left = Expr::Assign(mode, name, name_at, Box::new(self.expr(0)?));
                break;
            }
            if o == "?" {
                self.next();
                let then = self.expr(0)?;
                self.expect(":")?;
                let otherwise = self.expr(4)?;
                left = Expr::If(Box::new(left), Box::new(then), Box::new(otherwise));
                break;
            }
            if let Some(c) = comparison(o) {
                let mut ops = vec![c];
                self.next();
                let mut operands = vec![left, self.expr(11)?];
                while let Some(c) = match &self.peek().0 {
                    Tok::Op(o) => comparison(o),
                    _ => None,
                } {
                    self.next();
                    ops.push(c);
                    operands.push(self.expr(11)?);
                }
                left = Expr::Compare(ops, operands);
                continue;
            }
            self.next();
            let right = self.expr(bp + 1)?;
            let code = match o {
                "+" => op::ADD,
                "-" => op::SUB,
                "*" => op::MUL,
                "/" => op::DIV,
                "&" => op::BIT_AND,
                "|" => op::BIT_OR,
                "^" => op::BIT_XOR,
                "&&" => op::AND,
                "||" => op::OR,
                _ => op::CONCAT,
            };
            left = Expr::Binary(code, Box::new(left), Box::new(right));
        }
        self.depth -= 1;
        Ok(left)
    }
}

fn leak(o: &str) -> &'static str {
    TWO.iter().copied().find(|&t| t == o).or_else(|| ONE.find(o).map(|k| &ONE[k..k + o.len()])).unwrap_or("")
}

/// A parsed script: its statements.
#[derive(Clone, Debug, PartialEq)]
pub struct Script {
    statements: Vec<Expr>,
}

/// Parses a script as BehaviorTree.CPP does: statements, optionally separated by `;`.
///
/// # Errors
/// The first [`ScriptError`]; an empty script is one (BehaviorTree.CPP refuses it too).
pub fn parse(src: &str) -> Result<Script, ScriptError> {
    let mut p = Parser { toks: tokenize(src)?, at: 0, depth: 0 };
    let mut statements = Vec::new();
    while p.peek().0 != Tok::End {
        // As BehaviorTree.CPP, statements need no `;` between them (`1 2` is two).
        statements.push(p.expr(0)?);
        while p.peek().0 == Tok::Op(";") {
            p.next();
        }
    }
    if statements.is_empty() {
        return err(0, "the script is empty");
    }
    Ok(Script { statements })
}

/// What the compiler asks of its caller.
pub trait Symbols {
    /// The slot of blackboard key `name` (at byte `offset` of the script) and whether a
    /// port of the tree declares it.
    fn slot(&mut self, name: &str, offset: usize) -> Result<(u16, bool), ScriptError>;
    /// The constant holding string `text`.
    fn string(&mut self, text: &str) -> Result<u16, ScriptError>;
    /// The value of scripting enum `name` (BT.CPP's `registerScriptingEnum`), which a
    /// script reads instead of a key of that name.
    fn enum_value(&self, name: &str) -> Option<f64> {
        let _ = name;
        None
    }
}

impl Script {
    /// The blackboard keys the script assigns, in order of appearance.
    #[must_use]
    pub fn assigned(&self) -> Vec<&str> {
        let mut out = Vec::new();
        let mut stack: Vec<&Expr> = self.statements.iter().rev().collect();
        while let Some(e) = stack.pop() {
            match e {
                Expr::Assign(_, name, _, rhs) => {
                    out.push(name.as_str());
                    stack.push(rhs);
                }
                Expr::Unary(_, a) => stack.push(a),
                Expr::Binary(_, a, b) => stack.extend([b.as_ref(), a.as_ref()]),
                Expr::Compare(_, xs) => stack.extend(xs.iter().rev()),
                Expr::If(a, b, c) => stack.extend([c.as_ref(), b.as_ref(), a.as_ref()]),
                _ => {}
            }
        }
        out
    }

    /// The program, with keys and strings mapped by `symbols`.
    ///
    /// # Errors
    /// A [`ScriptError`] from `symbols`, or a script that needs more than the
    /// controller's [`STACK`] values at once.
    pub fn compile(&self, symbols: &mut dyn Symbols) -> Result<Vec<u16>, ScriptError> {
        let mut c = Compiler { code: Vec::new(), depth: 0, max: 0, symbols };
        for (i, s) in self.statements.iter().enumerate() {
            if i > 0 {
                c.emit(&[op::POP], -1);
            }
            c.expr(s)?;
        }
        if c.max > STACK {
            return err(0, format!("the script needs {} stack values; a controller has {STACK}", c.max));
        }
        // What the controller's loader checks, checked here first.
        if let Err(e) = bt_core::script::check_stack(&c.code) {
            return err(0, format!("the script does not fit a controller's checks ({e})"));
        }
        Ok(c.code)
    }
}

struct Compiler<'s> {
    code: Vec<u16>,
    depth: usize,
    max: usize,
    symbols: &'s mut dyn Symbols,
}

fn words(bits: u64) -> [u16; 4] {
    [bits as u16, (bits >> 16) as u16, (bits >> 32) as u16, (bits >> 48) as u16]
}

/// A value a loop element's program pushes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Push {
    /// An integer.
    Int(i64),
    /// A double.
    Double(f64),
    /// A string constant of the ports section.
    Str(u16),
}

/// The program of one element of a literal loop queue: it pushes `value` and, given the
/// loop's `value` slot, assigns it there (`:=`, the slot declared by that port).
#[must_use]
pub fn element_program(value: Push, slot: Option<u16>) -> Vec<u16> {
    let mut program = match value {
        Push::Int(v) => [op::INT].into_iter().chain(words(v as u64)).collect(),
        Push::Double(v) => [op::DOUBLE].into_iter().chain(words(v.to_bits())).collect(),
        Push::Str(k) => vec![op::STR, k],
    };
    if let Some(slot) = slot {
        program.extend_from_slice(&[op::STORE, 0, slot, op::DECLARED]);
    }
    program
}

/// A literal loop queue's table, as [`bt_core::script::queue`] reads it: the element
/// type, the string constant naming the node (`0xFFFF` for the built-in loops), the
/// count, then each element's program with its length. `None` past 65,535 elements or
/// words in one program.
#[must_use]
pub fn literal_queue(element: bt_core::script::Element, name: u16, programs: &[Vec<u16>]) -> Option<Vec<u16>> {
    let mut table = vec![element as u16, name, u16::try_from(programs.len()).ok()?];
    for p in programs {
        table.push(u16::try_from(p.len()).ok()?);
        table.extend_from_slice(p);
    }
    Some(table)
}

impl Compiler<'_> {
    fn emit(&mut self, w: &[u16], effect: isize) {
        self.code.extend_from_slice(w);
        self.depth = self.depth.saturating_add_signed(effect);
        self.max = self.max.max(self.depth);
    }

    fn here(&self) -> usize {
        self.code.len()
    }

    fn patch(&mut self, at: usize) -> Result<(), ScriptError> {
        let target = u16::try_from(self.code.len()).or_else(|_| err(0, "the script is too long"))?;
        if let Some(w) = self.code.get_mut(at) {
            *w = target;
        }
        Ok(())
    }

    fn expr(&mut self, e: &Expr) -> Result<(), ScriptError> {
        match e {
            Expr::Int(i) => {
                let w = words(*i as u64);
                self.emit(&[op::INT, w[0], w[1], w[2], w[3]], 1);
            }
            Expr::Real(r) => {
                let w = words(r.to_bits());
                self.emit(&[op::DOUBLE, w[0], w[1], w[2], w[3]], 1);
            }
            Expr::Str(s) => {
                let k = self.symbols.string(s)?;
                self.emit(&[op::STR, k], 1);
            }
            Expr::Name(name, at) => {
                if let Some(v) = self.symbols.enum_value(name) {
                    let w = words(v.to_bits());
                    self.emit(&[op::DOUBLE, w[0], w[1], w[2], w[3]], 1);
                } else {
                    let (slot, _) = self.symbols.slot(name, *at)?;
                    self.emit(&[op::LOAD, slot], 1);
                }
            }
            Expr::Unary(o, a) => {
                self.expr(a)?;
                self.emit(&[*o], 0);
            }
            Expr::Binary(o, a, b) => {
                self.expr(a)?;
                self.expr(b)?;
                self.emit(&[*o], -1);
            }
            Expr::Compare(ops, xs) => {
                let mut patches = Vec::new();
                let mut xs = xs.iter();
                if let Some(first) = xs.next() {
                    self.expr(first)?;
                }
                for (k, (c, x)) in ops.iter().zip(xs).enumerate() {
                    self.expr(x)?;
                    if k + 1 == ops.len() {
                        self.emit(&[op::CMP, *c], -1);
                    } else {
                        self.emit(&[op::CMP_CHAIN, *c, 0], -1);
                        patches.push(self.here() - 1);
                    }
                }
                for p in patches {
                    self.patch(p)?;
                }
            }
            Expr::If(cond, then, otherwise) => {
                self.expr(cond)?;
                self.emit(&[op::JUMP_UNLESS, 0], -1);
                let to_else = self.here() - 1;
                self.expr(then)?;
                self.emit(&[op::JUMP, 0], -1);
                let to_end = self.here() - 1;
                self.patch(to_else)?;
                self.expr(otherwise)?;
                self.patch(to_end)?;
            }
            Expr::Assign(mode, name, at, rhs) => {
                let (slot, declared) = self.symbols.slot(name, *at)?;
                self.expr(rhs)?;
                self.emit(&[op::STORE, *mode, slot, u16::from(declared)], 0);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::panic, clippy::indexing_slicing)]
    use super::*;

    #[test]
    fn precedence_and_chains_are_behaviortree_cpps() {
        let s = parse("a := 1 + 2 * 3 == 7 && b < c <= 4 ? 'x' : 'y'; c").unwrap();
        assert_eq!(s.statements.len(), 2);
        let Expr::Assign(0, name, _, rhs) = &s.statements[0] else { panic!("{s:?}") };
        assert_eq!(name, "a");
        assert!(matches!(rhs.as_ref(), Expr::If(..)), "{rhs:?}");
        assert_eq!(s.assigned(), ["a"]);
    }

    #[test]
    fn errors_name_the_offset() {
        assert_eq!(parse("x := ").unwrap_err().offset, 5);
        assert_eq!(parse("1 := 2").unwrap_err().message, "the left side of an assignment must be a blackboard key");
        assert_eq!(parse("x := 'open").unwrap_err().offset, 5);
        assert_eq!(parse("x := 3.").unwrap_err().message, "a malformed number");
        assert!(parse("  ").is_err());
        assert!(parse(&"(".repeat(200)).is_err());
    }
}
