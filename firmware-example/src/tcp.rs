//! The host side of the link controller: a TCP socket as the link, stdout for the
//! trace. Serves one connection, then exits.

use std::io::{ErrorKind, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::process::ExitCode;
use std::time::Instant;

use firmware_example::link::{self, LinkStorage};

struct Tcp {
    stream: TcpStream,
    buf: [u8; 256],
    len: usize,
    at: usize,
    closed: bool,
    started: Instant,
}

impl bt_link::Board for Tcp {
    fn read(&mut self) -> Option<u8> {
        if self.at == self.len && !self.closed {
            self.at = 0;
            self.len = 0;
            match self.stream.read(&mut self.buf) {
                Ok(0) => self.closed = true,
                Ok(n) => self.len = n,
                Err(e) if e.kind() == ErrorKind::WouldBlock || e.kind() == ErrorKind::Interrupted => {}
                Err(_) => self.closed = true,
            }
        }
        let b = self.buf.get(self.at).copied().filter(|_| self.at < self.len)?;
        self.at += 1;
        Some(b)
    }

    fn write(&mut self, mut bytes: &[u8]) {
        while !bytes.is_empty() && !self.closed {
            match self.stream.write(bytes) {
                Ok(n) => bytes = bytes.get(n..).unwrap_or_default(),
                Err(e) if e.kind() == ErrorKind::WouldBlock || e.kind() == ErrorKind::Interrupted => {
                    std::thread::yield_now();
                }
                Err(_) => self.closed = true,
            }
        }
    }

    fn micros(&mut self) -> u32 {
        self.started.elapsed().as_micros() as u32
    }

    fn closed(&mut self) -> bool {
        if self.closed || self.at < self.len {
            return self.closed && self.at >= self.len;
        }
        // Nothing buffered: look once more before sleeping, so that an idle loop does
        // not spin a core.
        std::thread::sleep(std::time::Duration::from_micros(200));
        false
    }
}

struct Stdout(std::io::StdoutLock<'static>);

impl firmware_example::Sink for Stdout {
    fn line(&mut self, line: &[u8]) {
        let _ = self.0.write_all(line).and_then(|()| self.0.write_all(b"\n"));
    }
}

pub fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let addr = match args.as_slice() {
        [_, flag, addr] if flag == "--listen" => addr.clone(),
        _ => {
            eprintln!("usage: controller --listen HOST:PORT");
            return ExitCode::from(2);
        }
    };
    let listener = match TcpListener::bind(&addr) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("controller: cannot listen on {addr}: {e}");
            return ExitCode::from(2);
        }
    };
    eprintln!("controller: listening on {addr}");
    let stream = match listener.accept() {
        Ok((s, _)) => s,
        Err(e) => {
            eprintln!("controller: accept: {e}");
            return ExitCode::FAILURE;
        }
    };
    let _ = stream.set_nodelay(true);
    if let Err(e) = stream.set_nonblocking(true) {
        eprintln!("controller: {e}");
        return ExitCode::FAILURE;
    }
    let mut board = Tcp { stream, buf: [0; 256], len: 0, at: 0, closed: false, started: Instant::now() };
    let mut out = Stdout(std::io::stdout().lock());
    let mut storage = Box::new(LinkStorage::new());
    link::serve(&mut storage, firmware_example::IMAGE, &mut board, &mut out);
    let _ = out.0.flush();
    ExitCode::SUCCESS
}
