//! The live link the firmware serves over a serial line (`deploywatch hil`):
//! the replay's frames ([`super::replay`]) on a byte stream that can lose,
//! corrupt and delay them, with a frame of link counters on request.
//!
//! ```text
//! host → MCU: ConfigHeader ‖ JointFrame × joints ‖ (Sample<N> | 0x00)*
//! MCU → host: LinkReport (ready) ‖ (Status<N> [Shed] | LinkReport)*
//! ```
//!
//! After the configuration frames the firmware answers with a
//! [`LinkReport`] (all counts 0: the monitor is built, the host may start
//! its clock). Then every sample frame that decodes goes through the
//! sample-rate path at once — `Monitor::update`, then its status frame,
//! written back — and then through the idle time's work, up to
//! `margin.rollout.slices_per_sample` slices of `Monitor::learn_or_predict` (the
//! replay's count, [`run_paths`](super::replay::run_paths), but after the
//! status: a status answers its sample with the sample-rate path's latency,
//! and its learned part — friction, margin, prediction — is as of the
//! previous sample's slices). The idle work yields to the next frame: when
//! bytes are waiting before a slice (the source's own buffer, or the
//! receiver's `pending()`), the rest of the slices is shed, a [`Shed`]
//! frame says after which sample and how many ran, and the sample is
//! served at once; the prediction goes on with the next sample's slices.
//! A sample path that keeps its period is never starved by the prediction,
//! on a slow emulator or a loaded board. The schedule is fixed but for the
//! shed slices, which the link reports, so the statuses are bit-identical
//! with the host's monitor fed the same samples in the same order and the
//! same slices ([`reference_statuses`]). A frame that does not decode (COBS,
//! CRC or payload: a corrupted frame) or is longer than a sample's is
//! counted and skipped, and the monitor goes on: a lost sample is a gap in
//! the time stamps, which the monitor's own rules handle
//! (`docs/robustness.md` §1: `time_jitter`, `time_gap`). An empty frame (a
//! `0x00` on its own) asks for a [`LinkReport`] of the counts so far.
//!
//! The loop is the core's, so that the host tests it on streams with
//! injected loss, corruption and bursts (`host-sim/tests/hil.rs`) and the
//! firmware only gives it a byte source, a writer, the receive overruns
//! and whether bytes are waiting.

use serde::{Deserialize, Serialize};

use super::counted::CountedSample;
use super::replay::{Error, FrameError, Paths, Source, SAMPLE_FRAME_MAX, STATUS_FRAME_MAX};
use super::sample_frame_max;
use crate::monitor::{Monitor, Sample};

/// First field of a [`LinkReport`]: "DWL1" as a little-endian word. A
/// status frame starts with its time stamp, and these bits as an `f32` are
/// 5.4·10⁷ s: no status is ever read as a report.
pub const LINK_MAGIC: u32 = u32::from_le_bytes(*b"DWL1");

/// First field of a [`Shed`] frame: "DWS1" as a little-endian word (never
/// a status, as [`LINK_MAGIC`]).
pub const SHED_MAGIC: u32 = u32::from_le_bytes(*b"DWS1");

/// Largest [`LinkReport`] frame \[bytes\]: the magic and six counts, each
/// a varint `u32` of up to 5 bytes, the CRC (4), COBS (1) and the `0x00`.
pub const LINK_REPORT_FRAME_MAX: usize = 7 * 5 + 4 + 2;

/// Largest [`Shed`] frame \[bytes\]: three varint `u32`, the CRC, COBS and
/// the `0x00`.
pub const SHED_FRAME_MAX: usize = 3 * 5 + 4 + 2;

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
    /// Samples whose idle work was cut short by a waiting frame (a
    /// [`Shed`] frame each).
    pub shed: u32,
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
        shed: 0,
    };
}

/// The idle work of one sample cut short: after the `sample`-th sample
/// frame used (counted from 1, the report's `samples` then) only `slices`
/// slices of `Monitor::learn_or_predict` ran, fewer than the configuration's, for a
/// frame was waiting. Sent after that sample's status.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shed {
    /// [`SHED_MAGIC`].
    pub magic: u32,
    /// The sample frames used up to and including this one.
    pub sample: u32,
    /// Slices run after it.
    pub slices: u32,
}

/// The shed frame in `frame` (decoded in place), if it is one.
pub fn read_shed(frame: &mut [u8]) -> Option<Shed> {
    super::decode::<Shed>(frame)
        .ok()
        .filter(|r| r.magic == SHED_MAGIC)
}

/// The slices run after each used sample (0-based), given the shed frames
/// of a link in the order they came (their samples rising, as the link
/// sends them) and the configuration's `slices` a sample: the schedule
/// [`reference_statuses`] follows. A binary search a sample, so that a long
/// run shed after every sample stays `O(n log n)`.
pub fn slices_after(sheds: &[Shed], slices: u8) -> impl Fn(usize) -> u8 + '_ {
    move |k| {
        sheds
            .binary_search_by_key(&(k as u64 + 1), |s| u64::from(s.sample))
            .ok()
            .and_then(|i| sheds.get(i))
            .map_or(slices, |s| {
                u8::try_from(s.slices).unwrap_or(slices).min(slices)
            })
    }
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
/// `paths` (`update`, the status to `write`, then the prediction's slices
/// until a frame waits: `pending()`, bytes the receiver holds that the
/// source has not read, or bytes in the source's own buffer; a [`Shed`]
/// frame when slices were left); bad frames counted in `report` and
/// skipped; a report frame on every empty frame (with `overrun()`, the
/// bytes the receiver lost, in it). Returns at the end of the input (a
/// host that closed the link) or on a read or write failure.
#[inline(never)]
pub fn serve<R, W, P>(
    paths: &mut P,
    src: &mut Source<R>,
    mut write: W,
    report: &mut LinkReport,
    overrun: impl Fn() -> u32,
    pending: impl Fn() -> bool,
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
            // The idle time until the next frame: the prediction.
            let mut ran = 0;
            while ran < slices && src.buffered() == 0 && !pending() {
                paths.learn_or_predict()?;
                ran += 1;
            }
            if ran == slices {
                continue;
            }
            report.shed = report.shed.saturating_add(1);
            let shed = Shed {
                magic: SHED_MAGIC,
                sample: report.samples,
                slices: u32::from(ran),
            };
            super::encode(&shed, &mut out)
                .map(|f| f.len())
                .map_err(|_| Error::Encode)?
        };
        write(out.get(..n).ok_or(Error::Encode)?).map_err(|_| Error::Write)?;
    }
}

/// The status frames the link gives for `samples`, computed on the host's
/// monitor in place: `update`, the status, then `slices(k)` slices after
/// the `k`-th sample (0-based; [`slices_after`] of the link's [`Shed`]
/// frames, or the configuration's count when none was shed) — the
/// reference a firmware's statuses must equal bit for bit.
pub fn reference_statuses<const N: usize>(
    monitor: &mut Monitor<N>,
    samples: &[Sample<N>],
    slices: impl Fn(usize) -> u8,
    mut write: impl FnMut(&[u8]),
) -> Result<(), Error> {
    let mut out = [0u8; STATUS_FRAME_MAX];
    for (k, s) in samples.iter().enumerate() {
        monitor.update(s);
        let n = super::replay::status_frame(monitor, &mut out)?;
        write(out.get(..n).ok_or(Error::Encode)?);
        for _ in 0..slices(k) {
            monitor.learn_or_predict();
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
        // A status frame is neither a report nor a shed frame.
        let s = crate::monitor::Status::<2> {
            t_s: 1.5,
            ..Default::default()
        };
        let mut sbuf = [0u8; 256];
        let f = super::super::encode(&s, &mut sbuf).expect("fits");
        let mut copy = [0u8; 256];
        copy[..f.len()].copy_from_slice(f);
        let len = f.len();
        assert_eq!(read_report(f), None);
        assert_eq!(read_shed(&mut copy[..len]), None);
    }

    #[test]
    fn the_largest_report_and_shed_fit_their_bounds() {
        let r = LinkReport {
            magic: LINK_MAGIC,
            samples: u32::MAX,
            corrupted: u32::MAX,
            too_long: u32::MAX,
            overrun: u32::MAX,
            requests: u32::MAX,
            shed: u32::MAX,
        };
        let mut buf = [0u8; LINK_REPORT_FRAME_MAX];
        let n = report_frame(&r, &mut buf).expect("the largest report fits");
        assert_eq!(read_report(&mut buf[..n]), Some(r));
        let shed = Shed {
            magic: SHED_MAGIC,
            sample: u32::MAX,
            slices: u32::MAX,
        };
        let mut buf = [0u8; SHED_FRAME_MAX];
        let n = super::super::encode(&shed, &mut buf)
            .expect("the largest shed frame fits")
            .len();
        let mut copy = buf;
        assert_eq!(read_shed(&mut buf[..n]), Some(shed));
        assert_eq!(
            read_report(&mut copy[..n]),
            None,
            "a shed frame is no report"
        );
    }

    #[test]
    fn the_schedule_follows_the_shed_frames() {
        let sheds = [
            Shed {
                magic: SHED_MAGIC,
                sample: 2,
                slices: 0,
            },
            Shed {
                magic: SHED_MAGIC,
                sample: 5,
                slices: 9,
            },
        ];
        let f = slices_after(&sheds, 17);
        let got: [u8; 6] = core::array::from_fn(&f);
        assert_eq!(got, [17, 0, 17, 17, 9, 17]);
        // A count beyond the configuration's is not believed.
        let odd = [Shed {
            magic: SHED_MAGIC,
            sample: 1,
            slices: 300,
        }];
        assert_eq!(slices_after(&odd, 17)(0), 17);
    }
}
