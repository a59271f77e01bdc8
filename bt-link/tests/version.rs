//! Hosts and controllers of different protocol versions refuse each other at `Hello`,
//! with the version error: the `Hello` reply keeps its layout in every version.

use std::collections::VecDeque;
use std::io::{self, Read, Write};

use bt_link::frame::{self, MAX_ENCODED};
use bt_link::host::{Client, LinkError};
use bt_link::{PROTOCOL_VERSION, Reply};

/// A controller that answers any request with one `Hello` of `version`.
struct OldController {
    version: u16,
    out: VecDeque<u8>,
}

impl Write for OldController {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        if buf.contains(&0) && self.out.is_empty() {
            let hello = Reply::Hello {
                version: self.version,
                fingerprint: 7,
                node_capacity: 64,
                image_capacity: 640,
                running: None,
            };
            let mut f = [0u8; MAX_ENCODED];
            self.out.extend(frame::encode(&hello, &mut f).unwrap().iter());
        }
        Ok(buf.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

impl Read for OldController {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        match self.out.pop_front() {
            Some(b) => {
                buf[0] = b;
                Ok(1)
            }
            None => Err(io::ErrorKind::WouldBlock.into()),
        }
    }
}

#[test]
fn controllers_of_versions_1_and_2_are_refused_with_the_version_error() {
    for old in [1, 2] {
        let mut client = Client::new(OldController { version: old, out: VecDeque::new() });
        match client.hello() {
            Err(LinkError::Version { controller, host }) => assert_eq!((controller, host), (old, PROTOCOL_VERSION)),
            other => panic!("expected the version error, got {other:?}"),
        }
    }
}

#[test]
fn a_deployment_to_a_version_2_controller_is_refused_at_its_hello() {
    // A client that has not said Hello says it before its first deployment, and so
    // never sends a version-2 controller a `Deploy` it would misread.
    let mut client = Client::new(OldController { version: 2, out: VecDeque::new() });
    match client.deploy(&[1, 2, 3], None, &mut |_| {}) {
        Err(LinkError::Version { controller: 2, .. }) => {}
        other => panic!("expected the version error, got {other:?}"),
    }
}

#[test]
fn the_hello_reply_keeps_the_layout_a_version_1_host_reads() {
    // Version 1's layout: tag 0, version u16, fingerprint u64, node capacity u16, image
    // capacity u32 (all little-endian), then the running image as an option.
    let hello = Reply::Hello {
        version: PROTOCOL_VERSION,
        fingerprint: 0x0102_0304_0506_0708,
        node_capacity: 64,
        image_capacity: 640,
        running: None,
    };
    let mut buf = [0u8; 64];
    let bytes = postcard::to_slice(&hello, &mut buf).unwrap();
    let mut expected = vec![0u8];
    expected.extend(PROTOCOL_VERSION.to_le_bytes());
    expected.extend(0x0102_0304_0506_0708u64.to_le_bytes());
    expected.extend(64u16.to_le_bytes());
    expected.extend(640u32.to_le_bytes());
    expected.push(0);
    assert_eq!(bytes, &expected[..]);
    assert_eq!(PROTOCOL_VERSION, 3, "a new version: say in the spec what changed");
}
