//! The Rust table `sim-host catalog --rust` writes compiles, and names the same behavior
//! set (fingerprint included) as an import against the same models.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::Path;

use bt_core::Catalog;
use btcpp::xml::{Models, document};

/// The table for Nav2's models, as generated (regenerate with
/// `sim-host catalog btcpp/tests/fixtures/nav2/nav2_tree_nodes.xml --rust`).
#[allow(dead_code, clippy::all)]
mod nav2 {
    include!("fixtures/nav2/behaviors.rs");
}

fn nav2_catalog() -> btcpp::xml::XmlCatalog {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/nav2/nav2_tree_nodes.xml");
    let doc = document::read_models(&[path]).unwrap();
    Models::new(&doc.models).unwrap().catalog()
}

#[test]
fn the_generated_table_is_the_imported_set() {
    let catalog = nav2_catalog();
    assert_eq!(nav2::FINGERPRINT, catalog.fingerprint());
    assert_eq!(nav2::BEHAVIORS.fingerprint(), catalog.fingerprint());
    assert_eq!(nav2::BEHAVIORS.len(), catalog.len());
    assert_eq!(usize::from(nav2::COMPUTE_PATH_TO_POSE), catalog.lookup("ComputePathToPose").unwrap().0 as usize);
    for id in 0..catalog.len() as u16 {
        assert_eq!(nav2::BEHAVIORS.info(id), catalog.info(id));
        for p in 0..usize::from(catalog.info(id).unwrap().arity) {
            assert_eq!(nav2::BEHAVIORS.port(id, p), catalog.port(id, p));
        }
    }
}

#[test]
fn the_checked_in_table_is_what_the_generator_writes() {
    let text = nav2_catalog().to_rust("nav2_tree_nodes.xml");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/nav2/behaviors.rs");
    assert_eq!(text, std::fs::read_to_string(path).unwrap(), "regenerate tests/fixtures/nav2/behaviors.rs");
}
