//! Whatever bytes come in, the importer answers with a tree or an error, never a panic.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

use btcpp::xml::{ImportOptions, import_text};
use proptest::prelude::*;

const DOC: &str = include_str!("fixtures/btcpp-examples/t05_crossdoor.xml");

fn models() -> ImportOptions<'static> {
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/btcpp-examples/example_nodes.xml");
    ImportOptions { models: vec![models], main: Some("MainTree".into()), ..ImportOptions::default() }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    /// A real document with bytes changed, cut or repeated.
    #[test]
    fn corrupted_documents_never_panic(edits in prop::collection::vec((0usize..4000, any::<u8>(), 0u8..3), 1..6)) {
        let mut bytes = DOC.as_bytes().to_vec();
        for (at, b, how) in edits {
            let at = at % bytes.len().max(1);
            match how {
                0 => bytes[at] = b,
                1 => bytes.truncate(at),
                _ => {
                    let copy = bytes[at..].to_vec();
                    bytes.extend_from_slice(&copy[..copy.len().min(64)]);
                }
            }
            if bytes.is_empty() {
                bytes.push(b'<');
            }
        }
        let text = String::from_utf8_lossy(&bytes);
        let _ = import_text(Path::new("t.xml"), &text, &models());
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let depth = 100_000;
    let doc = format!(
        "<root><BehaviorTree ID=\"M\">{}<AlwaysSuccess/>{}</BehaviorTree></root>",
        "<Inverter>".repeat(depth),
        "</Inverter>".repeat(depth)
    );
    let e = import_text(Path::new("t.xml"), &doc, &ImportOptions::default()).unwrap_err().to_string();
    assert!(e.contains("nested deeper than") || e.contains("not well-formed XML"), "{e}");
}
