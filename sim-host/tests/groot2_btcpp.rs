//! The Groot2 server against BehaviorTree.CPP 4.10.0's own Groot2Publisher: the
//! requests of `tests/btcpp/fixtures/groot2/session.txt`, sent through a libzmq client
//! to a server given the same tree and the same status changes, get the same replies,
//! but for the tree's UUID and the times (recorded by `tests/btcpp/groot2/record.sh`).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]

use std::path::{Path, PathBuf};

use btcpp::btlog::LogTree;
use btcpp::groot2::REPLY_HEADER;
use btcpp::xml::{ImportOptions, import_text};
use sim_host::groot2::{Listen, Server};

mod groot2_common;
use groot2_common::{ask, client, free_ports};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/btcpp/fixtures/groot2")
}

fn hex(s: &str) -> Vec<Vec<u8>> {
    s.split(';')
        .map(|p| (0..p.len()).step_by(2).map(|i| u8::from_str_radix(&p[i..i + 2], 16).unwrap()).collect())
        .collect()
}

fn tree() -> LogTree {
    let path = fixtures().join("tree.xml");
    let text = std::fs::read_to_string(&path).unwrap();
    LogTree::of_imported(&import_text(&path, &text, &ImportOptions::default()).unwrap()).unwrap()
}

#[test]
fn the_server_answers_groot2_as_behaviortree_cpp_does() {
    let session = std::fs::read_to_string(fixtures().join("session.txt")).unwrap();
    let port = free_ports();
    let server = Server::start(&Listen::parse(&format!("127.0.0.1:{port}")).unwrap(), &tree()).unwrap();
    let ctx = zmq::Context::new();
    let groot = client(&ctx, port);
    let mut lines = session.lines();
    let (mut requests, mut changes, mut transitions) = (0, 0, 0);
    while let Some(line) = lines.next() {
        let words: Vec<&str> = line.split(' ').collect();
        match words[0] {
            "change" => {
                server.set(words[1].parse().unwrap(), words[3].parse().unwrap());
                changes += 1;
            }
            "tick" => {}
            "request" => {
                let name = words[1..words.len() - 1].join(" ");
                let sent = hex(words[words.len() - 1]);
                let want = hex(lines.next().unwrap().strip_prefix("reply ").unwrap());
                let got = ask(&groot, &sent);
                requests += 1;
                assert_eq!(got.len(), want.len(), "{name}: parts");
                if want[0] == b"error" {
                    assert_eq!(got, want, "{name}");
                    continue;
                }
                // The header but the UUID, which is the server's own.
                assert_eq!(got[0].len(), REPLY_HEADER, "{name}");
                assert_eq!(got[0][..6], want[0][..6], "{name}: header");
                assert_eq!(got[0][6..], server.uuid(), "{name}: UUID");
                match (name.as_str(), sent.get(1).map(Vec::as_slice)) {
                    ("TOGGLE_RECORDING", Some(b"start")) => {
                        // The time: microseconds since 1970, as text.
                        let t: i64 = String::from_utf8(got[1].clone()).unwrap().parse().unwrap();
                        assert!(t > 1_600_000_000_000_000, "{name}: {t}");
                    }
                    ("GET_TRANSITIONS", _) => {
                        // Each 9 bytes: 6 of time, then uid and status, which must agree.
                        assert_eq!(got[1].len(), want[1].len(), "{name}: transitions");
                        for (g, w) in got[1].chunks(9).zip(want[1].chunks(9)) {
                            assert_eq!(g[6..], w[6..], "{name}: a transition");
                            transitions += 1;
                        }
                    }
                    _ => assert_eq!(got[1..], want[1..], "{name}"),
                }
            }
            other => panic!("unknown line {other}"),
        }
    }
    assert_eq!((requests, changes), (41, 120));
    assert!(transitions > 100, "{transitions}");
}
