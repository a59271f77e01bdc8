//! Which kind of world a scenario, an episode or a learning run plays in.

/// Which kind of world: exact and fast, or rigid-body physics.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WorldKind {
    /// Exact and fast: STRIPS semantics, or the reference's brick world (microseconds
    /// per episode).
    Symbolic,
    /// Rigid bodies on rapier3d.
    Physics,
}

impl WorldKind {
    /// Both kinds, symbolic first.
    pub const ALL: [WorldKind; 2] = [WorldKind::Symbolic, WorldKind::Physics];

    /// `symbolic` or `physics`: the name on the command line and in run folders.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Symbolic => "symbolic",
            Self::Physics => "physics",
        }
    }

    /// The kind with that name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }
}

impl std::fmt::Display for WorldKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::WorldKind;

    #[test]
    fn names_go_both_ways() {
        for k in WorldKind::ALL {
            assert_eq!(WorldKind::from_name(k.name()), Some(k));
            assert_eq!(k.to_string(), k.name());
        }
        assert_eq!(WorldKind::from_name("strips"), None);
    }
}
