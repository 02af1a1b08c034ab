//! The wire of `deploywatch hil`: QEMU started with the serial-link
//! firmware and its UART0 on a TCP socket, or a serial device to a board;
//! the frames written at their send times and the frames read back, each
//! stamped with the host's monotonic clock.

use std::io::{self, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use deploywatch_core::telemetry::link::{read_report, read_shed, LinkReport};

use crate::onboard::hil::{Outgoing, Received};
use crate::onboard::replay::{ReplayError, QEMU};

/// The joint counts the serial-link firmware is built for, one binary each
/// (its `JOINTS`, `firmware-example/Cargo.toml`: the firmware chooses the
/// joint count; it refuses a configuration of another).
pub const UART_JOINTS: [usize; 2] = [3, 6];

/// The serial-link firmware ELF of 3 joints, relative to the repository
/// root; that of `N` other joints is this path with `-N` appended
/// ([`default_uart_elf`]).
pub const DEFAULT_UART_ELF: &str =
    "firmware-example/target/thumbv7em-none-eabihf/release/deploywatch-firmware-uart";

/// The serial-link firmware ELF of `joints` joints, relative to the
/// repository root ([`DEFAULT_UART_ELF`] for 3).
pub fn default_uart_elf(joints: usize) -> String {
    if joints == 3 {
        DEFAULT_UART_ELF.to_string()
    } else {
        format!("{DEFAULT_UART_ELF}-{joints}")
    }
}

/// How long the firmware may take to come up and answer the configuration.
const READY_TIMEOUT: Duration = Duration::from_secs(20);

/// Where the firmware runs.
#[derive(Clone, Debug)]
pub enum Endpoint {
    /// QEMU's mps2-an386 with this ELF, UART0 on a local TCP socket; the
    /// firmware's defmt log to `log` (when given); `icount`: QEMU's
    /// `-icount shift=N,align=on` (`None`: no icount, guest time is the
    /// host's).
    Qemu {
        /// The serial-link firmware.
        elf: PathBuf,
        /// Where the firmware's raw defmt log goes.
        log: Option<PathBuf>,
        /// `-icount shift=N,align=on`.
        icount: Option<u8>,
    },
    /// A serial device (a board's UART through a USB bridge).
    Serial {
        /// The device, e.g. `/dev/ttyACM0`.
        port: String,
        /// The line's rate \[baud\].
        baud: u32,
    },
}

/// An open link: both directions, and QEMU when it was started here
/// (killed when the link is dropped).
pub struct Connection {
    reader: Box<dyn Read + Send>,
    writer: Box<dyn Write + Send>,
    qemu: Option<Child>,
}

impl Drop for Connection {
    fn drop(&mut self) {
        if let Some(q) = &mut self.qemu {
            let _ = q.kill();
            let _ = q.wait();
        }
    }
}

/// The serial-link ELF: `elf` when given, else that of `joints` joints
/// ([`default_uart_elf`]) under
/// the current directory, else under the source tree.
pub fn find_uart_elf(elf: Option<&Path>, joints: usize) -> Result<PathBuf, ReplayError> {
    crate::onboard::replay::find_firmware(
        elf,
        &default_uart_elf(joints),
        "run scripts/embedded-toolchain.sh (once per machine), then scripts/firmware.sh build",
    )
}

/// Opens the link to `endpoint`.
pub fn connect(endpoint: &Endpoint) -> Result<Connection, ReplayError> {
    match endpoint {
        Endpoint::Qemu { elf, log, icount } => start_qemu(elf, log.as_deref(), *icount),
        Endpoint::Serial { port, baud } => open_serial(port, *baud),
    }
}

fn start_qemu(
    elf: &Path,
    log: Option<&Path>,
    icount: Option<u8>,
) -> Result<Connection, ReplayError> {
    let setup = |e: io::Error| ReplayError::Setup(format!("a local TCP socket for QEMU: {e}"));
    let listener = TcpListener::bind("127.0.0.1:0").map_err(setup)?;
    let port = listener.local_addr().map_err(setup)?.port();
    let stdout = match log {
        Some(p) => Stdio::from(
            std::fs::File::create(p)
                .map_err(|e| ReplayError::Input(format!("{}: {e}", p.display())))?,
        ),
        None => Stdio::null(),
    };
    let mut cmd = Command::new(QEMU);
    cmd.args(["-cpu", "cortex-m4", "-machine", "mps2-an386", "-nographic"])
        .args(["-monitor", "none"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .arg("-chardev")
        .arg(format!(
            "socket,id=hil,host=127.0.0.1,port={port},nodelay=on"
        ))
        .args(["-serial", "chardev:hil"]);
    if let Some(shift) = icount {
        cmd.arg("-icount").arg(format!("shift={shift},align=on"));
    }
    let mut child = cmd
        .arg("-kernel")
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| match e.kind() {
            io::ErrorKind::NotFound => ReplayError::Setup(format!(
                "{QEMU} is not installed: run scripts/embedded-toolchain.sh"
            )),
            _ => ReplayError::Setup(format!("cannot start {QEMU}: {e}")),
        })?;
    let stream = match accept(&listener, &mut child) {
        Ok(s) => s,
        Err(e) => {
            let _ = child.kill();
            let _ = child.wait();
            return Err(e);
        }
    };
    let reader = stream
        .try_clone()
        .map_err(|e| ReplayError::Target(format!("the QEMU socket: {e}")))?;
    Ok(Connection {
        reader: Box::new(reader),
        writer: Box::new(stream),
        qemu: Some(child),
    })
}

/// QEMU's connection to `listener` (its UART0), or why it did not come.
fn accept(listener: &TcpListener, child: &mut Child) -> Result<TcpStream, ReplayError> {
    let err = |e: io::Error| ReplayError::Target(format!("waiting for QEMU's UART: {e}"));
    listener.set_nonblocking(true).map_err(err)?;
    let start = Instant::now();
    loop {
        match listener.accept() {
            Ok((s, _)) => {
                s.set_nonblocking(false).map_err(err)?;
                s.set_nodelay(true).map_err(err)?;
                return Ok(s);
            }
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => {}
            Err(e) => return Err(err(e)),
        }
        if let Ok(Some(st)) = child.try_wait() {
            let mut msg = String::new();
            if let Some(mut e) = child.stderr.take() {
                let _ = e.read_to_string(&mut msg);
            }
            return Err(ReplayError::Target(format!("{QEMU} exited ({st}): {msg}")));
        }
        if start.elapsed() > READY_TIMEOUT {
            return Err(ReplayError::Target(format!(
                "{QEMU} did not connect its UART within {} s",
                READY_TIMEOUT.as_secs()
            )));
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn open_serial(port: &str, baud: u32) -> Result<Connection, ReplayError> {
    let p = serialport::new(port, baud)
        .timeout(Duration::from_millis(50))
        .open()
        .map_err(|e| ReplayError::Input(format!("serial port {port}: {e}")))?;
    let reader = p
        .try_clone()
        .map_err(|e| ReplayError::Input(format!("serial port {port}: {e}")))?;
    Ok(Connection {
        reader: Box::new(reader),
        writer: Box::new(p),
        qemu: None,
    })
}

/// Reads frames from `reader` until it ends or fails, each sent with the
/// time it was complete (its `0x00` read).
fn spawn_reader(mut reader: Box<dyn Read + Send>) -> Receiver<(Vec<u8>, Instant)> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        let mut frame = Vec::new();
        loop {
            let n = match reader.read(&mut buf) {
                Ok(0) => return,
                Ok(n) => n,
                Err(e) if e.kind() == io::ErrorKind::TimedOut => continue,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(_) => return,
            };
            let now = Instant::now();
            for &b in &buf[..n] {
                frame.push(b);
                if b == 0 && tx.send((std::mem::take(&mut frame), now)).is_err() {
                    return;
                }
            }
        }
    });
    rx
}

/// The next link report from `rx` within `timeout`; other frames go to
/// `others`.
fn wait_report(
    rx: &Receiver<(Vec<u8>, Instant)>,
    timeout: Duration,
    mut others: impl FnMut(Vec<u8>, Instant),
) -> Option<LinkReport> {
    let end = Instant::now() + timeout;
    loop {
        let left = end.checked_duration_since(Instant::now())?;
        match rx.recv_timeout(left) {
            Ok((f, at)) => {
                let mut copy = f.clone();
                match read_report(&mut copy) {
                    Some(r) => return Some(r),
                    None => others(f, at),
                }
            }
            Err(RecvTimeoutError::Timeout) | Err(RecvTimeoutError::Disconnected) => return None,
        }
    }
}

/// Streams: the configuration, the wait for the firmware's "ready", then
/// every outgoing frame at its send time, then the statuses' stragglers and
/// the link report. `settle`: how long to wait for the last statuses.
pub fn stream(
    mut conn: Connection,
    config: &[u8],
    out: &Outgoing,
    settle: Duration,
) -> Result<Received, ReplayError> {
    let fail = |e: io::Error| ReplayError::Target(format!("writing to the link: {e}"));
    let reader = std::mem::replace(&mut conn.reader, Box::new(io::empty()));
    let rx = spawn_reader(reader);
    conn.writer.write_all(config).map_err(fail)?;
    conn.writer.flush().map_err(fail)?;
    wait_report(&rx, READY_TIMEOUT, |_, _| {}).ok_or_else(|| {
        ReplayError::Target(format!(
            "the firmware did not answer the configuration within {} s",
            READY_TIMEOUT.as_secs()
        ))
    })?;
    let mut got = Received::default();
    let start = Instant::now();
    for (bytes, at) in out.bytes.iter().zip(&out.at_s) {
        let due = start + Duration::from_secs_f64(at.max(0.0));
        if let Some(wait) = due.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
        if bytes.is_empty() {
            got.sent.push(None);
            continue;
        }
        got.sent.push(Some(start.elapsed()));
        conn.writer.write_all(bytes).map_err(fail)?;
        conn.writer.flush().map_err(fail)?;
    }
    // The statuses still on their way, then the counts.
    std::thread::sleep(settle);
    conn.writer.write_all(&[0]).map_err(fail)?;
    conn.writer.flush().map_err(fail)?;
    let (mut statuses, mut sheds) = (Vec::new(), Vec::new());
    got.report = wait_report(&rx, READY_TIMEOUT, |f, at| {
        let mut copy = f.clone();
        match read_shed(&mut copy) {
            Some(s) => sheds.push(s),
            None => statuses.push((f, at.saturating_duration_since(start))),
        }
    });
    got.statuses = statuses;
    got.sheds = sheds;
    Ok(got)
}
