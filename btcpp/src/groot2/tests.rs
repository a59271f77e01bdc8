use std::path::Path;

use super::*;
use crate::xml::{ImportOptions, import_text};

const XML: &str = r#"
<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Ready/>
      <SubTree ID="Sub" name="inner"/>
      <Go/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Sub">
    <Fallback>
      <Ready/>
      <Go/>
    </Fallback>
  </BehaviorTree>
  <TreeNodesModel>
    <Condition ID="Ready"/>
    <Action ID="Go"/>
  </TreeNodesModel>
</root>"#;

fn tree() -> LogTree {
    let imported = import_text(Path::new("t.xml"), XML, &ImportOptions::default()).unwrap();
    LogTree::of_imported(&imported).unwrap()
}

fn request(kind: u8, id: u32) -> Vec<u8> {
    Header { protocol: PROTOCOL, kind, id }.bytes().to_vec()
}

const UUID: [u8; 16] = [7; 16];

#[test]
fn status_buffer_lists_the_main_tree_then_each_subtree_instance() {
    let t = tree();
    // uids: 1 Sequence, 2 Ready, 3 SubTree, 4 Fallback, 5 Ready, 6 Go, 7 Go.
    let uids: Vec<u16> = status_order(&t).iter().map(|&i| t.nodes[i].uid).collect();
    assert_eq!(uids, [1, 2, 3, 7, 4, 5, 6]);
    let p = Publisher::new(&t, UUID);
    let buf = p.status_buffer();
    assert_eq!(buf.len(), 21);
    assert_eq!(&buf[..6], &[1, 0, 0, 2, 0, 0]);
}

#[test]
fn a_node_back_to_idle_shows_what_it_was_before() {
    let t = tree();
    let mut p = Publisher::new(&t, UUID);
    p.set(2, status::RUNNING, 0);
    p.set(2, status::SUCCESS, 1);
    assert_eq!(p.status_buffer()[5], status::SUCCESS);
    p.set(2, status::IDLE, 2);
    assert_eq!(p.status_buffer()[5], 10 + status::SUCCESS);
    // Idle again is no change: the mark stays.
    p.set(2, status::IDLE, 3);
    assert_eq!(p.status_buffer()[5], 12);
    p.set(99, status::RUNNING, 4);
    assert_eq!(p.status_buffer().len(), 21);
}

#[test]
fn replies_echo_the_header_with_protocol_2_and_the_uuid() {
    let mut p = Publisher::new(&tree(), UUID);
    let mut req = request(b'T', 0xdead_beef);
    req[0] = 9; // BehaviorTree.CPP does not check the protocol byte either
    let reply = p.handle(&[req], 0);
    assert_eq!(reply.len(), 2);
    assert_eq!(&reply[0][..6], &[2, b'T', 0xef, 0xbe, 0xad, 0xde]);
    assert_eq!(&reply[0][6..], &UUID);
    assert_eq!(reply[1], tree().xml().into_bytes());
}

#[test]
fn bad_requests_get_behaviortree_cpps_error_replies() {
    let mut p = Publisher::new(&tree(), UUID);
    assert_eq!(p.handle(&[vec![2, b'S', 0]], 0), error_reply("wrong request header"));
    assert_eq!(p.handle(&[Vec::<u8>::new()], 0), error_reply("wrong request header"));
    assert_eq!(p.handle(&[request(b'?', 1)], 0), error_reply(NOT_RECOGNIZED));
    assert_eq!(p.handle(&[request(b'N', 1)], 0), error_reply(NOT_RECOGNIZED));
    assert_eq!(p.handle(&[request(b'B', 1)], 0), error_reply("must be 2 parts message"));
    assert_eq!(p.handle(&[request(b'r', 1)], 0), error_reply("must be 2 parts message"));
    let hook = br#"{"enabled":true,"uid":2,"mode":0,"once":false,"desired_status":"FAILURE","position":0}"#;
    for kind in [b'I', b'R', b'U'] {
        assert_eq!(p.handle(&[request(kind, 1), hook.to_vec()], 0), error_reply(NOT_RECOGNIZED));
    }
    assert_eq!(p.handle(&[request(b'D', 1)], 0)[1], b"[]");
    assert_eq!(p.handle(&[request(b'A', 1)], 0).len(), 1);
    assert_eq!(p.handle(&[request(b'X', 1)], 0).len(), 1);
}

#[test]
fn recording_keeps_the_last_thousand_transitions_from_start() {
    let mut p = Publisher::new(&tree(), UUID);
    p.set(2, status::RUNNING, 5);
    let reply = p.handle(&[request(b'r', 1), b"start".to_vec()], 1_000);
    assert_eq!(reply[1], b"1000");
    assert!(p.recording());
    for k in 0..1001u16 {
        p.set(7, if k % 2 == 0 { status::RUNNING } else { status::IDLE }, 1_000 + i64::from(k));
    }
    let t = p.handle(&[request(b't', 2)], 3_000);
    assert_eq!(t[1].len(), 9 * MAX_TRANSITIONS);
    // The first kept is the second made: 1 us after start, node 7 back to Idle.
    assert_eq!(&t[1][..9], &[1, 0, 0, 0, 0, 0, 7, 0, status::IDLE]);
    assert!(p.handle(&[request(b't', 3)], 3_000)[1].is_empty());
    assert_eq!(p.handle(&[request(b'r', 4), b"stop".to_vec()], 4_000).len(), 1);
    p.set(2, status::SUCCESS, 4_001);
    assert!(p.handle(&[request(b't', 5)], 5_000)[1].is_empty());
}

#[test]
fn blackboards_are_empty_boards_of_the_names_the_tree_has() {
    let mut p = Publisher::new(&tree(), UUID);
    let bb = |p: &mut Publisher, names: &[u8]| p.handle(&[request(b'B', 1), names.to_vec()], 0).pop().unwrap();
    assert_eq!(bb(&mut p, b"nope"), [0xc0]);
    assert_eq!(bb(&mut p, b"Main;Main"), [0x81, 0xa4, b'M', b'a', b'i', b'n', 0xc0]);
    // A SubTree's board brings the root's along, keys in byte order.
    assert_eq!(
        bb(&mut p, b"inner"),
        [0x82, 0xa4, b'R', b'O', b'O', b'T', 0xc0, 0xa5, b'i', b'n', b'n', b'e', b'r', 0xc0]
    );
}

#[test]
fn a_swap_serves_the_new_tree_under_its_uuid_and_keeps_recording() {
    let t = tree();
    let mut p = Publisher::new(&t, UUID);
    p.handle(&[request(b'r', 1), b"start".to_vec()], 0);
    p.set(2, status::RUNNING, 1);
    p.swap(&t, [9; 16]);
    assert_eq!(p.status_buffer()[5], status::IDLE);
    let reply = p.handle(&[request(b't', 2)], 2);
    assert_eq!(&reply[0][6..], &[9; 16]);
    assert!(reply[1].is_empty());
    p.set(2, status::FAILURE, 3);
    assert_eq!(p.handle(&[request(b't', 3)], 4)[1].len(), 9);
}

#[test]
fn the_heartbeat_counts_a_client_present_for_five_seconds() {
    let mut p = Publisher::new(&tree(), UUID);
    assert!(!p.connected(0));
    p.handle(&[request(b'S', 1)], 10);
    assert!(p.connected(10 + HEARTBEAT_USEC - 1));
    assert!(!p.connected(10 + HEARTBEAT_USEC));
}

#[test]
fn uuids_print_as_uuids() {
    assert_eq!(uuid_text(&[0xab; 16]), "abababab-abab-abab-abab-abababababab");
}
