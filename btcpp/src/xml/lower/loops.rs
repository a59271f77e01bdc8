//! Loops: `LoopInt`, `LoopBool`, `LoopDouble`, `LoopString` and the `LoopNode<T>` a
//! program registers, their queue compiled into the value table.

use bt_core::{NodeKind, PortDirection, PortType, PortValue};

use super::Lowerer;
use super::builtins::NodeParams;
use super::scripts::script_name;
use crate::error::{Fault, ImportError, Location, Result};
use crate::kinds::{self, refuse};
use crate::xml::flatten::{Inst, Value};
use crate::xml::model::{Literal, convert};
use crate::xml::script;

impl Lowerer<'_> {
    /// A loop (`LoopInt`, ..., or one the program registers): its queue's table in the
    /// value table ([`bt_core::script::queue`]). A literal queue (`"1;2;3"`, split at
    /// `;` as BehaviorTree.CPP splits it, or a SubTree-local key that starts with one)
    /// becomes one assignment program per element; a `{key}` the slots
    /// [`BehaviorSet::pop`](bt_core::BehaviorSet::pop) is given.
    pub(super) fn loop_kind(&mut self, n: &Inst, element: bt_core::script::Element) -> Result<NodeKind> {
        use bt_core::script::{Element, QUEUE_KEY};
        use script::Push;
        let if_empty = kinds::status(&NodeParams { l: self, n, ports: &kinds::LOOP_PORTS }, "if_empty")?;
        let (ty, type_name) = match element {
            Element::Int => (PortType::Int, Some("int")),
            Element::Bool => (PortType::Bool, Some("bool")),
            Element::Double => (PortType::Double, Some("double")),
            Element::String => (PortType::String, Some("std::string")),
            Element::Registered => (PortType::Any, None),
        };
        let mut flat = Vec::new();
        // The `value` port: a key (BehaviorTree.CPP drops the elements without one).
        let value = match n.ports.iter().find(|b| b.port == "value") {
            None => None,
            Some(b) => match &b.value {
                Value::Literal(text) => {
                    return Err(ImportError::new(
                        &b.at,
                        Fault::OutputLiteral { node: n.id.clone(), port: "value".into(), value: text.clone() },
                    ));
                }
                Value::Key(k) => {
                    let v = self.slot_value(k, (ty, PortDirection::Output), type_name, &b.at, n, "value")?;
                    match PortValue::from_u16(v) {
                        PortValue::Slot(id) => Some(id),
                        _ => return Err(ImportError::new(&b.at, Fault::TooLarge("no slot for `value`".into()))),
                    }
                }
            },
        };
        let Some(queue) = n.ports.iter().find(|b| b.port == "queue") else {
            return Err(ImportError::new(&n.at, Fault::MissingAttribute { element: n.id.clone(), attribute: "queue" }));
        };
        let registered = |l: &mut Self, at: &Location| match element {
            Element::Registered => l.intern(Literal::Str(n.id.clone()), at),
            _ => Ok(u16::MAX),
        };
        let literal = match &queue.value {
            Value::Literal(text) => Ok(text.clone()),
            Value::Key(k) => self.initial_literal(k).ok_or(k),
        };
        let table;
        match literal {
            Ok(text) => {
                if element == Element::Registered {
                    return Err(refuse(
                        &queue.at,
                        format!("<{} queue=\"{}\">", n.id, queue.raw),
                        "BehaviorTree.CPP reads a literal queue only for LoopInt, LoopBool, LoopDouble and LoopString",
                    ));
                }
                let name = registered(self, &queue.at)?;
                // BehaviorTree.CPP's splitString: no element after a final `;`.
                let mut parts: Vec<&str> = text.split(';').collect();
                if parts.last() == Some(&"") {
                    parts.pop();
                }
                let mut programs = Vec::with_capacity(parts.len());
                for part in parts {
                    let bad = || {
                        ImportError::new(
                            &queue.at,
                            Fault::BadLiteral {
                                node: n.id.clone(),
                                port: "queue".into(),
                                value: part.into(),
                                ty: type_name.unwrap_or("any").into(),
                            },
                        )
                    };
                    let push = match convert(type_name, part).ok_or_else(bad)? {
                        Literal::Int(v) => Push::Int(v),
                        Literal::Double(v) => Push::Double(v),
                        // A string the slot's type converts (`true` for a boolean slot).
                        Literal::Bool(v) => Push::Str(self.intern(Literal::Str(v.to_string()), &queue.at)?),
                        Literal::Str(v) => Push::Str(self.intern(Literal::Str(v), &queue.at)?),
                    };
                    programs.push(script::element_program(push, value));
                }
                table = script::literal_queue(element, name, &programs).ok_or_else(|| {
                    ImportError::new(&queue.at, Fault::TooLarge("a queue of more than 65535 elements".into()))
                })?;
                flat.push(("queue".to_string(), text));
            }
            Err(k) => {
                let v = self.slot_value(k, (PortType::Any, PortDirection::InOut), None, &queue.at, n, "queue")?;
                let PortValue::Slot(slot) = PortValue::from_u16(v) else {
                    return Err(ImportError::new(&queue.at, Fault::TooLarge("no slot for `queue`".into())));
                };
                table = vec![QUEUE_KEY | element as u16, registered(self, &queue.at)?, slot, value.unwrap_or(u16::MAX)];
                flat.push((
                    "queue".to_string(),
                    format!("{{{}}}", script_name(&self.out.slots[usize::from(slot)].name)),
                ));
            }
        }
        if let Some(b) = n.ports.iter().find(|b| b.port == "if_empty") {
            flat.push(("if_empty".to_string(), b.raw.clone()));
        }
        if let Some(slot) = value {
            flat.push(("value".to_string(), format!("{{{}}}", script_name(&self.out.slots[usize::from(slot)].name))));
        }
        if let Some(meta) = self.out.meta.last_mut() {
            meta.flat = Some(flat);
        }
        Ok(NodeKind::Loop { table: self.place(n, &table)?, if_empty })
    }
}
