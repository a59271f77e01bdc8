//! The firmware with a corrupted image embedded: it must print the `LoadError` and exit
//! non-zero without ticking (`cargo xtask qemu` checks both).
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
#[cortex_m_rt::entry]
fn main() -> ! {
    firmware_example::target::run_and_exit(firmware_example::CORRUPT_IMAGE)
}

#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    host::run(firmware_example::CORRUPT_IMAGE)
}

#[cfg(not(target_os = "none"))]
#[path = "../host.rs"]
mod host;
