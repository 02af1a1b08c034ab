//! Where the monitor lives and how it is metered: the [`MonitorStore`]
//! (static memory on the firmware), the [`Meter`] around each call of its
//! two paths, the monitor built in place, and its status as a frame.

use super::error::Error;
use crate::monitor::config::ConfigRef;
use crate::monitor::Monitor;
#[cfg(test)]
use crate::monitor::MonitorConfig;
use crate::telemetry::counted::{CountedSample, StatusView};

/// The two kinds of work [`run`](super::run) does, each metered on its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Work {
    /// [`Monitor::update`]: the sample-rate path.
    Update,
    /// One slice of [`Monitor::learn_or_predict`]: the low-priority prediction.
    LearnOrPredict,
}

/// Brackets every [`Monitor::update`] and [`Monitor::learn_or_predict`] call of
/// [`run`](super::run): the firmware counts the instructions each takes; `()` does
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

    /// Slices of [`Monitor::learn_or_predict`] after each sample
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

    /// One slice of [`Monitor::learn_or_predict`], inside `meter`'s brackets;
    /// [`Error::Config`] when the store is empty.
    pub fn learn_or_predict<M: Meter>(&mut self, meter: &mut M) -> Result<(), Error> {
        let MonitorStore::Held(m) = self else {
            return Err(Error::Config);
        };
        meter.start();
        m.learn_or_predict();
        meter.stop(Work::LearnOrPredict);
        Ok(())
    }

    /// The frame of the monitor's current [`Status`](crate::monitor::Status) in `out`; its length.
    /// [`Error::Config`] when the store is empty.
    pub fn status_frame(&self, out: &mut [u8]) -> Result<usize, Error> {
        match self {
            MonitorStore::Empty => Err(Error::Config),
            MonitorStore::Held(m) => status_frame(m, out),
        }
    }
}

/// The frame of `monitor`'s current status in `out`; its length.
pub fn status_frame<const N: usize>(monitor: &Monitor<N>, out: &mut [u8]) -> Result<usize, Error> {
    StatusView::of(monitor.status())
        .encode(out)
        .map_err(|_| Error::Encode)
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
pub(super) fn build_from<const N: usize>(
    config: ConfigRef<'_>,
    store: &mut MonitorStore<N>,
) -> Result<(), Error> {
    let monitor = store.slot(config).ok_or(Error::Config)?;
    monitor.reset_from(config).map_err(|_| Error::Config)
}

#[cfg(test)]
mod tests;
