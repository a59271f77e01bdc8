//! Scripts: `Script`, `ScriptCondition` and `Precondition` programs and the guards of
//! scripted attributes, compiled into the value table with their keys as slots.

use bt_core::{Code, NodeKind, PortDirection, PortType, PortValue};

use super::Lowerer;
use crate::error::{Fault, ImportError, Location, Result};
use crate::kinds::SCRIPT_ATTRIBUTES;
use crate::xml::flatten::{Bound, Inst};
use crate::xml::model::Literal;
use crate::xml::script;

/// The name a slot has in the XML of the flattened tree, where scripts name it too: its
/// key when that is a script identifier, else (a SubTree's local key, `MySub::3/x`)
/// every run of other characters made one `_` (`MySub_3_x`), with a `_` in front of a
/// digit.
#[must_use]
pub fn script_name(name: &str) -> std::borrow::Cow<'_, str> {
    let word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    if name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') && name.chars().all(word) {
        return name.into();
    }
    let mut out = String::with_capacity(name.len() + 1);
    if !name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        out.push('_');
    }
    for c in name.chars() {
        if word(c) {
            out.push(c);
        } else if !out.ends_with('_') {
            out.push('_');
        }
    }
    out.into()
}

impl Lowerer<'_> {
    /// A `Script`'s or `ScriptCondition`'s program, in the value table: keys become slots
    /// (of no type unless a port gives them one), strings constants.
    pub(super) fn script_code(&mut self, n: &Inst, port: &'static str) -> Result<Code> {
        let Some(bound) = n.ports.iter().find(|b| b.port == port) else {
            return Err(ImportError::new(&n.at, Fault::MissingAttribute { element: n.id.clone(), attribute: port }));
        };
        let (words, flat) = self.compile_script(n, bound, n.scope)?;
        if let Some(meta) = self.out.meta.last_mut() {
            let written = |text: &String| {
                meta.params.iter().map(|(k, v)| (k.clone(), if k == port { text.clone() } else { v.clone() })).collect()
            };
            meta.flat = Some(written(&flat));
        }
        self.place(n, &words)
    }

    /// Words appended to the value table, as a [`Code`].
    pub(super) fn place(&mut self, n: &Inst, words: &[u16]) -> Result<Code> {
        let start = u16::try_from(self.out.values.len()).ok();
        let len = u16::try_from(words.len()).ok();
        let full = || ImportError::new(&n.at, Fault::TooLarge("the image's value table is full".into()));
        let (Some(start), Some(len)) = (start, len) else {
            return Err(full());
        };
        if start.checked_add(len).is_none() {
            return Err(full());
        }
        self.out.values.extend_from_slice(words);
        Ok(Code { start, len })
    }

    /// A script attribute of `n` (`bound`) compiled with its keys read in `scope`: its
    /// program, and its text with every key as the flattened tree names it.
    fn compile_script(&mut self, n: &Inst, bound: &Bound, scope: usize) -> Result<(Vec<u16>, String)> {
        let fault = |e: script::ScriptError| {
            let mut code: String = bound.raw.chars().take(80).collect();
            if code.len() < bound.raw.len() {
                code.push_str("...");
            }
            ImportError::new(
                &bound.at,
                Fault::Script {
                    node: n.id.clone(),
                    attribute: bound.port.clone(),
                    code,
                    message: e.message,
                    offset: e.offset,
                },
            )
        };
        let parsed = script::parse(&bound.raw).map_err(fault)?;
        let (words, mut keys) = {
            let mut symbols = ScriptSymbols { l: self, n, scope, at: &bound.at, failed: None, keys: Vec::new() };
            let compiled = parsed.compile(&mut symbols);
            if let Some(e) = symbols.failed {
                return Err(e);
            }
            (compiled.map_err(fault)?, symbols.keys)
        };
        // The script as the flattened tree names its keys.
        let mut flat = bound.raw.clone();
        keys.sort_by_key(|k| std::cmp::Reverse(k.0));
        for (offset, written, slot) in keys {
            let name = script_name(&self.out.slots[usize::from(slot)].name);
            if *name != written && flat.get(offset..offset + written.len()) == Some(written.as_str()) {
                flat.replace_range(offset..offset + written.len(), &name);
            }
        }
        Ok((words, flat))
    }

    /// The guard of a node with scripted attributes: their table (a mask, then each
    /// hook's length and program, in [`bt_core::script::Hook`] order) in the value table.
    pub(super) fn guard(&mut self, n: &Inst) -> Result<NodeKind> {
        let mut mask = 0u16;
        let mut table = vec![0u16];
        let mut flat = Vec::new();
        for (bit, name) in SCRIPT_ATTRIBUTES.iter().enumerate() {
            let Some(bound) = n.hooks.iter().find(|b| b.port == *name) else { continue };
            let (words, text) = self.compile_script(n, bound, n.hook_scope)?;
            mask |= 1 << bit;
            let len = u16::try_from(words.len())
                .map_err(|_| ImportError::new(&bound.at, Fault::TooLarge("a script longer than 65535 words".into())))?;
            table.push(len);
            table.extend_from_slice(&words);
            flat.push((name.to_string(), text));
        }
        table[0] = mask;
        if let Some(meta) = self.out.meta.last_mut() {
            meta.params = n.hooks.iter().map(|b| (b.port.clone(), b.raw.clone())).collect();
            meta.flat = Some(flat);
        }
        Ok(NodeKind::Guard(self.place(n, &table)?))
    }
}

/// The port name [`Lowerer::slot_value`] is given for a script's keys.
pub(super) const SCRIPT_PORT: &str = "code";

/// Keys and strings of a script, as [`Lowerer`] numbers them.
struct ScriptSymbols<'l, 'a, 'n> {
    l: &'l mut Lowerer<'a>,
    n: &'n Inst,
    at: &'n Location,
    /// The scope its keys are read in.
    scope: usize,
    /// An import error (a key conflict, a full table) met while compiling.
    failed: Option<ImportError>,
    /// Each key as written (its byte offset and text) and its slot.
    keys: Vec<(usize, String, u16)>,
}

impl script::Symbols for ScriptSymbols<'_, '_, '_> {
    fn slot(&mut self, name: &str, offset: usize) -> std::result::Result<(u16, bool), script::ScriptError> {
        let key = self.l.flat.resolve(self.scope, name);
        let declared = self.l.ported.contains(&key)
            || self.l.flat.scopes.get(key.scope).is_some_and(|s| s.initial.contains_key(&key.name));
        match self.l.slot_value(&key, (PortType::Any, PortDirection::InOut), None, self.at, self.n, SCRIPT_PORT) {
            Ok(v) => match PortValue::from_u16(v) {
                PortValue::Slot(id) => {
                    self.keys.push((offset, name.to_string(), id));
                    Ok((id, declared))
                }
                _ => Err(script::ScriptError { offset, message: format!("no slot for `{name}`") }),
            },
            Err(e) => {
                let message = e.to_string();
                self.failed = Some(e);
                Err(script::ScriptError { offset, message })
            }
        }
    }

    fn enum_value(&self, name: &str) -> Option<f64> {
        self.l.enums.get(name).map(|&v| v as f64)
    }

    fn string(&mut self, text: &str) -> std::result::Result<u16, script::ScriptError> {
        match self.l.intern(Literal::Str(text.to_string()), self.at) {
            Ok(k) => Ok(k),
            Err(e) => {
                let message = e.to_string();
                self.failed = Some(e);
                Err(script::ScriptError { offset: 0, message })
            }
        }
    }
}
