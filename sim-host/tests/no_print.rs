//! No `print!` family macro on the CLI's paths: they panic when stdout or stderr is
//! closed or full. Everything goes through `cli::output`, whose writes return errors.
//! Clippy's `print_stdout`/`print_stderr` are denied in sim-host's crate roots; this test
//! also covers the libraries the CLI calls and fails if the lint attributes go.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

mod source_scan;
use source_scan::rust_files;

#[test]
fn no_print_macros_in_the_cli_or_the_libraries_it_calls() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for krate in ["sim-host/src", "planner/src", "gp/src", "bt-core/src", "btcpp/src", "bt-link/src"] {
        rust_files(&root.join(krate), &mut files);
    }
    assert!(files.len() > 40, "found the sources: {}", files.len());
    let mut found = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for (i, line) in text.lines().enumerate() {
            let code = line.trim_start();
            if code.starts_with("//") {
                continue; // comments and doc examples
            }
            for mac in ["print!(", "println!(", "eprint!(", "eprintln!(", "dbg!("] {
                let hit = code
                    .match_indices(mac)
                    .any(|(at, _)| at == 0 || !code[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_'));
                if hit {
                    found.push(format!("{}:{}: {}", file.display(), i + 1, code));
                }
            }
        }
    }
    assert!(found.is_empty(), "print macros on CLI paths:\n{}", found.join("\n"));

    for root_file in ["sim-host/src/main.rs", "sim-host/src/lib.rs"] {
        let text = std::fs::read_to_string(root.join(root_file)).unwrap();
        assert!(text.contains("#![deny(clippy::print_stdout, clippy::print_stderr)]"), "{root_file}");
    }
}
