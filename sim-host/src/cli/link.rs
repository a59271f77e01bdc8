//! What `deploy` and `monitor` share: opening the link to a controller (a serial port
//! or a TCP socket, e.g. QEMU's `-serial tcp::4321,server=on`) and naming its faults.

use std::io::{Read, Write};
use std::time::Duration;

use anyhow::{Context as _, bail};
use bt_link::Fault;
use bt_link::host::{Client, ControllerInfo};
use sim_host::session::Session;

use super::catalogs;
use sim_host::text::count;

/// How a controller is reached.
#[derive(clap::Args, Debug)]
#[group(required = true, multiple = false)]
pub struct Target {
    /// A serial device (`/dev/ttyACM0`, `COM3`).
    #[arg(long, value_name = "PATH")]
    pub port: Option<String>,
    /// A TCP socket carrying the controller's serial line (QEMU's `-serial tcp::PORT,server=on`).
    #[arg(long, value_name = "HOST:PORT")]
    pub tcp: Option<String>,
}

/// Options of the serial line.
#[derive(clap::Args, Debug)]
pub struct Line {
    /// Baud rate of the serial device (ignored with --tcp).
    #[arg(long, default_value_t = 115_200)]
    pub baud: u32,
}

/// A byte link with reads that time out.
pub trait Io: Read + Write + Send {}
impl<T: Read + Write + Send> Io for T {}

/// How long one read of the link waits before the client checks its deadlines.
const POLL: Duration = Duration::from_millis(50);

/// Opens the link named by `target`: a session with the controller, and the link's
/// name for messages.
///
/// # Errors
/// One line naming the port or address and why it cannot be opened (busy, missing,
/// refused).
pub fn open(target: &Target, line: &Line) -> anyhow::Result<(Session<Box<dyn Io>>, String)> {
    if let Some(path) = &target.port {
        let port = serialport::new(path, line.baud).timeout(POLL).open().map_err(|e| match e.kind() {
            serialport::ErrorKind::NoDevice => anyhow::anyhow!("serial port {path}: no such device, or it is busy"),
            serialport::ErrorKind::Io(std::io::ErrorKind::PermissionDenied) => {
                anyhow::anyhow!("serial port {path}: permission denied (is your user in the `dialout` group?)")
            }
            _ => anyhow::anyhow!("serial port {path}: {e}"),
        })?;
        let io: Box<dyn Io> = Box::new(port);
        return Ok((Session::new(Client::new(io)), path.clone()));
    }
    let Some(addr) = &target.tcp else { bail!("give --port PATH or --tcp HOST:PORT") };
    let stream = std::net::TcpStream::connect(addr).with_context(|| format!("cannot connect to {addr}"))?;
    stream.set_read_timeout(Some(POLL)).with_context(|| addr.clone())?;
    let _ = stream.set_nodelay(true);
    let io: Box<dyn Io> = Box::new(stream);
    Ok((Session::new(Client::new(io)), addr.clone()))
}

/// `Hello`, with the controller's behavior set named when this binary knows it.
///
/// # Errors
/// No answer, another protocol version, or a link error, naming the link.
pub fn hello(link: &mut Session<Box<dyn Io>>, name: &str) -> anyhow::Result<(ControllerInfo, String)> {
    let info = link.hello().map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
    let set = catalogs::by_fingerprint(info.fingerprint)
        .map_or_else(|| format!("{:#018x}", info.fingerprint), |k| format!("{:#018x}, {}", info.fingerprint, k.name));
    Ok((info, set))
}

/// A refusal in words: the fault's code and what it means.
pub fn describe(fault: &Fault) -> String {
    let code = fault.code();
    match *fault {
        Fault::Load { node: Some(n), .. } => format!("{code} at node {n}"),
        Fault::Load { .. } => code.to_string(),
        Fault::TooLarge { len, capacity } => {
            format!("{code}: the image has {}, the controller holds {capacity}", count(len, "byte"))
        }
        Fault::Incomplete { received, len } => format!("{code}: {received} of {} arrived", count(len, "byte")),
        Fault::TransferCrc { expected, computed } => {
            format!("{code}: the bytes arrived with CRC-32 {computed:08x}, {expected:08x} was sent")
        }
        Fault::Overrun { offset, len } => {
            format!("{code}: a chunk of {} at {offset} ends past the image", count(len, "byte"))
        }
        Fault::NoTransfer => format!("{code}: chunk or commit without a deployment"),
        Fault::Superseded { crc } => format!("{code}: the transfer of image {crc:08x} was replaced by a newer one"),
        Fault::NoTree => format!("{code}: the controller has no tree"),
    }
}
