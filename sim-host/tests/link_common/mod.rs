//! A controller for the CLI's link tests: `bt_link::serve` in a thread of the test,
//! serving one TCP connection on the loopback interface, with the behavior set and the
//! world the test gives (the host build of the link controller).
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::io::{ErrorKind, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;

use bt_core::{BehaviorSet, Context, Leaf, NodeId, Status};
use bt_link::frame::{MAX_FRAME, message};
use bt_link::{App, Board, Decoder, Feed, Reply, Storage, WireStatus};

struct Tcp {
    stream: TcpStream,
    closed: bool,
    started: Instant,
    tap: Option<(Decoder<MAX_FRAME>, Tap)>,
}

impl Board for Tcp {
    fn read(&mut self) -> Option<u8> {
        let mut b = [0u8; 1];
        match self.stream.read(&mut b) {
            Ok(1) => Some(b[0]),
            Ok(_) => {
                self.closed = true;
                None
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock => None,
            Err(_) => {
                self.closed = true;
                None
            }
        }
    }
    fn write(&mut self, mut bytes: &[u8]) {
        if let Some((decoder, tap)) = &mut self.tap {
            for &b in bytes {
                if let Feed::Frame(frame) = decoder.feed(b) {
                    let sent = match message::<Reply<'_>>(frame) {
                        Ok(Reply::Status { tick, node, status }) => Some(Sent::Status { tick, node, status }),
                        Ok(Reply::Tick { tick, .. }) => Some(Sent::Tick(tick)),
                        Ok(Reply::Swapped { tick, .. }) => Some(Sent::Swapped(tick)),
                        _ => None,
                    };
                    tap.lock().unwrap().extend(sent);
                }
            }
        }
        while !bytes.is_empty() && !self.closed {
            match self.stream.write(bytes) {
                Ok(n) => bytes = &bytes[n..],
                Err(e) if e.kind() == ErrorKind::WouldBlock => std::thread::yield_now(),
                Err(_) => self.closed = true,
            }
        }
    }
    fn micros(&mut self) -> u32 {
        self.started.elapsed().as_micros() as u32
    }
    fn closed(&mut self) -> bool {
        std::thread::sleep(std::time::Duration::from_micros(100));
        self.closed
    }
}

/// The robot is far from everything with a free path and an empty hand, and every
/// action runs on: the planner's tree keeps `move-to(cube)` running.
pub struct World;

impl BehaviorSet for World {
    fn condition(&mut self, leaf: &Leaf, _: Context<'_>) -> Status {
        // cube-sphere ids: 2 hand-empty, 4 path-free (see the domain's predicates).
        if matches!(leaf.behavior(), 2 | 4) { Status::Success } else { Status::Failure }
    }
    fn action(&mut self, _: &Leaf, _: Context<'_>) -> Status {
        Status::Running
    }
    fn halt(&mut self, _: &Leaf, _: NodeId) {}
}

impl App for World {}

pub fn catalog() -> planner::PddlCatalog {
    let g = planner::domains::cube_sphere().unwrap();
    planner::PddlCatalog::new(g.problem())
}

/// The planner's cube tree as an image file.
pub fn cube_image(dir: &Path) -> (PathBuf, Vec<u8>) {
    let g = Arc::new(planner::domains::cube_sphere().unwrap());
    let c = Arc::new(planner::PddlCatalog::new(g.problem()));
    let plan = planner::plan(g, c.clone(), planner::Options::default()).unwrap();
    let image = bt_formats::Image::new(&plan.nodes).encode(bt_core::Catalog::fingerprint(c.as_ref())).unwrap();
    let path = dir.join("cube.bt");
    std::fs::write(&path, &image).unwrap();
    (path, image)
}

/// A controller holding at most `NODES` nodes of `catalog`'s behaviors, booted with
/// `boot`, acting on `app`, serving one connection on a free port: its address, and the
/// thread, which hands the world back when the connection closes.
pub fn controller<const NODES: usize, C, A>(catalog: C, boot: Option<Vec<u8>>, app: A) -> (String, JoinHandle<A>)
where
    C: bt_core::Catalog + Send + 'static,
    A: App + Send + 'static,
{
    spawn::<NODES, 640, C, A>(catalog, boot, app, None)
}

/// [`controller`] with images of at most `BYTES` bytes.
pub fn controller_of<const NODES: usize, const BYTES: usize, C, A>(
    catalog: C,
    boot: Option<Vec<u8>>,
    app: A,
) -> (String, JoinHandle<A>)
where
    C: bt_core::Catalog + Send + 'static,
    A: App + Send + 'static,
{
    spawn::<NODES, BYTES, C, A>(catalog, boot, app, None)
}

/// [`controller`] keeping every reply it sends in `tap`, in order (the controller's own
/// record of its status stream).
pub fn tapped<const NODES: usize, C, A>(catalog: C, boot: Option<Vec<u8>>, app: A, tap: Tap) -> (String, JoinHandle<A>)
where
    C: bt_core::Catalog + Send + 'static,
    A: App + Send + 'static,
{
    spawn::<NODES, 640, C, A>(catalog, boot, app, Some(tap))
}

fn spawn<const NODES: usize, const BYTES: usize, C, A>(
    catalog: C,
    boot: Option<Vec<u8>>,
    mut app: A,
    tap: Option<Tap>,
) -> (String, JoinHandle<A>)
where
    C: bt_core::Catalog + Send + 'static,
    A: App + Send + 'static,
{
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    listener.set_nonblocking(true).unwrap();
    let handle = std::thread::spawn(move || {
        // A command that fails before it connects must not hang the test.
        let started = Instant::now();
        let stream = loop {
            match listener.accept() {
                Ok((stream, _)) => break stream,
                Err(e) if e.kind() == ErrorKind::WouldBlock && started.elapsed().as_secs() < 60 => {
                    std::thread::sleep(std::time::Duration::from_millis(5));
                }
                Err(_) => return app,
            }
        };
        stream.set_nonblocking(true).unwrap();
        let mut board = Tcp { stream, closed: false, started: Instant::now(), tap: tap.map(|t| (Decoder::new(), t)) };
        let mut storage = Box::new(Storage::<NODES, BYTES, 32>::new());
        bt_link::serve::<_, _, _, NODES, BYTES, 32, 16>(&mut storage, &catalog, boot.as_deref(), &mut board, &mut app);
        app
    });
    (addr, handle)
}

/// What a controller sent, as `Sent`s.
pub type Tap = Arc<Mutex<Vec<Sent>>>;

/// A reply a controller sent, as the tests compare it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sent {
    /// `Status`.
    Status { tick: u32, node: u16, status: WireStatus },
    /// `Tick`.
    Tick(u32),
    /// `Swapped`.
    Swapped(u32),
}
