//! The repository stands alone: nothing in it (README, docs, help texts, comments)
//! points at files that exist only on the machines it was written on.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::{Path, PathBuf};

/// Text files of the repository, outside build output and version control.
fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            if !matches!(name.as_str(), "target" | ".git" | "corpus" | "artifacts") {
                files(&path, out);
            }
        } else if ["rs", "md", "toml", "txt", "pddl", "sh", "yml", "yaml"]
            .iter()
            .any(|e| path.extension().is_some_and(|x| x == *e))
            || name == "run"
        {
            out.push(path);
        }
    }
}

#[test]
fn nothing_points_outside_the_repository() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut all = Vec::new();
    files(&root, &mut all);
    assert!(all.len() > 50, "found the files: {}", all.len());
    let this = Path::new(file!()).file_name().unwrap();
    // Spelled in pieces, so that a plain grep of the repository finds no such path here.
    let outside = [
        concat!("shared", "/reference"),
        concat!("shared", "/seeds"),
        concat!("/work", "/shared"),
        concat!("/work", "/peers"),
        concat!("duplo", "-tasks.md"),
    ];
    let mut hits = Vec::new();
    for file in all.iter().filter(|f| f.file_name() != Some(this)) {
        let Ok(text) = std::fs::read_to_string(file) else { continue };
        for (i, line) in text.lines().enumerate() {
            if outside.iter().any(|o| line.contains(o)) {
                hits.push(format!("{}:{}: {}", file.display(), i + 1, line.trim()));
            }
        }
    }
    // The changelog records history, which may name what was once pointed at.
    hits.retain(|h| !h.contains("CHANGELOG.md"));
    assert!(hits.is_empty(), "pointers outside the repository:\n{}", hits.join("\n"));
    assert!(root.join("docs/brick-tasks.md").exists());
}

#[test]
fn the_documented_commands_are_the_ones_that_run() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    // `cargo run --release` in firmware-example (its README, DEVELOPERS.md) needs to know
    // which of its binaries to run.
    let manifest = std::fs::read_to_string(root.join("firmware-example/Cargo.toml")).unwrap();
    let default = manifest
        .lines()
        .find_map(|l| l.trim().strip_prefix("default-run = "))
        .expect("firmware-example has a default-run")
        .trim_matches('"');
    assert!(manifest.contains(&format!("name = \"{default}\"")), "default-run `{default}` is one of its binaries");
    // CI runs the README's test command and nothing else: the set-up is in it.
    let ci = std::fs::read_to_string(root.join(".ci/run")).unwrap();
    let commands: Vec<&str> = ci.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with('#')).collect();
    assert_eq!(commands, ["set -euo pipefail", "cd \"$(dirname \"$0\")/..\"", "exec cargo xtask ci"]);
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    assert!(readme.contains("cargo xtask ci"));
}
