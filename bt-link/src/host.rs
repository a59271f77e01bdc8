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

mod paced;
mod transfer;

pub use paced::Paced;

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
/// How many times in a row a deployment waits [`ANSWER_TIMEOUT`] / 4 without progress
/// before it gives up.
pub const CHUNK_TRIES: u32 = 8;
/// Bytes of chunks a deployment sends ahead of the controller's acknowledgement: four
/// chunks. A controller's receive queue should hold them (with their framing, about 320
/// bytes); [`Client::set_window`] changes it.
pub const WINDOW: usize = 4 * MAX_CHUNK;

/// The time a [`Client`] measures its deadlines with.
pub type ClockFn = Box<dyn Fn() -> Instant + Send>;

/// A blocking client: one request, then its answer; every other reply that arrives
/// meanwhile (status changes, tick statistics) goes to the caller's `watch`.
pub struct Client<T> {
    io: T,
    decoder: Decoder<MAX_FRAME>,
    /// Bytes read and not yet decoded: `buf[at..len]`.
    buf: Vec<u8>,
    at: usize,
    len: usize,
    /// Bytes written and read, for throughput figures.
    pub sent: u64,
    /// Bytes read.
    pub received: u64,
    /// Bytes of chunks sent ahead of the acknowledgement.
    window: usize,
    /// An operation gave up: replies to it may still arrive.
    stale: bool,
    /// The last token of a resynchronizing `Ping`.
    token: u32,
    /// The id of the last transfer (`Deploy`'s id); each deployment takes the next.
    transfer_id: u16,
    /// A `Hello` was answered: the controller's session, whose transfer ids are ours.
    greeted: bool,
    /// Where deadlines are measured: the system's clock, or a simulation's.
    clock: Option<ClockFn>,
}

impl<T: std::fmt::Debug> std::fmt::Debug for Client<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Client")
            .field("io", &self.io)
            .field("sent", &self.sent)
            .field("received", &self.received)
            .field("window", &self.window)
            .finish_non_exhaustive()
    }
}

impl<T: Read + Write> Client<T> {
    /// A client over `io`, whose reads should time out (say after 50 ms) so that the
    /// client can notice its own deadlines.
    pub fn new(io: T) -> Self {
        Self {
            io,
            decoder: Decoder::new(),
            buf: vec![0; 4096],
            at: 0,
            len: 0,
            sent: 0,
            received: 0,
            window: WINDOW,
            stale: false,
            token: 0,
            transfer_id: 0,
            greeted: false,
            clock: None,
        }
    }

    /// Measures deadlines with `clock` instead of the system's: for a simulated link
    /// whose reads advance a simulated time, so that timeouts and resends happen in
    /// that time (the loss tests run thousands of deployments so, in seconds).
    #[must_use]
    pub fn with_clock(mut self, clock: ClockFn) -> Self {
        self.clock = Some(clock);
        self
    }

    fn now(&self) -> Instant {
        self.clock.as_ref().map_or_else(Instant::now, |c| c())
    }

    /// Bytes of chunks a deployment sends ahead of the acknowledgement ([`WINDOW`]
    /// unless set).
    #[must_use]
    pub fn window(&self) -> usize {
        self.window
    }

    /// Sets [`Client::window`]: [`MAX_CHUNK`] is stop-and-wait, one chunk at a time.
    pub fn set_window(&mut self, bytes: usize) {
        self.window = bytes.max(MAX_CHUNK);
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
        let started = self.now();
        loop {
            while self.at < self.len {
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
            if self.now() >= deadline {
                return Err(LinkError::Timeout { waiting_for, after: deadline.saturating_duration_since(started) });
            }
            (self.at, self.len) = (0, 0);
            match self.io.read(&mut self.buf) {
                Ok(0) => return Err(LinkError::Closed),
                Ok(n) => {
                    self.received += n as u64;
                    self.len = n.min(self.buf.len());
                }
                Err(e) if matches!(e.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut) => {}
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
        let deadline = self.now() + timeout;
        loop {
            let reply = self.next(deadline, waiting_for)?;
            if let Some(r) = pick(&reply) {
                return Ok(r);
            }
            watch(&reply);
        }
    }

    /// Asks who the controller is; fails on another protocol version. Starts the
    /// controller's session: transfer ids from here on are this client's. Asked up to
    /// four times within [`ANSWER_TIMEOUT`], as a line may lose a request or its answer.
    ///
    /// # Errors
    /// [`LinkError::Version`], a timeout, or a link error.
    pub fn hello(&mut self) -> Result<ControllerInfo, LinkError> {
        self.greet(&mut |_| {})
    }

    /// [`Client::hello`], passing every other reply to `watch`.
    fn greet(&mut self, watch: &mut dyn FnMut(&Reply<'_>)) -> Result<ControllerInfo, LinkError> {
        const TRIES: u32 = 4;
        let mut answer = None;
        for _ in 0..TRIES {
            self.send(&Request::Hello { version: PROTOCOL_VERSION })?;
            match self.wait("Hello", ANSWER_TIMEOUT / TRIES, watch, |r| match *r {
                Reply::Hello { version, fingerprint, node_capacity, image_capacity, running } => {
                    Some(ControllerInfo { version, fingerprint, node_capacity, image_capacity, running })
                }
                _ => None,
            }) {
                Ok(info) => {
                    answer = Some(info);
                    break;
                }
                Err(LinkError::Timeout { .. }) => {}
                Err(e) => return Err(e),
            }
        }
        let info = answer.ok_or(LinkError::Timeout { waiting_for: "Hello", after: ANSWER_TIMEOUT })?;
        if info.version != PROTOCOL_VERSION {
            return Err(LinkError::Version { controller: info.version, host: PROTOCOL_VERSION });
        }
        self.greeted = true;
        Ok(info)
    }

    /// Sends `image` and waits for the verdict; every other reply goes to `watch`.
    ///
    /// Each call is one deployment, under a new transfer id: it swaps in at most once,
    /// however often the line makes the client repeat its requests, and deploying the
    /// image that runs already swaps it in again (restarting it). A client that has not
    /// said [`hello`](Client::hello) says it first: the `Hello` starts the controller's
    /// session, in which the transfer ids are this client's.
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
    /// Pipelined: `Deploy` and the chunks go out without waiting for answers, at most
    /// [`Client::window`] bytes of chunks ahead of the controller's cumulative
    /// acknowledgement, and `Commit` as soon as the `Deploy` is acknowledged and the
    /// last chunk sent, so a deployment takes one round trip plus its time on the
    /// line. A gap (a chunk lost or garbled on the way) is resent from its start once
    /// the acknowledgements show it, or after [`ANSWER_TIMEOUT`] / 4 without progress; a
    /// lost `Deploy` or `Commit` is sent again (the controller answers a repeat with
    /// where the transfer stands or its verdict, and never swaps it in twice). After
    /// [`CHUNK_TRIES`] such timeouts in a row the deployment gives up with
    /// [`LinkError::Timeout`].
    ///
    /// # Errors
    /// As [`Client::deploy`], and [`LinkError::Version`] from the first `Hello`.
    pub fn transfer(&mut self, t: &Transfer<'_>, watch: &mut dyn FnMut(&Reply<'_>)) -> Result<Verdict, LinkError> {
        if self.stale {
            self.resync(watch)?;
        }
        if !self.greeted {
            self.greet(watch)?;
        }
        self.stale = true;
        let verdict = self.pipelined(t, watch)?;
        self.stale = false;
        Ok(verdict)
    }

    /// Waits for the answer to a fresh `Ping`, dropping everything before it: replies
    /// to an operation that gave up, which would otherwise be taken for the next one's.
    fn resync(&mut self, watch: &mut dyn FnMut(&Reply<'_>)) -> Result<(), LinkError> {
        self.token = self.token.wrapping_add(1) | 0x8000_0000;
        let token = self.token;
        for _ in 0..CHUNK_TRIES {
            self.send(&Request::Ping { token })?;
            match self.wait("State", ANSWER_TIMEOUT / 4, watch, |r| {
                matches!(*r, Reply::State { token: t, .. } if t == token).then_some(())
            }) {
                Ok(()) => return Ok(()),
                Err(LinkError::Timeout { .. }) => {}
                Err(e) => return Err(e),
            }
        }
        Err(LinkError::Timeout { waiting_for: "State", after: ANSWER_TIMEOUT })
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
