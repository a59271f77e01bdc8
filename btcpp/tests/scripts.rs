//! BehaviorTree.CPP's script engine against ours: every script of
//! `tests/btcpp/cases/scripts.txt`, run by BehaviorTree.CPP 4.10 (recorded in
//! `tests/btcpp/fixtures/scripts/scripts.txt` by `tests/btcpp/scripts.cpp`; `record.sh` records it)
//! and by `btcpp::xml::script` + `bt_core::script`, must give the same result or both
//! fail, and leave the same blackboard.
//!
//! Two differences are allowed, both documented in `docs/behaviortree-cpp.md`: a script
//! that builds a string (BehaviorTree.CPP's `..` and `+` on strings) fails here, and the
//! rest of its case is not compared; an entry BehaviorTree.CPP created but left empty
//! (`v := w` with `w` unset) does not exist here.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::collections::BTreeMap;

use bt_core::PortType;
use bt_core::port::{Constant, PortTable, SlotInfo, encode_table};
use bt_core::script::{ScriptFault, Value, run};
use btcpp::xml::script::{ScriptError, Symbols, parse};

#[derive(Default)]
struct Table {
    keys: Vec<String>,
    strings: Vec<String>,
}

impl Symbols for Table {
    fn slot(&mut self, name: &str, _: usize) -> Result<(u16, bool), ScriptError> {
        let i = self.keys.iter().position(|k| k == name).unwrap_or_else(|| {
            self.keys.push(name.to_string());
            self.keys.len() - 1
        });
        Ok((i as u16, false))
    }

    fn string(&mut self, text: &str) -> Result<u16, ScriptError> {
        let i = self.strings.iter().position(|k| k == text).unwrap_or_else(|| {
            self.strings.push(text.to_string());
            self.strings.len() - 1
        });
        Ok(i as u16)
    }
}

fn show(v: Option<Value>, strings: &[String]) -> String {
    match v {
        None => "empty -".into(),
        Some(Value::Int(i)) => format!("int {i}"),
        Some(Value::Bool(b)) => format!("int {}", i64::from(b)),
        Some(Value::Double(d)) => format!("double {}", cpp_g17(d)),
        Some(Value::Str(k)) => format!("string '{}'", strings[usize::from(k)]),
    }
}

/// `printf("%.17g")`.
fn cpp_g17(d: f64) -> String {
    if d.is_infinite() {
        return if d > 0.0 { "inf".into() } else { "-inf".into() };
    }
    if d.is_nan() {
        return "nan".into();
    }
    if d == 0.0 {
        return if d.is_sign_negative() { "-0".into() } else { "0".into() };
    }
    let exp = d.abs().log10().floor() as i32;
    if (-5..17).contains(&exp) {
        let decimals = (16 - exp).max(0) as usize;
        let s = format!("{d:.decimals$}");
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
    } else {
        let s = format!("{d:.16e}");
        let (m, e) = s.split_once('e').unwrap();
        let m = if m.contains('.') { m.trim_end_matches('0').trim_end_matches('.') } else { m };
        let e: i32 = e.parse().unwrap();
        format!("{m}e{}{:02}", if e < 0 { '-' } else { '+' }, e.abs())
    }
}

/// One case run on our side: the output lines the harness would print.
fn ours(scripts: &[&str]) -> (Vec<String>, Option<usize>) {
    let mut table = Table::default();
    let programs: Vec<Result<Vec<u16>, ScriptError>> =
        scripts.iter().map(|s| parse(s).and_then(|p| p.compile(&mut table))).collect();
    let slots: Vec<SlotInfo> = table.keys.iter().map(|_| SlotInfo { ty: PortType::Any, initial: None }).collect();
    let constants: Vec<Constant<'_>> = table.strings.iter().map(|s| Constant::Str(s)).collect();
    let mut bytes = vec![0u8; 4096];
    let n = encode_table(&slots, &constants, &mut bytes).unwrap();
    let ports = PortTable::parse(&bytes[..n]).unwrap();
    let mut bb = vec![None; table.keys.len()];
    let mut out = Vec::new();
    let mut stopped = None;
    for (i, (s, program)) in scripts.iter().zip(&programs).enumerate() {
        out.push(format!("script {s}"));
        match program {
            Err(_) => out.push("! error".into()),
            Ok(code) => {
                bt_core::script::check(code, &ports).unwrap();
                match run(code, &ports, bb.as_mut_slice()) {
                    Ok(v) => out.push(format!("= {}", show(Some(v), &table.strings))),
                    Err(ScriptFault::StringBuilding) => {
                        out.push("! string building".into());
                        stopped.get_or_insert(i);
                    }
                    Err(_) => out.push("! error".into()),
                }
            }
        }
    }
    let mut keys: BTreeMap<&str, String> = BTreeMap::new();
    for (k, v) in table.keys.iter().zip(&bb) {
        if v.is_some() {
            keys.insert(k, show(*v, &table.strings));
        }
    }
    out.extend(keys.into_iter().map(|(k, v)| format!("key {k} {v}")));
    (out, stopped)
}

#[test]
fn scripts_run_as_behaviortree_cpp_runs_them() {
    let fixture =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/btcpp/fixtures/scripts/scripts.txt"))
            .expect("the fixture");
    let (mut compared, mut scripts_seen, mut building) = (0, 0, 0);
    for block in fixture.split("\nend\n").filter(|b| !b.trim().is_empty()) {
        let lines: Vec<&str> = block.lines().filter(|l| *l != "end").collect();
        let name = lines[0].strip_prefix("case ").expect("a case line");
        let theirs: Vec<&str> = lines[1..].iter().copied().filter(|l| *l != "key v empty -").collect();
        let scripts: Vec<&str> = theirs.iter().filter_map(|l| l.strip_prefix("script ")).collect();
        let (mine, stopped) = ours(&scripts);
        scripts_seen += scripts.len();
        match stopped {
            None => {
                assert_eq!(mine, theirs, "case {name}");
                compared += scripts.len();
            }
            Some(k) => {
                // Compared up to the script that builds a string.
                let upto = theirs.iter().enumerate().filter(|(_, l)| l.starts_with("script ")).nth(k).unwrap().0;
                assert_eq!(mine[..=upto], theirs[..=upto], "case {name}");
                compared += k;
                building += 1;
            }
        }
    }
    assert!(compared >= 100, "only {compared} scripts compared");
    eprintln!("{compared} of {scripts_seen} scripts gave BehaviorTree.CPP's result; {building} built a string");
}
