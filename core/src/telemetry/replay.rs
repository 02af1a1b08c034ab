//! The replay protocol the firmware speaks: a recorded run, sample by
//! sample, through the on-board [`Monitor`], with the
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
//!   header's joint count (at most [`MAX_JOINTS`]).
//!
//! # Joint count and storage
//! The joint count is the caller's: a firmware builds one monitor,
//! `Monitor<N>` in a [`MonitorStore<N>`] with its configuration in a
//! [`ConfigStore<N>`] (both in its static memory), and [`configure`]
//! refuses a header of another count with [`Error::JointCount`]. The loop
//! ([`run_paths`]) and the sample decoder are not generic: they take the
//! count at run time, up to [`MAX_JOINTS`].
//! - Output: one frame per input sample, the
//!   [`Status<N>`](crate::Status) that
//!   [`Monitor::update`](crate::Monitor::update) returned.
//!
//! Every frame is the core's telemetry frame
//! ([`crate::telemetry`]): postcard, CRC-32C, COBS, then `0x00`.
//! A frame that does not decode stops the replay with its index: a replay
//! input comes from a file, so a bad frame is a bad file, not line noise.

use crate::monitor::config::ConfigRef;
use crate::monitor::estimator::Monitor;
use crate::monitor::estimator::MonitorConfig;
use crate::telemetry::counted::{CountedSample, StatusView};
use crate::telemetry::{self, sample_frame_max, status_frame_max};

pub use super::config::{ConfigHeader, JointFrame, MAX_JOINTS};
use super::config::{CONFIG_HEADER_FRAME_MAX, CONFIG_VERSION, JOINT_FRAME_MAX};

/// Largest input sample frame of any joint count up to [`MAX_JOINTS`],
/// `0x00` included \[bytes\].
pub const SAMPLE_FRAME_MAX: usize = sample_frame_max(MAX_JOINTS);

/// Largest output frame of any joint count up to [`MAX_JOINTS`], `0x00`
/// included \[bytes\].
pub const STATUS_FRAME_MAX: usize = status_frame_max(MAX_JOINTS);

/// Bytes read from the input at a time.
pub const READ_CHUNK: usize = 256;

/// Why a replay stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// The configuration frames are missing, do not decode, are of another
    /// [`CONFIG_VERSION`] or give a joint count outside `1..=`[`MAX_JOINTS`].
    ConfigFrame,
    /// The configuration is of `found` joints where the monitor's store
    /// ([`MonitorStore<N>`]) has `expected`: the firmware was built for
    /// another joint count.
    JointCount {
        /// The monitor's joint count `N`.
        expected: u8,
        /// The header's.
        found: u8,
    },
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
            Error::JointCount { .. } => "the configuration is of another joint count",
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
            Error::JointCount { expected, found } => write!(
                f,
                "the configuration is of {found} joints, the monitor of {expected}"
            ),
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
    let joints = usize::from(header.joints);
    if header.version != CONFIG_VERSION || !(1..=MAX_JOINTS).contains(&joints) {
        return Err(Error::ConfigFrame);
    }
    Ok(header)
}

/// Where the monitor configuration of `N` joints is built: the firmware
/// gives static storage (a configuration of 3 joints is about 1.5 KiB: on
/// the stack, under the monitor's construction, it would set the stack's
/// peak), the host anything.
// `repr(u8)`: the tag comes first and `Empty` is 0, so an empty store is
// all zeros and a static one goes to .bss, not to .data (whose image
// would take its size in flash).
#[derive(Default)]
#[allow(clippy::large_enum_variant)]
#[repr(u8)]
pub enum ConfigStore<const N: usize> {
    /// No configuration yet.
    #[default]
    Empty,
    /// A configuration.
    Held(MonitorConfig<N>),
}

/// Puts a configuration of `N` placeholder joints (overwritten by the
/// joint frames) and the default tuning in `store`, and returns it. Out of
/// line: the placeholder leaves the stack before the joint frames are read.
#[inline(never)]
fn placeholder_config<const N: usize>(
    store: &mut ConfigStore<N>,
) -> Result<&mut MonitorConfig<N>, Error> {
    let (panel, joint, tuning) = placeholder()?;
    *store = ConfigStore::Held(MonitorConfig {
        panels: [panel; N],
        joints: [joint; N],
        sensor: tuning.sensor,
        observer: tuning.observer,
        latch: tuning.latch,
        margin: tuning.margin,
    });
    match store {
        ConfigStore::Held(config) => Ok(config),
        ConfigStore::Empty => Err(Error::Config),
    }
}

/// A placeholder joint (a spring of `None` always builds) and the default
/// tuning ([`MonitorConfig::new`]'s).
#[inline(never)]
fn placeholder() -> Result<
    (
        crate::physics::chain::Panel<f32>,
        crate::monitor::estimator::JointConfig,
        MonitorConfig<0>,
    ),
    Error,
> {
    let (panel, joint) = JointFrame::default()
        .to_config()
        .map_err(|_| Error::Config)?;
    Ok((panel, joint, MonitorConfig::new([], [])))
}

/// Reads the `N` joint frames that follow the header into `config`, one
/// frame at a time, each joint written in place (with `config` in static
/// memory, only one joint frame is ever on the stack).
pub fn read_config_into<const N: usize, R>(
    header: &ConfigHeader,
    src: &mut Source<R>,
    config: &mut MonitorConfig<N>,
) -> Result<(), Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    read_joints(header, src, config, N)
}

/// Reads the `joints` joint frames that follow the header into the first
/// `joints` panels and joints of `config`, and the header's deadline and
/// latch into its tuning; [`Error::JointCount`] unless the header gives
/// `joints` joints, [`Error::ConfigFrame`] unless `config` has as many.
#[inline(never)]
fn read_joints<const M: usize, R>(
    header: &ConfigHeader,
    src: &mut Source<R>,
    config: &mut MonitorConfig<M>,
    joints: usize,
) -> Result<(), Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    if usize::from(header.joints) != joints {
        return Err(Error::JointCount {
            expected: u8::try_from(joints).unwrap_or(u8::MAX),
            found: header.joints,
        });
    }
    let (Some(panels), Some(frames)) = (
        config.panels.get_mut(..joints),
        config.joints.get_mut(..joints),
    ) else {
        return Err(Error::ConfigFrame);
    };
    for (panel, joint) in panels.iter_mut().zip(frames) {
        read_joint(src, panel, joint)?;
    }
    config.margin.deadline_s = header.deadline_s;
    config.latch.physical = header.latch;
    Ok(())
}

/// Reads one joint frame and writes its panel and joint configuration.
/// Out of line: the frame buffer and the decoded frame are one joint's.
#[inline(never)]
fn read_joint<R>(
    src: &mut Source<R>,
    panel: &mut crate::physics::chain::Panel<f32>,
    joint: &mut crate::monitor::estimator::JointConfig,
) -> Result<(), Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    let mut buf = [0u8; JOINT_FRAME_MAX];
    let frame: JointFrame = match src.next_frame(&mut buf) {
        Ok(Some(f)) => telemetry::decode(f).map_err(|_| Error::ConfigFrame)?,
        Err(FrameError::Read) => return Err(Error::Read),
        _ => return Err(Error::ConfigFrame),
    };
    (*panel, *joint) = frame.to_config().map_err(|_| Error::Config)?;
    Ok(())
}

/// Reads the `N` joint frames that follow the header and returns the
/// monitor configuration (on the caller's stack: the host's way;
/// the firmware uses [`configure`]).
pub fn read_config<const N: usize, R>(
    header: &ConfigHeader,
    src: &mut Source<R>,
) -> Result<MonitorConfig<N>, Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    let (panel, joint) = JointFrame::default()
        .to_config()
        .map_err(|_| Error::Config)?;
    let mut config = MonitorConfig::new([panel; N], [joint; N]);
    read_config_into(header, src, &mut config)?;
    Ok(config)
}

/// The configuration phase of a replay, after [`read_header`]: reads the
/// joint frames into `config` and builds the monitor in `store`;
/// [`Error::JointCount`] when the header's joint count is not `N`. With
/// both stores in static memory the stack holds, in turn, one joint frame,
/// then the monitor's construction — never the configuration or two of
/// them at once.
pub fn configure<const N: usize, R>(
    header: &ConfigHeader,
    src: &mut Source<R>,
    config: &mut ConfigStore<N>,
    store: &mut MonitorStore<N>,
) -> Result<(), Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    if usize::from(header.joints) != N {
        return Err(Error::JointCount {
            expected: u8::try_from(N).unwrap_or(u8::MAX),
            found: header.joints,
        });
    }
    let c = placeholder_config(config)?;
    read_joints(header, src, c, N)?;
    build_from(ConfigRef::of(c), store)
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

/// Where the monitor of `N` joints lives: the firmware gives static
/// storage (a monitor is kilobytes; on the stack it would double the
/// stack's peak), the host anything.
// `repr(u8)`: an empty store is all zeros (.bss), as for [`ConfigStore`].
#[derive(Default)]
#[allow(clippy::large_enum_variant)]
#[repr(u8)]
pub enum MonitorStore<const N: usize> {
    /// No monitor yet.
    #[default]
    Empty,
    /// The monitor.
    Held(Monitor<N>),
}

impl<const N: usize> MonitorStore<N> {
    /// Joints of the monitor held (0 when empty).
    pub fn joints(&self) -> usize {
        match self {
            MonitorStore::Empty => 0,
            MonitorStore::Held(_) => N,
        }
    }

    /// The monitor held.
    pub fn monitor(&mut self) -> Option<&mut Monitor<N>> {
        match self {
            MonitorStore::Empty => None,
            MonitorStore::Held(m) => Some(m),
        }
    }

    /// A store holding a vacant monitor, for [`Monitor::reset`] to
    /// configure in place. Out of line and returned by value: the monitor
    /// is written straight into the returned store, which the caller copies
    /// into its slot once (one monitor on the stack, not the two or three
    /// that building it there takes).
    #[inline(never)]
    fn vacant(config: ConfigRef<'_>) -> Self {
        MonitorStore::Held(Monitor::vacant(config))
    }

    /// The monitor held, or a vacant one put there first.
    fn slot(&mut self, config: ConfigRef<'_>) -> Option<&mut Monitor<N>> {
        if matches!(self, MonitorStore::Empty) {
            *self = Self::vacant(config);
        }
        self.monitor()
    }

    /// Slices of [`Monitor::predict`] after each sample
    /// ([`Monitor::config_slices_per_sample`]); `None` when empty.
    pub fn slices_per_sample(&self) -> Option<u8> {
        match self {
            MonitorStore::Empty => None,
            MonitorStore::Held(m) => Some(m.config_slices_per_sample()),
        }
    }

    /// [`Monitor::update`] on `sample`, inside `meter`'s brackets (the
    /// sample's conversion stays outside them). [`Error::Config`] when the
    /// sample is not of the monitor's joint count or the store is empty.
    pub fn update<M: Meter>(&mut self, sample: &CountedSample, meter: &mut M) -> Result<(), Error> {
        let MonitorStore::Held(m) = self else {
            return Err(Error::Config);
        };
        let s = sample.to_sample().ok_or(Error::Config)?;
        meter.start();
        m.update(&s);
        meter.stop(Work::Update);
        Ok(())
    }

    /// One slice of [`Monitor::predict`], inside `meter`'s brackets;
    /// [`Error::Config`] when the store is empty.
    pub fn predict<M: Meter>(&mut self, meter: &mut M) -> Result<(), Error> {
        let MonitorStore::Held(m) = self else {
            return Err(Error::Config);
        };
        meter.start();
        m.predict();
        meter.stop(Work::Predict);
        Ok(())
    }

    /// The frame of the monitor's current [`Status`](crate::Status) in `out`; its length.
    /// [`Error::Config`] when the store is empty.
    pub fn status_frame(&self, out: &mut [u8]) -> Result<usize, Error> {
        match self {
            MonitorStore::Empty => Err(Error::Config),
            MonitorStore::Held(m) => status_frame(m, out),
        }
    }
}

/// How [`run_paths`] reaches the monitor's two paths. The loop (what runs,
/// in which order, how often) is [`run_paths`]'s alone; an implementation
/// only says *where* each path runs: [`Direct`] calls the monitor in
/// place (the host), the firmware hands each sample to its timer
/// interrupt and runs the prediction slices in its idle loop. Not generic
/// over the joint count: the loop takes it at run time.
pub trait Paths {
    /// Joints of the monitor, which the sample frames carry.
    fn joints(&mut self) -> Result<usize, Error>;
    /// Slices of [`Monitor::predict`] after each sample
    /// ([`Monitor::config_slices_per_sample`]).
    fn slices_per_sample(&mut self) -> Result<u8, Error>;
    /// Runs [`Monitor::update`] on `sample` (the sample-rate path) and
    /// returns once it has.
    fn update(&mut self, sample: &CountedSample) -> Result<(), Error>;
    /// Runs one slice of [`Monitor::predict`] (the low-priority path).
    fn predict(&mut self) -> Result<(), Error>;
    /// Writes the frame of the monitor's current [`Status`](crate::Status) into `out`
    /// ([`telemetry::encode`]) and returns its length.
    fn status_frame(&mut self, out: &mut [u8]) -> Result<usize, Error>;
}

/// Both paths called in place on the monitor in a store the caller holds,
/// each inside `meter`'s brackets.
pub struct Direct<'a, const N: usize, M> {
    /// The monitor.
    pub store: &'a mut MonitorStore<N>,
    /// Its meter.
    pub meter: &'a mut M,
}

impl<const N: usize, M: Meter> Paths for Direct<'_, N, M> {
    fn joints(&mut self) -> Result<usize, Error> {
        Ok(self.store.joints())
    }

    fn slices_per_sample(&mut self) -> Result<u8, Error> {
        self.store.slices_per_sample().ok_or(Error::Config)
    }

    fn update(&mut self, sample: &CountedSample) -> Result<(), Error> {
        self.store.update(sample, self.meter)
    }

    fn predict(&mut self) -> Result<(), Error> {
        self.store.predict(self.meter)
    }

    fn status_frame(&mut self, out: &mut [u8]) -> Result<usize, Error> {
        self.store.status_frame(out)
    }
}

/// The frame of `monitor`'s current status in `out`; its length.
pub fn status_frame<const N: usize>(monitor: &Monitor<N>, out: &mut [u8]) -> Result<usize, Error> {
    StatusView::of(monitor.status())
        .encode(out)
        .map_err(|_| Error::Encode)
}

/// Replays the sample frames left in `src` through the monitor in `store`
/// in place ([`Direct`]): [`run_paths`]'s loop.
pub fn run<const N: usize, R, W, M>(
    store: &mut MonitorStore<N>,
    src: &mut Source<R>,
    write: W,
    meter: &mut M,
) -> Result<u32, Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
    W: FnMut(&[u8]) -> Result<(), ()>,
    M: Meter,
{
    run_paths(&mut Direct { store, meter }, src, write)
}

/// The replay loop: the sample frames left in `src`, through the monitor's
/// two paths as a flight application schedules them —
/// [`Monitor::update`] on every sample (the sample-rate path), then
/// `margin.rollout.slices_per_sample` slices of [`Monitor::predict`] (the
/// idle time before the next sample; fixed, so that the replay is
/// deterministic and the same as the host's
/// [`Monitor::update_and_predict`]). Hands each status frame, as of the end
/// of the slices, to `write`. Returns the number of samples. The one
/// definition of the schedule: the host and the firmware both run it.
#[inline(never)]
pub fn run_paths<R, W, P>(paths: &mut P, src: &mut Source<R>, mut write: W) -> Result<u32, Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
    W: FnMut(&[u8]) -> Result<(), ()>,
    P: Paths,
{
    let mut frame = [0u8; SAMPLE_FRAME_MAX];
    let mut out = [0u8; STATUS_FRAME_MAX];
    let mut index: u32 = 0;
    let joints = paths.joints()?;
    let slices = paths.slices_per_sample()?;
    loop {
        let buf = frame
            .get_mut(..sample_frame_max(joints))
            .ok_or(Error::Config)?;
        let f = match src.next_frame(buf) {
            Ok(Some(f)) => f,
            Ok(None) => break,
            Err(FrameError::Read) => return Err(Error::Read),
            Err(FrameError::Truncated) => return Err(Error::Truncated),
            Err(FrameError::TooLong) => return Err(Error::Frame { index }),
        };
        let sample = CountedSample::decode(f, joints).map_err(|_| Error::Frame { index })?;
        paths.update(&sample)?;
        for _ in 0..slices {
            paths.predict()?;
        }
        let n = paths.status_frame(&mut out)?;
        write(out.get(..n).ok_or(Error::Encode)?).map_err(|_| Error::Write)?;
        index += 1;
    }
    Ok(index)
}

/// The whole replay of an input stream, in place: the configuration frames,
/// then the samples through the monitor of `N` joints built in `store`
/// ([`Direct`]); [`Error::JointCount`] for a header of another count. Returns the joint count and the number of samples.
/// `on_config` is called with the header once it is read. The configuration
/// is built on the stack here (the host's way); the firmware runs the same
/// steps with static stores and its own [`Paths`].
pub fn replay<const N: usize, R, W, M>(
    read: R,
    write: W,
    meter: &mut M,
    store: &mut MonitorStore<N>,
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
    let mut config = ConfigStore::Empty;
    configure(&header, &mut src, &mut config, store)?;
    let n = run(store, &mut src, write, meter)?;
    Ok((header.joints, n))
}

/// [`build_from`] of a whole configuration.
#[cfg(test)]
fn build<const N: usize>(
    config: &MonitorConfig<N>,
    store: &mut MonitorStore<N>,
) -> Result<(), Error> {
    build_from(ConfigRef::of(config), store)
}

/// Builds the monitor of `config` in `store`, in place ([`Monitor::reset`]'s
/// `reset_from` on the store's slot): neither a monitor nor a `Result` of
/// one is ever on the stack, which sets the firmware's stack peak otherwise
/// (`docs/performance.md`).
#[inline(never)]
fn build_from<const N: usize>(
    config: ConfigRef<'_>,
    store: &mut MonitorStore<N>,
) -> Result<(), Error> {
    let monitor = store.slot(config).ok_or(Error::Config)?;
    monitor.reset_from(config).map_err(|_| Error::Config)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::monitor::estimator::Sample;
    use crate::monitor::estimator::{ConfigError, JointParam, TuningParam};
    use crate::ChainError;

    /// A chain of `N` equal panels on linear springs, stowed at 90°, 100°, …
    fn config<const N: usize>() -> MonitorConfig<N> {
        crate::monitor::estimator::example_config()
    }

    /// A deployment at 100 Hz: every joint opens from its stowed angle to
    /// its latch in 1.5 s, then holds with the switch closed.
    fn sample<const N: usize>(config: &MonitorConfig<N>, k: usize) -> Sample<N> {
        let t = k as f32 * 0.01;
        let x = (1.0 - t / 1.5).max(0.0);
        Sample::new(
            t,
            core::array::from_fn(|j| config.joints[j].stowed_deg * x * x),
            [x == 0.0; N],
        )
    }

    /// The status frames of `monitor` over samples `from..to`, two
    /// prediction slices after each.
    fn frames<const N: usize>(
        monitor: &mut Monitor<N>,
        config: &MonitorConfig<N>,
        from: usize,
        to: usize,
    ) -> Vec<u8> {
        let mut all = Vec::new();
        let mut out = [0u8; STATUS_FRAME_MAX];
        for k in from..to {
            monitor.update(&sample(config, k));
            monitor.predict();
            monitor.predict();
            let n = status_frame(monitor, &mut out).expect("status frame");
            all.extend_from_slice(&out[..n]);
        }
        all
    }

    /// The frames of a fresh monitor of `c`, and of one built in `store`
    /// after it held a used monitor (used for `used` samples).
    fn rebuilt<const N: usize>(
        c: &MonitorConfig<N>,
        store: &mut MonitorStore<N>,
        used: usize,
    ) -> (Vec<u8>, Vec<u8>) {
        let fresh = frames(&mut Monitor::new(c).expect("config"), c, 0, 200);
        let m = store.slot(ConfigRef::of(c)).expect("a monitor");
        frames(m, c, 0, used);
        build(c, store).expect("build");
        let m = store.monitor().expect("built");
        (frames(m, c, 0, 200), fresh)
    }

    #[test]
    fn a_monitor_built_in_its_slot_answers_as_a_new_one() {
        // Built in an empty slot, and in one holding a used monitor
        // (used for an odd number of samples: stopped mid-way through the
        // joints' turns), for several joint counts up to the most.
        let c3 = config::<3>();
        let mut store = MonitorStore::<3>::Empty;
        build(&c3, &mut store).expect("build");
        let fresh3 = frames(&mut Monitor::new(&c3).expect("config"), &c3, 0, 200);
        let m = store.monitor().expect("3 joints");
        assert_eq!(m.clone().status().joints.len(), 3);
        assert_eq!(frames(m, &c3, 0, 200), fresh3);
        for used in [137, 91] {
            let (built, fresh) = rebuilt(&c3, &mut store, used);
            assert_eq!(built, fresh);
        }
        let (built, fresh) = rebuilt(&config::<1>(), &mut MonitorStore::Empty, 77);
        assert_eq!(built, fresh);
        let (built, fresh) = rebuilt(&config::<6>(), &mut MonitorStore::Empty, 137);
        assert_eq!(built, fresh);
        let (built, fresh) = rebuilt(&config::<MAX_JOINTS>(), &mut MonitorStore::Empty, 91);
        assert_eq!(built, fresh);
    }

    #[test]
    fn a_configuration_of_another_joint_count_is_refused_by_name() {
        let c2 = config::<2>();
        let mut m = Monitor::new(&c2).expect("config");
        frames(&mut m, &c2, 0, 80);
        let mut before = m.clone();
        assert_eq!(
            m.reset_from(ConfigRef::of(&config::<3>())),
            Err(ConfigError::JointCount {
                expected: 2,
                found: 3
            })
        );
        assert_eq!(
            frames(&mut m, &c2, 80, 200),
            frames(&mut before, &c2, 80, 200)
        );
        // The replay's configuration: a header of 3 joints to a store of 6.
        let header = ConfigHeader {
            version: CONFIG_VERSION,
            joints: 3,
            deadline_s: 20.0,
            latch: None,
        };
        let mut src = Source::new(|_: &mut [u8]| Ok(0));
        let mut config = ConfigStore::<6>::Empty;
        let mut store = MonitorStore::<6>::Empty;
        assert_eq!(
            configure(&header, &mut src, &mut config, &mut store),
            Err(Error::JointCount {
                expected: 6,
                found: 3
            })
        );
        assert_eq!(store.joints(), 0);
    }

    #[test]
    fn a_rejected_configuration_leaves_the_monitor_as_it_was() {
        let c = config::<3>();
        let mut m = Monitor::new(&c).expect("config");
        frames(&mut m, &c, 0, 80);
        let mut before = m.clone();
        let mut bad_panel = c;
        bad_panel.panels[1].mass_kg = 0.0;
        assert_eq!(
            m.reset(&bad_panel),
            Err(ConfigError::Chain(ChainError::BadPanel { index: 1 }))
        );
        let mut bad_joint = c;
        bad_joint.joints[2].prior.coulomb_sd_nm = 0.0;
        assert_eq!(
            m.reset(&bad_joint),
            Err(ConfigError::Joint {
                index: 2,
                what: JointParam::CoulombPriorSd
            })
        );
        let mut bad_tuning = c;
        bad_tuning.sensor.encoder_sd_deg = -1.0;
        assert_eq!(
            m.reset(&bad_tuning),
            Err(ConfigError::Parameter(TuningParam::EncoderSdDeg))
        );
        assert_eq!(
            frames(&mut m, &c, 80, 200),
            frames(&mut before, &c, 80, 200)
        );
    }

    #[test]
    fn reset_reports_what_validate_reports() {
        // A bad joint before a bad tuning parameter, as `validate` orders them.
        let mut c = config::<3>();
        c.joints[1].stowed_deg = f32::NAN;
        c.observer.gate_sigma = 0.0;
        let mut m = Monitor::new(&config::<3>()).expect("config");
        assert_eq!(m.reset(&c).err(), c.validate().err());
        c.joints[1].stowed_deg = 90.0;
        assert_eq!(m.reset(&c).err(), c.validate().err());
        c.observer = config::<3>().observer;
        assert_eq!(m.reset(&c), Ok(()));
    }
}
