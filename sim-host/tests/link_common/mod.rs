//! A controller for the CLI's link tests: `bt_link::serve` in a thread of the test,
//! serving one TCP connection on the loopback interface, with the behavior set and the
//! world the test gives.
#![allow(dead_code, clippy::unwrap_used)]

use std::io::{ErrorKind, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::thread::JoinHandle;
use std::time::Instant;

use bt_core::Catalog;
use bt_link::{App, Board, Storage};

/// The controller's end of the socket, polled as a UART would be.
struct Tcp {
    stream: TcpStream,
    closed: bool,
    started: Instant,
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

/// A controller holding at most `NODES` nodes of `catalog`'s behaviors, booted with
/// `boot`, acting on `app`, serving one connection on a free port: its address, and the
/// thread, which hands the world back when the connection closes.
pub fn controller<const NODES: usize, C, A>(catalog: C, boot: Option<Vec<u8>>, app: A) -> (String, JoinHandle<A>)
where
    C: Catalog + Send + 'static,
    A: App + Send + 'static,
{
    controller_of::<NODES, 640, C, A>(catalog, boot, app)
}

/// [`controller`] with images of at most `BYTES` bytes.
pub fn controller_of<const NODES: usize, const BYTES: usize, C, A>(
    catalog: C,
    boot: Option<Vec<u8>>,
    mut app: A,
) -> (String, JoinHandle<A>)
where
    C: Catalog + Send + 'static,
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
        let mut board = Tcp { stream, closed: false, started: Instant::now() };
        let mut storage = Box::new(Storage::<NODES, BYTES, 32>::new());
        bt_link::serve::<_, _, _, NODES, BYTES, 32, 16>(&mut storage, &catalog, boot.as_deref(), &mut board, &mut app);
        app
    });
    (addr, handle)
}
