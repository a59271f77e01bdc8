//! `<TreeNodesModel>`: the node types a document declares and their ports, and how a
//! port's declared type decides what a literal written for it means.

use bt_core::{PortDirection, PortType};

use crate::error::{Fault, ImportError, Location, Result};
use crate::xml::document::Element;

/// What kind of node a model declares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ModelKind {
    /// `<Action ID>`: a leaf that may run over several ticks.
    Action,
    /// `<Condition ID>`: a leaf that answers at once.
    Condition,
    /// `<Control ID>`: a node with children.
    Control,
    /// `<Decorator ID>`: a node with one child.
    Decorator,
    /// `<SubTree ID>`: the ports of a `<BehaviorTree>` used as a SubTree.
    SubTree,
}

impl ModelKind {
    /// The model tag: `Action`, `Condition`, ...
    #[must_use]
    pub const fn tag(self) -> &'static str {
        match self {
            Self::Action => "Action",
            Self::Condition => "Condition",
            Self::Control => "Control",
            Self::Decorator => "Decorator",
            Self::SubTree => "SubTree",
        }
    }

    /// The kind a model tag (or an explicit node element: `<Action ID>`) names.
    #[must_use]
    pub fn from_tag(tag: &str) -> Option<Self> {
        Some(match tag {
            "Action" => Self::Action,
            "Condition" => Self::Condition,
            "Control" => Self::Control,
            "Decorator" => Self::Decorator,
            "SubTree" => Self::SubTree,
            _ => return None,
        })
    }
}

/// One declared port.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PortModel {
    /// Its name.
    pub name: String,
    /// Input, output or both.
    pub direction: PortDirection,
    /// The `type` attribute as written (`None` when absent: any type).
    pub type_name: Option<String>,
    /// The `default` attribute.
    pub default: Option<String>,
}

impl PortModel {
    /// The type class the controller sees.
    #[must_use]
    pub fn ty(&self) -> PortType {
        classify(self.type_name.as_deref())
    }
}

/// Where a model comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// A file given as models (`--nodes`): what the C++ program registers, which
    /// BehaviorTree.CPP goes by.
    Given,
    /// The tree file or a file it includes: a copy, as Groot saves it, which
    /// BehaviorTree.CPP itself ignores.
    InFile,
}

/// One `<Action ID>`, `<Condition ID>`, ... entry.
#[derive(Clone, Debug)]
pub struct NodeModel {
    /// The node type's registration ID.
    pub id: String,
    /// What it is.
    pub kind: ModelKind,
    /// Its ports, in the order the model lists them.
    pub ports: Vec<PortModel>,
    /// Where the entry is.
    pub at: Location,
    /// Which file it comes from.
    pub origin: Origin,
}

impl NodeModel {
    /// The port named `name`.
    #[must_use]
    pub fn port(&self, name: &str) -> Option<&PortModel> {
        self.ports.iter().find(|p| p.name == name)
    }
}

/// The entries of one `<TreeNodesModel>` element of a file of that origin.
pub(crate) fn read_models(models: &Element, origin: Origin) -> Result<Vec<NodeModel>> {
    let mut out = Vec::new();
    for entry in &models.children {
        let Some(kind) = ModelKind::from_tag(&entry.tag) else {
            continue; // BehaviorTree.CPP ignores other tags here as well
        };
        let Some(id) = entry.attr("ID") else {
            return Err(ImportError::new(
                &entry.at,
                Fault::MissingAttribute { element: entry.tag.clone(), attribute: "ID" },
            ));
        };
        let mut ports: Vec<PortModel> = Vec::new();
        for p in &entry.children {
            let direction = match p.tag.as_str() {
                "input_port" => PortDirection::Input,
                "output_port" => PortDirection::Output,
                "inout_port" | "bidirectional_port" => PortDirection::InOut,
                _ => continue, // <MetadataFields>, <description>
            };
            let Some(name) = p.attr("name") else {
                return Err(ImportError::new(
                    &p.at,
                    Fault::MissingAttribute { element: p.tag.clone(), attribute: "name" },
                ));
            };
            if ports.iter().any(|q| q.name == name) {
                return Err(ImportError::new(
                    &p.at,
                    Fault::ModelConflict {
                        id: id.to_string(),
                        first: entry.at.clone(),
                        difference: format!("port `{name}` is declared twice in it"),
                        hint: String::new(),
                    },
                ));
            }
            ports.push(PortModel {
                name: name.to_string(),
                direction,
                type_name: p.attr("type").map(str::to_string),
                default: p.attr("default").map(str::to_string),
            });
        }
        out.push(NodeModel { id: id.to_string(), kind, ports, at: entry.at.clone(), origin });
    }
    Ok(out)
}

/// The type class of a declared C++ type name. Integers of every width (and
/// `std::chrono::milliseconds`, which BehaviorTree.CPP reads as an integer), `double`
/// and `float`, `bool`, `std::string`; no type, `AnyTypeAllowed` or `BT::Any` is any
/// type; every other type (messages, vectors, enums) is opaque.
#[must_use]
pub fn classify(type_name: Option<&str>) -> PortType {
    let Some(t) = type_name else {
        return PortType::Any;
    };
    let t = t.trim();
    let t = t.strip_prefix("std::").unwrap_or(t);
    if int_range(t).is_some() {
        return PortType::Int;
    }
    match t {
        // Not strongly typed in BehaviorTree.CPP (`PortInfo::isStronglyTyped`).
        "" | "AnyTypeAllowed" | "BT::AnyTypeAllowed" | "Any" | "BT::Any" => PortType::Any,
        "double" | "float" => PortType::Double,
        "bool" => PortType::Bool,
        "string" | "__cxx11::basic_string<char, std::char_traits<char>, std::allocator<char> >" => PortType::String,
        _ => PortType::Other,
    }
}

/// The range of an integer type name (without `std::`).
fn int_range(t: &str) -> Option<(i128, i128)> {
    let t = t.strip_prefix("chrono::").map_or(t, |_| "milliseconds");
    Some(match t {
        "int8_t" | "int8" | "char" | "signed char" => (i8::MIN.into(), i8::MAX.into()),
        "uint8_t" | "uint8" | "unsigned char" => (0, u8::MAX.into()),
        "int16_t" | "int16" | "short" => (i16::MIN.into(), i16::MAX.into()),
        "uint16_t" | "uint16" | "unsigned short" => (0, u16::MAX.into()),
        "int" | "int32_t" | "int32" => (i32::MIN.into(), i32::MAX.into()),
        "unsigned" | "unsigned int" | "uint32_t" | "uint32" | "uint" => (0, u32::MAX.into()),
        "long" | "long int" | "long long" | "int64_t" | "int64" | "milliseconds" | "ssize_t" => {
            (i64::MIN.into(), i64::MAX.into())
        }
        "unsigned long" | "unsigned long long" | "uint64_t" | "uint64" | "size_t" => (0, u64::MAX.into()),
        _ => return None,
    })
}

/// A literal converted for a port of type `type_name`, as BehaviorTree.CPP's
/// `convertFromString` would read it; `None` when it does not convert.
#[must_use]
pub fn convert(type_name: Option<&str>, literal: &str) -> Option<Literal> {
    match classify(type_name) {
        PortType::Int => {
            let t = type_name.unwrap_or("").trim();
            let (lo, hi) =
                int_range(t.strip_prefix("std::").unwrap_or(t)).unwrap_or((i64::MIN.into(), i64::MAX.into()));
            let v: i128 = literal.trim().parse().ok()?;
            // Stored as i64: an unsigned 64-bit value above i64::MAX does not fit.
            (v >= lo && v <= hi).then_some(())?;
            Some(Literal::Int(i64::try_from(v).ok()?))
        }
        PortType::Double => {
            let v: f64 = literal.trim().parse().ok()?;
            v.is_finite().then_some(Literal::Double(v))
        }
        PortType::Bool => match literal {
            "1" | "true" | "TRUE" | "True" => Some(Literal::Bool(true)),
            "0" | "false" | "FALSE" | "False" => Some(Literal::Bool(false)),
            _ => None,
        },
        PortType::Any | PortType::String | PortType::Other => Some(Literal::Str(literal.to_string())),
    }
}

/// A constant as the image holds it (interned by [`Literal::key`], written back by
/// [`Literal::text`]).
pub use bt_formats::Constant as Literal;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn types_are_classified_as_the_controller_reads_them() {
        assert_eq!(classify(Some("double")), PortType::Double);
        assert_eq!(classify(Some("unsigned int")), PortType::Int);
        assert_eq!(classify(Some("chrono::milliseconds")), PortType::Int);
        assert_eq!(classify(Some("std::chrono::milliseconds")), PortType::Int);
        assert_eq!(classify(Some("uint16")), PortType::Int);
        assert_eq!(classify(Some("std::string")), PortType::String);
        assert_eq!(classify(Some("string")), PortType::String);
        assert_eq!(classify(Some("geometry_msgs::msg::PoseStamped")), PortType::Other);
        assert_eq!(classify(Some("vector<int>")), PortType::Other);
        assert_eq!(classify(None), PortType::Any);
        assert_eq!(classify(Some("BT::Any")), PortType::Any);
    }

    #[test]
    fn literals_convert_as_behaviortree_cpp_reads_them() {
        assert_eq!(convert(Some("int"), "-3"), Some(Literal::Int(-3)));
        assert_eq!(convert(Some("unsigned int"), "-3"), None);
        assert_eq!(convert(Some("uint16"), "65536"), None);
        assert_eq!(convert(Some("int"), "1.5"), None);
        assert_eq!(convert(Some("double"), "1.57"), Some(Literal::Double(1.57)));
        assert_eq!(convert(Some("double"), "12"), Some(Literal::Double(12.0)));
        assert_eq!(convert(Some("double"), "fast"), None);
        assert_eq!(convert(Some("bool"), "True"), Some(Literal::Bool(true)));
        assert_eq!(convert(Some("bool"), "yes"), None);
        assert_eq!(convert(Some("nav_msgs::msg::Path"), "x"), Some(Literal::Str("x".into())));
        assert_eq!(Literal::Double(1.0).text(), "1.0");
        assert_eq!(Literal::Double(0.1).text(), "0.1");
        assert_eq!(Literal::Double(1e300).text(), "1e300");
    }
}
