//! Makes the embedded images on the host, with the project's own code, every time the
//! firmware builds:
//!
//! - `$OUT_DIR/tree.img`: the tree of `gen/tree.rs` for the behavior set of
//!   `src/catalog.rs`;
//! - `$OUT_DIR/tree-corrupt.img`: the same bytes with one bit of the first node flipped,
//!   which the loader must refuse (the `firmware-corrupt-image` binary embeds it).
//!
//! For the bare-metal target it also puts `memory.x` on the linker's search path, where
//! cortex-m-rt's `link.x` includes it.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[allow(dead_code)]
#[path = "src/catalog.rs"]
mod catalog;
#[path = "gen/tree.rs"]
mod tree;

/// The byte of the image whose lowest bit the corrupted image flips: the first byte of
/// the first node (its subtree size), so only the CRC can tell.
const CORRUPT_AT: usize = bt_core::image::HEADER_LEN;

fn main() -> ExitCode {
    for path in ["build.rs", "gen/tree.rs", "src/catalog.rs", "memory.x"].into_iter().chain(tree::SOURCES) {
        println!("cargo::rerun-if-changed={path}");
    }
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("firmware-example build script: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let out = PathBuf::from(std::env::var_os("OUT_DIR").ok_or("OUT_DIR is not set")?);
    let image = tree::image()?;
    write(&out.join("tree.img"), &image)?;

    let mut corrupt = image;
    let byte = corrupt.get_mut(CORRUPT_AT).ok_or("image too short to corrupt")?;
    *byte ^= 1;
    write(&out.join("tree-corrupt.img"), &corrupt)?;

    // The mps2-an386 programs' memory map; a board project that uses this crate for the
    // plant (without the feature) brings its own.
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("none")
        && std::env::var_os("CARGO_FEATURE_MPS2_AN386").is_some()
    {
        let memory = std::fs::read("memory.x").map_err(|e| format!("memory.x: {e}"))?;
        write(&out.join("memory.x"), &memory)?;
        // cortex-m-rt's `device` feature includes device.x for the interrupt handlers'
        // names; src/target.rs points every vector at the default handler instead.
        write(&out.join("device.x"), b"/* no named interrupt handlers */\n")?;
        println!("cargo::rustc-link-search={}", out.display());
    }
    Ok(())
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    std::fs::write(path, bytes).map_err(|e| format!("{}: {e}", path.display()))
}
