//! How the writer names things: node type IDs that are XML names, port names, argument
//! texts, escaped attribute values.

use bt_core::{BehaviorId, Catalog};

/// An argument as the catalog renders it, e.g. `cube`.
pub(crate) fn arg_text<C: Catalog + ?Sized>(catalog: &C, behavior: u16, position: usize, value: u16) -> String {
    struct A<'a, C: ?Sized>(&'a C, u16, usize, u16);
    impl<C: Catalog + ?Sized> std::fmt::Display for A<'_, C> {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            self.0.write_arg(f, self.1, self.2, self.3)
        }
    }
    A(catalog, behavior, position, value).to_string()
}

/// Attributes as written: ` key="value"` each.
pub(super) fn attr_text<K: AsRef<str>>(written: &[(K, String)]) -> String {
    written.iter().map(|(k, v)| format!(" {}=\"{}\"", k.as_ref(), escape(v))).collect()
}

/// Text as an XML attribute value (between double quotes) or element text.
pub(crate) fn escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&apos;"),
            c => o.push(c),
        }
    }
    o
}

/// Whether the writer uses `p` as a port name as it is (after `-` becomes `_`).
fn is_port_name(p: &str) -> bool {
    p.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && p.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        && p != "name"
        && p != "ID"
}

/// The port value `position` of `behavior` is written as: a declared port's name as it
/// is; a grounded argument's name ([`Catalog::port_name`]) when BehaviorTree.CPP accepts
/// it (a letter first, not `name` or `ID`; `-` becomes `_`), else `arg{position}`.
pub(crate) fn port_name<C: Catalog + ?Sized>(catalog: &C, behavior: BehaviorId, position: usize) -> String {
    if let Some(p) = catalog.port(behavior, position) {
        return p.name.to_string();
    }
    match catalog.port_name(behavior, position) {
        Some(p) if is_port_name(p) => p.replace('-', "_"),
        _ => format!("arg{position}"),
    }
}

pub(super) fn behavior_name<C: Catalog + ?Sized>(catalog: &C, id: BehaviorId) -> String {
    catalog.info(id).map_or_else(|| format!("behavior{id}"), |i| i.name.to_string())
}

/// A node type ID usable as an XML element name: letters, digits, `_` and `-`,
/// starting with a letter; other characters become `_` (one per run, none at the ends).
/// A name that already is one is kept as it is.
pub(crate) fn type_id(name: &str) -> String {
    if name.starts_with(|c: char| c.is_ascii_alphabetic())
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        return name.to_string();
    }
    let mut id = String::with_capacity(name.len() + 1);
    for c in name.chars() {
        if c.is_ascii_alphanumeric() || c == '-' {
            id.push(c);
        } else if !id.is_empty() && !id.ends_with('_') {
            id.push('_');
        }
    }
    while id.ends_with('_') {
        id.pop();
    }
    if !id.starts_with(|c: char| c.is_ascii_alphabetic()) {
        id.insert(0, 'b');
    }
    id
}

#[cfg(test)]
mod tests {
    use super::type_id;

    #[test]
    fn type_ids_are_xml_names() {
        assert_eq!(type_id("place"), "place");
        assert_eq!(type_id("hand-over"), "hand-over");
        assert_eq!(type_id("put 0 on 1!"), "put_0_on_1");
        assert_eq!(type_id("0 at pos (0.0, 0.05, 0.0)?"), "b0_at_pos_0_0_0_05_0_0");
        assert_eq!(type_id("?!"), "b");
    }
}
