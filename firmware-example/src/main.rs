//! The firmware: the cube-and-sphere tree on a Cortex-M4F (run it with `cargo run
//! --release` under QEMU's mps2-an386). Built for the host (`--target <host triple>`),
//! the same loop prints the reference trace to stdout.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
#[cortex_m_rt::entry]
fn main() -> ! {
    firmware_example::target::run_and_exit(firmware_example::IMAGE)
}

#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    host::run(firmware_example::IMAGE)
}

#[cfg(not(target_os = "none"))]
#[path = "host.rs"]
mod host;
