//! The live link the firmware serves over a serial line (`deploywatch hil`):
//! the replay's frames ([`super::replay`]) on a byte stream that can lose,
//! corrupt and delay them, with a frame of link counters on request.
//!
//! ```text
//! host → MCU: ConfigHeader ‖ JointFrame × joints ‖ (Sample<N> | 0x00)*
//! MCU → host: LinkReport (ready) ‖ (Status<N> | LinkReport)*
//! ```
//!
//! After the configuration frames the firmware answers with a
//! [`LinkReport`] (all counts 0: the monitor is built, the host may start
//! its clock). Then every sample frame that decodes goes through the
//! sample-rate path at once — `Monitor::update`, then its status frame,
//! written back — and then through the idle time's work, the
//! `margin.rollout.slices_per_sample` slices of `Monitor::predict` (the
//! replay's count, [`run_paths`](super::replay::run_paths), but after the
//! status: a status answers its sample with the sample-rate path's latency,
//! and its learned part — friction, margin, prediction — is as of the
//! previous sample's slices). The schedule is fixed, so the statuses are
//! bit-identical with the host's monitor fed the same samples in the same
//! order ([`reference_statuses`]). A frame that does not decode (COBS, CRC or payload: a
//! corrupted frame) or is longer than a sample's is counted and skipped,
//! and the monitor goes on: a lost sample is a gap in the time stamps, which
//! the monitor's own rules handle (`docs/robustness.md` §1: `time_jitter`,
//! `time_gap`). An empty frame (a `0x00` on its own) asks for a
//! [`LinkReport`] of the counts so far.
//!
//! The loop is the core's, so that the host tests it on streams with
//! injected loss and corruption (`host-sim/tests/hil.rs`) and the firmware
//! only gives it a byte source, a writer and the receive overruns.

use serde::{Deserialize, Serialize};

use super::counted::CountedSample;
use super::replay::{Error, FrameError, Paths, Source, SAMPLE_FRAME_MAX, STATUS_FRAME_MAX};
use super::sample_frame_max;
use crate::monitor::estimator::{Monitor, Sample};

/// First field of a [`LinkReport`]: "DWL1" as a little-endian word. A
/// status frame starts with its time stamp, and these bits as an `f32` are
/// 5.4·10⁷ s: no status is ever read as a report.
pub const LINK_MAGIC: u32 = u32::from_le_bytes(*b"DWL1");

/// Largest [`LinkReport`] frame \[bytes\]: the magic (4) and five varint
/// `u32` (5 each), the CRC, COBS and the `0x00`.
pub const LINK_REPORT_FRAME_MAX: usize = 4 + 5 * 5 + 4 + 2;

/// The link's counts, as the firmware sends them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct LinkReport {
    /// [`LINK_MAGIC`].
    pub magic: u32,
    /// Sample frames that decoded and went through the monitor.
    pub samples: u32,
    /// Frames that did not decode (COBS, CRC or payload): corrupted.
    pub corrupted: u32,
    /// Frames longer than a sample's (skipped to their `0x00`).
    pub too_long: u32,
    /// Bytes lost on reception (the receive queue or the UART full); the
    /// firmware's count, 0 on the host.
    pub overrun: u32,
    /// Empty frames (report requests) seen, this one included.
    pub requests: u32,
}

impl LinkReport {
    /// A report with no counts (the "ready" frame).
    pub const READY: LinkReport = LinkReport {
        magic: LINK_MAGIC,
        samples: 0,
        corrupted: 0,
        too_long: 0,
        overrun: 0,
        requests: 0,
    };
}

/// Writes `report` as one frame into `buf`; its length.
pub fn report_frame(report: &LinkReport, buf: &mut [u8]) -> Result<usize, Error> {
    super::encode(report, buf)
        .map(|f| f.len())
        .map_err(|_| Error::Encode)
}

/// The report in `frame` (decoded in place), if it is one.
pub fn read_report(frame: &mut [u8]) -> Option<LinkReport> {
    super::decode::<LinkReport>(frame)
        .ok()
        .filter(|r| r.magic == LINK_MAGIC)
}

/// Serves the link after the configuration: every sample frame through
/// `paths` (`update`, the status to `write`, then the prediction's slices);
/// bad frames counted in `report` and skipped; a report frame
/// on every empty frame (with `overrun()`, the bytes the receiver lost, in
/// it). Returns at the end of the input (a host that closed the link) or
/// on a read or write failure.
#[inline(never)]
pub fn serve<R, W, P>(
    paths: &mut P,
    src: &mut Source<R>,
    mut write: W,
    report: &mut LinkReport,
    overrun: impl Fn() -> u32,
) -> Result<(), Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
    W: FnMut(&[u8]) -> Result<(), ()>,
    P: Paths,
{
    let joints = paths.joints()?;
    let slices = paths.slices_per_sample()?;
    let mut frame = [0u8; SAMPLE_FRAME_MAX];
    let mut out = [0u8; STATUS_FRAME_MAX];
    let buf = frame
        .get_mut(..sample_frame_max(joints))
        .ok_or(Error::Config)?;
    loop {
        let f = match src.next_frame(buf) {
            Ok(Some(f)) => f,
            Ok(None) | Err(FrameError::Truncated) => return Ok(()),
            Err(FrameError::Read) => return Err(Error::Read),
            Err(FrameError::TooLong) => {
                report.too_long = report.too_long.saturating_add(1);
                continue;
            }
        };
        let n = if f.len() <= 1 {
            report.requests = report.requests.saturating_add(1);
            report.overrun = overrun();
            report_frame(report, &mut out)?
        } else {
            let Ok(sample) = CountedSample::decode(f, joints) else {
                report.corrupted = report.corrupted.saturating_add(1);
                continue;
            };
            paths.update(&sample)?;
            report.samples = report.samples.saturating_add(1);
            let n = paths.status_frame(&mut out)?;
            write(out.get(..n).ok_or(Error::Encode)?).map_err(|_| Error::Write)?;
            // The idle time until the next sample: the prediction.
            for _ in 0..slices {
                paths.predict()?;
            }
            continue;
        };
        write(out.get(..n).ok_or(Error::Encode)?).map_err(|_| Error::Write)?;
    }
}

/// The status frames the link gives for `samples`, computed on the host's
/// monitor in place: `update`, the status, then the slices — the reference
/// a firmware's statuses must equal bit for bit.
pub fn reference_statuses<const N: usize>(
    monitor: &mut Monitor<N>,
    samples: &[Sample<N>],
    mut write: impl FnMut(&[u8]),
) -> Result<(), Error> {
    let mut out = [0u8; STATUS_FRAME_MAX];
    let slices = monitor.config_slices_per_sample();
    for s in samples {
        monitor.update(s);
        let n = super::replay::status_frame(monitor, &mut out)?;
        write(out.get(..n).ok_or(Error::Encode)?);
        for _ in 0..slices {
            monitor.predict();
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_report_round_trips_and_is_never_a_status() {
        let r = LinkReport {
            samples: 70_000,
            corrupted: 3,
            too_long: 1,
            overrun: u32::MAX,
            requests: 2,
            ..LinkReport::READY
        };
        let mut buf = [0u8; LINK_REPORT_FRAME_MAX];
        let n = report_frame(&r, &mut buf).expect("fits");
        assert_eq!(read_report(&mut buf[..n]), Some(r));
        // A status frame is not a report.
        let s = crate::monitor::estimator::Status::<2> {
            t_s: 1.5,
            ..Default::default()
        };
        let mut sbuf = [0u8; 256];
        let f = super::super::encode(&s, &mut sbuf).expect("fits");
        assert_eq!(read_report(f), None);
    }
}
