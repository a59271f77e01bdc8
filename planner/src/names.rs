//! The names an image carries for tools on the host: its title, every behavior of its
//! behavior set (name, kind, arity, parameter names) and the names of its leaves'
//! values (the problem's objects).
//!
//! Written into the image's names section (`bt_core::image::SECTION_NAMES`), which a
//! controller never reads. With it, `inspect` and `export` print what the tree really
//! names even for a domain or problem the binary has never seen; a [`NameTable`] is a
//! [`Catalog`] whose fingerprint must equal the image's, so names that do not belong to
//! the image are detected, not shown.
//!
//! Layout of the section body: one byte, the table's own format version (1), then the
//! table as [postcard](https://docs.rs/postcard) writes [`NameTable`]'s fields in order.
//!
//! ```
//! use planner::{domains, names::NameTable, PddlCatalog};
//! let g = domains::cube_sphere()?;
//! let catalog = PddlCatalog::new(g.problem());
//! let table = NameTable::of_pddl("problem `blocked`", &catalog);
//! let back = NameTable::from_bytes(&table.to_bytes())?;
//! assert_eq!(back, table);
//! assert_eq!(bt_core::Catalog::fingerprint(&back), bt_core::Catalog::fingerprint(&catalog));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use bt_core::{BehaviorId, BehaviorInfo, Catalog, LeafKind};
use serde::{Deserialize, Serialize};

use crate::catalog::{PddlCatalog, Ports};

/// The version of the names section's own layout.
const FORMAT: u8 = 1;

/// One behavior as the names section records it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct BehaviorName {
    /// Its name, e.g. `at` or `MoveTo`.
    pub name: String,
    /// True for an action, false for a condition.
    pub action: bool,
    /// Number of values a leaf of it carries.
    pub arity: u8,
    /// Names of its parameters or ports (may be empty when unknown).
    pub params: Vec<String>,
}

/// An image's names: see the module docs.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct NameTable {
    /// What the tree is for, e.g. "PDDL problem `blocked` of domain `cube-sphere`".
    pub title: String,
    /// Every behavior of the set, in id order.
    pub behaviors: Vec<BehaviorName>,
    /// The names of leaf values by value id (a PDDL problem's objects).
    pub values: Vec<String>,
}

/// Why a names section could not be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NamesError {
    /// The section is of a later layout than this build knows.
    #[error("names section format {0} is not supported (this build reads format {FORMAT})")]
    Format(u8),
    /// The bytes do not decode.
    #[error("names section is malformed: {0}")]
    Malformed(String),
}

impl NameTable {
    /// The names of any catalog, with value names `values` and parameter names where
    /// `ports` knows them.
    #[must_use]
    pub fn of<C: Catalog + ?Sized>(title: &str, catalog: &C, ports: Option<&dyn Ports>, values: &[String]) -> Self {
        let behaviors = (0..catalog.len())
            .filter_map(|i| {
                let id = BehaviorId::try_from(i).ok()?;
                let info = catalog.info(id)?;
                let params = match ports {
                    Some(p) => (0..usize::from(info.arity)).filter_map(|k| p.port(id, k).map(str::to_string)).collect(),
                    None => Vec::new(),
                };
                Some(BehaviorName {
                    name: info.name.to_string(),
                    action: info.kind == LeafKind::Action,
                    arity: info.arity,
                    params,
                })
            })
            .collect();
        Self { title: title.to_string(), behaviors, values: values.to_vec() }
    }

    /// The names of a PDDL problem's catalog: predicates and actions with their
    /// parameter names, and the problem's objects.
    #[must_use]
    pub fn of_pddl(title: &str, catalog: &PddlCatalog) -> Self {
        Self::of(title, catalog, Some(catalog), catalog.objects())
    }

    /// The section body.
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = vec![FORMAT];
        // Serializing strings and vectors into a Vec cannot fail.
        out.extend(postcard::to_allocvec(self).unwrap_or_default());
        out
    }

    /// Reads a section body.
    ///
    /// # Errors
    /// [`NamesError`] for another layout version or bytes that do not decode.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, NamesError> {
        match bytes.split_first() {
            Some((&FORMAT, rest)) => {
                let (table, tail) =
                    postcard::take_from_bytes::<Self>(rest).map_err(|e| NamesError::Malformed(e.to_string()))?;
                if tail.is_empty() {
                    Ok(table)
                } else {
                    let n = tail.len();
                    Err(NamesError::Malformed(format!("{n} byte{} after the table", if n == 1 { "" } else { "s" })))
                }
            }
            Some((&other, _)) => Err(NamesError::Format(other)),
            None => Err(NamesError::Malformed("empty".to_string())),
        }
    }
}

impl Catalog for NameTable {
    fn len(&self) -> usize {
        self.behaviors.len()
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        self.behaviors.get(usize::from(id)).map(|b| BehaviorInfo {
            name: &b.name,
            kind: if b.action { LeafKind::Action } else { LeafKind::Condition },
            arity: b.arity,
        })
    }

    fn write_arg(&self, f: &mut core::fmt::Formatter<'_>, _: BehaviorId, _: usize, value: u16) -> core::fmt::Result {
        match self.values.get(usize::from(value)) {
            Some(name) => f.write_str(name),
            None => write!(f, "#{value}"),
        }
    }
}

impl Ports for NameTable {
    fn port(&self, behavior: BehaviorId, position: usize) -> Option<&str> {
        self.behaviors.get(usize::from(behavior))?.params.get(position).map(String::as_str)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_keeps_the_fingerprint_and_names_of_its_catalog() {
        let g = crate::domains::cube_sphere().unwrap();
        let catalog = PddlCatalog::new(g.problem());
        let t = NameTable::of_pddl("t", &catalog);
        assert_eq!(t.fingerprint(), catalog.fingerprint());
        assert_eq!(t.values, catalog.objects());
        let at = t.behaviors.iter().position(|b| b.name == "at").unwrap() as u16;
        assert_eq!(Ports::port(&t, at, 1), catalog.param(at, 1));
    }

    #[test]
    fn bad_sections_are_named() {
        assert_eq!(NameTable::from_bytes(&[]), Err(NamesError::Malformed("empty".into())));
        assert_eq!(NameTable::from_bytes(&[7, 0]), Err(NamesError::Format(7)));
        assert!(matches!(NameTable::from_bytes(&[1, 200]), Err(NamesError::Malformed(_))));
        let mut b = NameTable::default().to_bytes();
        b.push(0);
        assert_eq!(NameTable::from_bytes(&b), Err(NamesError::Malformed("1 byte after the table".into())));
    }
}
