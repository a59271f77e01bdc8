//! A libzmq client for the Groot2 tests, and free ports to serve on.
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::net::TcpListener;

/// Two free consecutive ports on the loopback interface (the request port first).
pub fn free_ports() -> u16 {
    loop {
        let a = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = a.local_addr().unwrap().port();
        if port < u16::MAX && TcpListener::bind(("127.0.0.1", port + 1)).is_ok() {
            return port;
        }
    }
}

/// A REQ socket, as Groot2 connects, with a receive timeout.
pub fn client(ctx: &zmq::Context, port: u16) -> zmq::Socket {
    let s = ctx.socket(zmq::REQ).unwrap();
    s.set_linger(0).unwrap();
    s.set_rcvtimeo(5000).unwrap();
    s.set_sndtimeo(5000).unwrap();
    s.connect(&format!("tcp://127.0.0.1:{port}")).unwrap();
    s
}

/// Sends `parts`, returns the reply's parts.
pub fn ask(s: &zmq::Socket, parts: &[Vec<u8>]) -> Vec<Vec<u8>> {
    s.send_multipart(parts, 0).unwrap();
    s.recv_multipart(0).expect("no reply within 5 s")
}

/// A request header: protocol 2, `kind`, `id`.
pub fn header(kind: u8, id: u32) -> Vec<u8> {
    let mut h = vec![2, kind];
    h.extend_from_slice(&id.to_le_bytes());
    h
}
