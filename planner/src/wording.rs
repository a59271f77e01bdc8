//! Words in messages: counts with the right noun form.

/// `n` and the noun, singular for 1: `1 tick`, `0 ticks`, `3 control nodes`.
pub(crate) fn count<N: std::fmt::Display + PartialEq + From<u8>>(n: N, noun: &str) -> String {
    if n == N::from(1) { format!("1 {noun}") } else { format!("{n} {noun}s") }
}
