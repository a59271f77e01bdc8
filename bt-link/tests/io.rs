//! The `embedded-io` adapters against a UART double: a `Ping` and a `Start` in, their
//! answers and the ticks out, with the bytes arriving in pieces and the transmit side
//! taking a few bytes a call, as a UART's FIFOs do.

use std::collections::VecDeque;
use std::future::Future;
use std::pin::pin;
use std::task::{Context as TaskContext, Poll, Waker};

use bt_core::{BehaviorInfo, BehaviorSet, Builder, Context, Leaf, Node, NodeId, Status, fingerprint};
use bt_link::frame::{self, Decoder, Feed, MAX_ENCODED, MAX_FRAME};
use bt_link::{App, Clock, Controller, Reply, Request, Storage};

const SET: [BehaviorInfo<'static>; 2] = [BehaviorInfo::condition("ok?", 0), BehaviorInfo::action("work", 0)];

struct World;
impl BehaviorSet for World {
    fn condition(&mut self, _: &Leaf, _: Context<'_>) -> Status {
        Status::Success
    }
    fn action(&mut self, _: &Leaf, _: Context<'_>) -> Status {
        Status::Running
    }
    fn halt(&mut self, _: &Leaf, _: NodeId) {}
}
impl App for World {}

/// A clock that moves 1 ms per reading.
struct Ms(u32);
impl Clock for Ms {
    fn micros(&mut self) -> u32 {
        self.0 += 1000;
        self.0
    }
}

/// A UART: the host's bytes in, up to 5 bytes out per write.
struct Uart {
    rx: VecDeque<u8>,
    tx: Vec<u8>,
}

impl embedded_io::ErrorType for Uart {
    type Error = std::convert::Infallible;
}
impl embedded_io::ReadReady for Uart {
    fn read_ready(&mut self) -> Result<bool, Self::Error> {
        Ok(!self.rx.is_empty())
    }
}
impl embedded_io::Read for Uart {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        let n = buf.len().min(self.rx.len());
        for b in &mut buf[..n] {
            *b = self.rx.pop_front().unwrap();
        }
        Ok(n)
    }
}
impl embedded_io::Write for Uart {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        let n = buf.len().min(5);
        self.tx.extend_from_slice(&buf[..n]);
        Ok(n)
    }
    fn flush(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}
impl embedded_io_async::Read for Uart {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        embedded_io::Read::read(self, buf)
    }
}
impl embedded_io_async::Write for Uart {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        embedded_io::Write::write(self, buf)
    }
    async fn flush(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}

fn boot_image() -> Vec<u8> {
    let mut nodes = [Node::EMPTY; 3];
    let mut b = Builder::<4>::new(&mut nodes);
    b.sequence().unwrap().condition(0, &[]).unwrap().action(1, &[]).unwrap().end().unwrap();
    let nodes = b.finish().unwrap();
    let mut out = vec![0u8; 64];
    let n = bt_core::encode(nodes, fingerprint(&SET), &mut out).unwrap();
    out.truncate(n);
    out
}

fn requests() -> VecDeque<u8> {
    let mut bytes = VecDeque::new();
    for r in [Request::Ping { token: 42 }, Request::Start { until: Some(3), period_ms: 1 }] {
        let mut buf = [0u8; MAX_ENCODED];
        bytes.extend(frame::encode(&r, &mut buf).unwrap().iter());
    }
    bytes
}

/// (ping token answered, ticks reported)
fn replies(bytes: &[u8]) -> (Option<u32>, Vec<u32>) {
    let mut dec = Decoder::<MAX_FRAME>::new();
    let (mut token, mut ticks) = (None, Vec::new());
    for &b in bytes {
        if let Feed::Frame(f) = dec.feed(b) {
            match frame::message::<Reply<'_>>(f).unwrap() {
                Reply::State { token: t, .. } if t != 0 => token = Some(t),
                Reply::Tick { tick, .. } => ticks.push(tick),
                _ => {}
            }
        }
    }
    (token, ticks)
}

#[test]
fn step_over_a_blocking_uart_answers_and_ticks() {
    let image = boot_image();
    let mut storage = Storage::<8, 64, 0>::new();
    let mut controller = Controller::<_, 8, 64, 0, 4, 256>::new(&mut storage, &SET);
    controller.boot(&image, &mut World).unwrap();
    let mut uart = Uart { rx: requests(), tx: Vec::new() };
    let mut clock = Ms(0);
    for _ in 0..50 {
        bt_link::io::step(&mut controller, &mut uart, &mut World, &mut clock).unwrap();
    }
    assert_eq!(replies(&uart.tx), (Some(42), vec![0, 1, 2]));
}

/// A delay that gives control back to the test once per call.
struct Yield(u32);
impl embedded_hal_async::delay::DelayNs for Yield {
    async fn delay_ns(&mut self, _: u32) {
        self.0 += 1;
        let mut yielded = false;
        std::future::poll_fn(|_| {
            if yielded {
                Poll::Ready(())
            } else {
                yielded = true;
                Poll::Pending
            }
        })
        .await;
    }
}

#[test]
fn run_async_over_an_async_uart_answers_and_ticks() {
    let image = boot_image();
    let mut storage = Storage::<8, 64, 0>::new();
    let mut controller = Controller::<_, 8, 64, 0, 4, 256>::new(&mut storage, &SET);
    controller.boot(&image, &mut World).unwrap();
    let mut uart = Uart { rx: requests(), tx: Vec::new() };
    let mut delay = Yield(0);
    let mut clock = Ms(0);
    {
        let mut world = World;
        let mut task = pin!(bt_link::io::run_async(&mut controller, &mut uart, &mut delay, &mut world, &mut clock));
        // The task never ends: each poll runs it to its next sleep.
        let mut cx = TaskContext::from_waker(Waker::noop());
        for _ in 0..50 {
            if let Poll::Ready(r) = task.as_mut().poll(&mut cx) {
                panic!("the task ended: {r:?}");
            }
        }
    }
    assert_eq!(replies(&uart.tx), (Some(42), vec![0, 1, 2]));
}
