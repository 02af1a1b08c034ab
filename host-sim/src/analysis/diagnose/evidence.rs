//! What the residuals of a model look like, in numbers and words: which
//! joints, when (phase of the stroke), how they correlate with rate, rate²,
//! angle, distance from the stowed angle and proximity to the latch, and
//! whether they look like a sensor effect (present at rest and after the
//! latch) or a dynamic one (zero at release, growing with the motion).

use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::diagnose::smoothing::third_difference_sigma;
use crate::data::campaign::{Campaign, CampaignRun};
use crate::model::effect::Effect;

/// "Near the latch": within this angle of it \[deg\] (the detent zone is 3°,
/// the tape springs snap within about 1.3°; 5° holds both with room).
pub const NEAR_LATCH_DEG: f64 = 5.0;

/// "At release": the first this many seconds of a run \[s\], before the panel
/// has moved by more than the sensor noise.
pub const RELEASE_WINDOW_S: f64 = 0.05;

/// A residual is "clear" beyond this many noise floors σ̂ \[1\].
pub const CLEAR_SIGMAS: f64 = 3.0;

/// A residual at release that changes by less than this share of itself
/// after the latch is a sensor effect (an offset) \[1\].
pub const SENSOR_CHANGE_SHARE: f64 = 0.25;

/// Correlations weaker than this are not worth a word \[1\] (|r| ≤ 0.3 is
/// "weak" on Cohen's scale).
pub const MIN_CORRELATION: f64 = 0.3;

/// A series gives a noise estimate with at least this many third
/// differences \[1\] ([`noise_sigma_deg`]).
pub const MIN_NOISE_DIFFERENCES: usize = 10;

/// A latch lead or lag shorter than this is within a sample's timing \[s\]
/// (half a sample at 100 Hz).
pub const LATCH_LEAD_S: f64 = 0.005;

/// Residual statistics of one joint in one run (model − measured, deg).
#[derive(Clone, Debug, PartialEq)]
pub struct JointEvidence {
    /// Run file name.
    pub run: String,
    /// 1-based joint.
    pub joint: usize,
    /// RMS over the whole run \[deg\].
    pub rms_deg: f64,
    /// RMS over the first, middle and last third of the stroke, by the
    /// measured angle's distance to the latch (`|φ| > ⅔|φ_s|`, between,
    /// `< ⅓|φ_s|`) \[deg\]; NaN where no sample falls.
    pub stroke_thirds_rms_deg: [f64; 3],
    /// RMS within [`NEAR_LATCH_DEG`] of the latch angle, before the latch \[deg\].
    pub near_latch_rms_deg: f64,
    /// Mean residual after the joint latched in both model and run \[deg\].
    pub after_latch_mean_deg: f64,
    /// Mean residual over the first [`RELEASE_WINDOW_S`] (the panel has hardly moved) \[deg\].
    pub at_release_mean_deg: f64,
    /// Model latch time minus measured latch time \[s\] (None if either never latched).
    pub latch_lead_s: Option<f64>,
    /// Pearson correlation of the residual, before the measured latch, with
    /// rate, rate², angle, distance from stowed, latch proximity.
    pub correlation: [f64; 5],
    /// What the statistics tell (in words by `report::diagnosis_words`).
    pub reading: Reading,
}

/// Names of the correlates, in the order of [`JointEvidence::correlation`].
pub const CORRELATES: [&str; 5] = [
    "rate",
    "rate²",
    "angle",
    "stowed distance",
    "latch proximity",
];

fn rms(x: impl Iterator<Item = f64>) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for v in x {
        s += v * v;
        n += 1;
    }
    if n == 0 {
        f64::NAN
    } else {
        (s / n as f64).sqrt()
    }
}

fn mean(x: impl Iterator<Item = f64>) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for v in x {
        s += v;
        n += 1;
    }
    if n == 0 {
        f64::NAN
    } else {
        s / n as f64
    }
}

fn pearson(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n < 3 {
        return 0.0;
    }
    let ma = a.iter().take(n).sum::<f64>() / n as f64;
    let mb = b.iter().take(n).sum::<f64>() / n as f64;
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (x, y) = (a[i] - ma, b[i] - mb);
        sab += x * y;
        saa += x * x;
        sbb += y * y;
    }
    if saa <= 0.0 || sbb <= 0.0 {
        0.0
    } else {
        sab / (saa * sbb).sqrt()
    }
}

/// Pearson correlations of the residual `r` before sample `end` (the
/// measured latch) with rate, rate², angle, stowed distance and latch
/// proximity ([`CORRELATES`]); rates by central differences.
fn correlations(t: &[f64], meas: &[f64], r: &[f64], end: usize, stowed: f64) -> [f64; 5] {
    let mut regs: [Vec<f64>; 5] = Default::default();
    let mut rr = Vec::new();
    for k in 1..end.saturating_sub(1) {
        let rate = (meas[k + 1] - meas[k - 1]) / (t[k + 1] - t[k - 1]);
        regs[0].push(rate);
        regs[1].push(rate * rate.abs());
        regs[2].push(meas[k]);
        regs[3].push((meas[k] - stowed).abs());
        regs[4].push((-meas[k].abs() / NEAR_LATCH_DEG).exp());
        rr.push(r[k]);
    }
    [0, 1, 2, 3, 4].map(|q| pearson(&rr, &regs[q]))
}

/// The residual evidence of a model (`effects` on the campaign's
/// mechanisms) against every run and joint. `sigma` is the noise floor \[deg\].
pub fn analyse(campaign: &Campaign, effects: &[Effect], sigma: f64) -> Vec<JointEvidence> {
    let mut out = Vec::new();
    for (i, cr) in campaign.runs.iter().enumerate() {
        let Ok(traj) = campaign.simulate(i, effects) else {
            continue;
        };
        let run = &cr.run;
        for j in 0..run.joints() {
            let meas = &run.phi_deg[j];
            let model = &traj.phi_deg[j];
            let r: Vec<f64> = model.iter().zip(meas).map(|(m, y)| m - y).collect();
            let stowed = cr.mechanism.joints[j].stowed_deg.abs();
            let latched_meas = &run.latch[j];
            let end = latched_meas.iter().position(|&l| l).unwrap_or(run.len());
            let frac = |k: usize| meas[k].abs() / stowed.max(1e-9);
            let third = |lo: f64, hi: f64| {
                rms((0..end)
                    .filter(|&k| frac(k) > lo && frac(k) <= hi)
                    .map(|k| r[k]))
            };
            let thirds = [
                third(2.0 / 3.0, f64::INFINITY),
                third(1.0 / 3.0, 2.0 / 3.0),
                third(-1.0, 1.0 / 3.0),
            ];
            let near = rms((0..end)
                .filter(|&k| meas[k].abs() < NEAR_LATCH_DEG)
                .map(|k| r[k]));
            let after = mean(
                (0..run.len())
                    .filter(|&k| latched_meas[k] && traj.latched[j][k])
                    .map(|k| r[k]),
            );
            let release = mean(
                (0..run.len())
                    .filter(|&k| run.t_s[k] <= RELEASE_WINDOW_S)
                    .map(|k| r[k]),
            );
            let latch_meas = latched_meas.iter().position(|&l| l).map(|k| run.t_s[k]);
            let latch_model = traj.latched[j].iter().position(|&l| l).map(|k| traj.t_s[k]);
            let lead = match (latch_model, latch_meas) {
                (Some(a), Some(b)) => Some(a - b),
                _ => None,
            };
            let stowed = cr.mechanism.joints[j].stowed_deg;
            let correlation = correlations(&run.t_s, meas, &r, end, stowed);
            let total = rms(r.iter().copied());
            let reading = let_go_reading(cr, j, &r).unwrap_or_else(|| {
                read(
                    total,
                    &thirds,
                    near,
                    after,
                    release,
                    lead,
                    &correlation,
                    sigma,
                )
            });
            out.push(JointEvidence {
                run: cr.name(),
                joint: j + 1,
                rms_deg: total,
                stroke_thirds_rms_deg: thirds,
                near_latch_rms_deg: near,
                after_latch_mean_deg: after,
                at_release_mean_deg: release,
                latch_lead_s: lead,
                correlation,
                reading,
            });
        }
    }
    out
}

/// [`Reading::LetGo`] of joint `j` of run `cr` with residual `r` \[deg\]
/// where its ideal latch let go ([`crate::data::consistency::let_go`]) and
/// the residual after that holds most of it.
fn let_go_reading(cr: &CampaignRun, j: usize, r: &[f64]) -> Option<Reading> {
    if cr.mechanism.latch(j).is_some() {
        return None;
    }
    let run = &cr.run;
    let g = crate::data::consistency::let_go(run, j).filter(|g| carries_most(r, g.opened))?;
    Some(Reading::LetGo {
        closed_s: run.t_s[g.closed],
        opened_s: run.t_s[g.opened],
        left_deg: g.left_deg,
        after_rms_deg: rms(r[g.opened..].iter().copied()),
    })
}

/// Whether the residual `r` from sample `from` on holds most (more than
/// half) of its sum of squares.
fn carries_most(r: &[f64], from: usize) -> bool {
    let ss = |x: &[f64]| {
        x.iter()
            .filter(|v| v.is_finite())
            .map(|v| v * v)
            .sum::<f64>()
    };
    let tail = ss(r.get(from..).unwrap_or_default());
    tail > 0.5 * ss(r)
}

/// What a joint's residual statistics tell ([`read`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reading {
    /// Its ideal latch let go in the run
    /// ([`crate::data::consistency::let_go`]) and the residual after that
    /// holds most of it: no effect of the model explains it.
    LetGo {
        /// When its switch first closed \[s\].
        closed_s: f64,
        /// When it opened again \[s\].
        opened_s: f64,
        /// How far the reading left the stop after that, at most \[deg\].
        left_deg: f64,
        /// The residual's RMS from the opening on \[deg\].
        after_rms_deg: f64,
    },
    /// The residual is within [`CLEAR_SIGMAS`] of the noise σ̂.
    AtNoise {
        /// The noise σ̂ \[deg\].
        sigma_deg: f64,
    },
    /// Already clear at release and changed by less than
    /// [`SENSOR_CHANGE_SHARE`] after the latch: a sensor effect (offset),
    /// not dynamics.
    Sensor,
    /// A clear residual of the motion.
    Dynamic {
        /// The third of the stroke where it is largest.
        largest: Option<StrokeThird>,
        /// It is clear within [`NEAR_LATCH_DEG`] of the latch too.
        near_latch: bool,
        /// It is zero at release and grows with the motion.
        zero_at_release: bool,
        /// The model latches earlier or later than the run by more than
        /// [`LATCH_LEAD_S`].
        latch: Option<LatchTiming>,
        /// The correlate of [`CORRELATES`] (its index) with the strongest
        /// correlation, when stronger than [`MIN_CORRELATION`].
        correlate: Option<usize>,
    },
}

/// When the model latches against the run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatchTiming {
    /// Early: the model runs ahead.
    Early,
    /// Late: the model lags.
    Late,
}

/// The reading of a joint's residual statistics against the noise σ̂
/// `sigma` \[deg\]: `total` RMS, RMS per third of the stroke, near the
/// latch, mean after the latch and at release \[deg\], the model's latch
/// lead \[s\] and the correlations.
#[allow(clippy::too_many_arguments)]
fn read(
    total: f64,
    thirds: &[f64; 3],
    near: f64,
    after: f64,
    release: f64,
    lead: Option<f64>,
    corr: &[f64; 5],
    sigma: f64,
) -> Reading {
    let clear = CLEAR_SIGMAS * sigma.max(1e-6);
    if !(total > clear) {
        return Reading::AtNoise { sigma_deg: sigma };
    }
    let sensor = release.abs() > clear
        && after.is_finite()
        && (after - release).abs() < SENSOR_CHANGE_SHARE * release.abs();
    if sensor {
        return Reading::Sensor;
    }
    let largest = thirds
        .iter()
        .enumerate()
        .filter(|(_, v)| v.is_finite())
        .max_by(|a, b| a.1.total_cmp(b.1))
        .and_then(|(k, _)| StrokeThird::of_index(k));
    let latch = match lead {
        Some(l) if l < -LATCH_LEAD_S => Some(LatchTiming::Early),
        Some(l) if l > LATCH_LEAD_S => Some(LatchTiming::Late),
        _ => None,
    };
    let correlate = corr
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .filter(|(_, c)| c.abs() > MIN_CORRELATION)
        .map(|(k, _)| k);
    Reading::Dynamic {
        largest,
        near_latch: near.is_finite() && near > clear,
        zero_at_release: release.abs() < clear,
        latch,
        correlate,
    }
}

/// A third of a joint's stroke, from the stowed angle to the latch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StrokeThird {
    /// The first third (near the stowed angle).
    First,
    /// The middle third.
    Middle,
    /// The last third (near the latch).
    Last,
}

impl StrokeThird {
    /// The third of index `k` (0, 1, 2 from the stowed angle); `None`
    /// beyond.
    pub fn of_index(k: usize) -> Option<StrokeThird> {
        [StrokeThird::First, StrokeThird::Middle, StrokeThird::Last]
            .get(k)
            .copied()
    }

    /// Its index: 0, 1, 2 from the stowed angle.
    pub fn index(self) -> usize {
        match self {
            StrokeThird::First => 0,
            StrokeThird::Middle => 1,
            StrokeThird::Last => 2,
        }
    }
}

/// Where a residual is largest: a joint and a third of its stroke, or
/// the run after its latch let go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResidualPlace {
    /// 1-based joint.
    pub joint: usize,
    /// The third of its stroke.
    pub third: StrokeThird,
    /// When its ideal latch let go, where that holds most of its
    /// residual ([`Reading::LetGo`]) \[s\]: the place, over `third`.
    pub let_go_s: Option<f64>,
}

/// Where a residual is largest: the joint with the largest RMS over the
/// runs, and the third of its stroke where that joint's residual is
/// largest.
pub fn locate(evidence: &[JointEvidence]) -> Option<ResidualPlace> {
    let joints = evidence.iter().map(|e| e.joint).max()?;
    let per_joint = |j: usize| evidence.iter().filter(move |e| e.joint == j);
    let worst = (1..=joints).max_by(|&a, &b| {
        let ra = per_joint(a).map(|e| e.rms_deg).fold(0.0, f64::max);
        let rb = per_joint(b).map(|e| e.rms_deg).fold(0.0, f64::max);
        ra.total_cmp(&rb)
    })?;
    let mut thirds = [0.0f64; 3];
    for e in per_joint(worst) {
        for (t, v) in thirds.iter_mut().zip(e.stroke_thirds_rms_deg) {
            if v.is_finite() {
                *t = t.max(v);
            }
        }
    }
    let k = (0..3).max_by(|&a, &b| thirds[a].total_cmp(&thirds[b]))?;
    let let_go_s = per_joint(worst).find_map(|e| match e.reading {
        Reading::LetGo { opened_s, .. } => Some(opened_s),
        _ => None,
    });
    Some(ResidualPlace {
        joint: worst,
        third: StrokeThird::of_index(k)?,
        let_go_s,
    })
}

/// How many times the noise the on-board monitor is configured for
/// (`SensorConfig::encoder_sd_deg`) a run's noise may be before its
/// replay is said to be outside the monitor's tuning: its friction fits
/// are gated at 40 σ² of that noise, and its stall rule reads rates the
/// noise then swamps.
pub const NOISE_ABOVE_MONITOR_FACTOR: f64 = 2.0;

/// A run's encoder noise σ̂ \[deg\] for its replay, from its joints at
/// rest on their stops: [`third_difference_sigma`] of each joint's longest
/// stretch of samples with its switch closed, past its first
/// [`REST_SETTLE_S`] (readings that are noise
/// alone; where a joint moves, its third differences carry `φ⃛ Δt³` too,
/// which doubles σ̂ of a short clean run at 20 Hz), the least over the
/// joints; `None` where no joint rests on its stop for
/// [`MIN_NOISE_DIFFERENCES`] third differences.
pub fn run_noise_sigma(run: &crate::data::run::Run) -> Option<f64> {
    run.phi_deg
        .iter()
        .zip(&run.latch)
        .filter_map(|(phi, latch)| {
            let (start, len) = longest_closed(latch);
            let t0 = *run.t_s.get(start)?;
            let settled = start
                + run.t_s[start..start + len]
                    .iter()
                    .take_while(|&&t| t < t0 + REST_SETTLE_S)
                    .count();
            third_difference_sigma(phi.get(settled..start + len)?, MIN_NOISE_DIFFERENCES)
        })
        .min_by(f64::total_cmp)
}

/// Time after a switch closes that [`run_noise_sigma`] leaves out \[s\]:
/// a physical latch's contact, and a panel on a rig, ring down on the stop
/// within the default `settle_s` of a mechanism (0.2 s).
const REST_SETTLE_S: f64 = 0.2;

/// The start and length of the longest stretch of `true` in `closed`.
fn longest_closed(closed: &[bool]) -> (usize, usize) {
    let (mut best, mut start) = ((0, 0), 0);
    for (i, &c) in closed.iter().enumerate() {
        if !c {
            start = i + 1;
        } else if i + 1 - start > best.1 {
            best = (start, i + 1 - start);
        }
    }
    best
}

/// Estimates the sensor noise σ \[deg\] from the runs alone: the median
/// absolute third difference of each angle series, scaled for white noise
/// (`Var Δ³e = 20 σ²`, MAD → σ by 1.4826); smooth motion contributes only
/// `φ⃛·Δt³`, and latch instants are outliers the median ignores.
pub fn noise_sigma_deg(campaign: &Campaign) -> f64 {
    noise_sigma_estimate(campaign).unwrap_or(0.0)
}

/// [`noise_sigma_deg`], or `None` where no angle series has the
/// [`MIN_NOISE_DIFFERENCES`] third differences it needs (runs of 12
/// samples or fewer: the noise cannot be told from them).
pub fn noise_sigma_estimate(campaign: &Campaign) -> Option<f64> {
    let mut est: Vec<f64> = campaign
        .runs
        .iter()
        .flat_map(|r| &r.run.phi_deg)
        .filter_map(|phi| third_difference_sigma(phi, MIN_NOISE_DIFFERENCES))
        .collect();
    est.sort_by(f64::total_cmp);
    est.get(est.len() / 2).copied()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::run::Run;

    /// One joint at 20 Hz: a cubic swing of 180 deg in 1 s (third
    /// differences of 0.135 deg, above the noise), then `tail` samples at rest on
    /// its stop with the switch closed; a pseudo-random noise of σ ≈ 0.02
    /// deg on every reading.
    fn run(tail: usize) -> Run {
        let n = 20 + tail;
        let mut k: u64 = 11;
        let mut noise = || {
            k = k
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            // A uniform draw on ±0.0346 deg: σ = 0.02.
            ((k >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.0693
        };
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.05).collect();
        let phi = t
            .iter()
            .map(|&t| {
                let s = (1.0 - t).max(0.0);
                -180.0 * s * s * s + noise()
            })
            .collect();
        Run {
            t_s: t,
            phi_deg: vec![phi],
            latch: vec![(0..n).map(|i| i >= 20).collect()],
            ..Run::default()
        }
    }

    #[test]
    fn the_noise_of_a_replay_is_read_at_rest_not_in_the_motion() {
        let sigma = run_noise_sigma(&run(40)).expect("a tail at rest");
        assert!((sigma - 0.02).abs() < 0.008, "σ̂ = {sigma}");
        // The swing's third differences alone read twice the noise: the
        // false warning of a short clean run at 20 Hz.
        let all = third_difference_sigma(&run(0).phi_deg[0], 1).expect("differences");
        assert!(all > 2.0 * 0.02, "{all}");
        // No stretch at rest long enough: nothing said.
        assert_eq!(run_noise_sigma(&run(5)), None);
    }
}
