//! The link controller on QEMU's mps2-an386: the CMSDK UART0 as the link (QEMU's first
//! `-serial`), SysTick as the clock, semihosting for the trace.
//!
//! UART0 is polled: QEMU holds back bytes while the receive register is full, so none is
//! lost. On a real board at 115200 baud a byte arrives every 87 µs, while a tick that
//! sends status frames blocks for their length; such a port wants a receive interrupt
//! and a ring buffer in its [`Board::read`] (the host resends a chunk that was not
//! acked, so a lost byte costs a retry, never a wrong tree).

use bt_link::Board;
use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;

use crate::link::{self, LinkStorage};
use crate::target::{Semihosting, stack_usage};

/// Base address of the CMSDK APB UART0 on the AN385/AN386 memory map.
const UART0: usize = 0x4000_4000;
const DATA: usize = UART0;
const STATE: usize = UART0 + 0x04;
const CTRL: usize = UART0 + 0x08;
const BAUDDIV: usize = UART0 + 0x10;
const TX_FULL: u32 = 1 << 0;
const RX_FULL: u32 = 1 << 1;
/// The board's system clock, which drives the UART and SysTick.
const SYSCLK_HZ: u32 = 25_000_000;

#[allow(unsafe_code)]
fn read_reg(addr: usize) -> u32 {
    // SAFETY: a CMSDK UART0 register on this board's memory map: mapped, word
    // aligned, and read with no side effect but the UART's own (DATA pops a byte).
    unsafe { core::ptr::read_volatile(addr as *const u32) }
}

#[allow(unsafe_code)]
fn write_reg(addr: usize, value: u32) {
    // SAFETY: as `read_reg`; the UART is used by nothing else in this program.
    unsafe { core::ptr::write_volatile(addr as *mut u32, value) }
}

/// The UART link and the SysTick clock.
struct Uart {
    syst: SYST,
    last: u32,
    micros: u32,
    cycles: u32,
}

impl Uart {
    fn new(mut syst: SYST) -> Self {
        write_reg(BAUDDIV, SYSCLK_HZ / 115_200);
        write_reg(CTRL, 0b11);
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(0x00ff_ffff);
        syst.clear_current();
        syst.enable_counter();
        Self { last: SYST::get_current(), syst, micros: 0, cycles: 0 }
    }
}

impl Board for Uart {
    fn read(&mut self) -> Option<u8> {
        (read_reg(STATE) & RX_FULL != 0).then(|| read_reg(DATA) as u8)
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            while read_reg(STATE) & TX_FULL != 0 {}
            write_reg(DATA, u32::from(b));
        }
    }

    fn micros(&mut self) -> u32 {
        // SysTick counts down from 0xffffff; the loop reads it far more often than
        // once per wrap (0.67 s).
        let now = SYST::get_current();
        let elapsed = self.last.wrapping_sub(now) & 0x00ff_ffff;
        self.last = now;
        self.cycles = self.cycles.wrapping_add(elapsed);
        let per_us = SYSCLK_HZ / 1_000_000;
        self.micros = self.micros.wrapping_add(self.cycles / per_us);
        self.cycles %= per_us;
        let _ = &self.syst;
        self.micros
    }

    fn stack_used(&mut self) -> u32 {
        stack_usage().used
    }
}

/// Runs the link controller with `boot` as its first tree; never returns.
pub fn run(boot: &[u8]) -> ! {
    let Some(peripherals) = cortex_m::Peripherals::take() else {
        loop {
            cortex_m::asm::wfi();
        }
    };
    let mut uart = Uart::new(peripherals.SYST);
    let mut out = Semihosting::stdout();
    let mut storage = LinkStorage::new();
    link::serve(&mut storage, boot, &mut uart, &mut out);
    loop {
        cortex_m::asm::wfi();
    }
}
