//! Every count sim-host prints goes through `sim_host::text::count` (or `count_as`), so it
//! reads `1 run`, `1 tick`, `2 runs`, never `1 runs` or `run(s)`. This test reads the
//! string literals of sim-host's sources (tests left out) and fails on a number
//! placeholder followed by a plural noun, `{} runs`, and on `(s)`-style plurals; a new
//! message that counts must use the helper, or, if what follows the number is no count
//! noun, be added to `NOT_COUNTS` with the reason.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

mod source_scan;
use source_scan::rust_files;

/// Words after a placeholder that are verbs, units or function words, never the noun of
/// a count.
const NOT_NOUNS: &[&str] =
    &["as", "does", "exists", "fails", "has", "is", "its", "ms", "s", "starts", "succeeds", "this", "us", "was"];

/// Fragments that read like a count but are not one (or cannot be 1).
const NOT_COUNTS: &[&str] = &[
    // A device's name, then a verb.
    "{name} runs",
    "{name} holds",
    // An offset, then a verb.
    "{offset} ends",
    // input.rs: a size limit with thousands separators; limits are far above 1 byte.
    "{out} bytes",
];

/// The contents of the string literals of `code` (ordinary and raw), with the line each
/// starts on. Comments and char literals are skipped.
fn literals(code: &str) -> Vec<(usize, String)> {
    let c: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    while i < c.len() {
        match c[i] {
            '\n' => line += 1,
            '/' if c.get(i + 1) == Some(&'/') => {
                while i < c.len() && c[i] != '\n' {
                    i += 1;
                }
                continue;
            }
            '/' if c.get(i + 1) == Some(&'*') => {
                while i + 1 < c.len() && !(c[i] == '*' && c[i + 1] == '/') {
                    line += usize::from(c[i] == '\n');
                    i += 1;
                }
                i += 2;
                continue;
            }
            '\'' => {
                // A char literal ('x', '\n', '"'); else a lifetime.
                if c.get(i + 1) == Some(&'\\') {
                    i += 2;
                    while i < c.len() && c[i] != '\'' {
                        i += 1;
                    }
                } else if c.get(i + 2) == Some(&'\'') {
                    i += 2;
                }
            }
            'r' if (c.get(i + 1) == Some(&'#') || c.get(i + 1) == Some(&'"'))
                && (i == 0 || !(c[i - 1].is_alphanumeric() || c[i - 1] == '_')) =>
            {
                let mut j = i + 1;
                while c.get(j) == Some(&'#') {
                    j += 1;
                }
                if c.get(j) == Some(&'"') {
                    let hashes = j - i - 1;
                    let (start, at) = (j + 1, line);
                    let mut k = start;
                    while k < c.len() && !(c[k] == '"' && (1..=hashes).all(|h| c.get(k + h) == Some(&'#'))) {
                        line += usize::from(c[k] == '\n');
                        k += 1;
                    }
                    out.push((at, c[start..k.min(c.len())].iter().collect()));
                    i = k + 1 + hashes;
                    continue;
                }
            }
            '"' => {
                let at = line;
                let mut s = String::new();
                i += 1;
                while i < c.len() && c[i] != '"' {
                    if c[i] == '\\' {
                        i += 1;
                    }
                    line += usize::from(c.get(i) == Some(&'\n'));
                    if let Some(&ch) = c.get(i) {
                        s.push(ch);
                    }
                    i += 1;
                }
                out.push((at, s));
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// What in `lit` counts without the helper.
fn bare_counts(lit: &str) -> Vec<String> {
    let b = lit.as_bytes();
    let mut found = Vec::new();
    let mut i = 0;
    while let Some(open) = lit[i..].find('{').map(|o| o + i) {
        let Some(close) = lit[open..].find('}').map(|c| c + open) else { break };
        let name = &lit[open + 1..close];
        i = close + 1;
        if name.contains('{')
            || name
                .split(':')
                .next()
                .is_some_and(|n| !n.is_empty() && n.chars().all(|c| c.is_ascii_uppercase() || c == '_'))
        {
            continue; // `{{`, or a constant such as {MAX_RUNS}: fixed and above 1
        }
        let rest = &lit[close + 1..];
        let Some(after) = rest.strip_prefix(' ') else { continue };
        let word: String = after.chars().take_while(|c| c.is_ascii_lowercase() || *c == '-').collect();
        let next = b.get(close + 2 + word.len()).copied();
        if !word.ends_with('s') || matches!(next, Some(b'=' | b'/')) || NOT_NOUNS.contains(&word.as_str()) {
            continue;
        }
        let fragment = format!("{{{name}}} {word}");
        if !NOT_COUNTS.contains(&fragment.as_str()) {
            found.push(fragment);
        }
    }
    for plural in ["(s)", "(es)", "(ies)"] {
        if lit.match_indices(plural).any(|(at, _)| at > 0 && b[at - 1].is_ascii_lowercase()) {
            found.push(plural.to_string());
        }
    }
    found
}

#[test]
fn the_scan_finds_bare_counts_and_passes_the_helper() {
    assert_eq!(bare_counts("{} runs, {episodes} episodes in {secs:.2} s"), ["{} runs", "{episodes} episodes"]);
    assert_eq!(bare_counts("{} task(s) x {} copy(ies)"), ["(s)", "(ies)"]);
    assert!(bare_counts("{}, {} in {secs:.2} s: {:.0} episodes/s on {}").is_empty());
    assert!(bare_counts("more than {MAX_RUNS} seeds; {name} succeeds; nodes={} changes={n}").is_empty());
    let code = "let a = 'x'; let q = '\"'; f(\"{} nodes\"); // \"{} ticks\"\n g(r#\"<a b=\"{}\">{n} rows\"#);";
    let lits: Vec<String> = literals(code).into_iter().map(|(_, s)| s).collect();
    assert_eq!(lits, ["{} nodes", "<a b=\"{}\">{n} rows"]);
}

#[test]
fn every_count_in_sim_hosts_messages_goes_through_the_helper() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    assert!(files.len() > 40, "found the sources: {}", files.len());
    let mut found = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        // Unit tests come last in a file and assert text; they are not messages.
        let code = text.find("#[cfg(test)]").map_or(text.as_str(), |at| &text[..at]);
        for (line, lit) in literals(code) {
            for hit in bare_counts(&lit) {
                found.push(format!("{}:{line}: `{hit}` in \"{lit}\"", file.display()));
            }
        }
    }
    assert!(found.is_empty(), "counts printed without sim_host::text::count (singular for 1):\n{}", found.join("\n"));
}
