//! A simulated run served to Groot2 as it runs: a [`Recorder`] that passes every status
//! change of every tick to a [`Server`], serves the tree again under a new UUID whenever
//! it grows (the planner's expansions at run time), and holds each tick to its time so
//! that a person can follow it.

use std::sync::Arc;
use std::time::{Duration, Instant};

use bt_core::Catalog;
use btcpp::btlog::LogTree;
use worlds::agent::TreeState;
use worlds::record::{Recorder, Ticked};

use super::{Listen, ServeError, Server};

/// A catalog a run names its leaves with.
pub type Names = Arc<dyn Catalog + Send + Sync>;

/// Serves a run to Groot2 while it runs ([`Watch::off`]: does nothing).
#[derive(Default)]
pub struct Watch {
    server: Option<Server>,
    names: Option<Names>,
    period: Duration,
    next: Option<Instant>,
    /// Trees served: the tick from which each was, and its UUID.
    served: Vec<(u32, [u8; 16])>,
    /// A tree Groot2 cannot be given (a kind BehaviorTree.CPP does not have).
    error: Option<String>,
}

impl std::fmt::Debug for Watch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Watch").field("server", &self.server).field("served", &self.served).finish_non_exhaustive()
    }
}

impl Watch {
    /// A watch that serves nothing.
    #[must_use]
    pub fn off() -> Self {
        Self::default()
    }

    /// Listens on `listen` at once (an empty tree until the run starts) and holds each
    /// tick `period` after the previous one (zero: as fast as the run goes).
    ///
    /// # Errors
    /// The port cannot be listened on.
    pub fn new(listen: &Listen, period: Duration) -> Result<Self, ServeError> {
        let empty = LogTree { main: "MainTree".into(), nodes: Vec::new(), models: Vec::new() };
        Ok(Self { server: Some(Server::start(listen, &empty)?), period, ..Self::default() })
    }

    /// The catalog naming the leaves of the trees to come.
    pub fn names(&mut self, names: Names) {
        self.names = Some(names);
    }

    /// The server, while on.
    #[must_use]
    pub const fn server(&self) -> Option<&Server> {
        self.server.as_ref()
    }

    /// The trees served: from which tick, under which UUID.
    #[must_use]
    pub fn served(&self) -> &[(u32, [u8; 16])] {
        &self.served
    }

    /// Why a tree could not be served, if one could not.
    #[must_use]
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    fn serve(&mut self, tick: u32, nodes: &[bt_core::Node]) {
        let (Some(server), Some(names)) = (&self.server, &self.names) else { return };
        match LogTree::new(nodes, names.as_ref()) {
            Ok(tree) => self.served.push((tick, server.swap(&tree))),
            Err(e) => self.error = Some(format!("Groot2: the tree from tick {tick}: {e}")),
        }
    }
}

impl<W: ?Sized, G: ?Sized> Recorder<W, G> for Watch {
    const CHANGES: bool = true;

    fn start(&mut self, _: &W, tree: &TreeState<'_>) {
        self.serve(1, tree.nodes);
        self.next = Some(Instant::now());
    }

    fn ticked(&mut self, tick: &Ticked<'_>, _: &W) {
        let Some(server) = &self.server else { return };
        for &(node, _, new) in tick.changes {
            server.change(usize::from(node), new);
        }
        if let Some(next) = &mut self.next {
            *next += self.period;
            let now = Instant::now();
            if *next > now {
                std::thread::sleep(*next - now);
            } else {
                *next = now;
            }
        }
    }

    fn grown(&mut self, tick: u32, _: &G, nodes: &[bt_core::Node]) {
        self.serve(tick, nodes);
    }
}
