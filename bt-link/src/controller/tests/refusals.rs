//! Every fault a transfer can have is refused with its reason, and the image running
//! before goes on: corrupted, truncated, too large, for another behavior set, chunks out
//! of place, garbage between frames.

use super::*;

#[test]
fn an_image_with_a_bad_crc_is_refused_by_the_loader() {
    let mut bad = tree_b();
    bad[bt_core::image::HEADER_LEN] ^= 1;
    let host = refused(deploy_image(&bad, None));
    assert_eq!(host.rejections(), ["crc-mismatch"]);
}

#[test]
fn a_transfer_corrupted_in_transit_is_refused() {
    let b = tree_b();
    let mut sent = b.clone();
    sent[5] ^= 0x40;
    let host = refused(deploy(b.len(), crc32(&b), &sent, None));
    assert_eq!(
        host.replies.iter().find(|r| matches!(r, Reply::Rejected { .. })),
        Some(&Reply::Rejected { fault: Fault::TransferCrc { expected: crc32(&b), computed: crc32(&sent) } })
    );
}

#[test]
fn a_truncated_transfer_is_refused() {
    let b = tree_b();
    let host = refused(deploy(b.len(), crc32(&b), &b[..b.len() - 3], None));
    assert!(
        host.replies.contains(&Reply::Rejected {
            fault: Fault::Incomplete { received: b.len() as u32 - 3, len: b.len() as u32 }
        })
    );
}

#[test]
fn a_truncated_image_is_refused_by_the_loader() {
    let b = tree_b();
    let host = refused(deploy_image(&b[..12], None));
    assert_eq!(host.rejections(), ["truncated"]);
}

#[test]
fn an_image_for_another_behavior_set_is_refused() {
    let foreign = image(3, Some(4), 0xdead_beef);
    let host = refused(deploy_image(&foreign, None));
    assert_eq!(host.rejections(), ["foreign-behavior-set"]);
}

#[test]
fn an_image_that_loads_but_breaks_the_behavior_set_is_refused_at_its_node() {
    // work takes one argument; two make the leaf's arity wrong, at node 2.
    let mut nodes = [Node::EMPTY; 3];
    let mut b = Builder::<4>::new(&mut nodes);
    b.sequence().unwrap().condition(OK, &[]).unwrap().action(WORK, &[1, 2]).unwrap().end().unwrap();
    let nodes = b.finish().unwrap();
    let mut img = vec![0u8; max_image_len(3)];
    let n = bt_core::encode(nodes, fingerprint(&SET), &mut img).unwrap();
    img.truncate(n);
    let host = refused(deploy_image(&img, None));
    assert!(host.replies.contains(&Reply::Rejected { fault: Fault::Load { code: 17, node: Some(2) } }));
}

#[test]
fn an_image_larger_than_the_buffer_is_refused_before_any_byte() {
    let host =
        refused(vec![Step::Bytes(frame(&Request::Deploy { id: transfer_id(), len: 257, crc: 0, swap_at: None }))]);
    assert_eq!(host.replies.iter().filter(|r| matches!(r, Reply::ChunkAck { .. })).count(), 0);
    assert!(host.replies.contains(&Reply::Rejected { fault: Fault::TooLarge { len: 257, capacity: 256 } }));
}

#[test]
fn a_chunk_past_the_announced_length_is_refused() {
    let host = refused(vec![
        Step::Bytes(frame(&Request::Deploy { id: transfer_id(), len: 10, crc: 0, swap_at: None })),
        Step::Bytes(frame(&Request::Chunk { offset: 4, bytes: &[1; 8] })),
    ]);
    assert_eq!(host.rejections(), ["overrun"]);
}

#[test]
fn chunks_and_commits_without_a_transfer_are_refused() {
    let host = refused(vec![
        Step::Bytes(frame(&Request::Chunk { offset: 0, bytes: &[1, 2] })),
        Step::Bytes(frame(&Request::Commit)),
    ]);
    assert_eq!(host.rejections(), ["no-transfer", "no-transfer"]);
}

#[test]
fn a_new_deploy_supersedes_an_unfinished_one() {
    let b = tree_b();
    let mut steps = vec![Step::Bytes(frame(&Request::Deploy { id: transfer_id(), len: 40, crc: 77, swap_at: None }))];
    steps.push(Step::Bytes(frame(&Request::Chunk { offset: 0, bytes: &[1; 20] })));
    steps.extend(deploy_image(&b, Some(1000)));
    steps.extend(deploy_image(&tree_a(), Some(1000)));
    let host = refused(steps);
    assert_eq!(host.rejections(), ["superseded", "superseded"]);
    assert!(host.replies.contains(&Reply::Rejected { fault: Fault::Superseded { crc: 77 } }));
    assert!(host.replies.contains(&Reply::Rejected { fault: Fault::Superseded { crc: crate::image_crc(&b) } }));
}

#[test]
fn repeated_and_early_chunks_are_acked_with_where_to_go_on() {
    let b = tree_b();
    let mut steps = vec![Step::Bytes(frame(&Request::Deploy {
        id: transfer_id(),
        len: b.len() as u32,
        crc: crc32(&b),
        swap_at: None,
    }))];
    steps.push(Step::Bytes(frame(&Request::Chunk { offset: 0, bytes: &b[..10] })));
    steps.push(Step::Bytes(frame(&Request::Chunk { offset: 0, bytes: &b[..10] })));
    steps.push(Step::Bytes(frame(&Request::Chunk { offset: 15, bytes: &b[15..20] })));
    steps.push(Step::Bytes(frame(&Request::Chunk { offset: 10, bytes: &b[10..] })));
    steps.push(Step::Bytes(frame(&Request::Commit)));
    let (host, log) = run(steps);
    let acks: Vec<u32> = host
        .replies
        .iter()
        .filter_map(|r| match *r {
            Reply::ChunkAck { received, .. } => Some(received),
            _ => None,
        })
        .collect();
    assert_eq!(acks, [0, 10, 10, 10, b.len() as u32]);
    assert_eq!(log.seen, vec![Seen::Swap(0, crate::image_crc(&b))]);
}

#[test]
fn garbage_between_frames_is_skipped_and_reported() {
    let b = tree_b();
    let mut garbage = vec![0x00, 0x05, 0x41, 0x00, 0x03, 0x13, 0x37, 0x00];
    garbage.extend(std::iter::repeat_n(0x5a, 200));
    garbage.push(0);
    let mut steps = vec![Step::Bytes(garbage)];
    steps.extend(deploy(b.len(), crc32(&b), &b, Some(1000)));
    steps.insert(3, Step::Bytes(vec![0x07, 1, 2, 3, 4, 5, 6, 0x00]));
    steps.push(Step::Bytes(frame(&Request::Deploy { id: transfer_id(), len: 4, crc: 0, swap_at: None })));
    let host = refused(steps);
    let garbled: Vec<FrameFault> = host
        .replies
        .iter()
        .filter_map(|r| match *r {
            Reply::Garbled { fault } => Some(fault),
            _ => None,
        })
        .collect();
    assert_eq!(garbled, [FrameFault::Cobs, FrameFault::TooShort, FrameFault::TooLong, FrameFault::Crc]);
    // The chunks around the garbage still arrived: B was accepted (then superseded).
    assert!(host.replies.iter().any(|r| matches!(r, Reply::Accepted { .. })) || host.rejections() == ["superseded"]);
}
