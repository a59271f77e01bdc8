//! Values, ports and slots: a leaf's ports as packed values, constants interned once,
//! blackboard keys numbered as slots (typed by the first port that names them, checked
//! against the others, polymorphic casts allowed).

use bt_core::port::{SlotInfo, UNSET};
use bt_core::{Catalog, PortDirection, PortType, PortValue};

use super::scripts::SCRIPT_PORT;
use super::{Lowerer, Slot};
use crate::error::{Fault, ImportError, Location, Result};
use crate::xml::flatten::{Bound, Inst, Key, Value};
use crate::xml::model::{Literal, convert};

/// What a port of a node reads: the attribute, or the model's default.
enum Given<'b> {
    Attr(&'b Bound),
    Default(String),
    Unset,
}

impl Lowerer<'_> {
    /// The literal a key starts with, when it is a SubTree-local entry no port writes.
    pub(super) fn initial_literal(&self, k: &Key) -> Option<String> {
        if self.written.contains(k) {
            return None;
        }
        self.flat.scopes.get(k.scope)?.initial.get(&k.name).map(|(v, _)| v.clone())
    }

    /// The literal a SubTree instance starts key `k` at, and where it is written.
    fn start_literal(&self, k: &Key) -> Option<(String, Location)> {
        self.flat.scopes.get(k.scope)?.initial.get(&k.name).cloned()
    }

    /// A slot's start value: `text` converted for `type_name`, interned.
    fn typed_constant(
        &mut self,
        text: &str,
        type_name: Option<&str>,
        at: &Location,
        n: &Inst,
        key: &str,
    ) -> Result<u16> {
        let Some(lit) = convert(type_name, text) else {
            return Err(ImportError::new(
                at,
                Fault::BadLiteral {
                    node: n.id.clone(),
                    port: key.into(),
                    value: text.into(),
                    ty: type_name.unwrap_or("any").into(),
                },
            ));
        };
        self.intern(lit, at)
    }

    pub(super) fn leaf_values(&mut self, n: &Inst, behavior: u16) -> Result<Vec<u16>> {
        let model = self.catalog.behaviors()[usize::from(behavior)].clone();
        for b in &n.ports {
            if !model.ports.iter().any(|p| p.name == b.port) {
                return Err(ImportError::new(
                    &b.at,
                    Fault::UnknownPort {
                        node: n.id.clone(),
                        port: b.port.clone(),
                        declared: model.ports.iter().map(|p| p.name.clone()).collect(),
                    },
                ));
            }
        }
        let mut values = Vec::with_capacity(model.ports.len());
        for (position, p) in model.ports.iter().enumerate() {
            let info = self.catalog.port(behavior, position).map(|i| (i.ty, i.direction));
            let (ty, direction) = info.unwrap_or((PortType::Any, PortDirection::Input));
            let given = match n.ports.iter().find(|b| b.port == p.name) {
                Some(b) => Given::Attr(b),
                None => match &p.default {
                    Some(d) => Given::Default(d.clone()),
                    None => Given::Unset,
                },
            };
            let v = match given {
                Given::Unset => UNSET,
                Given::Default(d) => match self.flat.port_key(&p.name, &d) {
                    Some(k) => {
                        let key = self.flat.resolve(n.scope, k);
                        self.slot_value(&key, (ty, direction), p.type_name.as_deref(), &n.at, n, &p.name)?
                    }
                    // The behavior applies a literal default itself.
                    None => UNSET,
                },
                Given::Attr(b) => match &b.value {
                    Value::Literal(text) => {
                        if direction == PortDirection::Output {
                            return Err(ImportError::new(
                                &b.at,
                                Fault::OutputLiteral { node: n.id.clone(), port: p.name.clone(), value: text.clone() },
                            ));
                        }
                        self.constant(text, p.type_name.as_deref(), &b.at, n, &p.name)?
                    }
                    Value::Key(k) => match self.initial_literal(k) {
                        Some(text) if direction == PortDirection::Input => {
                            self.constant(&text, p.type_name.as_deref(), &b.at, n, &p.name)?
                        }
                        _ => self.slot_value(k, (ty, direction), p.type_name.as_deref(), &b.at, n, &p.name)?,
                    },
                },
            };
            values.push(v);
        }
        Ok(values)
    }

    fn constant(&mut self, text: &str, type_name: Option<&str>, at: &Location, n: &Inst, port: &str) -> Result<u16> {
        let Some(lit) = convert(type_name, text) else {
            return Err(ImportError::new(
                at,
                Fault::BadLiteral {
                    node: n.id.clone(),
                    port: port.into(),
                    value: text.into(),
                    ty: type_name.unwrap_or("any").into(),
                },
            ));
        };
        let id = self.intern(lit, at)?;
        Ok(PortValue::Constant(id).to_u16().unwrap_or(UNSET))
    }

    pub(super) fn intern(&mut self, lit: Literal, at: &Location) -> Result<u16> {
        let key = lit.key();
        if let Some(&id) = self.constant_ids.get(&key) {
            return Ok(id);
        }
        let id = u16::try_from(self.out.constants.len())
            .ok()
            .filter(|&i| i < bt_core::port::MAX_CONSTANTS)
            .ok_or_else(|| ImportError::new(at, Fault::TooLarge("more constants than a ports section holds".into())))?;
        self.out.constants.push(lit);
        self.constant_ids.insert(key, id);
        Ok(id)
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn slot_value(
        &mut self,
        key: &Key,
        (ty, direction): (PortType, PortDirection),
        type_name: Option<&str>,
        at: &Location,
        n: &Inst,
        port: &str,
    ) -> Result<u16> {
        if let Some(&id) = self.slot_ids.get(key) {
            // A slot a script named first takes the type of the first port that names it.
            if self.script_slots.contains(&id) && port != SCRIPT_PORT {
                self.script_slots.remove(&id);
                // The literal a SubTree starts it at, read again by the port's type.
                let initial = match self.start_literal(key) {
                    Some((text, lit_at)) => Some(self.typed_constant(&text, type_name, &lit_at, n, &key.name)?),
                    None => None,
                };
                let slot = &mut self.out.slots[usize::from(id)];
                slot.info.ty = ty;
                slot.info.initial = initial;
                slot.type_name = type_name.map(str::to_string);
                return Ok(PortValue::Slot(id).to_u16().unwrap_or(UNSET));
            }
            let slot = &self.out.slots[usize::from(id)];
            // BehaviorTree.CPP's rule: two typed ports on one key must agree, unless the
            // key was first created as a string.
            let first = slot.info.ty;
            let conflict = ty != PortType::Any
                && first != PortType::Any
                && first != PortType::String
                && (ty != first || (ty == PortType::Other && slot.type_name.as_deref() != type_name))
                // An input port may read through a registered polymorphic cast.
                && !(direction == PortDirection::Input
                    && slot.type_name.as_deref().zip(type_name).is_some_and(|(from, to)| converts(self.casts, from, to)));
            if conflict {
                return Err(ImportError::new(
                    at,
                    Fault::KeyTypeConflict {
                        key: slot.name.clone(),
                        first: slot.type_name.clone().unwrap_or_else(|| "any".into()),
                        second: type_name.unwrap_or("any").into(),
                        at: self.slot_first[usize::from(id)].clone(),
                    },
                ));
            }
            return Ok(PortValue::Slot(id).to_u16().unwrap_or(UNSET));
        }
        let id =
            u16::try_from(self.out.slots.len()).ok().filter(|&i| i < bt_core::port::MAX_SLOTS).ok_or_else(|| {
                ImportError::new(at, Fault::TooLarge("more blackboard keys than a ports section holds".into()))
            })?;
        let scope = self.flat.scopes.get(key.scope);
        let initial = match self.start_literal(key) {
            Some((text, lit_at)) => Some(self.typed_constant(&text, type_name, &lit_at, n, &key.name)?),
            None => None,
        };
        let name = match scope {
            Some(s) if key.scope != 0 => format!("{}/{}", s.path, key.name),
            _ => key.name.clone(),
        };
        self.out.slots.push(Slot { name, info: SlotInfo { ty, initial }, type_name: type_name.map(str::to_string) });
        self.slot_first.push(at.clone());
        self.slot_ids.insert(key.clone(), id);
        if port == SCRIPT_PORT {
            self.script_slots.insert(id);
        }
        Ok(PortValue::Slot(id).to_u16().unwrap_or(UNSET))
    }
}

/// Whether a value of type `from` may be read as `to` through `casts`
/// (`(derived, base)`): upwards through any number of casts, or down one, as
/// BehaviorTree.CPP's polymorphic cast registry allows.
fn converts(casts: &[(String, String)], from: &str, to: &str) -> bool {
    if casts.iter().any(|(derived, base)| derived == to && base == from) {
        return true;
    }
    // Upwards: the bases reachable from `from` (a cycle of casts ends when no type is new).
    let mut reached = vec![from];
    let mut next = 0;
    while let Some(&t) = reached.get(next) {
        if t == to {
            return true;
        }
        for (derived, base) in casts {
            if derived == t && !reached.contains(&base.as_str()) {
                reached.push(base);
            }
        }
        next += 1;
    }
    false
}
