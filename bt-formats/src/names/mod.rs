//! The names an image carries for tools on the host: its title and tree ID, every behavior of its
//! behavior set (name, kind, arity, the names of its values and, for behaviors that
//! declare them, its ports with direction, type and default), the names of its leaves'
//! values (a PDDL problem's objects), of its blackboard slots (the keys) and of the
//! scripting enums its scripts read.
//!
//! Written into the image's names section (`bt_core::image::SECTION_NAMES`), which a
//! controller never reads and `sim-host deploy --strip-names` drops. With it, `inspect`,
//! `export` and `btlog` show the tree as its user wrote it even for a behavior set the
//! binary has never seen. [`Names`] is a [`Catalog`] whose fingerprint must equal the
//! image's, so names that do not belong to the image are detected, not shown. The
//! constants of the image's ports section (which the controller does read) come with
//! it from [`Names::of_image`].
//!
//! The section body's layout is in [`section`].

pub mod section;

use bt_core::{BehaviorId, BehaviorInfo, Catalog, LeafKind, PortDirection, PortInfo, PortTable, PortType};

use crate::constant::{Constant, write_port_value};

pub use section::NamesError;

/// An image's names: see the module docs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Names {
    /// What the tree is, e.g. "PDDL problem `blocked` of domain `cube-sphere`".
    pub title: String,
    /// The tree's ID in BehaviorTree.CPP XML (`FollowPoint`); empty when it has none.
    pub tree_id: String,
    /// Every behavior of the set, in id order.
    pub behaviors: Vec<BehaviorNames>,
    /// The names of grounded leaf values by value (a PDDL problem's objects).
    pub values: Vec<String>,
    /// The blackboard keys by slot (`goal` for slot 0).
    pub slots: Vec<String>,
    /// The scripting enums the tree's scripts were compiled with, as `(name, value)`.
    pub enums: Vec<(String, i64)>,
    /// The constants of the image's ports section by index (not part of the names
    /// section: the controller reads them there).
    pub constants: Vec<Constant>,
    /// The `BTCPP_format` of the BehaviorTree.CPP document the tree was imported from
    /// (3 or 4), whose rules its XML is written by; 0 for trees made otherwise.
    pub source_format: u8,
    /// What the document the tree was imported from says of each node, in node order
    /// (empty for trees made otherwise): what tools need to write it back as it was
    /// written (scripts, loops, node names) and number it as its library does.
    pub nodes: Vec<NodeSource>,
    /// The document's SubTree nodes, which the flat tree has no nodes for.
    pub subtrees: Vec<SubtreeSource>,
}

/// What the source document says of one node of the tree, which the bt-core node does
/// not keep.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NodeSource {
    /// Its registration ID (`Sequence`, `SetBlackboard`, `ComputePathToPose`).
    pub id: String,
    /// Its `name` attribute.
    pub name: Option<String>,
    /// BehaviorTree.CPP's node id: creation order from 1, SubTree nodes included.
    pub uid: u16,
    /// A built-in node's parameters as written (`num_cycles="-1"`), in document order:
    /// what BehaviorTree.CPP writes back into its logs, where bt-core keeps only the
    /// resolved value. Empty for leaves and plugin decorators (their ports are values).
    pub params: Vec<(String, String)>,
    /// For a script node or a guard: its attributes as the XML of the flattened tree
    /// writes them, each script with every key as that tree names it (a key a SubTree
    /// remaps becomes its parent's, a SubTree's local key a name made of its instance's
    /// path; a guard's attributes go on the node it guards). `None` for other nodes,
    /// whose `params` are written as they are.
    pub flat: Option<Vec<(String, String)>>,
}

/// A `<SubTree>` node of the source document: BehaviorTree.CPP keeps it as a node (with
/// a uid and a status), the flattened tree does not.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SubtreeSource {
    /// The node its subtree's root became.
    pub node: u16,
    /// BehaviorTree.CPP's node id.
    pub uid: u16,
    /// The subtree's ID.
    pub id: String,
    /// Its `name` attribute.
    pub name: Option<String>,
    /// The node's `_fullpath`.
    pub path: String,
    /// The instance's path (the `_fullpath` of its `<BehaviorTree>`).
    pub instance: String,
    /// Its port attributes as written.
    pub attrs: Vec<(String, String)>,
}

/// One behavior as the names section records it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BehaviorNames {
    /// Its name, e.g. `at` or `ComputePathToPose`.
    pub name: String,
    /// Condition or action.
    pub kind: LeafKind,
    /// Number of values a leaf of it carries.
    pub arity: u8,
    /// Its values in order, one per value, or none when the set does not name them.
    pub params: Vec<Param>,
}

/// One value of a behavior: its name, and its declaration when it is a declared port.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Param {
    /// The name it is shown and written under (empty: none).
    pub name: String,
    /// Its declaration as a port, which the fingerprint covers; `None` for a grounded
    /// argument (a PDDL parameter).
    pub port: Option<Declared>,
}

/// A declared port's direction, type and default (its name is the [`Param`]'s).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Declared {
    /// Input, output or both.
    pub direction: PortDirection,
    /// The type class the controller reads.
    pub ty: PortType,
    /// The type as the model writes it (empty when none is declared).
    pub type_name: String,
    /// The default value's text, when the model declares one.
    pub default: Option<String>,
}

impl Names {
    /// The names of any behavior set: each behavior with the names of its values and
    /// its declared ports ([`Catalog::port_name`], [`Catalog::port`]), titled `title`,
    /// with `values` naming grounded leaf values. Slots, enums and constants are left
    /// empty for the producer to fill in.
    #[must_use]
    pub fn of<C: Catalog + ?Sized>(title: &str, catalog: &C, values: &[String]) -> Self {
        let behaviors = (0..catalog.len())
            .filter_map(|i| {
                let id = BehaviorId::try_from(i).ok()?;
                let info = catalog.info(id)?;
                let mut params: Vec<Param> = (0..usize::from(info.arity))
                    .map(|k| Param {
                        name: catalog.port_name(id, k).unwrap_or_default().to_string(),
                        port: catalog.port(id, k).map(|p| Declared {
                            direction: p.direction,
                            ty: p.ty,
                            type_name: p.type_name.to_string(),
                            default: p.default.map(str::to_string),
                        }),
                    })
                    .collect();
                if params.iter().all(|p| p.name.is_empty() && p.port.is_none()) {
                    params.clear();
                }
                Some(BehaviorNames { name: info.name.to_string(), kind: info.kind, arity: info.arity, params })
            })
            .collect();
        Self { title: title.to_string(), behaviors, values: values.to_vec(), ..Self::default() }
    }

    /// The names of an image and the constants of its ports section; `Ok(None)` when
    /// the image has no names section.
    ///
    /// # Errors
    /// [`NamesError::Image`] for a bad envelope, nodes or sections (the image itself is
    /// at fault), another [`NamesError`] for a names section this build cannot read.
    pub fn of_image(bytes: &[u8]) -> Result<Option<Self>, NamesError> {
        let Some(body) = bt_core::image::section(bytes, bt_core::image::SECTION_NAMES)? else {
            return Ok(None);
        };
        let mut names = Self::from_section(body)?;
        let table = PortTable::of_image(bytes)?;
        names.constants = (0..table.constant_count()).filter_map(|i| table.constant(i)).map(Constant::from).collect();
        Ok(Some(names))
    }

    /// Whether some behavior declares ports: the fingerprint then covers them, and a
    /// BehaviorTree.CPP document must declare every behavior to give the set back.
    #[must_use]
    pub fn declares_ports(&self) -> bool {
        self.behaviors.iter().any(|b| b.params.iter().any(|p| p.port.is_some()))
    }

    fn param(&self, behavior: BehaviorId, position: usize) -> Option<&Param> {
        self.behaviors.get(usize::from(behavior))?.params.get(position)
    }
}

impl Catalog for Names {
    fn len(&self) -> usize {
        self.behaviors.len()
    }

    fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
        self.behaviors.get(usize::from(id)).map(|b| BehaviorInfo { name: &b.name, kind: b.kind, arity: b.arity })
    }

    fn port(&self, id: BehaviorId, position: usize) -> Option<PortInfo<'_>> {
        let p = self.param(id, position)?;
        let d = p.port.as_ref()?;
        Some(PortInfo {
            name: &p.name,
            direction: d.direction,
            ty: d.ty,
            type_name: &d.type_name,
            default: d.default.as_deref(),
        })
    }

    fn port_name(&self, id: BehaviorId, position: usize) -> Option<&str> {
        Some(self.param(id, position)?.name.as_str()).filter(|n| !n.is_empty())
    }

    /// A declared port's value as written (`{goal}`, `GridBased`); a grounded value by
    /// its name (`cube`), else `#value`.
    fn write_arg(
        &self,
        f: &mut std::fmt::Formatter<'_>,
        behavior: BehaviorId,
        position: usize,
        value: u16,
    ) -> std::fmt::Result {
        if self.port(behavior, position).is_some() {
            return write_port_value(
                f,
                value,
                |s| self.slots.get(usize::from(s)).map(String::as_str),
                |c| self.constants.get(usize::from(c)).map(Constant::as_constant),
            );
        }
        write_value_name(f, &self.values, value)
    }

    /// A grounded value by its name (`#index` when the names have no values); a
    /// declared port's value cannot be read back without its tree's ports section.
    fn parse_arg(&self, behavior: BehaviorId, position: usize, text: &str) -> Option<u16> {
        if self.port(behavior, position).is_some() {
            return None;
        }
        parse_value_name(&self.values, text)
    }
}

/// Writes grounded value `value` by its name in `names` (a PDDL problem's objects),
/// `#value` when it has none.
///
/// # Errors
/// Whatever the formatter returns.
pub fn write_value_name(f: &mut std::fmt::Formatter<'_>, names: &[String], value: u16) -> std::fmt::Result {
    match names.get(usize::from(value)) {
        Some(name) => f.write_str(name),
        None => write!(f, "#{value}"),
    }
}

/// The grounded value named `text` in `names`: the inverse of [`write_value_name`]
/// (`#index` when there are no names at all).
#[must_use]
pub fn parse_value_name(names: &[String], text: &str) -> Option<u16> {
    match text.strip_prefix('#') {
        Some(n) if names.is_empty() => n.parse().ok(),
        _ => names.iter().position(|v| v == text).and_then(|i| u16::try_from(i).ok()),
    }
}

#[cfg(test)]
mod tests {
    use bt_core::{Behavior, BehaviorInfo, Leaf, PortInfo, fingerprint, fingerprint_with_ports};

    use super::*;

    const PORTS: [PortInfo<'static>; 3] = [
        PortInfo::input("goal", PortType::Other, "Pose"),
        PortInfo::input("planner_id", PortType::String, "std::string").with_default("GridBased"),
        PortInfo::output("path", PortType::Other, "nav_msgs::msg::Path"),
    ];

    fn shown<C: Catalog + ?Sized>(c: &C, behavior: u16, values: &[u16]) -> String {
        bt_core::render::display_leaf(c, &Leaf::with_args(behavior, values).unwrap(), values).to_string()
    }

    #[test]
    fn names_of_a_set_with_ports_keep_its_fingerprint_and_show_ports_as_written() {
        let set = [
            Behavior::new(BehaviorInfo::condition("IsStuck", 0), &[]),
            Behavior::new(BehaviorInfo::action("ComputePathToPose", 3), &PORTS),
        ];
        let mut names = Names::of("t", &set[..], &[]);
        assert_eq!(names.fingerprint(), fingerprint_with_ports(&set));
        assert!(names.declares_ports());
        assert!(names.behaviors[0].params.is_empty());
        names.slots = vec!["goal".into(), "path".into()];
        names.constants = vec![Constant::Str("GridBased".into())];
        assert_eq!(
            shown(&names, 1, &[0x8000, 0, 0x8001]),
            "ComputePathToPose(goal={goal}, planner_id=GridBased, path={path})"
        );
        assert_eq!(
            shown(&names, 1, &[0x8000, bt_core::port::UNSET, 0x8001]),
            "ComputePathToPose(goal={goal}, path={path})"
        );
        assert_eq!(
            shown(&names, 1, &[0x8005, 7, 0x8001]),
            "ComputePathToPose(goal={#slot5}, planner_id=#const7, path={path})"
        );
        assert_eq!(names.port(1, 1).and_then(|p| p.default), Some("GridBased"));
        assert_eq!(names.parse_arg(1, 0, "{goal}"), None);
    }

    #[test]
    fn names_of_grounded_arguments_keep_the_fingerprint_without_ports() {
        struct Pddl;
        const SET: [BehaviorInfo<'static>; 2] = [BehaviorInfo::condition("at", 2), BehaviorInfo::action("pick", 1)];
        impl Catalog for Pddl {
            fn len(&self) -> usize {
                SET.len()
            }
            fn info(&self, id: BehaviorId) -> Option<BehaviorInfo<'_>> {
                SET.get(usize::from(id)).copied()
            }
            fn port_name(&self, id: BehaviorId, position: usize) -> Option<&str> {
                [["o", "p"], ["o", ""]].get(usize::from(id))?.get(position).copied()
            }
        }
        let objects = vec!["cube".to_string(), "goal".to_string()];
        let names = Names::of("t", &Pddl, &objects);
        assert_eq!(names.fingerprint(), fingerprint(&SET));
        assert!(!names.declares_ports());
        assert_eq!(names.port_name(0, 1), Some("p"));
        assert_eq!(shown(&names, 0, &[0, 1]), "at(cube, goal)");
        assert_eq!(shown(&names, 0, &[0, 9]), "at(cube, #9)");
        assert_eq!(names.parse_arg(0, 1, "goal"), Some(1));
        assert_eq!(names.parse_arg(0, 1, "#1"), None);
        assert_eq!(Names::of("t", &SET[..], &[]).parse_arg(0, 1, "#1"), Some(1));
    }
}
