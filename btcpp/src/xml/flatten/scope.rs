//! Blackboard scopes and how a port attribute names a key, by the rules of each
//! BehaviorTree.CPP version.
//!
//! | written | BehaviorTree.CPP 4 | BehaviorTree.CPP 3 |
//! |---|---|---|
//! | `{key}` | the key (spaces around the braces allowed) | the key (no spaces) |
//! | `${key}` | a literal | the key |
//! | `{=}`, `=` | the key named as the port | `=`: the key named as the port; `{=}`: the key `=` |
//! | `{@key}` | the root scope's `key` | the key `@key` |
//! | a literal on an output port | refused | the key of that name |

use std::collections::BTreeMap;

use crate::error::Location;
use crate::xml::document::Version;

/// A blackboard entry: a key in a scope.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Key {
    /// The scope (0 is the root).
    pub scope: usize,
    /// The key's name in it.
    pub name: String,
}

/// Which keys a SubTree instance's scope takes from its parent's without a remapping.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Autoremap {
    /// None: unmapped keys are local (an isolated SubTree).
    #[default]
    Off,
    /// Every key but those starting with `_` (BehaviorTree.CPP 4's `_autoremap`).
    Public,
    /// Every key (BehaviorTree.CPP 3's `SubTreePlus __autoremap` and
    /// `SubTree __shared_blackboard`).
    All,
}

/// A blackboard scope: the root, or one SubTree instance.
#[derive(Clone, Debug, Default)]
pub struct Scope {
    /// The instance's path (`""` for the root).
    pub path: String,
    /// Local entries that start with a literal, with where the literal is written.
    pub initial: BTreeMap<String, (String, Location)>,
    pub(super) parent: Option<usize>,
    pub(super) remap: BTreeMap<String, Key>,
    pub(super) autoremap: Autoremap,
}

/// The entry `key` names in `scope`: the parent's key the instance remaps it to, a local
/// entry that starts with a literal, the parent's key of that name when the scope takes
/// it from its parent ([`Autoremap`]), else a key local to the scope. In a
/// BehaviorTree.CPP 4 document `@key` names `key` of the root scope from anywhere.
#[must_use]
pub fn resolve(scopes: &[Scope], version: Version, scope: usize, key: &str) -> Key {
    if version == Version::V4
        && let Some(k) = key.strip_prefix('@')
    {
        return Key { scope: 0, name: k.to_string() };
    }
    let mut scope = scope;
    loop {
        let Some(s) = scopes.get(scope) else {
            return Key { scope, name: key.to_string() };
        };
        if let Some(k) = s.remap.get(key) {
            return k.clone();
        }
        if s.initial.contains_key(key) {
            return Key { scope, name: key.to_string() };
        }
        let inherits = match s.autoremap {
            Autoremap::Off => false,
            Autoremap::Public => !key.starts_with('_'),
            Autoremap::All => true,
        };
        match s.parent {
            Some(p) if inherits => scope = p,
            _ => return Key { scope, name: key.to_string() },
        }
    }
}

/// Whether an attribute value names a blackboard entry, and which key: BehaviorTree.CPP
/// 4's rule (`{key}`, spaces around the braces allowed) or 3's (`{key}` or `${key}`, no
/// spaces).
#[must_use]
pub fn key_in(version: Version, value: &str) -> Option<&str> {
    match version {
        Version::V4 => {
            let t = value.trim_matches(' ');
            (t.len() >= 3 && t.starts_with('{') && t.ends_with('}')).then(|| &t[1..t.len() - 1])
        }
        Version::V3 => {
            if value.len() >= 4 && value.starts_with("${") && value.ends_with('}') {
                Some(&value[2..value.len() - 1])
            } else if value.len() >= 3 && value.starts_with('{') && value.ends_with('}') {
                Some(&value[1..value.len() - 1])
            } else {
                None
            }
        }
    }
}

/// Whether an attribute value names a blackboard entry by BehaviorTree.CPP 4's rule.
#[must_use]
pub fn blackboard_key(value: &str) -> Option<&str> {
    key_in(Version::V4, value)
}

/// The key a port attribute names, by `version`'s rules: `{key}` (and `${key}` in
/// version 3), or the port's own name for `=` (and `{=}` in version 4).
#[must_use]
pub fn port_key<'a>(version: Version, port: &'a str, value: &'a str) -> Option<&'a str> {
    match (version, value) {
        (_, "=") | (Version::V4, "{=}") => Some(port),
        _ => key_in(version, value),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_named_by_each_versions_rules() {
        use Version::{V3, V4};
        assert_eq!(key_in(V4, " {goal} "), Some("goal"));
        assert_eq!(key_in(V3, " {goal} "), None);
        assert_eq!(key_in(V3, "${goal}"), Some("goal"));
        assert_eq!(key_in(V4, "${goal}"), None);
        assert_eq!(key_in(V3, "{}"), None);
        assert_eq!(port_key(V4, "goal", "{=}"), Some("goal"));
        assert_eq!(port_key(V3, "goal", "{=}"), Some("="));
        assert_eq!(port_key(V3, "goal", "="), Some("goal"));
    }

    #[test]
    fn private_keys_stay_local_only_under_version_4s_autoremap() {
        let child = |autoremap| Scope { parent: Some(0), autoremap, ..Scope::default() };
        let scopes = [Scope::default(), child(Autoremap::Public), child(Autoremap::All)];
        assert_eq!(resolve(&scopes, Version::V4, 1, "_x"), Key { scope: 1, name: "_x".into() });
        assert_eq!(resolve(&scopes, Version::V4, 1, "x"), Key { scope: 0, name: "x".into() });
        assert_eq!(resolve(&scopes, Version::V3, 2, "_x"), Key { scope: 0, name: "_x".into() });
        assert_eq!(resolve(&scopes, Version::V3, 1, "@x"), Key { scope: 0, name: "@x".into() });
        assert_eq!(resolve(&scopes, Version::V4, 2, "@x"), Key { scope: 0, name: "x".into() });
    }
}
