//! The name table of a PDDL problem's behavior set, as a bt-core [`Catalog`].
//!
//! The contract (fixed; worlds and firmware build on it): behavior ids are the
//! predicates in declaration order (conditions; name = predicate name, arity =
//! parameter count), then the action templates in declaration order (actions); a
//! leaf's arguments are object indices in the problem's `:objects` order. The
//! fingerprint depends on the domain only; the object names come from the problem and
//! are used to render leaves, e.g. `holding(cube)`, and read back from text. The
//! parameter names name the leaves' values ([`Catalog::port_name`]) without declaring
//! ports, so they leave the fingerprint as it is.

use bt_core::{BehaviorId, BehaviorInfo, Catalog, LeafKind};

use crate::model::{Domain, Problem};

/// Names the behaviors of a PDDL domain and the objects of one of its problems.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PddlCatalog {
    behaviors: Vec<(String, LeafKind, u8)>,
    /// Parameter names per behavior, for XML ports.
    params: Vec<Vec<String>>,
    objects: Vec<String>,
}

impl PddlCatalog {
    /// The catalog of `problem`'s domain with its object names.
    #[must_use]
    pub fn new(problem: &Problem) -> Self {
        let mut c = Self::for_domain(&problem.domain);
        c.objects = problem.objects.iter().map(|o| o.name.clone()).collect();
        c
    }

    /// The catalog of a domain alone: arguments render as `#index`.
    #[must_use]
    pub fn for_domain(d: &Domain) -> Self {
        let mut behaviors = Vec::new();
        let mut params = Vec::new();
        for p in &d.predicates {
            behaviors.push((p.name.clone(), LeafKind::Condition, p.params.len().min(255) as u8));
            params.push(p.params.iter().map(|x| x.name.clone()).collect());
        }
        for a in &d.actions {
            behaviors.push((a.name.clone(), LeafKind::Action, a.params.len().min(255) as u8));
            params.push(a.params.iter().map(|x| x.name.clone()).collect());
        }
        Self { behaviors, params, objects: Vec::new() }
    }

    /// The object names used to render arguments.
    #[must_use]
    pub fn objects(&self) -> &[String] {
        &self.objects
    }

    /// The name of parameter `position` of `behavior` (without `?`).
    #[must_use]
    pub fn param(&self, behavior: BehaviorId, position: usize) -> Option<&str> {
        self.params.get(usize::from(behavior))?.get(position).map(String::as_str)
    }

    /// The behavior id and leaf kind of a name.
    #[must_use]
    pub fn lookup(&self, name: &str) -> Option<(BehaviorId, LeafKind, u8)> {
        let i = self.behaviors.iter().position(|b| b.0 == name)?;
        let b = &self.behaviors[i];
        Some((BehaviorId::try_from(i).ok()?, b.1, b.2))
    }

    /// The object index of a name.
    #[must_use]
    pub fn object(&self, name: &str) -> Option<u16> {
        self.objects.iter().position(|o| o == name).and_then(|i| u16::try_from(i).ok())
    }
}

impl Catalog for PddlCatalog {
    fn len(&self) -> usize {
        self.behaviors.len()
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        self.behaviors.get(usize::from(id)).map(|(name, kind, arity)| BehaviorInfo { name, kind: *kind, arity: *arity })
    }

    /// The parameter's name: written as the port of BehaviorTree.CPP XML, read back by it.
    fn port_name(&self, behavior: BehaviorId, position: usize) -> Option<&str> {
        self.param(behavior, position)
    }

    /// The object's name (`#index` for a domain alone).
    fn write_arg(
        &self,
        f: &mut core::fmt::Formatter<'_>,
        _behavior: BehaviorId,
        _position: usize,
        value: u16,
    ) -> core::fmt::Result {
        bt_formats::names::write_value_name(f, &self.objects, value)
    }

    /// The object with this name (`#index` for a domain alone).
    fn parse_arg(&self, _behavior: BehaviorId, _position: usize, text: &str) -> Option<u16> {
        bt_formats::names::parse_value_name(&self.objects, text)
    }
}
