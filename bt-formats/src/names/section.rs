//! The names section's body, as bytes.
//!
//! One byte, the layout's own version, then the table as
//! [postcard](https://docs.rs/postcard) writes these fields in order (a `String` is a
//! varint length and UTF-8 bytes, a list a varint length and its items, an `Option` a
//! byte 0 or 1 and the value):
//!
//! | version | fields |
//! |--------:|--------|
//! | 3 (written) | version 2's, then the source document's `BTCPP_format` `u8` (0: none), the source nodes: list of (ID `String`; name `Option<String>`; uid `u16`; parameters: list of (`String`, `String`); flat: `Option` of such a list), then the SubTree nodes: list of (node `u16`; uid `u16`; ID `String`; name `Option<String>`; path `String`; instance `String`; attributes: list of (`String`, `String`)) |
//! | 2 (read) | title `String`; tree ID `String`; behaviors: list of (name `String`, action `bool`, arity `u8`, values: list of (name `String`, port: `Option` of (direction `u8`: 0 input, 1 output, 2 in/out; type `u8` as [`bt_core::PortType`]; type name `String`; default `Option<String>`))); value names: list of `String`; slot names: list of `String`; enums: list of (name `String`, value `i64` zigzag varint) |
//! | 1 (read) | title; behaviors: list of (name, action, arity, parameter names: list of `String`); value names |
//!
//! A behavior's list of values is empty or has one entry per value (its arity). The
//! version changes with any change to these fields; a controller never reads the
//! section, so only host tools follow it.

use bt_core::{LeafKind, PortDirection, PortType};
use serde::{Deserialize, Serialize};

use super::{BehaviorNames, Declared, Names, NodeSource, Param, SubtreeSource};

/// The version of the names section's layout this build writes.
pub const FORMAT: u8 = 3;

/// Why a names section could not be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum NamesError {
    /// The section is of a layout this build does not know.
    #[error("names section format {0} is not supported (this build reads formats 1 to {FORMAT})")]
    Format(u8),
    /// The bytes do not decode, or decode to names that contradict themselves.
    #[error("names section is malformed: {0}")]
    Malformed(String),
    /// The image around the section is at fault.
    #[error(transparent)]
    Image(#[from] bt_core::LoadError),
}

#[derive(Serialize, Deserialize)]
struct V2 {
    title: String,
    tree_id: String,
    behaviors: Vec<BehaviorV2>,
    values: Vec<String>,
    slots: Vec<String>,
    enums: Vec<(String, i64)>,
}

#[derive(Serialize, Deserialize)]
struct V3 {
    v2: V2,
    source_format: u8,
    nodes: Vec<NodeV3>,
    subtrees: Vec<SubtreeV3>,
}

type Attrs = Vec<(String, String)>;

#[derive(Serialize, Deserialize)]
struct NodeV3 {
    id: String,
    name: Option<String>,
    uid: u16,
    params: Attrs,
    flat: Option<Attrs>,
}

#[derive(Serialize, Deserialize)]
struct SubtreeV3 {
    node: u16,
    uid: u16,
    id: String,
    name: Option<String>,
    path: String,
    instance: String,
    attrs: Attrs,
}

#[derive(Serialize, Deserialize)]
struct BehaviorV2 {
    name: String,
    action: bool,
    arity: u8,
    params: Vec<ParamV2>,
}

#[derive(Serialize, Deserialize)]
struct ParamV2 {
    name: String,
    port: Option<PortV2>,
}

#[derive(Serialize, Deserialize)]
struct PortV2 {
    direction: u8,
    ty: u8,
    type_name: String,
    default: Option<String>,
}

#[derive(Deserialize)]
struct V1 {
    title: String,
    behaviors: Vec<BehaviorV1>,
    values: Vec<String>,
}

#[derive(Deserialize)]
struct BehaviorV1 {
    name: String,
    action: bool,
    arity: u8,
    params: Vec<String>,
}

const fn kind(action: bool) -> LeafKind {
    if action { LeafKind::Action } else { LeafKind::Condition }
}

const fn direction_byte(d: PortDirection) -> u8 {
    match d {
        PortDirection::Input => 0,
        PortDirection::Output => 1,
        PortDirection::InOut => 2,
    }
}

impl Names {
    /// The section body (the constants are not part of it).
    #[must_use]
    pub fn to_section(&self) -> Vec<u8> {
        let v2 = V2 {
            title: self.title.clone(),
            tree_id: self.tree_id.clone(),
            behaviors: self
                .behaviors
                .iter()
                .map(|b| BehaviorV2 {
                    name: b.name.clone(),
                    action: b.kind == LeafKind::Action,
                    arity: b.arity,
                    params: b
                        .params
                        .iter()
                        .map(|p| ParamV2 {
                            name: p.name.clone(),
                            port: p.port.as_ref().map(|d| PortV2 {
                                direction: direction_byte(d.direction),
                                ty: d.ty as u8,
                                type_name: d.type_name.clone(),
                                default: d.default.clone(),
                            }),
                        })
                        .collect(),
                })
                .collect(),
            values: self.values.clone(),
            slots: self.slots.clone(),
            enums: self.enums.clone(),
        };
        let v3 = V3 {
            v2,
            source_format: self.source_format,
            nodes: self
                .nodes
                .iter()
                .map(|n| NodeV3 {
                    id: n.id.clone(),
                    name: n.name.clone(),
                    uid: n.uid,
                    params: n.params.clone(),
                    flat: n.flat.clone(),
                })
                .collect(),
            subtrees: self
                .subtrees
                .iter()
                .map(|s| SubtreeV3 {
                    node: s.node,
                    uid: s.uid,
                    id: s.id.clone(),
                    name: s.name.clone(),
                    path: s.path.clone(),
                    instance: s.instance.clone(),
                    attrs: s.attrs.clone(),
                })
                .collect(),
        };
        let mut out = vec![FORMAT];
        // Serializing strings and vectors into a Vec cannot fail.
        out.extend(postcard::to_allocvec(&v3).unwrap_or_default());
        out
    }

    /// Reads a section body, of this layout, of version 2 (no source nodes) or of
    /// version 1 (no ports, slots or enums either).
    ///
    /// # Errors
    /// [`NamesError::Format`] for another layout version, [`NamesError::Malformed`] for
    /// bytes that do not decode or a behavior whose values do not match its arity.
    pub fn from_section(bytes: &[u8]) -> Result<Self, NamesError> {
        let names = match bytes.split_first() {
            Some((&FORMAT, rest)) => from_v3(whole::<V3>(rest)?)?,
            Some((&2, rest)) => from_v2(whole::<V2>(rest)?)?,
            Some((&1, rest)) => from_v1(whole::<V1>(rest)?),
            Some((&other, _)) => return Err(NamesError::Format(other)),
            None => return Err(NamesError::Malformed("empty".to_string())),
        };
        Ok(names)
    }
}

/// Decodes `bytes` as one `T` with nothing after it.
fn whole<'de, T: Deserialize<'de>>(bytes: &'de [u8]) -> Result<T, NamesError> {
    let (table, tail) = postcard::take_from_bytes::<T>(bytes).map_err(|e| NamesError::Malformed(e.to_string()))?;
    match tail.len() {
        0 => Ok(table),
        1 => Err(NamesError::Malformed("1 byte after the table".to_string())),
        n => Err(NamesError::Malformed(format!("{n} bytes after the table"))),
    }
}

fn from_v1(t: V1) -> Names {
    let behaviors = t
        .behaviors
        .into_iter()
        .map(|b| BehaviorNames {
            name: b.name,
            kind: kind(b.action),
            arity: b.arity,
            params: b.params.into_iter().map(|name| Param { name, port: None }).collect(),
        })
        .collect();
    Names { title: t.title, behaviors, values: t.values, ..Names::default() }
}

fn from_v3(t: V3) -> Result<Names, NamesError> {
    let mut names = from_v2(t.v2)?;
    names.source_format = t.source_format;
    names.nodes = t
        .nodes
        .into_iter()
        .map(|n| NodeSource { id: n.id, name: n.name, uid: n.uid, params: n.params, flat: n.flat })
        .collect();
    names.subtrees = t
        .subtrees
        .into_iter()
        .map(|s| SubtreeSource {
            node: s.node,
            uid: s.uid,
            id: s.id,
            name: s.name,
            path: s.path,
            instance: s.instance,
            attrs: s.attrs,
        })
        .collect();
    Ok(names)
}

fn from_v2(t: V2) -> Result<Names, NamesError> {
    let mut behaviors = Vec::with_capacity(t.behaviors.len());
    for (id, b) in t.behaviors.into_iter().enumerate() {
        if !b.params.is_empty() && b.params.len() != usize::from(b.arity) {
            return Err(NamesError::Malformed(format!(
                "behavior {id} (`{}`) has arity {} but names {} values",
                b.name,
                b.arity,
                b.params.len()
            )));
        }
        let mut params = Vec::with_capacity(b.params.len());
        for (position, p) in b.params.into_iter().enumerate() {
            let port = match p.port {
                None => None,
                Some(d) => {
                    let bad = |what: &str, byte: u8| {
                        NamesError::Malformed(format!("behavior {id}, port {position}: {what} byte {byte}"))
                    };
                    let direction = match d.direction {
                        0 => PortDirection::Input,
                        1 => PortDirection::Output,
                        2 => PortDirection::InOut,
                        other => return Err(bad("direction", other)),
                    };
                    let ty = PortType::from_u8(d.ty).ok_or_else(|| bad("type", d.ty))?;
                    Some(Declared { direction, ty, type_name: d.type_name, default: d.default })
                }
            };
            params.push(Param { name: p.name, port });
        }
        behaviors.push(BehaviorNames { name: b.name, kind: kind(b.action), arity: b.arity, params });
    }
    Ok(Names {
        title: t.title,
        tree_id: t.tree_id,
        behaviors,
        values: t.values,
        slots: t.slots,
        enums: t.enums,
        ..Names::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Names {
        Names {
            title: "BehaviorTree.CPP tree `Main`".into(),
            tree_id: "Main".into(),
            behaviors: vec![
                BehaviorNames { name: "at".into(), kind: LeafKind::Condition, arity: 0, params: vec![] },
                BehaviorNames {
                    name: "MoveTo".into(),
                    kind: LeafKind::Action,
                    arity: 2,
                    params: vec![
                        Param {
                            name: "goal".into(),
                            port: Some(Declared {
                                direction: PortDirection::InOut,
                                ty: PortType::Double,
                                type_name: "double".into(),
                                default: Some("0.5".into()),
                            }),
                        },
                        Param { name: "path".into(), port: None },
                    ],
                },
            ],
            values: vec!["cube".into()],
            slots: vec!["goal".into()],
            enums: vec![("RED".into(), 1), ("BLUE".into(), -2)],
            constants: Vec::new(),
            source_format: 3,
            nodes: vec![NodeSource {
                id: "SetBlackboard".into(),
                name: Some("init".into()),
                uid: 2,
                params: vec![("value".into(), "1".into()), ("output_key".into(), "k".into())],
                flat: Some(vec![("output_key".into(), "S_3_k".into())]),
            }],
            subtrees: vec![SubtreeSource {
                node: 1,
                uid: 3,
                id: "S".into(),
                name: None,
                path: "S::3".into(),
                instance: "S::3".into(),
                attrs: vec![("x".into(), "{a}".into())],
            }],
        }
    }

    #[test]
    fn a_section_reads_back_as_written() {
        let names = sample();
        let bytes = names.to_section();
        assert_eq!(bytes[0], FORMAT);
        assert_eq!(Names::from_section(&bytes), Ok(names));
    }

    #[test]
    fn version_2_sections_read_without_source_nodes() {
        let mut names = sample();
        names.nodes.clear();
        names.subtrees.clear();
        names.source_format = 0;
        // Version 3 is version 2's fields then the format and two lists, all 0 here.
        let mut bytes = names.to_section();
        assert_eq!(bytes.split_off(bytes.len() - 3), [0, 0, 0]);
        bytes[0] = 2;
        assert_eq!(Names::from_section(&bytes), Ok(names));
    }

    #[test]
    fn version_1_sections_of_images_on_disk_still_read() {
        // Title "t", behavior `at` (condition, arity 2, parameters x and p), object "cube".
        let v1 = [1, 1, b't', 1, 2, b'a', b't', 0, 2, 2, 1, b'x', 1, b'p', 1, 4, b'c', b'u', b'b', b'e'];
        let names = Names::from_section(&v1).unwrap();
        assert_eq!(names.title, "t");
        assert_eq!(names.behaviors[0].name, "at");
        assert_eq!(names.behaviors[0].params[1], Param { name: "p".into(), port: None });
        assert_eq!(names.values, ["cube"]);
        assert!(names.slots.is_empty() && names.enums.is_empty() && names.tree_id.is_empty());
    }

    #[test]
    fn bad_sections_are_named() {
        assert_eq!(Names::from_section(&[]), Err(NamesError::Malformed("empty".into())));
        assert_eq!(Names::from_section(&[7, 0]), Err(NamesError::Format(7)));
        assert!(matches!(Names::from_section(&[3, 200]), Err(NamesError::Malformed(_))));
        let mut b = Names::default().to_section();
        b.push(0);
        assert_eq!(Names::from_section(&b), Err(NamesError::Malformed("1 byte after the table".into())));
        let mut wrong = sample();
        wrong.behaviors[1].arity = 3;
        assert_eq!(
            Names::from_section(&wrong.to_section()),
            Err(NamesError::Malformed("behavior 1 (`MoveTo`) has arity 3 but names 2 values".into()))
        );
        let bytes = sample().to_section();
        // The direction byte of MoveTo's first port: after its two values' count, its
        // name and the `Some` of its declaration.
        let at = bytes.windows(6).position(|w| w == [2, 4, b'g', b'o', b'a', b'l']).unwrap() + 6 + 1;
        let mut bad = bytes.clone();
        bad[at] = 9;
        assert_eq!(
            Names::from_section(&bad),
            Err(NamesError::Malformed("behavior 1, port 0: direction byte 9".into()))
        );
    }
}
