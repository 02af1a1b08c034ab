//! The replay protocol the firmware speaks: a recorded run, sample by
//! sample, through the on-board [`Monitor`](crate::Monitor), with the
//! statuses written back.
//!
//! It lives in the core so that the host (`deploywatch replay`) and the
//! firmware share one implementation and the host never depends on a
//! firmware crate: the host writes the configuration frames with these
//! types, checks them against its own conversion of the mechanism file, and
//! can run this very loop itself.
//!
//! # Files
//! - Input: the monitor configuration ([`super::config`]: a [`ConfigHeader`] frame,
//!   then one [`JointFrame`] per joint), then one frame per sample, a
//!   [`Sample<N>`](crate::Sample) each, in time order, `N` the
//!   header's joint count (one of [`JOINT_COUNTS`]).
//! - Output: one frame per input sample, the
//!   [`Status<N>`](crate::Status) that
//!   [`Monitor::update`](crate::Monitor::update) returned.
//!
//! Every frame is the core's telemetry frame
//! ([`crate::telemetry`]): postcard, CRC-32C, COBS, then `0x00`.
//! A frame that does not decode stops the replay with its index: a replay
//! input comes from a file, so a bad frame is a bad file, not line noise.

use crate::monitor::MonitorConfig;
use crate::telemetry::{self, sample_frame_max, status_frame_max};
use crate::{Monitor, Sample, Status};

pub use super::config::{ConfigHeader, JointFrame, JOINT_COUNTS, MAX_JOINTS};
use super::config::{CONFIG_HEADER_FRAME_MAX, CONFIG_VERSION, JOINT_FRAME_MAX};

/// Largest input sample frame of any joint count the firmware takes, `0x00`
/// included [bytes].
pub const SAMPLE_FRAME_MAX: usize = sample_frame_max(MAX_JOINTS);

/// Largest output frame of any joint count, `0x00` included [bytes].
pub const STATUS_FRAME_MAX: usize = status_frame_max(MAX_JOINTS);

/// Bytes read from the input at a time.
pub const READ_CHUNK: usize = 256;

/// Why a replay stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// The configuration frames are missing, do not decode, are of another
    /// [`CONFIG_VERSION`](super::config::CONFIG_VERSION) or give a joint count not in
    /// [`JOINT_COUNTS`].
    ConfigFrame,
    /// The monitor (or the core's spring constructor) rejects the
    /// configuration.
    Config,
    /// Reading the input failed.
    Read,
    /// Writing the output failed.
    Write,
    /// Sample frame `index` (0-based, after the configuration frames) does
    /// not decode as a sample of the configured joint count, or is too long.
    Frame {
        /// 0-based index of the sample frame.
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
            Error::ConfigFrame => "the configuration frames are missing or do not decode",
            Error::Config => "the monitor rejects the configuration",
            Error::Read => "cannot read the input",
            Error::Write => "cannot write the output",
            Error::Frame { .. } => "a sample frame does not decode",
            Error::Truncated => "the input ends inside a frame",
            Error::Encode => "a status does not fit its frame",
        }
    }
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Frame { index } => {
                write!(f, "sample frame {index} does not decode")
            }
            other => f.write_str(other.as_str()),
        }
    }
}

impl core::error::Error for Error {}

/// Why [`Source::next_frame`] gave no frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameError {
    /// Reading failed.
    Read,
    /// The frame was longer than the buffer (it was skipped up to its `0x00`).
    TooLong,
    /// The input ended inside a frame.
    Truncated,
}

/// A byte stream read in chunks and split into `0x00`-terminated frames,
/// without allocating.
pub struct Source<R> {
    read: R,
    chunk: [u8; READ_CHUNK],
    pos: usize,
    len: usize,
}

impl<R: FnMut(&mut [u8]) -> Result<usize, ()>> Source<R> {
    /// A source over `read` (like `std::io::Read::read`: `Ok(0)` at the end).
    pub const fn new(read: R) -> Self {
        Source {
            read,
            chunk: [0; READ_CHUNK],
            pos: 0,
            len: 0,
        }
    }

    fn byte(&mut self) -> Result<Option<u8>, FrameError> {
        if self.pos == self.len {
            let n = (self.read)(&mut self.chunk).map_err(|_| FrameError::Read)?;
            self.pos = 0;
            self.len = n.min(READ_CHUNK);
            if self.len == 0 {
                return Ok(None);
            }
        }
        let b = self.chunk.get(self.pos).copied();
        self.pos += 1;
        Ok(b)
    }

    /// The next frame (its `0x00` included) in `buf`, `Ok(None)` at the end
    /// of the input.
    pub fn next_frame<'b>(
        &mut self,
        buf: &'b mut [u8],
    ) -> Result<Option<&'b mut [u8]>, FrameError> {
        let mut len = 0usize;
        let mut too_long = false;
        loop {
            let Some(b) = self.byte()? else {
                return if len == 0 && !too_long {
                    Ok(None)
                } else {
                    Err(FrameError::Truncated)
                };
            };
            match buf.get_mut(len) {
                Some(slot) if !too_long => {
                    *slot = b;
                    len += 1;
                }
                _ => too_long = true,
            }
            if b == 0 {
                if too_long {
                    return Err(FrameError::TooLong);
                }
                return Ok(buf.get_mut(..len));
            }
        }
    }
}

/// Reads the configuration header (the input's first frame).
pub fn read_header<R>(src: &mut Source<R>) -> Result<ConfigHeader, Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    let mut buf = [0u8; CONFIG_HEADER_FRAME_MAX];
    let header: ConfigHeader = match src.next_frame(&mut buf) {
        Ok(Some(f)) => telemetry::decode(f).map_err(|_| Error::ConfigFrame)?,
        Err(FrameError::Read) => return Err(Error::Read),
        _ => return Err(Error::ConfigFrame),
    };
    if header.version != CONFIG_VERSION || !JOINT_COUNTS.contains(&header.joints) {
        return Err(Error::ConfigFrame);
    }
    Ok(header)
}

/// Reads the `N` joint frames that follow the header and builds the
/// monitor configuration, one joint frame at a time (the configuration is
/// built on the MCU's stack, just before the monitor's own frame).
#[inline(never)]
pub fn read_config<const N: usize, R>(
    header: &ConfigHeader,
    src: &mut Source<R>,
) -> Result<MonitorConfig<N>, Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    if usize::from(header.joints) != N {
        return Err(Error::ConfigFrame);
    }
    // Placeholders, all overwritten (a spring of `None` always builds).
    let (panel, joint) = JointFrame::default()
        .to_config()
        .map_err(|_| Error::Config)?;
    let mut config = MonitorConfig::new([panel; N], [joint; N]);
    config.margin.deadline_s = header.deadline_s;
    let mut buf = [0u8; JOINT_FRAME_MAX];
    for j in 0..N {
        let frame: JointFrame = match src.next_frame(&mut buf) {
            Ok(Some(f)) => telemetry::decode(f).map_err(|_| Error::ConfigFrame)?,
            Err(FrameError::Read) => return Err(Error::Read),
            _ => return Err(Error::ConfigFrame),
        };
        let (p, c) = frame.to_config().map_err(|_| Error::Config)?;
        if let (Some(ps), Some(cs)) = (config.panels.get_mut(j), config.joints.get_mut(j)) {
            *ps = p;
            *cs = c;
        }
    }
    Ok(config)
}

/// The two kinds of work [`run`] does, each metered on its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Work {
    /// [`Monitor::update`]: the sample-rate path.
    Update,
    /// One slice of [`Monitor::predict`]: the low-priority prediction.
    Predict,
}

/// Brackets every [`Monitor::update`] and [`Monitor::predict`] call of
/// [`run`]: the firmware counts the instructions each takes; `()` does
/// nothing.
pub trait Meter {
    /// Just before the call.
    fn start(&mut self);
    /// Just after it.
    fn stop(&mut self, work: Work);
}

impl Meter for () {
    fn start(&mut self) {}
    fn stop(&mut self, _: Work) {}
}

/// Where the monitor lives: the firmware gives static storage (a monitor is
/// kilobytes; on the stack it would double the stack's peak), the host
/// anything. One slot serves every joint count.
#[derive(Default)]
#[allow(clippy::large_enum_variant)]
pub enum MonitorStore {
    /// No monitor yet.
    #[default]
    Empty,
    /// The 2-joint monitor.
    Two(Monitor<2>),
    /// The 3-joint monitor.
    Three(Monitor<3>),
}

/// Replays the sample frames left in `src` through `monitor`, as a flight
/// application schedules the two paths: [`Monitor::update`] on every sample
/// (the sample-rate path), then `margin.rollout.slices_per_sample` slices
/// of [`Monitor::predict`] (the idle time before the next sample; fixed, so
/// that the replay is deterministic and the same as the host's
/// [`Monitor::update_and_predict`]), each inside `meter`'s brackets. Hands
/// each status frame, as of the end of the slices, to `write`. Returns the
/// number of samples.
#[inline(never)]
pub fn run<const N: usize, R, W, M>(
    monitor: &mut Monitor<N>,
    src: &mut Source<R>,
    mut write: W,
    meter: &mut M,
) -> Result<u32, Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
    W: FnMut(&[u8]) -> Result<(), ()>,
    M: Meter,
{
    let mut frame = [0u8; SAMPLE_FRAME_MAX];
    let mut out = [0u8; STATUS_FRAME_MAX];
    let mut index: u32 = 0;
    let slices = monitor.config_slices_per_sample();
    loop {
        let buf = frame.get_mut(..sample_frame_max(N)).ok_or(Error::Encode)?;
        let f = match src.next_frame(buf) {
            Ok(Some(f)) => f,
            Ok(None) => break,
            Err(FrameError::Read) => return Err(Error::Read),
            Err(FrameError::Truncated) => return Err(Error::Truncated),
            Err(FrameError::TooLong) => return Err(Error::Frame { index }),
        };
        let sample: Sample<N> = telemetry::decode(f).map_err(|_| Error::Frame { index })?;
        meter.start();
        monitor.update(&sample);
        meter.stop(Work::Update);
        for _ in 0..slices {
            meter.start();
            monitor.predict();
            meter.stop(Work::Predict);
        }
        let status: &Status<N> = monitor.status();
        let bytes = telemetry::encode(status, &mut out).map_err(|_| Error::Encode)?;
        write(bytes).map_err(|_| Error::Write)?;
        index += 1;
    }
    Ok(index)
}

/// The whole replay of an input stream: the configuration frames, then the
/// samples through a monitor of the header's joint count, built in `store`.
/// Returns the joint count and the number of samples. `on_config` is called
/// with the header once it is read (the firmware logs it).
pub fn replay<R, W, M>(
    read: R,
    write: W,
    meter: &mut M,
    store: &mut MonitorStore,
    on_config: impl FnOnce(&ConfigHeader),
) -> Result<(u8, u32), Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
    W: FnMut(&[u8]) -> Result<(), ()>,
    M: Meter,
{
    let mut src = Source::new(read);
    let header = read_header(&mut src)?;
    on_config(&header);
    let n = match header.joints {
        2 => {
            let config = read_config::<2, R>(&header, &mut src)?;
            build(&config, store)?;
            match store {
                MonitorStore::Two(m) => run(m, &mut src, write, meter),
                _ => Err(Error::Config),
            }
        }
        3 => {
            let config = read_config::<3, R>(&header, &mut src)?;
            build(&config, store)?;
            match store {
                MonitorStore::Three(m) => run(m, &mut src, write, meter),
                _ => Err(Error::Config),
            }
        }
        _ => Err(Error::ConfigFrame),
    }?;
    Ok((header.joints, n))
}

/// Builds the monitor of `config` in `store`. Out of line, so that the
/// monitor under construction is not on the stack under [`run`].
#[inline(never)]
fn build<const N: usize>(config: &MonitorConfig<N>, store: &mut MonitorStore) -> Result<(), Error>
where
    Monitor<N>: Into<MonitorStore>,
{
    *store = Monitor::new(config).map_err(|_| Error::Config)?.into();
    Ok(())
}

impl From<Monitor<2>> for MonitorStore {
    fn from(m: Monitor<2>) -> Self {
        MonitorStore::Two(m)
    }
}

impl From<Monitor<3>> for MonitorStore {
    fn from(m: Monitor<3>) -> Self {
        MonitorStore::Three(m)
    }
}
