//! Serving a running tree to Groot2 over ZeroMQ, as BehaviorTree.CPP's `Groot2Publisher`
//! does: a REP socket on the listening port answers Groot2's requests
//! ([`btcpp::groot2::Publisher`] makes the replies), and a PUB socket on the next port
//! is bound for Groot2 to subscribe to (it publishes nothing: breakpoints are refused).
//!
//! Whatever produces a tree and its status changes feeds a [`Server`]: the link bridge
//! (`sim-host groot2`), simulated runs (`--groot2`). Requests are answered on a thread
//! of their own; the producer only takes a lock for the moment of a change, so a slow,
//! silent or hostile client never holds it up.
//!
//! The sockets are libzmq's (the `zmq` crate builds libzmq 4.3 from source). A client
//! may send at most [`MAX_REQUEST`] bytes in one message (libzmq drops the connection of
//! one that sends more), and may have at most 1000 requests queued (libzmq's high-water
//! mark); each is answered in the order libzmq fair-queues them.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use bt_core::NodeStatus;
use btcpp::btlog::LogTree;
use btcpp::groot2::Publisher;

mod watch;
pub use watch::{Names, Watch};

/// Groot2's default port (BehaviorTree.CPP's `Groot2Publisher` default); the publish
/// socket is on the next one.
pub const DEFAULT_PORT: u16 = 1667;
/// Longest request message accepted, in bytes: Groot2's largest request is a hook of
/// about a hundred bytes of JSON, or a list of blackboard names.
pub const MAX_REQUEST: i64 = 64 * 1024;
/// How long the request thread waits for a request before it checks whether to stop
/// and whether the client is still there.
const POLL_MS: i32 = 100;

/// Why a server cannot start.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// `--groot2`/`--listen` is neither `PORT` nor `HOST:PORT`.
    #[error("`{0}` is neither PORT nor HOST:PORT (Groot2 listens on a port and the next one)")]
    Address(String),
    /// The port is the last one: the publish socket needs the next.
    #[error("port {0}: Groot2's publish socket needs the next port, and there is none")]
    LastPort(u16),
    /// ZeroMQ refused (the port is taken, the host is not this machine's).
    #[error("cannot listen on {address}: {error} (another Groot2 publisher on that port?)")]
    Bind {
        /// The endpoint.
        address: String,
        /// libzmq's error.
        error: zmq::Error,
    },
    /// ZeroMQ could not make a socket.
    #[error("ZeroMQ: {0}")]
    Zmq(#[from] zmq::Error),
    /// The request thread could not start.
    #[error("cannot start the Groot2 thread: {0}")]
    Thread(std::io::Error),
}

/// Where to listen: `PORT` (every interface, as BehaviorTree.CPP binds) or `HOST:PORT`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Listen {
    /// The interface (`*`: all).
    pub host: String,
    /// The request port; the publish socket takes `port + 1`.
    pub port: u16,
}

impl Listen {
    /// Reads `PORT` or `HOST:PORT`.
    ///
    /// # Errors
    /// [`ServeError::Address`] or [`ServeError::LastPort`].
    pub fn parse(s: &str) -> Result<Self, ServeError> {
        let (host, port) = match s.rsplit_once(':') {
            Some((h, p)) if !h.is_empty() => (h.trim_start_matches('[').trim_end_matches(']').to_string(), p),
            _ => ("*".to_string(), s),
        };
        let port: u16 = port.parse().map_err(|_| ServeError::Address(s.to_string()))?;
        if port == u16::MAX {
            return Err(ServeError::LastPort(port));
        }
        Ok(Self { host, port })
    }

    fn endpoint(&self, port: u16) -> String {
        if self.host.contains(':') {
            format!("tcp://[{}]:{port}", self.host)
        } else {
            format!("tcp://{}:{port}", self.host)
        }
    }
}

impl std::fmt::Display for Listen {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} (requests) and {} (publish)", self.endpoint(self.port), self.endpoint(self.port + 1))
    }
}

/// Something a server noticed, for the caller to report.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Event {
    /// A client made its first request after a silence (BehaviorTree.CPP's heartbeat).
    Connected,
    /// No request for the heartbeat delay (5 s): the client is gone.
    Gone,
    /// The request socket failed and was made again.
    Fault(String),
}

struct Shared {
    publisher: Mutex<Publisher>,
    events: Mutex<Vec<Event>>,
    stop: AtomicBool,
}

/// A tree served to Groot2 until the server is dropped.
#[derive(Debug)]
pub struct Server {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    listen: Listen,
}

impl std::fmt::Debug for Shared {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Shared").finish_non_exhaustive()
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Microseconds since 1970, the clock of Groot2's recordings.
#[must_use]
pub fn now_usec() -> i64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| i64::try_from(d.as_micros()).unwrap_or(i64::MAX))
}

/// A fresh random tree UUID (version 4, as BehaviorTree.CPP makes them).
#[must_use]
pub fn new_uuid() -> [u8; 16] {
    uuid::Uuid::new_v4().into_bytes()
}

impl Server {
    /// Serves `tree` (every node Idle) on `listen` and the next port.
    ///
    /// # Errors
    /// A port taken or an address not this machine's ([`ServeError::Bind`]).
    pub fn start(listen: &Listen, tree: &LogTree) -> Result<Self, ServeError> {
        let ctx = zmq::Context::new();
        let rep = rep_socket(&ctx, listen)?;
        let publish = ctx.socket(zmq::PUB)?;
        publish.set_linger(0)?;
        let address = listen.endpoint(listen.port + 1);
        publish.bind(&address).map_err(|error| ServeError::Bind { address, error })?;
        let shared = Arc::new(Shared {
            publisher: Mutex::new(Publisher::new(tree, new_uuid())),
            events: Mutex::new(Vec::new()),
            stop: AtomicBool::new(false),
        });
        let thread = {
            let shared = Arc::clone(&shared);
            let listen = listen.clone();
            std::thread::Builder::new()
                .name("groot2".into())
                .spawn(move || serve(&ctx, rep, &publish, &listen, &shared))
                .map_err(ServeError::Thread)?
        };
        Ok(Self { shared, thread: Some(thread), listen: listen.clone() })
    }

    /// Where it listens.
    #[must_use]
    pub const fn listen(&self) -> &Listen {
        &self.listen
    }

    /// bt-core node `core` changed to `status` (stamped with the wall clock).
    pub fn change(&self, core: usize, status: NodeStatus) {
        lock(&self.shared.publisher).change(core, status, now_usec());
    }

    /// Node `uid` (BehaviorTree.CPP's numbering) changed to `status` (its status byte,
    /// 0 to 4): for producers that speak BehaviorTree.CPP's terms.
    pub fn set(&self, uid: u16, status: u8) {
        lock(&self.shared.publisher).set(uid, status, now_usec());
    }

    /// Serves `tree` from now on under a new UUID; returns it.
    pub fn swap(&self, tree: &LogTree) -> [u8; 16] {
        let uuid = new_uuid();
        lock(&self.shared.publisher).swap(tree, uuid);
        uuid
    }

    /// The tree's UUID.
    #[must_use]
    pub fn uuid(&self) -> [u8; 16] {
        lock(&self.shared.publisher).uuid()
    }

    /// Whether a client asked anything in the last 5 s.
    #[must_use]
    pub fn connected(&self) -> bool {
        lock(&self.shared.publisher).connected(now_usec())
    }

    /// What happened since the last call.
    #[must_use]
    pub fn events(&self) -> Vec<Event> {
        std::mem::take(&mut *lock(&self.shared.events))
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn rep_socket(ctx: &zmq::Context, listen: &Listen) -> Result<zmq::Socket, ServeError> {
    let rep = ctx.socket(zmq::REP)?;
    rep.set_linger(0)?;
    rep.set_rcvtimeo(POLL_MS)?;
    rep.set_sndtimeo(1000)?;
    rep.set_maxmsgsize(MAX_REQUEST)?;
    let address = listen.endpoint(listen.port);
    rep.bind(&address).map_err(|error| ServeError::Bind { address, error })?;
    Ok(rep)
}

/// The request thread: answers until told to stop.
fn serve(ctx: &zmq::Context, mut rep: zmq::Socket, _publish: &zmq::Socket, listen: &Listen, shared: &Shared) {
    let mut was_connected = false;
    while !shared.stop.load(Ordering::Relaxed) {
        let received = rep.recv_multipart(0);
        let now = now_usec();
        match received {
            Ok(parts) => {
                let reply = lock(&shared.publisher).handle(&parts, now);
                if let Err(e) = rep.send_multipart(reply, 0) {
                    // The socket is left waiting to send: make it again.
                    lock(&shared.events).push(Event::Fault(format!("a reply could not be sent ({e})")));
                    drop(rep);
                    rep = loop {
                        if shared.stop.load(Ordering::Relaxed) {
                            return;
                        }
                        match rep_socket(ctx, listen) {
                            Ok(s) => break s,
                            Err(_) => std::thread::sleep(Duration::from_millis(u64::from(POLL_MS.unsigned_abs()))),
                        }
                    };
                }
            }
            Err(zmq::Error::EAGAIN | zmq::Error::EINTR) => {}
            Err(e) => {
                lock(&shared.events).push(Event::Fault(format!("receiving: {e}")));
                std::thread::sleep(Duration::from_millis(u64::from(POLL_MS.unsigned_abs())));
            }
        }
        let connected = lock(&shared.publisher).connected(now_usec());
        if connected != was_connected {
            lock(&shared.events).push(if connected { Event::Connected } else { Event::Gone });
            was_connected = connected;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn listen_takes_a_port_or_a_host_and_port() {
        assert_eq!(Listen::parse("1667").unwrap(), Listen { host: "*".into(), port: 1667 });
        assert_eq!(Listen::parse("127.0.0.1:9000").unwrap(), Listen { host: "127.0.0.1".into(), port: 9000 });
        assert_eq!(Listen::parse("[::1]:9000").unwrap().endpoint(9000), "tcp://[::1]:9000");
        assert!(matches!(Listen::parse("x"), Err(ServeError::Address(_))));
        assert!(matches!(Listen::parse("65535"), Err(ServeError::LastPort(65535))));
    }
}
