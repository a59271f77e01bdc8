//! A byte link paced to a serial line's rate, for measuring deployments over an
//! emulator's socket.

use std::io::{self, Read, Write};
use std::time::{Duration, Instant};

/// A byte link paced to a serial line's rate: writes and reads no faster than `baud`
/// bits per second, 10 bits per byte (8N1). Wraps a faster link (QEMU's socket) to
/// measure what a real line would sustain.
#[derive(Debug)]
pub struct Paced<T> {
    inner: T,
    byte_time: Duration,
    write_free: Instant,
    read_free: Instant,
}

impl<T> Paced<T> {
    /// Paces `inner` at `baud`.
    pub fn new(inner: T, baud: u32) -> Self {
        let now = Instant::now();
        Self {
            inner,
            byte_time: Duration::from_nanos(10_000_000_000 / u64::from(baud.max(1))),
            write_free: now,
            read_free: now,
        }
    }

    fn pace(free: &mut Instant, byte_time: Duration, n: usize) {
        let now = Instant::now();
        let start = (*free).max(now);
        *free = start + byte_time * n as u32;
        if *free > now {
            std::thread::sleep(*free - now);
        }
    }
}

impl<T: Read> Read for Paced<T> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        // One byte at a time, as a UART delivers them.
        let Some(first) = buf.first_mut() else { return Ok(0) };
        let n = self.inner.read(std::slice::from_mut(first))?;
        Self::pace(&mut self.read_free, self.byte_time, n);
        Ok(n)
    }
}

impl<T: Write> Write for Paced<T> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        Self::pace(&mut self.write_free, self.byte_time, n);
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}
