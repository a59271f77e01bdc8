//! The controller side: trace over semihosting, stack high-water mark, exit code, panic
//! handler. Lines printed here start with `fw ` and are not part of the trace that the
//! host reproduces.

use cortex_m_semihosting::debug::{self, EXIT_FAILURE, EXIT_SUCCESS};
use cortex_m_semihosting::hio::{self, HostStream};

use crate::control::{self, Line, Outcome, Sink};

/// The interrupt vectors of the MPS2 AN386 (32 external interrupts, CMSDK), all on
/// cortex-m-rt's default handler: the firmware uses none. Declared here (cortex-m-rt's
/// `device` feature) instead of cortex-m-rt's generic 240-entry table, saving 832 bytes
/// of flash.
#[cfg(feature = "mps2-an386")]
#[allow(unsafe_code)]
#[unsafe(link_section = ".vector_table.interrupts")]
#[unsafe(no_mangle)]
static __INTERRUPTS: [unsafe extern "C" fn(); 32] = [DefaultHandler; 32];

#[cfg(feature = "mps2-an386")]
#[allow(unsafe_code)]
unsafe extern "C" {
    /// cortex-m-rt's handler for unused vectors (an endless loop).
    fn DefaultHandler();
}

/// Trace lines to the debugger's stdout (QEMU: the terminal).
pub struct Semihosting(Option<HostStream>);

impl core::fmt::Debug for Semihosting {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(if self.0.is_some() { "Semihosting(stdout)" } else { "Semihosting(none)" })
    }
}

impl Semihosting {
    /// The debugger's stdout, if there is one.
    pub fn stdout() -> Self {
        Self(hio::hstdout().ok())
    }
}

impl Sink for Semihosting {
    fn line(&mut self, line: &[u8]) {
        if let Some(out) = self.0.as_mut() {
            // Nothing to do if the host stops listening: the exit code still tells.
            let _ = out.write_all(line).and_then(|()| out.write_all(b"\n"));
        }
    }
}

/// Runs the scenario on `image`, reports the stack high-water mark and exits through
/// semihosting: status 0 when the run reached its goal, 1 otherwise (a load error, a
/// failed or timed-out run).
pub fn run_and_exit(image: &[u8]) -> ! {
    let mut out = Semihosting(hio::hstdout().ok());
    let outcome = control::run(image, &mut out, |_| {});
    let stack = stack_usage();
    let mut line = Line::new();
    line.text("fw stack_hwm=").num(stack.used).text("B stack_size=").num(stack.size).text("B paint=0xcccccccc");
    line.send(&mut out);
    let code = u8::from(!outcome.reached_goal());
    let what = match outcome {
        Outcome::Goal { .. } => "goal reached",
        Outcome::RootFailure { .. } => "root returned FAILURE",
        Outcome::Timeout => "timeout",
        Outcome::Load(_) => "image refused",
        Outcome::Tick { .. } => "tick error",
    };
    line.text("fw exit=").num(code.into()).text(" (").text(what).text(")").send(&mut out);
    debug::exit(if code == 0 { EXIT_SUCCESS } else { EXIT_FAILURE });
    // Only reached if the debugger resumes after the exit request.
    loop {
        cortex_m::asm::wfi();
    }
}

/// How much of the stack the run used.
#[derive(Clone, Copy, Debug)]
pub struct StackUsage {
    /// Bytes below the initial stack pointer that were written since boot.
    pub used: u32,
    /// Bytes between the end of the statics and the top of RAM.
    size: u32,
}

/// Scans the stack region, painted with `0xcccccccc` by cortex-m-rt at boot
/// (`paint-stack`), from its lowest address upwards for the first word the program
/// wrote: everything above it has been used at some point.
#[allow(unsafe_code)]
pub fn stack_usage() -> StackUsage {
    unsafe extern "C" {
        static _stack_end: u32;
        static _stack_start: u32;
    }
    let bottom = (&raw const _stack_end) as usize;
    let top = (&raw const _stack_start) as usize;
    let mut addr = bottom;
    while addr < top {
        // SAFETY: `[_stack_end, _stack_start)` is the stack region of RAM that
        // cortex-m-rt's linker script reserves; it is mapped, word aligned (asserted by
        // the script), and reading it has no side effect. Volatile: the compiler must not
        // assume anything about memory the stack pointer wrote.
        let word = unsafe { core::ptr::read_volatile(addr as *const u32) };
        if word != cortex_m_rt::STACK_PAINT_VALUE {
            break;
        }
        addr = addr.wrapping_add(4);
    }
    StackUsage { used: top.wrapping_sub(addr) as u32, size: top.wrapping_sub(bottom) as u32 }
}

/// A panic cannot come from bt-core or the plant (the release build is checked for
/// `core::panicking` symbols); should one happen all the same, say where and fail.
#[cfg(feature = "mps2-an386")]
#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    let mut out = Semihosting(hio::hstdout().ok());
    let (file, at) = info.location().map_or(("?", 0), |l| (l.file(), l.line()));
    Line::new().text("fw panic at ").text(file).text(":").num(at).send(&mut out);
    debug::exit(EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}
