//! The messages, both ways, as postcard encodes them (`spec/link-protocol.md` gives the
//! bytes). Tags are the variant indices: never reorder, only append, and bump
//! [`PROTOCOL_VERSION`] for any change a peer of the previous version would misread.

use bt_core::{LoadError, NodeStatus, Status};
use serde::{Deserialize, Serialize};

/// The protocol version both ends announce in `Hello`.
pub const PROTOCOL_VERSION: u16 = 3;

/// Most image bytes one `Chunk` (host to controller) or `Image` (controller to host)
/// frame carries.
pub const MAX_CHUNK: usize = 64;

/// Host to controller.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Request<'a> {
    /// Who are you? Answered by [`Reply::Hello`].
    Hello {
        /// The host's protocol version.
        version: u16,
    },
    /// An image of `len` bytes whose CRC-32 is `crc` follows in chunks. It is swapped
    /// in at the first tick boundary at or after tick `swap_at` once validated (at the
    /// next boundary when `None`). A transfer or an image waiting for its tick that was
    /// not finished is dropped, and reported as [`Fault::Superseded`].
    ///
    /// A `Deploy` with the `id` of the controller's transfer (under way, accepted, or
    /// refused since the last `Hello`) is a repeat: it is answered with where that
    /// transfer stands ([`Reply::ChunkAck`]) or its verdict, and changes nothing, so a
    /// deployment swaps in at most once however often its `Deploy` is sent.
    Deploy {
        /// Names the transfer: a host gives each deployment of a session (from its
        /// `Hello` on) a new one. The same image under a new id is a new deployment,
        /// swapped in again.
        id: u16,
        /// Image length in bytes.
        len: u32,
        /// CRC-32 (ISO-HDLC) of the whole image.
        crc: u32,
        /// The tick before which the new tree replaces the old one.
        swap_at: Option<u32>,
    },
    /// Image bytes at `offset`. Acked with [`Reply::ChunkAck`] carrying the bytes held
    /// so far: a chunk already received is acked again, a chunk past the end of what was
    /// received is not taken (the ack tells the host where to go on).
    Chunk {
        /// Where the bytes go in the image.
        offset: u32,
        /// At most [`MAX_CHUNK`] bytes.
        #[serde(borrow)]
        bytes: &'a [u8],
    },
    /// Every chunk was sent: check length and CRC, validate, answer
    /// [`Reply::Accepted`] or [`Reply::Rejected`]. Fewer bytes than announced leave the
    /// transfer open ([`Fault::Incomplete`]). A `Commit` after the transfer's verdict
    /// is answered with the verdict again, and changes nothing.
    Commit,
    /// Tick (from the current tick number) every `period_ms`, up to but not including
    /// tick `until` when given. Answered by [`Reply::State`].
    Start {
        /// Stop before this tick; `None` runs on.
        until: Option<u32>,
        /// Milliseconds between ticks; 0 ticks as fast as the controller can.
        period_ms: u16,
    },
    /// Stop ticking and halt every running action. Answered by [`Reply::State`].
    Stop,
    /// Are you there? Answered by [`Reply::State`] with the same token.
    Ping {
        /// Echoed back.
        token: u32,
    },
    /// Send the running image's bytes from `offset`: answered by [`Reply::Image`].
    Read {
        /// Where to start.
        offset: u32,
    },
}

/// Controller to host.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Reply<'a> {
    /// The controller's identity, in answer to [`Request::Hello`].
    Hello {
        /// The controller's protocol version.
        #[serde(with = "postcard::fixint::le")]
        version: u16,
        /// Fingerprint of its behavior set: an image must carry the same.
        #[serde(with = "postcard::fixint::le")]
        fingerprint: u64,
        /// Most nodes a tree may have.
        #[serde(with = "postcard::fixint::le")]
        node_capacity: u16,
        /// Most bytes an image may have.
        #[serde(with = "postcard::fixint::le")]
        image_capacity: u32,
        /// The running tree's image, if any.
        running: Option<ImageInfo>,
    },
    /// `received` bytes of the transfer `id` are held (every byte before that offset).
    ChunkAck {
        /// The transfer, as its `Deploy` named it.
        #[serde(with = "postcard::fixint::le")]
        id: u16,
        /// Bytes held so far: the offset of the next chunk.
        #[serde(with = "postcard::fixint::le")]
        received: u32,
    },
    /// The image of transfer `id` passed every check and waits for its tick boundary
    /// (or was swapped in already, when this answers a repeated request).
    Accepted {
        /// The transfer, as its `Deploy` named it.
        #[serde(with = "postcard::fixint::le")]
        id: u16,
        /// Its CRC-32.
        #[serde(with = "postcard::fixint::le")]
        crc: u32,
        /// Its node count.
        #[serde(with = "postcard::fixint::le")]
        nodes: u16,
        /// The tick before which it will be swapped in; `None`: the next boundary.
        #[serde(with = "fixed_option_u32")]
        swap_at: Option<u32>,
    },
    /// The transfer or request was refused; the running tree is untouched.
    Rejected {
        /// Why.
        fault: Fault,
    },
    /// The old tree's running actions were halted (their `Status` changes came before
    /// this) and the new tree runs from tick `tick` on.
    Swapped {
        /// The first tick of the new tree.
        #[serde(with = "postcard::fixint::le")]
        tick: u32,
        /// The new image.
        image: ImageInfo,
        /// Actions of the old tree halted for the swap.
        #[serde(with = "postcard::fixint::le")]
        halted: u16,
    },
    /// A node changed status (the executor's observer), during tick `tick` or, for
    /// halts at a swap or a stop, at the boundary before it.
    Status {
        /// The tick.
        #[serde(with = "postcard::fixint::le")]
        tick: u32,
        /// Node id in the running tree.
        #[serde(with = "postcard::fixint::le")]
        node: u16,
        /// Its new status.
        status: WireStatus,
    },
    /// Tick statistics, after every tick.
    Tick {
        /// The tick that finished.
        #[serde(with = "postcard::fixint::le")]
        tick: u32,
        /// What the root returned (`Idle` stands for a tick error).
        status: WireStatus,
        /// Status changes reported during the tick.
        #[serde(with = "postcard::fixint::le")]
        changes: u16,
        /// Microseconds the tick took on the controller's clock.
        #[serde(with = "postcard::fixint::le")]
        micros: u32,
    },
    /// Where the controller stands, in answer to `Start`, `Stop` and `Ping`.
    State {
        /// The `Ping` token, 0 for `Start` and `Stop`.
        #[serde(with = "postcard::fixint::le")]
        token: u32,
        /// The next tick to run.
        #[serde(with = "postcard::fixint::le")]
        tick: u32,
        /// Whether it is ticking.
        ticking: bool,
        /// The tick it stops before, if any.
        #[serde(with = "fixed_option_u32")]
        until: Option<u32>,
        /// The running tree's image, if any.
        running: Option<ImageInfo>,
        /// Actions halted by a `Stop`; 0 otherwise.
        #[serde(with = "postcard::fixint::le")]
        halted: u16,
        /// Bytes of stack used since boot, when the controller can tell (0 if not).
        #[serde(with = "postcard::fixint::le")]
        stack_used: u32,
    },
    /// Running image bytes, in answer to [`Request::Read`].
    Image {
        /// Where these bytes are.
        #[serde(with = "postcard::fixint::le")]
        offset: u32,
        /// The whole image's length.
        #[serde(with = "postcard::fixint::le")]
        total: u32,
        /// At most [`MAX_CHUNK`] bytes.
        #[serde(borrow)]
        bytes: &'a [u8],
    },
    /// A frame arrived that could not be used; it was skipped.
    Garbled {
        /// Why.
        fault: FrameFault,
    },
    /// Replies the controller dropped because its transmit queue was full (status
    /// changes, mostly), since the last `Lost`; sent before the `Tick` of tick `tick`.
    Lost {
        /// The tick during or before which they were dropped.
        #[serde(with = "postcard::fixint::le")]
        tick: u32,
        /// How many frames.
        #[serde(with = "postcard::fixint::le")]
        frames: u16,
    },
}

/// An image the controller holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ImageInfo {
    /// The CRC-32 the image stores (see [`image_crc`](crate::image_crc)).
    #[serde(with = "postcard::fixint::le")]
    pub crc: u32,
    /// Image length in bytes.
    #[serde(with = "postcard::fixint::le")]
    pub len: u32,
    /// Node count.
    #[serde(with = "postcard::fixint::le")]
    pub nodes: u16,
}

/// A node status on the wire.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum WireStatus {
    /// Not ticked in its parent's current activation, or halted.
    Idle,
    /// Success.
    Success,
    /// Failure.
    Failure,
    /// Running.
    Running,
    /// Only in a [`Reply::Tick`]: the root returned Skipped (it did nothing, as
    /// BehaviorTree.CPP's SKIPPED). A node never has this status.
    Skipped,
}

impl WireStatus {
    /// The status in capitals, as bt-core names it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Skipped => Status::Skipped.name(),
            s => NodeStatus::from(s).name(),
        }
    }
}

impl From<NodeStatus> for WireStatus {
    fn from(s: NodeStatus) -> Self {
        match s {
            NodeStatus::Idle => Self::Idle,
            NodeStatus::Success => Self::Success,
            NodeStatus::Failure => Self::Failure,
            NodeStatus::Running => Self::Running,
        }
    }
}

impl From<Status> for WireStatus {
    fn from(s: Status) -> Self {
        match s {
            Status::Skipped => Self::Skipped,
            s => NodeStatus::from(s).into(),
        }
    }
}

impl From<WireStatus> for NodeStatus {
    /// A node's status; `Skipped` (a root's tick result only) is Idle, as bt-core
    /// leaves a node that skipped.
    fn from(s: WireStatus) -> Self {
        match s {
            WireStatus::Idle | WireStatus::Skipped => Self::Idle,
            WireStatus::Success => Self::Success,
            WireStatus::Failure => Self::Failure,
            WireStatus::Running => Self::Running,
        }
    }
}

/// Why a deployment or request was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Fault {
    /// bt-core's loader refused the image: [`LOAD_CODES`] names `code`.
    Load {
        /// Index into [`LOAD_CODES`].
        code: u8,
        /// The node the fault is at, if it has one.
        #[serde(with = "fixed_option_u16")]
        node: Option<u16>,
    },
    /// The image is larger than the controller's image buffer.
    TooLarge {
        /// Announced length.
        #[serde(with = "postcard::fixint::le")]
        len: u32,
        /// Bytes the buffer holds.
        #[serde(with = "postcard::fixint::le")]
        capacity: u32,
    },
    /// `Commit` came before every byte had arrived.
    Incomplete {
        /// Bytes received.
        #[serde(with = "postcard::fixint::le")]
        received: u32,
        /// Bytes announced.
        #[serde(with = "postcard::fixint::le")]
        len: u32,
    },
    /// The bytes received do not have the CRC the `Deploy` announced.
    TransferCrc {
        /// Announced.
        #[serde(with = "postcard::fixint::le")]
        expected: u32,
        /// Computed over what arrived.
        #[serde(with = "postcard::fixint::le")]
        computed: u32,
    },
    /// A chunk would end past the announced length.
    Overrun {
        /// The chunk's offset.
        #[serde(with = "postcard::fixint::le")]
        offset: u32,
        /// Its length.
        #[serde(with = "postcard::fixint::le")]
        len: u32,
    },
    /// `Chunk` without a transfer under way, or `Commit` with none since the last
    /// `Hello`.
    NoTransfer,
    /// A transfer, or an accepted image waiting for its tick, was dropped by a new
    /// `Deploy`.
    Superseded {
        /// CRC the dropped transfer announced.
        #[serde(with = "postcard::fixint::le")]
        crc: u32,
    },
    /// `Start` or `Read` with no tree loaded.
    NoTree,
}

/// `Option<u16>`/`Option<u32>` in replies: postcard's option tag, then the value as a
/// fixed-width little-endian integer.
macro_rules! fixed_option {
    ($name:ident, $t:ty) => {
        mod $name {
            use serde::{Deserialize, Deserializer, Serialize, Serializer};

            #[derive(Serialize, Deserialize)]
            struct Fixed(#[serde(with = "postcard::fixint::le")] $t);

            pub fn serialize<S: Serializer>(v: &Option<$t>, s: S) -> Result<S::Ok, S::Error> {
                v.map(Fixed).serialize(s)
            }

            pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<$t>, D::Error> {
                Ok(Option::<Fixed>::deserialize(d)?.map(|f| f.0))
            }
        }
    };
}
fixed_option!(fixed_option_u16, u16);
fixed_option!(fixed_option_u32, u32);

/// Why a frame was skipped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum FrameFault {
    /// Not valid COBS (a zero byte inside a run).
    Cobs,
    /// Longer than the receive buffer.
    TooLong,
    /// Shorter than a message and its CRC.
    TooShort,
    /// The frame's CRC-32 does not match its bytes.
    Crc,
    /// The bytes do not decode as a message of this protocol version.
    Message,
}

impl FrameFault {
    /// A short stable name.
    #[must_use]
    pub const fn code(self) -> &'static str {
        match self {
            Self::Cobs => "bad-cobs",
            Self::TooLong => "frame-too-long",
            Self::TooShort => "frame-too-short",
            Self::Crc => "frame-crc",
            Self::Message => "bad-message",
        }
    }
}

/// bt-core's `LoadError::code()` names, indexed by the code [`Fault::Load`] carries.
/// The last entry stands for a variant a newer bt-core adds.
pub const LOAD_CODES: [&str; 21] = [
    "truncated",
    "bad-magic",
    "unsupported-version",
    "crc-mismatch",
    "foreign-behavior-set",
    "too-many-nodes",
    "malformed-node",
    "trailing-bytes",
    "unknown-section",
    "malformed-section",
    "too-many-values",
    "empty-tree",
    "subtree-size-inconsistent",
    "wrong-arity",
    "depth-over-limit",
    "unknown-behavior",
    "wrong-leaf-kind",
    "bad-argument",
    "bad-port",
    "unsupported-kind",
    "other",
];

/// The [`Fault::Load`] for a loader error.
#[must_use]
pub fn load_fault(e: &LoadError) -> Fault {
    let code = match e {
        LoadError::Truncated { .. } => 0,
        LoadError::BadMagic { .. } => 1,
        LoadError::UnsupportedVersion { .. } => 2,
        LoadError::CrcMismatch { .. } => 3,
        LoadError::ForeignBehaviorSet { .. } => 4,
        LoadError::TooManyNodes { .. } => 5,
        LoadError::MalformedNode { .. } => 6,
        LoadError::TrailingBytes { .. } => 7,
        LoadError::UnknownSection { .. } => 8,
        LoadError::MalformedSection { .. } => 9,
        LoadError::TooManyValues { .. } => 10,
        LoadError::EmptyTree => 11,
        LoadError::SubtreeSizeInconsistent { .. } => 12,
        LoadError::WrongArity { .. } => 13,
        LoadError::DepthOverLimit { .. } => 14,
        LoadError::UnknownBehavior { .. } => 15,
        LoadError::WrongLeafKind { .. } => 16,
        LoadError::BadArgument { .. } => 17,
        LoadError::BadPort { .. } => 18,
        LoadError::UnsupportedKind { .. } => 19,
        _ => 20,
    };
    Fault::Load { code, node: e.node() }
}

impl Fault {
    /// A short stable name: bt-core's code for loader faults.
    #[must_use]
    pub fn code(&self) -> &'static str {
        match *self {
            Self::Load { code, .. } => LOAD_CODES.get(usize::from(code)).copied().unwrap_or("other"),
            Self::TooLarge { .. } => "too-large",
            Self::Incomplete { .. } => "incomplete",
            Self::TransferCrc { .. } => "transfer-crc",
            Self::Overrun { .. } => "overrun",
            Self::NoTransfer => "no-transfer",
            Self::Superseded { .. } => "superseded",
            Self::NoTree => "no-tree",
        }
    }
}
