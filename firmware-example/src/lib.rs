//! The replay that the deploywatch example firmware runs on the MCU: a
//! recorded run, sample by sample, through the on-board
//! [`Monitor`](deploywatch_core::Monitor), with the statuses written back.
//!
//! This crate is `no_std` and also builds on the host, where `host/` (the
//! `deploywatch-replay` tool) uses its mechanism table to check it against
//! the host's own conversion of the mechanism files.
//!
//! # Files
//! - Input: one frame per sample, a [`Sample<3>`](deploywatch_core::Sample)
//!   each, in time order.
//! - Output: one frame per input sample, the
//!   [`Status<3>`](deploywatch_core::Status) that
//!   [`Monitor::update`](deploywatch_core::Monitor::update) returned.
//!
//! Every frame is the core's telemetry frame
//! ([`deploywatch_core::telemetry`]): postcard, CRC-32C, COBS, then `0x00`.
//! A frame that does not decode stops the replay with its index: a replay
//! input comes from a file, so a bad frame is a bad file, not line noise.
//!
//! # Mechanism
//! The monitor's configuration is compiled in ([`mechanism`]): the firmware
//! is told which one by name, as a run names its mechanism.
#![no_std]
#![deny(missing_docs)]
#![forbid(unsafe_code)]

use deploywatch_core::monitor::MonitorConfig;
use deploywatch_core::telemetry::{self, sample_frame_max, status_frame_max};
use deploywatch_core::{Monitor, Sample, Status};

pub mod mechanism;

/// Joints of the mechanisms this firmware monitors.
pub const JOINTS: usize = 3;

/// Largest input frame, `0x00` included [bytes].
pub const SAMPLE_FRAME_MAX: usize = sample_frame_max(JOINTS);

/// Largest output frame, `0x00` included [bytes].
pub const STATUS_FRAME_MAX: usize = status_frame_max(JOINTS);

/// Bytes read from the input at a time.
pub const READ_CHUNK: usize = 256;

/// Why a replay stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// The monitor rejects the configuration.
    Config,
    /// Reading the input failed.
    Read,
    /// Writing the output failed.
    Write,
    /// Input frame `index` (0-based) does not decode as a `Sample<3>`, or is
    /// longer than [`SAMPLE_FRAME_MAX`].
    Frame {
        /// 0-based index of the frame in the input.
        index: u32,
    },
    /// The input ends inside a frame (no `0x00` after its last bytes).
    Truncated,
    /// A status did not fit its frame (a bug: [`STATUS_FRAME_MAX`] is the bound).
    Encode,
}

impl Error {
    /// A short description, for logs that cannot format (defmt).
    pub fn as_str(&self) -> &'static str {
        match self {
            Error::Config => "the monitor rejects the configuration",
            Error::Read => "cannot read the input",
            Error::Write => "cannot write the output",
            Error::Frame { .. } => "an input frame does not decode as a 3-joint sample",
            Error::Truncated => "the input ends inside a frame",
            Error::Encode => "a status does not fit its frame",
        }
    }
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Frame { index } => {
                write!(f, "input frame {index} does not decode as a 3-joint sample")
            }
            other => f.write_str(other.as_str()),
        }
    }
}

impl core::error::Error for Error {}

/// Splits a byte stream into `0x00`-terminated frames of at most `MAX`
/// bytes, without allocating.
pub struct Framer<const MAX: usize> {
    buf: [u8; MAX],
    len: usize,
    overflow: bool,
}

impl<const MAX: usize> Default for Framer<MAX> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const MAX: usize> Framer<MAX> {
    /// An empty framer.
    pub const fn new() -> Self {
        Framer {
            buf: [0; MAX],
            len: 0,
            overflow: false,
        }
    }

    /// True when bytes of an unfinished frame are held.
    pub fn is_pending(&self) -> bool {
        self.len > 0 || self.overflow
    }

    /// Feeds `input`; calls `frame` with each complete frame (its `0x00`
    /// included), or with `None` for a frame longer than `MAX`. Stops at the
    /// first error `frame` returns.
    pub fn feed<E>(
        &mut self,
        input: &[u8],
        mut frame: impl FnMut(Option<&mut [u8]>) -> Result<(), E>,
    ) -> Result<(), E> {
        for &b in input {
            if !self.overflow {
                match self.buf.get_mut(self.len) {
                    Some(slot) => {
                        *slot = b;
                        self.len += 1;
                    }
                    None => self.overflow = true,
                }
            }
            if b == 0 {
                let overflow = core::mem::replace(&mut self.overflow, false);
                let len = core::mem::replace(&mut self.len, 0);
                if overflow {
                    frame(None)?;
                } else if let Some(f) = self.buf.get_mut(..len) {
                    frame(Some(f))?;
                }
            }
        }
        Ok(())
    }
}

/// Brackets every [`Monitor::update`] call of [`run`]: the firmware counts
/// the instructions it takes; `()` does nothing.
pub trait Meter {
    /// Just before the call.
    fn start(&mut self);
    /// Just after it.
    fn stop(&mut self);
}

impl Meter for () {
    fn start(&mut self) {}
    fn stop(&mut self) {}
}

/// Replays a whole input stream through a monitor: reads the input with
/// `read` (like `std::io::Read::read`: `Ok(0)` at the end), runs
/// [`Monitor::update`] on every sample (inside `meter`'s brackets) and hands
/// each status frame to `write`. Returns the number of samples.
pub fn run<R, W, M>(
    config: &MonitorConfig<JOINTS>,
    mut read: R,
    mut write: W,
    meter: &mut M,
) -> Result<u32, Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
    W: FnMut(&[u8]) -> Result<(), ()>,
    M: Meter,
{
    let mut monitor = Monitor::new(config).map_err(|_| Error::Config)?;
    let mut framer = Framer::<SAMPLE_FRAME_MAX>::new();
    let mut chunk = [0u8; READ_CHUNK];
    let mut out = [0u8; STATUS_FRAME_MAX];
    let mut index: u32 = 0;
    loop {
        let n = read(&mut chunk).map_err(|_| Error::Read)?;
        if n == 0 {
            break;
        }
        let input = chunk.get(..n).ok_or(Error::Read)?;
        framer.feed(input, |frame| {
            let sample: Sample<JOINTS> = frame
                .and_then(|f| telemetry::decode(f).ok())
                .ok_or(Error::Frame { index })?;
            meter.start();
            let status: Status<JOINTS> = monitor.update(&sample);
            meter.stop();
            let bytes = telemetry::encode(&status, &mut out).map_err(|_| Error::Encode)?;
            write(bytes).map_err(|_| Error::Write)?;
            index += 1;
            Ok::<(), Error>(())
        })?;
    }
    if framer.is_pending() {
        return Err(Error::Truncated);
    }
    Ok(index)
}
