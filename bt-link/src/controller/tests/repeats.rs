//! A deployment swaps in at most once: a repeated `Deploy` or `Commit` (the host's
//! resend after a lost answer) is answered with where its transfer stands or its
//! verdict; the same image under a new id is a new deployment.

use super::*;

/// `Deploy` of `img` as transfer `id`, swapped in at the next boundary.
fn deploy_as(id: u16, img: &[u8], swap_at: Option<u32>) -> Step {
    Step::Bytes(frame(&Request::Deploy { id, len: img.len() as u32, crc: crc32(img), swap_at }))
}

/// Chunk `i` of `img` cut in pieces of 16 bytes.
fn piece(img: &[u8], i: usize) -> Step {
    Step::Bytes(frame(&Request::Chunk { offset: (i * 16) as u32, bytes: img.chunks(16).nth(i).unwrap() }))
}

fn commit() -> Step {
    Step::Bytes(frame(&Request::Commit))
}

fn hello() -> Step {
    Step::Bytes(frame(&Request::Hello { version: PROTOCOL_VERSION }))
}

fn swaps(log: &Log) -> usize {
    log.seen.iter().filter(|s| matches!(s, Seen::Swap(..))).count()
}

/// The replies a deployment's requests got (status and tick reports left out).
fn answers(host: &Host) -> Vec<Reply<'static>> {
    host.replies
        .iter()
        .filter(|r| matches!(r, Reply::ChunkAck { .. } | Reply::Accepted { .. } | Reply::Rejected { .. }))
        .copied()
        .collect()
}

/// The requests one deployment of the loss test (`tests/lossy.rs`, 10^-2, deployment
/// 624 of the version-2 protocol) delivered, in order. The second chunk is garbled on
/// the way, so the host sends the rest again twice (once for the ack that shows the
/// gap, once for the `incomplete` its early `Commit` got), each time with a `Commit`.
/// The first of those completes the transfer, which is accepted and swapped in at
/// once; its `Accepted` is garbled on the way back. The repeats find no transfer; the
/// host asks with a `Commit`, whose `Accepted` is garbled too, and after 500 ms of
/// silence sends the whole deployment again, `Deploy` first. Version 2 took that for
/// a new deployment and swapped the same image in a second time, restarting the tree.
#[test]
fn a_deployment_sent_again_after_its_verdict_was_lost_swaps_in_once() {
    let b = tree_b();
    assert_eq!(b.len().div_ceil(16), 3, "three pieces");
    let steps = vec![
        start(2),
        Step::UntilTick(2),
        deploy_as(40, &b, None),
        piece(&b, 0),
        piece(&b, 2),
        commit(),
        piece(&b, 1),
        piece(&b, 2),
        commit(),
        piece(&b, 1),
        piece(&b, 2),
        commit(),
        deploy_as(40, &b, None),
        piece(&b, 0),
        piece(&b, 1),
        piece(&b, 2),
        commit(),
        start(4),
        Step::UntilTick(4),
    ];
    let (host, log) = run(steps);
    assert_eq!(swaps(&log), 1, "swapped in once: {:?}", log.seen);
    assert_eq!(log.seen, vec![Seen::Start(2), Seen::Halt(2), Seen::Swap(2, crate::image_crc(&b)), Seen::Start(2)]);
    let accepted = Reply::Accepted { id: 40, crc: crate::image_crc(&b), nodes: 4, swap_at: None };
    let no_transfer = Reply::Rejected { fault: Fault::NoTransfer };
    let incomplete = Reply::Rejected { fault: Fault::Incomplete { received: 16, len: b.len() as u32 } };
    let ack = |received| Reply::ChunkAck { id: 40, received };
    let len = b.len() as u32;
    assert_eq!(
        answers(&host),
        [
            ack(0),
            ack(16),
            ack(16),
            incomplete,
            ack(32),
            ack(len),
            accepted,
            no_transfer,
            no_transfer,
            accepted,
            // The repeated `Deploy`: the verdict again, and its chunks find no transfer.
            accepted,
            no_transfer,
            no_transfer,
            no_transfer,
            accepted,
        ]
    );
}

#[test]
fn a_repeated_deploy_while_receiving_is_acked_with_where_the_transfer_stands() {
    let b = tree_b();
    let steps =
        vec![deploy_as(7, &b, None), piece(&b, 0), deploy_as(7, &b, None), piece(&b, 1), piece(&b, 2), commit()];
    let (host, log) = run(steps);
    let len = b.len() as u32;
    assert_eq!(
        answers(&host),
        [
            Reply::ChunkAck { id: 7, received: 0 },
            Reply::ChunkAck { id: 7, received: 16 },
            Reply::ChunkAck { id: 7, received: 16 },
            Reply::ChunkAck { id: 7, received: 32 },
            Reply::ChunkAck { id: 7, received: len },
            Reply::Accepted { id: 7, crc: crate::image_crc(&b), nodes: 4, swap_at: None },
        ]
    );
    assert_eq!(swaps(&log), 1);
}

#[test]
fn a_repeated_deploy_of_an_image_waiting_for_its_tick_keeps_it_waiting() {
    let b = tree_b();
    let mut steps = vec![start(2), Step::UntilTick(2)];
    steps.extend([deploy_as(9, &b, Some(5)), piece(&b, 0), piece(&b, 1), piece(&b, 2), commit()]);
    steps.extend([deploy_as(9, &b, Some(5)), commit(), start(8), Step::UntilTick(8)]);
    let (host, log) = run(steps);
    let accepted = Reply::Accepted { id: 9, crc: crate::image_crc(&b), nodes: 4, swap_at: Some(5) };
    assert_eq!(answers(&host).iter().filter(|&&r| r == accepted).count(), 3, "the commit and both repeats");
    assert!(host.rejections().is_empty(), "not superseded: {:?}", host.rejections());
    assert_eq!(log.seen, vec![Seen::Start(2), Seen::Halt(2), Seen::Swap(5, crate::image_crc(&b)), Seen::Start(2)]);
}

#[test]
fn a_repeated_deploy_or_commit_of_a_refused_transfer_is_refused_again() {
    let mut bad = tree_b();
    bad[bt_core::image::HEADER_LEN] ^= 1;
    let host = refused(vec![
        deploy_as(3, &bad, None),
        piece(&bad, 0),
        piece(&bad, 1),
        piece(&bad, 2),
        commit(),
        commit(),
        deploy_as(3, &bad, None),
    ]);
    assert_eq!(host.rejections(), ["crc-mismatch"; 3]);
}

#[test]
fn the_running_image_deployed_again_under_a_new_id_restarts() {
    // Deliberate redeploys of the image that runs: a new id swaps it in again, and so
    // does the same id after a `Hello` (a new session, whose ids are its own).
    let b = tree_b();
    let whole = |id| vec![deploy_as(id, &b, None), piece(&b, 0), piece(&b, 1), piece(&b, 2), commit()];
    let mut steps = vec![start(2), Step::UntilTick(2)];
    steps.extend(whole(1));
    steps.extend([start(4), Step::UntilTick(4)]);
    steps.extend(whole(2));
    steps.extend([start(6), Step::UntilTick(6), hello()]);
    steps.extend(whole(2));
    steps.extend([start(8), Step::UntilTick(8)]);
    let (_, log) = run(steps);
    let crc = crate::image_crc(&b);
    assert_eq!(
        log.seen,
        vec![
            Seen::Start(2),
            Seen::Halt(2),
            Seen::Swap(2, crc),
            Seen::Start(2),
            Seen::Halt(2),
            Seen::Swap(4, crc),
            Seen::Start(2),
            Seen::Halt(2),
            Seen::Swap(6, crc),
            Seen::Start(2),
        ]
    );
}

#[test]
fn a_hello_drops_a_transfer_under_way_and_forgets_the_last_verdict() {
    let b = tree_b();
    let host = refused(vec![
        deploy_as(5, &b, Some(1000)),
        piece(&b, 0),
        hello(),
        // Not the transfer before the Hello: a chunk finds none, a commit no verdict.
        piece(&b, 1),
        commit(),
    ]);
    assert_eq!(host.rejections(), ["superseded", "no-transfer", "no-transfer"]);
}
