//! UART0 of the LM3S6965, an ARM PL011: 115200 baud 8N1 from the 12 MHz system clock,
//! its 16-byte FIFOs on, an interrupt when a byte arrives. A board with a HAL has all
//! of this in its UART driver; the LM3S6965's PAC has no peripherals, so here it is.

/// UART0's registers.
const BASE: usize = 0x4000_c000;
const DR: usize = BASE;
const FR: usize = BASE + 0x18;
const IBRD: usize = BASE + 0x24;
const FBRD: usize = BASE + 0x28;
const LCRH: usize = BASE + 0x2c;
const CR: usize = BASE + 0x30;
const IMSC: usize = BASE + 0x38;
const ICR: usize = BASE + 0x44;
/// FR: receive FIFO empty, transmit FIFO full.
const RXFE: u32 = 1 << 4;
const TXFF: u32 = 1 << 5;
/// IMSC and ICR: receive, receive timeout.
const RX_INTERRUPTS: u32 = (1 << 4) | (1 << 6);

#[allow(unsafe_code)]
fn read(addr: usize) -> u32 {
    // SAFETY: a UART0 register of the LM3S6965's memory map: mapped, word aligned, and
    // read with no side effect but the UART's own (DR pops a byte).
    unsafe { core::ptr::read_volatile(addr as *const u32) }
}

#[allow(unsafe_code)]
fn write(addr: usize, value: u32) {
    // SAFETY: as `read`; UART0 is used by nothing else in this program.
    unsafe { core::ptr::write_volatile(addr as *mut u32, value) }
}

/// 115200 baud from 12 MHz: divisor 12e6 / (16 x 115200) = 6.5104 = 6 + 33/64.
pub fn init() {
    write(CR, 0);
    write(IBRD, 6);
    write(FBRD, 33);
    // 8 data bits, FIFOs on.
    write(LCRH, (0b11 << 5) | (1 << 4));
    write(IMSC, RX_INTERRUPTS);
    // UART, transmitter and receiver on.
    write(CR, 1 | (1 << 8) | (1 << 9));
}

/// The next received byte, if the FIFO has one.
pub fn receive() -> Option<u8> {
    (read(FR) & RXFE == 0).then(|| read(DR) as u8)
}

/// Acknowledges the receive interrupts (after the FIFO was emptied).
pub fn clear() {
    write(ICR, RX_INTERRUPTS);
}

/// Puts as many of `bytes` into the transmit FIFO as it takes; returns how many.
pub fn send(bytes: &[u8]) -> usize {
    let mut n = 0;
    for &b in bytes {
        if read(FR) & TXFF != 0 {
            break;
        }
        write(DR, u32::from(b));
        n += 1;
    }
    n
}
