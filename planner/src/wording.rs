//! Words in messages: counts with the right noun form, articles before names.

/// `n` and the noun, singular for 1: `1 tick`, `0 ticks`, `3 control nodes`.
pub(crate) fn count<N: std::fmt::Display + PartialEq + From<u8>>(n: N, noun: &str) -> String {
    if n == N::from(1) { format!("1 {noun}") } else { format!("{n} {noun}s") }
}

/// `a` or `an` and the word, by its first letter's sound: `an Inverter`, `a Sequence`.
pub(crate) fn article(word: &str) -> String {
    let vowel = word.chars().next().is_some_and(|c| "aeiouAEIOU".contains(c));
    format!("{} {word}", if vowel { "an" } else { "a" })
}
