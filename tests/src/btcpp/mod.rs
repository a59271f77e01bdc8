//! Differential testing against BehaviorTree.CPP: the tree spec, the random cases, the
//! fixtures recorded from BehaviorTree.CPP by `tests/btcpp/record.sh`.

pub mod btlog;
pub mod case;
pub mod compare;
pub mod generate;
pub mod run;
pub mod spec;
pub mod v3;

/// Every case of the `.txt` fixture files in `dir` (relative to the `tests` crate), in
/// file-name order, each with the name of its file; `parse` reads one file's cases.
///
/// # Panics
/// On a fixture that cannot be read or parsed: the test's input is broken.
#[must_use]
pub fn fixtures<R>(dir: &str, parse: impl Fn(&str) -> Result<Vec<R>, String>) -> Vec<(String, R)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "txt"))
        .collect();
    files.sort();
    let mut out = vec![];
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let name = f.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        for rec in parse(&text).unwrap_or_else(|e| panic!("{}: {e}", f.display())) {
            out.push((name.clone(), rec));
        }
    }
    out
}
