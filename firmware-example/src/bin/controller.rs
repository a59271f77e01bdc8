//! The link controller: boots the embedded tree, ticks it when the host says `Start`,
//! and swaps in trees deployed over the link between two ticks (see `src/link.rs`).
//!
//! On the Cortex-M4F the link is the CMSDK UART0 (QEMU: `-serial tcp::4321,server=on`);
//! on the host, `controller --listen 127.0.0.1:4321` serves one TCP connection and
//! exits when it closes. Both print the same trace.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
#[cortex_m_rt::entry]
fn main() -> ! {
    firmware_example::board::run(firmware_example::IMAGE)
}

#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    tcp::main()
}

#[cfg(not(target_os = "none"))]
#[path = "../tcp.rs"]
mod tcp;
