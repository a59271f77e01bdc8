//! The link controller: the same plant and scripted events as [`control::run`](crate::control::run),
//! but the tree comes and goes over a serial link ([`bt_link`]): it boots with the
//! embedded image, ticks only when the host says `Start` (up to the tick the host
//! names), and swaps in a deployed tree between two ticks.
//!
//! # Trace
//!
//! The same `tick` and `event` lines as the firmware's, and
//!
//! ```text
//! boot image=162B nodes=37 crc=5e1f09a2 fp=133dc6ffb352d15f
//! swap 40 image=117B nodes=25 crc=0c5b7a31 halt=10
//! stop 90 halt=35
//! ```
//!
//! - `boot`: the embedded image, or `boot refused <code>` when it does not load;
//! - `swap N`: before tick N, the new image replaced the old; `halt=` lists the old
//!   tree's actions halted for it, before the new tree's first tick;
//! - `stop N`: the host's `Stop` halted these actions before tick N.
//!
//! Only what happens at tick boundaries is traced: the link's own traffic (acks,
//! refusals, garbage skipped) depends on when bytes arrive, and goes back to the host
//! instead, so the trace is the same whatever the link's timing.

use bt_core::{BehaviorSet, Context, Leaf, LoadError, Node, NodeId, Status, TickError};
use bt_link::{App, Board, ImageInfo, Storage};

use crate::catalog::BEHAVIORS;
use crate::control::{Line, MAX_NODES, Ran, Sink};
use crate::script::{self, Event};

/// Deepest tree the controller accepts.
pub const DEPTH: usize = crate::control::DEPTH;
/// Longest image the controller accepts: the worst case for [`MAX_NODES`] nodes with
/// three arguments each is 1,108 bytes; the planner's trees take 4-5 bytes a node.
pub const IMAGE_BYTES: usize = 640;

/// Most entries of a tree's value table (leaves with more than three values).
pub const VALUES: usize = 32;

/// The controller's two image slots and the running tree's state.
pub type LinkStorage = Storage<MAX_NODES, IMAGE_BYTES, VALUES>;

/// The plant, the trace, and the record of one tick's leaves and halts: the
/// [`App`] a link controller runs, on this board or another.
#[derive(Debug)]
pub struct Plant<'s, S> {
    plant: crate::plant::Plant,
    sink: &'s mut S,
    ran: heapless::Vec<Ran, MAX_NODES>,
    halted: heapless::Vec<NodeId, MAX_NODES>,
    line: Line,
}

impl<S: Sink> BehaviorSet for Plant<'_, S> {
    fn condition(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let status = self.plant.condition(leaf, ctx);
        let _ = self.ran.push(Ran { node: ctx.node, status });
        status
    }

    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        let status = self.plant.action(leaf, ctx);
        let _ = self.ran.push(Ran { node: ctx.node, status });
        status
    }

    fn halt(&mut self, leaf: &Leaf, node: NodeId) {
        self.plant.halt(leaf, node);
        let _ = self.halted.push(node);
    }
}

impl<S: Sink> App for Plant<'_, S> {
    fn booted(&mut self, result: Result<(ImageInfo, &[Node]), LoadError>) {
        let line = &mut self.line;
        match result {
            Ok((image, _)) => {
                line.text("boot ");
                image_fields(line, image);
                line.text(" fp=").hex(crate::catalog::FINGERPRINT, 16);
            }
            Err(e) => {
                line.text("boot refused ").load_error(&e);
            }
        }
        line.send(self.sink);
    }

    fn before_tick(&mut self, tick: u32) {
        self.ran.clear();
        self.halted.clear();
        let Some(e) = script::event_at(tick) else { return };
        let line = &mut self.line;
        line.text("event ").num(tick).text(" ").text(e.name());
        match script::apply(e, &mut self.plant) {
            Ok(()) => {
                let (what, at) = match e {
                    Event::Help | Event::Slip => ("cube", self.plant.cube),
                    Event::Block | Event::Unblock => ("sphere", self.plant.sphere),
                };
                line.text(" ").text(what).text("=").point(at).text(": ").text(e.describe());
            }
            Err(why) => {
                line.text(" skipped: ").text(why.reason());
            }
        }
        line.send(self.sink);
    }

    fn after_tick(&mut self, tick: u32, result: Result<Status, TickError>, nodes: &[Node]) {
        let line = &mut self.line;
        line.text("tick ").num(tick).text(" ");
        match result {
            Ok(status) => {
                let act = self
                    .ran
                    .iter()
                    .rev()
                    .find(|r| r.status == Status::Running)
                    .and_then(|r| nodes.get(usize::from(r.node)));
                line.text(status.name()).text(" ran=").ran(&self.ran).text(" act=").leaf(act);
            }
            Err(e) => {
                line.text("ERROR ").text(e.code()).text(" ran=").ran(&self.ran);
            }
        }
        line.text(" halt=").ids(&self.halted).text(" robot=").point(self.plant.robot);
        line.text(" hand=").text(self.plant.hand.name()).text(" dig=").hex(u64::from(self.plant.digest()), 8);
        line.send(self.sink);
        self.halted.clear();
    }

    fn swapped(&mut self, tick: u32, image: ImageInfo, _nodes: &[Node]) {
        let line = &mut self.line;
        line.text("swap ").num(tick).text(" ");
        image_fields(line, image);
        line.text(" halt=").ids(&self.halted).send(self.sink);
        self.halted.clear();
    }

    fn stopped(&mut self, tick: u32) {
        self.line.text("stop ").num(tick).text(" halt=").ids(&self.halted).send(self.sink);
        self.halted.clear();
    }
}

/// `image=162B nodes=37 crc=5e1f09a2`.
fn image_fields(line: &mut Line, image: ImageInfo) {
    line.text("image=").num(image.len).text("B nodes=").num(image.nodes.into());
    line.text(" crc=").hex(u64::from(image.crc), 8);
}

impl<'s, S: Sink> Plant<'s, S> {
    /// The plant at its start, tracing to `sink`.
    pub fn new(sink: &'s mut S) -> Self {
        Self {
            plant: crate::plant::Plant::new(),
            sink,
            ran: heapless::Vec::new(),
            halted: heapless::Vec::new(),
            line: Line::new(),
        }
    }
}

/// Runs the controller on `board` with `boot` as the first tree, tracing to `sink`,
/// until the board closes (never, on the controller).
pub fn serve<B: Board, S: Sink>(storage: &mut LinkStorage, boot: &[u8], board: &mut B, sink: &mut S) {
    let mut app = Plant::new(sink);
    bt_link::serve::<_, _, _, MAX_NODES, IMAGE_BYTES, VALUES, DEPTH>(storage, &BEHAVIORS, Some(boot), board, &mut app);
}
