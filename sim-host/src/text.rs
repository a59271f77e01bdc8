//! Words in what the tools print: counts with the right form of the noun.

/// `n` and the noun, singular for 1: `1 tick`, `0 ticks`, `3 expansions`. Give the plural
/// with [`count_as`] where it is not the noun and `s`.
#[must_use]
pub fn count<N: std::fmt::Display + PartialEq + From<u8>>(n: N, noun: &str) -> String {
    if n == N::from(1) { format!("1 {noun}") } else { format!("{n} {noun}s") }
}

/// `n` and the noun, with both forms given: `count_as(1, "entry", "entries")`.
#[must_use]
pub fn count_as<N: std::fmt::Display + PartialEq + From<u8>>(n: N, singular: &str, plural: &str) -> String {
    if n == N::from(1) { format!("1 {singular}") } else { format!("{n} {plural}") }
}

#[cfg(test)]
mod tests {
    #[test]
    fn singular_for_one_only() {
        assert_eq!(super::count(1u32, "tick"), "1 tick");
        assert_eq!(super::count(0usize, "tick"), "0 ticks");
        assert_eq!(super::count(2u16, "node"), "2 nodes");
        assert_eq!(super::count(1u64, "run"), "1 run");
        assert_eq!(super::count_as(1usize, "copy", "copies"), "1 copy");
        assert_eq!(super::count_as(2u64, "entry", "entries"), "2 entries");
    }
}
