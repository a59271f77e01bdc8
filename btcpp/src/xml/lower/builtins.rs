//! BehaviorTree.CPP's built-ins and Nav2's control nodes, lowered by their entry of
//! [`crate::kinds`]: refused, a kind without parameters, a kind whose parameters the
//! entry reads (through [`NodeParams`]), or a loop.

use bt_core::{Code, NodeKind};

use super::Lowerer;
use crate::error::{Fault, ImportError, Location, Result};
use crate::kinds::{Entry, Map, Params, Port, refuse};
use crate::xml::document::Version;
use crate::xml::flatten::{Inst, Value};

impl Lowerer<'_> {
    /// The kind of a node of a built-in type.
    pub(super) fn builtin(&mut self, n: &Inst, entry: &'static Entry) -> Result<NodeKind> {
        match entry.map {
            Map::Refused(reason) => Err(unsupported(&n.at, &n.id, reason)),
            Map::Plain(kind, _) => {
                check_ports(n, entry.ports)?;
                Ok(kind)
            }
            Map::Params { read, .. } => {
                check_ports(n, entry.ports)?;
                read(&mut NodeParams { l: self, n, ports: entry.ports })
            }
            Map::Loop(element) => {
                check_ports(n, entry.ports)?;
                self.loop_kind(n, element)
            }
        }
    }
}

/// A node's parameters as a table entry reads them: literals, SubTree-local keys that
/// start at a literal, defaults from `ports`.
pub(super) struct NodeParams<'l, 'a, 'n> {
    pub l: &'l mut Lowerer<'a>,
    pub n: &'n Inst,
    pub ports: &'static [Port],
}

impl Params for NodeParams<'_, '_, '_> {
    fn id(&self) -> &str {
        &self.n.id
    }

    fn at(&self) -> &Location {
        &self.n.at
    }

    fn children(&self) -> usize {
        self.n.children.len()
    }

    fn attr(&self, port: &str) -> Option<(&str, &Location)> {
        self.n.ports.iter().find(|b| b.port == port).map(|b| (b.raw.as_str(), &b.at))
    }

    fn text(&self, port: &str) -> Result<Option<(String, Location)>> {
        let n = self.n;
        let Some(b) = n.ports.iter().find(|b| b.port == port) else {
            let default = self.ports.iter().find(|p| p.name == port).and_then(|p| p.default);
            return Ok(default.map(|d| (d.to_string(), n.at.clone())));
        };
        match &b.value {
            Value::Literal(v) => Ok(Some((v.clone(), b.at.clone()))),
            Value::Key(k) => match self.l.initial_literal(k) {
                Some(v) => Ok(Some((v, b.at.clone()))),
                None => Err(ImportError::new(
                    &b.at,
                    Fault::ParameterFromBlackboard { node: n.id.clone(), port: port.into(), value: b.raw.clone() },
                )),
            },
        }
    }

    fn script(&mut self, port: &'static str) -> Result<Code> {
        self.l.script_code(self.n, port)
    }

    fn set_blackboard(&mut self) -> Result<Code> {
        self.l.set_blackboard(self.n)
    }

    fn count_slot(&mut self, port: &'static str) -> Result<Option<u16>> {
        self.l.count_slot(self.n, port)
    }

    fn comparison(&mut self, ty: crate::kinds::Compared) -> Result<Code> {
        self.l.comparison(self.n, ty)
    }
}

/// Refuses a port the node type does not have.
pub(super) fn check_ports(n: &Inst, ports: &[Port]) -> Result<()> {
    for p in &n.ports {
        if !ports.iter().any(|port| port.name == p.port) {
            return Err(ImportError::new(
                &p.at,
                Fault::UnknownPort {
                    node: n.id.clone(),
                    port: p.port.clone(),
                    declared: ports.iter().map(|port| port.name.to_string()).collect(),
                },
            ));
        }
    }
    Ok(())
}

/// The refusal of a node no model declares that is a built-in of the other
/// BehaviorTree.CPP version than the document's.
pub(super) fn of_the_other_version(n: &Inst, version: Version) -> Option<ImportError> {
    let other = match version {
        Version::V3 => Version::V4,
        Version::V4 => Version::V3,
    };
    crate::kinds::by_id_in(&n.id, other)?;
    let how = match version {
        Version::V3 => "it has no BTCPP_format=\"4\"; add it if the document is written for BehaviorTree.CPP 4",
        Version::V4 => {
            "it has BTCPP_format=\"4\"; leave the attribute out if the document is written for BehaviorTree.CPP 3"
        }
    };
    Some(unsupported(
        &n.at,
        &n.id,
        &format!(
            "it is a node type of {}, and the document is read as {} ({how}); or declare it in a <TreeNodesModel> if the program registers a node of its own under that ID",
            other.library(),
            version.library(),
        ),
    ))
}

/// Refuses node type `id`.
pub(super) fn unsupported(at: &Location, id: &str, reason: &str) -> ImportError {
    refuse(at, format!("<{id}>"), reason)
}
