//! `cargo xtask`: the project's automation, the usual Rust way.
//!
//! - `cargo xtask ci`: everything CI checks (what `.ci/run` calls): first the
//!   prerequisites (installed when missing where it may, see `setup.rs`), then
//!   formatting, clippy, the test suite, the doc tests, the core-only cross builds of
//!   bt-core, the firmware's own checks (it is a Cargo project outside the workspace)
//!   and `qemu`.
//! - `cargo xtask cross`: bt-core and bt-link built with `core` only for Cortex-M4F and
//!   Cortex-M0+.
//! - `cargo xtask qemu`: the firmware under QEMU, its trace compared with the host's,
//!   the corrupted-image run, the panic gate and the footprint; the link controller on
//!   mps2-an386 and the RTIC program on lm3s6965evb (see `qemu.rs`); blended planning
//!   and acting on the controller (`blend.rs`).
//! - `cargo xtask fuzz --seconds N [--target load|serve|controller]`: the `load` fuzz
//!   target of bt-core, or the `serve` and `controller` targets of bt-link (nightly +
//!   cargo-fuzz).
//!
//! Cross builds always build `core` from source (`-Zbuild-std=core`): with rustup's
//! `rust-src` component where it is installed, and otherwise with Debian's packaged
//! compiler and its std sources (`apt-get install rustc-web cargo-web rust-web-src`).
//! See DEVELOPERS.md. Build output goes under `$CARGO_TARGET_DIR`
//! when it is set, `target/` otherwise.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

use clap::{Parser, Subcommand};

mod blend;
mod boards;
mod link;
mod qemu;
mod setup;

// The firmware's tree A, made exactly as its build script makes it (the link scenario
// boots the controller with it and must recognise it).
#[allow(dead_code, unreachable_pub)]
#[path = "../../firmware-example/src/catalog.rs"]
mod catalog;
#[allow(dead_code)]
#[path = "../../firmware-example/gen/tree.rs"]
mod firmware_tree;

#[derive(Parser)]
#[command(name = "cargo xtask", about = "Project automation: CI, cross builds, fuzzing", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run every check CI runs: fmt, clippy, tests, doc tests, cross builds, firmware.
    /// Checks the prerequisites first and installs missing Debian packages when it runs
    /// as root or with password-less sudo.
    Ci {
        /// Only check the prerequisites: install nothing, name what is missing.
        #[arg(long)]
        no_install: bool,
    },
    /// Build bt-core and bt-link with `core` only for thumbv7em-none-eabihf and thumbv6m-none-eabi.
    Cross,
    /// Build the firmware, run it under QEMU and compare its trace with the host's;
    /// check the corrupted image, panic freedom, flash and RAM.
    Qemu {
        /// Longest a QEMU run may take, in seconds.
        #[arg(long, default_value_t = 60)]
        timeout: u64,
    },
    /// Fuzz `bt_core::load` or the link controller (needs nightly and cargo-fuzz).
    Fuzz {
        /// How long to fuzz.
        #[arg(long, default_value_t = 60)]
        seconds: u64,
        /// `load` (bt-core's image loader), `serve` (bt-link's blocking controller loop) or
        /// `controller` (bt-link's sans-IO controller: feed, poll, transmit).
        #[arg(long, default_value = "load", value_parser = ["load", "serve", "controller"])]
        target: String,
    },
}

/// bt-link's UART adapters: tested on the host, built for the Cortex-M targets.
const LINK_IO: &str = "bt-link/embedded-io,bt-link/embedded-io-async";

/// Targets bt-core must build for with nothing but `core`: Cortex-M4F (FPU) and
/// Cortex-M0+ (no FPU, no atomic read-modify-write).
const CORE_TARGETS: [&str; 2] = ["thumbv7em-none-eabihf", "thumbv6m-none-eabi"];

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Cmd::Ci { no_install } => ci(!no_install),
        Cmd::Cross => cross(),
        Cmd::Qemu { timeout } => qemu::qemu(qemu::Options { timeout: std::time::Duration::from_secs(timeout) }),
        Cmd::Fuzz { seconds, target } => fuzz(seconds, &target),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}

type Result<T = ()> = std::result::Result<T, String>;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().map(Path::to_path_buf).unwrap_or_default()
}

/// Where build output goes: `$CARGO_TARGET_DIR` if set (relative to the current
/// directory, as cargo takes it), else the workspace's `target/`.
fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR").filter(|d| !d.is_empty()) {
        Some(d) => std::path::absolute(&d).unwrap_or_else(|_| PathBuf::from(d)),
        None => root().join("target"),
    }
}

fn step(title: &str) {
    eprintln!("\n==> {title}");
}

/// Runs a command in the workspace root, failing with its command line.
fn run(cmd: &mut Command) -> Result {
    run_in(&root(), cmd)
}

/// Runs a command in `dir`, failing with its command line.
fn run_in(dir: &Path, cmd: &mut Command) -> Result {
    cmd.current_dir(dir);
    let shown = format!("{cmd:?}");
    let status = cmd.status().map_err(|e| format!("cannot start {shown}: {e}"))?;
    if status.success() { Ok(()) } else { Err(format!("failed ({status}): {shown}")) }
}

fn cargo() -> Command {
    Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
}

fn ci(install_missing: bool) -> Result {
    let started = std::time::Instant::now();
    setup::prerequisites(install_missing)?;
    step("formatting");
    run(cargo().args(["fmt", "--all", "--", "--check"]))?;
    step("clippy (warnings are errors)");
    run(cargo().args(["clippy", "--workspace", "--all-targets", "--", "-D", "warnings"]))?;
    step("tests");
    if has_nextest() {
        run(cargo().args(["nextest", "run", "--workspace", "--no-fail-fast", "--features", LINK_IO]))?;
    } else {
        run(cargo().args(["test", "--workspace", "--lib", "--bins", "--tests", "--features", LINK_IO]))?;
    }
    step("doc tests");
    run(cargo().args(["test", "--workspace", "--doc"]))?;
    step("API docs (broken or private links are errors)");
    run(cargo().args(["doc", "--workspace", "--no-deps"]).env("RUSTDOCFLAGS", "-D warnings"))?;
    cross()?;
    firmware_checks()?;
    qemu::qemu(qemu::Options { timeout: std::time::Duration::from_secs(60) })?;
    let secs = started.elapsed().as_secs();
    eprintln!("\nxtask ci: all checks passed in {} min {} s", secs / 60, secs % 60);
    Ok(())
}

fn has_nextest() -> bool {
    cargo().args(["nextest", "--version"]).output().is_ok_and(|o| o.status.success())
}

/// The firmware is a Cargo project of its own (outside the workspace, so that a host
/// `cargo test` never links it): its formatting, lints and host tests, on the host.
fn firmware_checks() -> Result {
    let fw = root().join("firmware-example");
    let host_dir = target_dir().join("firmware-host");
    let host = host_triple()?;
    step("firmware: formatting, clippy and host tests");
    run_in(&fw, cargo().args(["fmt", "--", "--check"]))?;
    // The RTIC board builds for its Cortex-M3 only (`cargo xtask qemu` builds it).
    run_in(&root().join("examples").join("lm3s6965-rtic"), cargo().args(["fmt", "--", "--check"]))?;
    run_in(
        &fw,
        cargo()
            .args(["clippy", "--quiet", "--all-targets", "--target", &host, "--target-dir"])
            .arg(&host_dir)
            .args(["--", "-D", "warnings"]),
    )?;
    run_in(&fw, cargo().args(["test", "--quiet", "--target", &host, "--target-dir"]).arg(&host_dir))
}

/// The host's target triple, from `rustc -vV`.
fn host_triple() -> Result<String> {
    let out = Command::new("rustc").arg("-vV").output().map_err(|e| format!("cannot run rustc -vV: {e}"))?;
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("host: ").map(str::to_owned))
        .ok_or_else(|| "rustc -vV names no host triple".into())
}

/// How to build for a bare-metal target on this machine. Both ways build `core` (and
/// compiler-builtins) from source with the firmware's own profile, so the flash figure
/// the gates check does not depend on the route.
///
/// rustup's prebuilt `core` (`rustup target add`) is deliberately not one of them: its
/// compiler-builtins comes compiled for speed. With it the firmware was reported at
/// 17,252 B against 16,004 B from source while it still divided 64-bit numbers; without
/// that, compiler-builtins built at `opt-level = 3` as the prebuilt one is still adds
/// 176 B, over the 16 KiB gate on that route alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Toolchain {
    /// rustup's compiler with its `rust-src` component.
    RustupSource,
    /// Debian's rustc-web with rust-web-src.
    Debian,
}

/// Whether rustup's active toolchain has the library sources (`rust-src`).
fn rustup_rust_src() -> bool {
    Command::new("rustc").args(["--print", "sysroot"]).output().ok().filter(|o| o.status.success()).is_some_and(|o| {
        let sysroot = String::from_utf8_lossy(&o.stdout).trim().to_owned();
        Path::new(&sysroot).join("lib/rustlib/src/rust/library/core").exists()
    })
}

/// Whether Debian's compiler and its library sources are installed.
fn debian_toolchain() -> bool {
    Path::new("/usr/bin/rustc").exists() && Path::new("/usr/lib/rustlib/src/rust/library/core").exists()
}

/// The route to take: rustup's `rust-src` first, then Debian's compiler; `None` when
/// neither is installed.
const fn choose(rust_src: bool, debian: bool) -> Option<Toolchain> {
    if rust_src {
        Some(Toolchain::RustupSource)
    } else if debian {
        Some(Toolchain::Debian)
    } else {
        None
    }
}

fn toolchain_for(target: &str) -> Result<Toolchain> {
    choose(rustup_rust_src(), debian_toolchain()).ok_or_else(|| {
        format!(
            "cannot build core for {target} from source: run `rustup component add rust-src`, or on \
             Debian `apt-get install -y rustc-web cargo-web rust-web-src` (see DEVELOPERS.md). rustup's \
             prebuilt core (`rustup target add`) is not used here: its compiler-builtins, compiled \
             for speed, makes the firmware larger than the flash gate measures"
        )
    })
}

/// A `cargo build` for a bare-metal target, `core` built from source.
fn cross_cargo(target: &str) -> Result<Command> {
    let mut c = match toolchain_for(target)? {
        Toolchain::RustupSource => cargo(),
        Toolchain::Debian => {
            let mut c = Command::new("/usr/bin/cargo");
            c.env("RUSTC", "/usr/bin/rustc").env_remove("RUSTUP_TOOLCHAIN");
            c
        }
    };
    // `-Zbuild-std` is unstable; RUSTC_BOOTSTRAP lets a stable compiler take it.
    c.env("RUSTC_BOOTSTRAP", "1");
    c.args(["build", "--release", "--target", target, "-Zbuild-std=core"]);
    Ok(c)
}

fn cross() -> Result {
    for target in CORE_TARGETS {
        step(&format!("bt-core and bt-link with core only for {target}"));
        let target_dir = target_dir().join("cross");
        run(cross_cargo(target)?
            .args(["-p", "bt-core", "-p", "bt-link", "--features", LINK_IO, "--target-dir"])
            .arg(&target_dir))?;
    }
    no_std_leaks()
}

/// bt-core must not name std or alloc outside tests, whatever the toolchain enforces.
fn no_std_leaks() -> Result {
    // Every file under src/, modules in folders included.
    let mut dirs = vec![root().join("bt-core").join("src")];
    let mut files = Vec::new();
    while let Some(dir) = dirs.pop() {
        let entries = std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() { dirs.push(path) } else { files.push(path) }
        }
    }
    if files.is_empty() {
        return Err("bt-core/src: no source files found".into());
    }
    for path in files {
        let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        for (n, line) in text.lines().enumerate() {
            let l = line.trim_start();
            if l.starts_with("extern crate std")
                || l.starts_with("extern crate alloc")
                || l.starts_with("use std::")
                || l.starts_with("use alloc::")
            {
                return Err(format!("{}:{}: bt-core must use core only: {l}", path.display(), n + 1));
            }
        }
    }
    Ok(())
}

fn fuzz(seconds: u64, target: &str) -> Result {
    let (dir, what) = match target {
        "serve" => ("bt-link", "bt_link::serve"),
        "controller" => ("bt-link", "bt_link::Controller"),
        _ => ("bt-core", "bt_core::load"),
    };
    step(&format!("fuzzing {what} for {seconds} s"));
    // The rustup proxy, not $CARGO: `+nightly` selects the toolchain.
    if !Command::new("cargo").args(["+nightly", "--version"]).output().is_ok_and(|o| o.status.success()) {
        return Err("fuzzing needs the nightly toolchain: rustup toolchain install nightly".into());
    }
    if !Command::new("cargo").args(["+nightly", "fuzz", "--version"]).output().is_ok_and(|o| o.status.success()) {
        return Err("fuzzing needs cargo-fuzz, which is not installed: cargo install cargo-fuzz".into());
    }
    let mut c = Command::new("cargo");
    c.current_dir(root().join(dir));
    c.args(["+nightly", "fuzz", "run", target, "--", &format!("-max_total_time={seconds}"), "-print_final_stats=1"]);
    let shown = format!("{c:?}");
    let status = c.status().map_err(|e| format!("cannot start {shown}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("fuzzing stopped ({status}); a crash, if it found one, is in {dir}/fuzz/artifacts/{target}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn core_is_always_built_from_source() {
        assert_eq!(choose(true, true), Some(Toolchain::RustupSource));
        assert_eq!(choose(true, false), Some(Toolchain::RustupSource));
        assert_eq!(choose(false, true), Some(Toolchain::Debian));
        // rustup's prebuilt targets alone are no route: the firmware's size would
        // depend on them.
        assert_eq!(choose(false, false), None);
    }
}
