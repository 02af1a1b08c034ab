//! Hardware in the loop (`deploywatch hil`): a run streamed to the
//! firmware's serial link in real time, what it may do to the frames on the
//! way (loss, corruption, delay), the host core's statuses for the samples
//! that arrived, and what the statuses that came back say: latency,
//! deadline misses, counts and bit-identity.
//!
//! ```text
//! Mechanism + Run ──plan──> config frames, sample frames (time stamps)
//!       inject (seeded): each sample Sent | Dropped | Corrupted | Delayed
//!       link (hil_link.rs): frames out at their time stamps, statuses back
//!       reference: link::reference_statuses over the delivered samples,
//!                  with the slices the firmware reports it shed
//!       assess: latency, misses, counts, bit-identity
//! ```
//!
//! The protocol is the core's live link
//! ([`deploywatch_core::telemetry::link`]): the firmware answers each
//! sample that decodes with its status at once (`Monitor::update`), then
//! runs the prediction's slices until a frame waits (the rest shed, and
//! said in a shed frame); a frame that does not decode is counted and
//! skipped. The host's reference is the same schedule on the host's `f32`
//! monitor, fed exactly the samples the firmware could decode and the
//! slices it ran, so every status must be bit-identical even when frames
//! were lost or the firmware fell behind.

use std::io::Write;
use std::time::Duration;

use deploywatch_core::monitor::{Monitor, Sample};
use deploywatch_core::telemetry::link::{self, LinkReport, Shed};
use deploywatch_core::telemetry::{self};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::data::run::Run;
use crate::model::mechanism::{with_joints, Mechanism};
use crate::onboard::replay::{
    config_and_samples, config_frames, decode_statuses, ReplayError, StatusRow,
};

/// A run ready to stream: the frames and their time stamps.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Joints.
    pub joints: usize,
    /// The configuration frames (header, joints).
    pub config: Vec<u8>,
    /// One frame per sample, `0x00` included.
    pub samples: Vec<Vec<u8>>,
    /// Each sample's time stamp \[s\].
    pub t_s: Vec<f64>,
    /// The run's sample period: the median step of its time stamps \[s\].
    pub period_s: f64,
}

/// What the host does to the sample frames on their way out.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Inject {
    /// Probability that a frame is not sent at all.
    pub drop: f64,
    /// Probability that one byte of a frame (not its `0x00`) is changed
    /// into another non-zero byte: the frame fails its CRC or its COBS,
    /// and the frames around it are untouched.
    pub corrupt: f64,
    /// Probability that a frame leaves late by [`Inject::delay_s`].
    pub delay: f64,
    /// The lateness of a delayed frame \[s\] (the frames after it wait).
    pub delay_s: f64,
    /// Seed of the choices.
    pub seed: u64,
}

/// What happened to one sample frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fate {
    /// Sent as it is, on time.
    Sent,
    /// Not sent.
    Dropped,
    /// Sent with one byte changed.
    Corrupted,
    /// Sent late.
    Delayed,
}

impl Fate {
    /// True when the firmware gets the sample (and answers it).
    pub fn delivered(self) -> bool {
        matches!(self, Fate::Sent | Fate::Delayed)
    }
}

/// The frames as they go out: the bytes (empty when dropped), when
/// (seconds after the first sample's send time), and the fate of each.
#[derive(Clone, Debug)]
pub struct Outgoing {
    /// Bytes of each frame as sent (empty: dropped).
    pub bytes: Vec<Vec<u8>>,
    /// Send time of each, from the stream's start \[s\].
    pub at_s: Vec<f64>,
    /// Fate of each.
    pub fate: Vec<Fate>,
}

impl Outgoing {
    /// Frames of a fate.
    pub fn count(&self, fate: Fate) -> usize {
        self.fate.iter().filter(|f| **f == fate).count()
    }
}

fn plan_n<const N: usize>(mech: &Mechanism, run: &Run) -> Result<Plan, ReplayError> {
    let (config, s) = config_and_samples::<N>(mech, run)?;
    let mut frames = Vec::with_capacity(s.len());
    let mut buf = [0u8; 256];
    for (i, x) in s.iter().enumerate() {
        let f = telemetry::encode(x, &mut buf)
            .map_err(|e| ReplayError::Input(format!("sample {i}: {e}")))?;
        frames.push(f.to_vec());
    }
    Ok(Plan {
        joints: N,
        config: config_frames::<N>(mech, &config)?,
        samples: frames,
        t_s: run.t_s.clone(),
        period_s: median_step(&run.t_s),
    })
}

/// The median of the steps of `t` \[s\] (0 for fewer than two).
pub fn median_step(t: &[f64]) -> f64 {
    let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    steps.get(steps.len() / 2).copied().unwrap_or(0.0)
}

/// The frames of `run` on `mech` (1 to 4 joints on the host; the firmware
/// takes 2 and 3).
pub fn plan(mech: &Mechanism, run: &Run) -> Result<Plan, ReplayError> {
    let n = crate::onboard::replay::run_of(mech, run)?;
    with_joints!(n, N => plan_n::<N>(mech, run), else Err(ReplayError::Input(format!(
        "{}: {n} joints; the monitor is built for 1 to 4",
        mech.name
    ))))
}

/// Applies `inject` to the plan's frames (seeded: the same seed, the same
/// choices). Send times are the time stamps from the first, plus the
/// accumulated delays.
pub fn inject(plan: &Plan, inject: &Inject) -> Outgoing {
    let mut rng = ChaCha8Rng::seed_from_u64(inject.seed);
    let t0 = plan.t_s.first().copied().unwrap_or(0.0);
    let mut late = 0.0;
    let mut out = Outgoing {
        bytes: Vec::with_capacity(plan.samples.len()),
        at_s: Vec::with_capacity(plan.samples.len()),
        fate: Vec::with_capacity(plan.samples.len()),
    };
    for (frame, t) in plan.samples.iter().zip(&plan.t_s) {
        // One draw of each kind per frame, so that a rate's choices do not
        // depend on the other rates.
        let (d, c, l) = (rng.gen::<f64>(), rng.gen::<f64>(), rng.gen::<f64>());
        let pos = rng.gen_range(0..frame.len().saturating_sub(1).max(1));
        let value = rng.gen_range(1..=255u8);
        let (fate, bytes) = if d < inject.drop {
            (Fate::Dropped, Vec::new())
        } else if c < inject.corrupt {
            (Fate::Corrupted, corrupt(frame, pos, value))
        } else if l < inject.delay {
            late += inject.delay_s;
            (Fate::Delayed, frame.clone())
        } else {
            (Fate::Sent, frame.clone())
        };
        out.bytes.push(bytes);
        out.at_s.push(t - t0 + late);
        out.fate.push(fate);
    }
    out
}

/// `frame` with byte `pos` (not the final `0x00`) replaced by `value`
/// (non-zero: a `0x00` would split the frame in two), or by the next
/// non-zero byte when it already holds `value`.
fn corrupt(frame: &[u8], pos: usize, value: u8) -> Vec<u8> {
    let mut f = frame.to_vec();
    let body = f.len().saturating_sub(1);
    if let Some(b) = f.get_mut(pos.min(body.saturating_sub(1))) {
        *b = if *b == value {
            value.wrapping_add(1).max(1)
        } else {
            value
        };
    }
    f
}

fn reference_n<const N: usize>(
    mech: &Mechanism,
    run: &Run,
    keep: &[bool],
    sheds: &[Shed],
) -> Result<Vec<Vec<u8>>, ReplayError> {
    let (config, all) = config_and_samples::<N>(mech, run)?;
    let s: Vec<Sample<N>> = all
        .into_iter()
        .zip(keep)
        .filter_map(|(s, k)| k.then_some(s))
        .collect();
    let mut monitor =
        Monitor::new(&config).map_err(|e| ReplayError::Input(format!("{}: {e}", mech.name)))?;
    let mut frames = Vec::with_capacity(s.len());
    let slices = link::slices_after(sheds, monitor.config_slices_per_sample());
    link::reference_statuses(&mut monitor, &s, slices, |f| frames.push(f.to_vec()))
        .map_err(|e| ReplayError::Input(format!("the host's statuses: {e}")))?;
    Ok(frames)
}

/// The host core's status frames for the samples of `run` where `keep` is
/// true, in the link's schedule (`update`, status, slices), the slices
/// after a sample those `sheds` report for it (none shed: every sample's
/// configured slices, the schedule of a firmware that keeps up).
pub fn reference(
    mech: &Mechanism,
    run: &Run,
    keep: &[bool],
    sheds: &[Shed],
) -> Result<Vec<Vec<u8>>, ReplayError> {
    let n = mech.joint_count();
    with_joints!(n, N => reference_n::<N>(mech, run, keep, sheds), else Err(ReplayError::Input(format!(
        "{}: {n} joints", mech.name
    ))))
}

/// What came back over the link.
#[derive(Clone, Debug, Default)]
pub struct Received {
    /// Every frame that is neither a link report nor a shed frame, in
    /// order, with the time it arrived after the stream's start.
    pub statuses: Vec<(Vec<u8>, Duration)>,
    /// The shed frames: the samples after which the firmware ran fewer
    /// slices than configured, a frame waiting.
    pub sheds: Vec<Shed>,
    /// The last link report (asked for after the stream).
    pub report: Option<LinkReport>,
    /// When each frame was written, after the stream's start (`None`:
    /// dropped).
    pub sent: Vec<Option<Duration>>,
}

/// The verdict on a streamed run.
#[derive(Clone, Debug)]
pub struct Assessment {
    /// Latency of each answered sample (sample sent → status received) \[s\].
    pub latency_s: Vec<f64>,
    /// Statuses later than one period after their sample.
    pub misses: usize,
    /// Frames back that decode neither as a status nor as a report.
    pub corrupted_back: usize,
    /// Delivered samples without a status back.
    pub lost_back: usize,
    /// Statuses equal to the host's, bit for bit, of those compared.
    pub identical: usize,
    /// The first status that differs (index of the delivered sample).
    pub first_difference: Option<usize>,
    /// The statuses that came back, decoded.
    pub rows: Vec<StatusRow>,
}

/// Compares what came back with the host's `reference` (one frame per
/// delivered sample) and times it against the send times.
pub fn assess(plan: &Plan, out: &Outgoing, got: &Received, reference: &[Vec<u8>]) -> Assessment {
    let sent: Vec<Duration> = out
        .fate
        .iter()
        .zip(&got.sent)
        .filter(|(f, _)| f.delivered())
        .filter_map(|(_, s)| *s)
        .collect();
    let mut a = Assessment {
        latency_s: Vec::new(),
        misses: 0,
        corrupted_back: 0,
        lost_back: 0,
        identical: 0,
        first_difference: None,
        rows: Vec::new(),
    };
    let mut k = 0;
    for (frame, at) in &got.statuses {
        let Ok(mut row) = decode_statuses(frame, plan.joints) else {
            a.corrupted_back += 1;
            continue;
        };
        if let (Some(r), Some(s)) = (reference.get(k), sent.get(k)) {
            if r == frame {
                a.identical += 1;
            } else if a.first_difference.is_none() {
                a.first_difference = Some(k);
            }
            let l = at.saturating_sub(*s).as_secs_f64();
            a.latency_s.push(l);
            if l > plan.period_s {
                a.misses += 1;
            }
        }
        a.rows.append(&mut row);
        k += 1;
    }
    a.lost_back = reference.len().saturating_sub(k);
    a
}

/// One row per sample: `t_s`, `fate` (`sent`, `dropped`, `corrupted`,
/// `delayed`), `sent_ms` (from the stream's start; empty when dropped),
/// `latency_ms` (sample sent → status received; empty without a status).
pub fn write_latency_csv<W: std::io::Write>(
    w: W,
    plan: &Plan,
    out: &Outgoing,
    got: &Received,
    a: &Assessment,
) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(w);
    writeln!(w, "t_s,fate,sent_ms,latency_ms")?;
    let mut k = 0;
    for (i, fate) in out.fate.iter().enumerate() {
        let name = match fate {
            Fate::Sent => "sent",
            Fate::Dropped => "dropped",
            Fate::Corrupted => "corrupted",
            Fate::Delayed => "delayed",
        };
        let sent = got.sent.get(i).copied().flatten();
        let latency = if fate.delivered() {
            k += 1;
            a.latency_s.get(k - 1).copied()
        } else {
            None
        };
        let ms = |x: Option<f64>| x.map_or(String::new(), |v| format!("{:.3}", v * 1e3));
        writeln!(
            w,
            "{},{name},{},{}",
            plan.t_s.get(i).copied().unwrap_or(f64::NAN),
            ms(sent.map(|d| d.as_secs_f64())),
            ms(latency)
        )?;
    }
    w.flush()
}

/// The `q`-quantile of `x` (nearest rank), `NaN` when empty.
pub fn quantile(x: &[f64], q: f64) -> f64 {
    let mut v = x.to_vec();
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return f64::NAN;
    }
    let i = ((q * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1;
    v[i]
}

/// What a lossy stream did to the monitor, judged against the host's
/// statuses of the whole run (`full`): a joint `latched` earlier than in
/// the whole run, or latched where the whole run never is (a false latch),
/// and the fault flags the lossy statuses raise that the whole run's never
/// do (joint, flag name).
pub fn against_full(full: &[StatusRow], lossy: &[StatusRow]) -> (Vec<usize>, Vec<(usize, String)>) {
    use deploywatch_core::monitor::LatchState;
    let joints = full.first().map_or(0, |s| s.joints.len());
    let first_latched = |rows: &[StatusRow], j: usize| {
        rows.iter()
            .find(|r| r.joints[j].latch == LatchState::Latched)
            .map(|r| r.t_s)
    };
    let mut false_latch = Vec::new();
    let mut extra = Vec::new();
    for j in 0..joints {
        match (first_latched(full, j), first_latched(lossy, j)) {
            (None, Some(_)) => false_latch.push(j + 1),
            (Some(a), Some(b)) if b < a => false_latch.push(j + 1),
            _ => {}
        }
        let seen: std::collections::BTreeSet<&str> = full
            .iter()
            .flat_map(|r| r.joints[j].faults.iter().map(|f| f.as_str()))
            .collect();
        let mut new: Vec<String> = lossy
            .iter()
            .flat_map(|r| r.joints[j].faults.iter().map(|f| f.as_str()))
            .filter(|f| !seen.contains(f))
            .map(str::to_string)
            .collect();
        new.sort();
        new.dedup();
        extra.extend(new.into_iter().map(|f| (j + 1, f)));
    }
    (false_latch, extra)
}
