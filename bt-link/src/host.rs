//! The host side (feature `std`): a blocking client over any `Read + Write` byte link
//! whose reads time out (a serial port, a TCP socket to QEMU).
//!
//! ```no_run
//! use bt_link::host::{Client, Verdict};
//! let stream = std::net::TcpStream::connect("127.0.0.1:4321")?;
//! stream.set_read_timeout(Some(std::time::Duration::from_millis(50)))?;
//! let mut link = Client::new(stream);
//! let hello = link.hello()?;
//! let image = std::fs::read("tree.bt")?;
//! match link.deploy(&image, None, &mut |_| {})? {
//!     Verdict::Accepted { nodes, .. } => println!("accepted, {nodes} nodes"),
//!     Verdict::Rejected(fault) => println!("rejected: {}", fault.code()),
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
// Host code: every index below is bounded by the loop or the buffer it walks.
#![allow(clippy::indexing_slicing)]

use std::io::{self, Read, Write};
use std::time::{Duration, Instant};

use crate::frame::{self, Decoder, Feed, MAX_ENCODED, MAX_FRAME, crc32};
use crate::wire::{Fault, FrameFault, ImageInfo, MAX_CHUNK, PROTOCOL_VERSION, Reply, Request};

/// What went wrong on the host's side of the link.
#[derive(Debug)]
pub enum LinkError {
    /// Reading or writing the link failed.
    Io(io::Error),
    /// The link closed.
    Closed,
    /// No answer in time.
    Timeout {
        /// What was awaited.
        waiting_for: &'static str,
        /// How long.
        after: Duration,
    },
    /// The controller speaks another protocol version.
    Version {
        /// The controller's.
        controller: u16,
        /// Ours.
        host: u16,
    },
    /// The controller answered something this request does not expect.
    Unexpected {
        /// What was awaited.
        waiting_for: &'static str,
        /// What came, as `Debug` text.
        got: String,
    },
}

impl std::fmt::Display for LinkError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Io(e) => write!(f, "link: {e}"),
            Self::Closed => f.write_str("the link closed"),
            Self::Timeout { waiting_for, after } => {
                write!(f, "no {waiting_for} from the controller within {} ms", after.as_millis())
            }
            Self::Version { controller, host } => {
                write!(f, "the controller speaks link protocol version {controller}, this host speaks version {host}")
            }
            Self::Unexpected { waiting_for, got } => write!(f, "expected {waiting_for} from the controller, got {got}"),
        }
    }
}

impl std::error::Error for LinkError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io(e) => Some(e),
            _ => None,
        }
    }
}

impl From<io::Error> for LinkError {
    fn from(e: io::Error) -> Self {
        Self::Io(e)
    }
}

/// The controller's answer to `Hello`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ControllerInfo {
    /// Its protocol version (equal to ours: [`Client::hello`] checks).
    pub version: u16,
    /// Its behavior set's fingerprint.
    pub fingerprint: u64,
    /// Most nodes a tree may have.
    pub node_capacity: u16,
    /// Most bytes an image may have.
    pub image_capacity: u32,
    /// The running image.
    pub running: Option<ImageInfo>,
}

/// How a deployment ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Validated; swapped in at tick `swap_at` (or the next boundary).
    Accepted {
        /// CRC-32 of the image.
        crc: u32,
        /// Its node count.
        nodes: u16,
        /// The tick it replaces the running tree at.
        swap_at: Option<u32>,
    },
    /// Refused; the running tree is untouched.
    Rejected(Fault),
}

/// A deployment as the host sends it, faults included: the scenario tests send
/// truncated and corrupted transfers on purpose.
#[derive(Clone, Copy, Debug)]
pub struct Transfer<'a> {
    /// Length announced in `Deploy`.
    pub len: u32,
    /// CRC announced in `Deploy`.
    pub crc: u32,
    /// Tick to swap at.
    pub swap_at: Option<u32>,
    /// The bytes actually sent (the image, or a part of it).
    pub bytes: &'a [u8],
    /// Flip the lowest bit of this byte on the wire (not in the announced CRC).
    pub flip: Option<usize>,
    /// Raw bytes sent on the wire before the chunk of this index, outside any frame.
    pub garbage: Option<(usize, &'a [u8])>,
}

impl<'a> Transfer<'a> {
    /// A faithful transfer of `image`.
    #[must_use]
    pub fn of(image: &'a [u8], swap_at: Option<u32>) -> Self {
        Self { len: image.len() as u32, crc: crc32(image), swap_at, bytes: image, flip: None, garbage: None }
    }
}

/// How long to wait for the controller to answer one request.
pub const ANSWER_TIMEOUT: Duration = Duration::from_secs(2);
/// How often a chunk is sent before the deployment gives up.
pub const CHUNK_TRIES: u32 = 4;

/// A blocking client: one request, then its answer; every other reply that arrives
/// meanwhile (status changes, tick statistics) goes to the caller's `watch`.
#[derive(Debug)]
pub struct Client<T> {
    io: T,
    decoder: Decoder<MAX_FRAME>,
    buf: Vec<u8>,
    at: usize,
    /// Bytes written and read, for throughput figures.
    pub sent: u64,
    /// Bytes read.
    pub received: u64,
}

impl<T: Read + Write> Client<T> {
    /// A client over `io`, whose reads should time out (say after 50 ms) so that the
    /// client can notice its own deadlines.
    pub fn new(io: T) -> Self {
        Self { io, decoder: Decoder::new(), buf: vec![0; 4096], at: 0, sent: 0, received: 0 }
    }

    /// The byte link.
    pub fn io(&mut self) -> &mut T {
        &mut self.io
    }

    /// Sends one request as a frame, preceded by a delimiter so that any partial frame
    /// on the wire ends before it.
    ///
    /// # Errors
    /// The link's write error.
    pub fn send(&mut self, request: &Request<'_>) -> Result<(), LinkError> {
        let mut buf = [0u8; MAX_ENCODED + 1];
        let n = match frame::encode(request, &mut buf[1..]) {
            Ok(b) => b.len(),
            Err(_) => return Err(LinkError::Io(io::Error::other("request too long for a frame"))),
        };
        self.raw(&buf[..=n])
    }

    /// Writes bytes as they are, outside any frame.
    ///
    /// # Errors
    /// The link's write error.
    pub fn raw(&mut self, bytes: &[u8]) -> Result<(), LinkError> {
        self.io.write_all(bytes)?;
        self.io.flush()?;
        self.sent += bytes.len() as u64;
        Ok(())
    }

    /// The next reply, waiting at most until `deadline`.
    ///
    /// # Errors
    /// [`LinkError::Timeout`] (naming `waiting_for`), [`LinkError::Closed`], or the
    /// link's read error.
    pub fn next(&mut self, deadline: Instant, waiting_for: &'static str) -> Result<Reply<'_>, LinkError> {
        let started = Instant::now();
        loop {
            while self.at < self.buf.len() {
                let byte = self.buf[self.at];
                self.at += 1;
                match self.decoder.feed(byte) {
                    Feed::Pending => {}
                    Feed::Skipped(fault) => return Ok(Reply::Garbled { fault }),
                    Feed::Frame(_) => {
                        // Decoded again below: the borrow of the decoder has to outlive
                        // this loop.
                        return Ok(self.take_frame());
                    }
                }
            }
            if Instant::now() >= deadline {
                return Err(LinkError::Timeout { waiting_for, after: deadline.saturating_duration_since(started) });
            }
            self.buf.resize(4096, 0);
            match self.io.read(&mut self.buf) {
                Ok(0) => return Err(LinkError::Closed),
                Ok(n) => {
                    self.received += n as u64;
                    self.buf.truncate(n);
                    self.at = 0;
                }
                Err(e) if matches!(e.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut) => {
                    self.buf.clear();
                    self.at = 0;
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e.into()),
            }
        }
    }

    /// The frame the decoder just completed, as a reply.
    fn take_frame(&mut self) -> Reply<'_> {
        match self.decoder.last_frame() {
            Some(bytes) => frame::message(bytes).unwrap_or(Reply::Garbled { fault: FrameFault::Message }),
            None => Reply::Garbled { fault: FrameFault::Message },
        }
    }

    /// Waits for a reply that `pick` accepts, passing every other one to `watch`.
    fn wait<R>(
        &mut self,
        waiting_for: &'static str,
        timeout: Duration,
        watch: &mut dyn FnMut(&Reply<'_>),
        mut pick: impl FnMut(&Reply<'_>) -> Option<R>,
    ) -> Result<R, LinkError> {
        let deadline = Instant::now() + timeout;
        loop {
            let reply = self.next(deadline, waiting_for)?;
            if let Some(r) = pick(&reply) {
                return Ok(r);
            }
            watch(&reply);
        }
    }

    /// Asks who the controller is; fails on another protocol version.
    ///
    /// # Errors
    /// [`LinkError::Version`], a timeout, or a link error.
    pub fn hello(&mut self) -> Result<ControllerInfo, LinkError> {
        self.send(&Request::Hello { version: PROTOCOL_VERSION })?;
        let info = self.wait("Hello", ANSWER_TIMEOUT, &mut |_| {}, |r| match *r {
            Reply::Hello { version, fingerprint, node_capacity, image_capacity, running } => {
                Some(ControllerInfo { version, fingerprint, node_capacity, image_capacity, running })
            }
            _ => None,
        })?;
        if info.version != PROTOCOL_VERSION {
            return Err(LinkError::Version { controller: info.version, host: PROTOCOL_VERSION });
        }
        Ok(info)
    }

    /// Sends `image` and waits for the verdict; every other reply goes to `watch`.
    ///
    /// # Errors
    /// A timeout or a link error; a refusal is a [`Verdict::Rejected`], not an error.
    pub fn deploy(
        &mut self,
        image: &[u8],
        swap_at: Option<u32>,
        watch: &mut dyn FnMut(&Reply<'_>),
    ) -> Result<Verdict, LinkError> {
        self.transfer(&Transfer::of(image, swap_at), watch)
    }

    /// Sends a [`Transfer`] as described, faults included, and waits for the verdict.
    ///
    /// # Errors
    /// As [`Client::deploy`].
    pub fn transfer(&mut self, t: &Transfer<'_>, watch: &mut dyn FnMut(&Reply<'_>)) -> Result<Verdict, LinkError> {
        enum Step {
            Ack(u32),
            Refused(Fault),
        }
        let ack = |r: &Reply<'_>| match *r {
            Reply::ChunkAck { received } => Some(Step::Ack(received)),
            Reply::Rejected { fault } if !matches!(fault, Fault::Superseded { .. }) => Some(Step::Refused(fault)),
            _ => None,
        };
        self.send(&Request::Deploy { len: t.len, crc: t.crc, swap_at: t.swap_at })?;
        if let Step::Refused(fault) = self.wait("ChunkAck", ANSWER_TIMEOUT, watch, ack)? {
            return Ok(Verdict::Rejected(fault));
        }
        let mut offset = 0usize;
        let mut tries = 0;
        let mut index = 0usize;
        let mut wire = [0u8; MAX_CHUNK];
        while offset < t.bytes.len() {
            let end = (offset + MAX_CHUNK).min(t.bytes.len());
            let chunk = &mut wire[..end - offset];
            chunk.copy_from_slice(&t.bytes[offset..end]);
            if let Some(at) = t.flip.filter(|&at| (offset..end).contains(&at)) {
                chunk[at - offset] ^= 1;
            }
            if let Some((_, garbage)) = t.garbage.filter(|&(i, _)| i == index) {
                self.raw(garbage)?;
            }
            self.send(&Request::Chunk { offset: offset as u32, bytes: chunk })?;
            index += 1;
            match self.wait("ChunkAck", ANSWER_TIMEOUT / 4, watch, ack) {
                Ok(Step::Ack(received)) => {
                    let received = received as usize;
                    if received > offset {
                        tries = 0;
                    }
                    offset = received.min(t.bytes.len());
                }
                Ok(Step::Refused(fault)) => return Ok(Verdict::Rejected(fault)),
                Err(LinkError::Timeout { .. }) if tries + 1 < CHUNK_TRIES => tries += 1,
                Err(e) => return Err(e),
            }
        }
        self.send(&Request::Commit)?;
        self.wait("Accepted or Rejected", ANSWER_TIMEOUT, watch, |r| match *r {
            Reply::Accepted { crc, nodes, swap_at } => Some(Verdict::Accepted { crc, nodes, swap_at }),
            Reply::Rejected { fault } if !matches!(fault, Fault::Superseded { .. }) => Some(Verdict::Rejected(fault)),
            _ => None,
        })
    }

    /// Starts ticking; returns the controller's state reply fields `(tick, until)`.
    ///
    /// # Errors
    /// A refusal (no tree) as [`LinkError::Unexpected`], a timeout, or a link error.
    pub fn start(
        &mut self,
        until: Option<u32>,
        period_ms: u16,
        watch: &mut dyn FnMut(&Reply<'_>),
    ) -> Result<u32, LinkError> {
        self.send(&Request::Start { until, period_ms })?;
        self.state_reply("State", 0, watch).map(|s| s.tick)
    }

    /// Stops ticking, halting the running actions; returns the actions halted.
    ///
    /// # Errors
    /// A timeout or a link error.
    pub fn stop(&mut self, watch: &mut dyn FnMut(&Reply<'_>)) -> Result<State, LinkError> {
        self.send(&Request::Stop)?;
        self.state_reply("State", 0, watch)
    }

    /// Pings; returns the controller's state.
    ///
    /// # Errors
    /// A timeout or a link error.
    pub fn ping(&mut self, token: u32, watch: &mut dyn FnMut(&Reply<'_>)) -> Result<State, LinkError> {
        self.send(&Request::Ping { token })?;
        self.state_reply("State", token, watch)
    }

    fn state_reply(
        &mut self,
        waiting_for: &'static str,
        want: u32,
        watch: &mut dyn FnMut(&Reply<'_>),
    ) -> Result<State, LinkError> {
        let r = self.wait(waiting_for, ANSWER_TIMEOUT, watch, |r| match *r {
            Reply::State { token, tick, ticking, until, running, halted, stack_used } if token == want => {
                Some(Ok(State { tick, ticking, until, running, halted, stack_used }))
            }
            Reply::Rejected { fault: Fault::NoTree } => Some(Err(Fault::NoTree)),
            _ => None,
        })?;
        r.map_err(|f| LinkError::Unexpected { waiting_for, got: format!("Rejected({})", f.code()) })
    }

    /// Reads the running image back.
    ///
    /// # Errors
    /// [`LinkError::Unexpected`] when the controller has no tree, a timeout, or a link
    /// error.
    pub fn read_image(&mut self, watch: &mut dyn FnMut(&Reply<'_>)) -> Result<Vec<u8>, LinkError> {
        let mut image = Vec::new();
        loop {
            self.send(&Request::Read { offset: image.len() as u32 })?;
            let want = image.len() as u32;
            let (total, bytes) = self
                .wait("Image", ANSWER_TIMEOUT, watch, |r| match *r {
                    Reply::Image { offset, total, bytes } if offset == want => Some(Ok((total, bytes.to_vec()))),
                    Reply::Rejected { fault: Fault::NoTree } => Some(Err(())),
                    _ => None,
                })?
                .map_err(|()| LinkError::Unexpected { waiting_for: "Image", got: "Rejected(no-tree)".into() })?;
            image.extend_from_slice(&bytes);
            if image.len() >= total as usize || bytes.is_empty() {
                return Ok(image);
            }
        }
    }
}

/// The controller's answer to `Start`, `Stop` and `Ping`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct State {
    /// The next tick to run.
    pub tick: u32,
    /// Ticking.
    pub ticking: bool,
    /// Stops before this tick.
    pub until: Option<u32>,
    /// The running image.
    pub running: Option<ImageInfo>,
    /// Actions a `Stop` halted.
    pub halted: u16,
    /// Stack bytes used since boot (0: unknown).
    pub stack_used: u32,
}

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
