//! The replay loop: the one schedule of the monitor's two paths
//! ([`run_paths`]), the paths called in place ([`Direct`]), and the whole
//! replay of an input stream ([`replay`]).

use super::configure::{configure, read_header, ConfigStore};
use super::error::Error;
use super::frames::{FrameError, Source, SAMPLE_FRAME_MAX, STATUS_FRAME_MAX};
use super::store::{Meter, MonitorStore};
use crate::telemetry::config::ConfigHeader;
use crate::telemetry::counted::CountedSample;
use crate::telemetry::sample_frame_max;

/// How [`run_paths`] reaches the monitor's two paths. The loop (what runs,
/// in which order, how often) is [`run_paths`]'s alone; an implementation
/// only says *where* each path runs: [`Direct`] calls the monitor in
/// place (the host), the firmware hands each sample to its timer
/// interrupt and runs the prediction slices in its idle loop. Not generic
/// over the joint count: the loop takes it at run time.
pub trait Paths {
    /// Joints of the monitor, which the sample frames carry.
    fn joints(&mut self) -> Result<usize, Error>;
    /// Slices of [`Monitor::learn_or_predict`](crate::monitor::Monitor::learn_or_predict) after each sample
    /// ([`Monitor::config_slices_per_sample`](crate::monitor::Monitor::config_slices_per_sample)).
    fn slices_per_sample(&mut self) -> Result<u8, Error>;
    /// Runs [`Monitor::update`](crate::monitor::Monitor::update) on `sample` (the sample-rate path) and
    /// returns once it has.
    fn update(&mut self, sample: &CountedSample) -> Result<(), Error>;
    /// Runs one slice of [`Monitor::learn_or_predict`](crate::monitor::Monitor::learn_or_predict) (the low-priority path).
    fn learn_or_predict(&mut self) -> Result<(), Error>;
    /// Writes the frame of the monitor's current [`Status`](crate::monitor::Status) into `out`
    /// ([`telemetry::encode`](crate::telemetry::encode)) and returns its length.
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

    fn learn_or_predict(&mut self) -> Result<(), Error> {
        self.store.learn_or_predict(self.meter)
    }

    fn status_frame(&mut self, out: &mut [u8]) -> Result<usize, Error> {
        self.store.status_frame(out)
    }
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
/// [`Monitor::update`](crate::monitor::Monitor::update) on every sample (the sample-rate path), then
/// `margin.rollout.slices_per_sample` slices of [`Monitor::learn_or_predict`](crate::monitor::Monitor::learn_or_predict) (the
/// idle time before the next sample; fixed, so that the replay is
/// deterministic and the same as the host's
/// [`Monitor::replay_step`](crate::monitor::Monitor::replay_step)). Hands each status frame, as of the end
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
            paths.learn_or_predict()?;
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
