//! The torque the model lacks, from the data itself.
//!
//! Each run is simulated with the model, and the measured angles' difference
//! from it is smoothed ([`crate::analysis::diagnose::smoothing`]: a local cubic, its
//! window chosen by GCV) into `φ, φ̇, φ̈` (the model's, exact, plus the
//! smoothed difference's) with standard errors, segment by segment between
//! the latch instants of run and model (a latch is an impact: the free
//! joints' rates jump). Smoothing the difference, not the angle, keeps the
//! smoother's bias small where the motion changes fast (near the latches of
//! a whipping wing) and lets GCV choose wide windows where the model is
//! close. The core's chain equations, solved
//! for the torque ([`deploywatch_core::Chain::missing_torque`]), then give at
//! every sample the joint torque the model (springs, friction, the effects
//! found so far) lacks:
//!
//! ```text
//! τ_res = M(φ) φ̈ − (τ_model(φ, φ̇) + Sᵀ(Q_ext − C))           [N·m]
//! ```
//!
//! with a band from the smoother's standard errors. Samples within a window
//! of the release, of a latch instant, within [`LATCH_GUARD_DEG`] of the
//! latch angle, and after the joint latched are left out. Each joint's
//! residual torque is then localised: whether it is significant against its
//! own band ([`JointTorque::significant`]), where in the stroke and at which
//! rates.

use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::diagnose::evidence::StrokeThird;
use crate::analysis::diagnose::smoothing::{noise_sigma, smooth_segment, CubicWeights, Smoothed};
use crate::data::campaign::Campaign;
use crate::model::effect::{self, Effect};
use crate::model::mechanism::{with_joints, Mechanism};
use crate::model::torque_table::HostChain;
use crate::simulate::deployment::Trajectory;
use deploywatch_core::{Branch, ChainState, Mode};
use rayon::prelude::*;

/// Samples within this angle of the latch \[deg\] are left out: the tape
/// springs' snap-through (within about 1.3°) and the detent zone (3°) make
/// the torque change faster than any window resolves.
pub const LATCH_GUARD_DEG: f64 = 2.0;

/// Bins over a joint's stroke (and over its rates) in which the residual
/// torque is averaged and tested (each a twelfth of the range).
pub const BINS: usize = 12;

/// A joint's residual torque is significant when the χ² of its bin means
/// against their bands exceeds the bins' count by this many standard
/// deviations of χ² (`√(2·bins)`): χ² > 29 for 12 bins, a 1-in-250 false
/// alarm for independent Gaussian bins.
pub const SIGNIFICANCE_SD: f64 = 3.5;

/// And when its largest bin mean exceeds this many standard errors (one
/// feature must stand out, not only the sum of many small ones).
pub const BIN_Z: f64 = 3.0;

/// A bin mean this many standard errors from zero is "clear of its band"
/// when a residual torque is described in words.
pub const CLEAR_BIN_Z: f64 = 2.0;

/// One sample of a joint's residual torque.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorqueSample {
    /// Index of the run in the campaign.
    pub run: usize,
    /// Index of the sample in the run.
    pub index: usize,
    /// Time \[s\].
    pub t_s: f64,
    /// Smoothed angle \[deg\].
    pub phi_deg: f64,
    /// Smoothed rate [deg/s].
    pub rate_deg_s: f64,
    /// The torque the model lacks [N·m] (positive increases `φ`).
    pub torque_nm: f64,
    /// Its standard error [N·m].
    pub se_nm: f64,
    /// The hinge spring's torque at the sample [N·m] (before any
    /// softening): what a softened spring's missing torque is a share of.
    pub spring_nm: f64,
    /// The angle from the stowed angle, `φ_stowed − φ` \[rad\]: what a
    /// harness's torque is proportional to.
    pub from_stowed_rad: f64,
    /// Half-width of the smoothing window at this sample \[samples\]: about
    /// the distance over which neighbouring samples' errors correlate.
    pub window: usize,
}

/// A synthetic stroke for the tests of the evidence modules: `n` samples
/// from 180° to 0° in 1 s, the rate a half sine peaking at `peak_deg_s`
/// (negative: closing), the torque `f(φ, φ̇)` with standard error `se_nm`
/// and smoothing half-width `window`.
#[cfg(test)]
pub(crate) fn synthetic_stroke(
    n: usize,
    peak_deg_s: f64,
    se_nm: f64,
    window: usize,
    f: impl Fn(f64, f64) -> f64,
) -> Vec<TorqueSample> {
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let phi = 180.0 * (1.0 - t);
            let rate = -peak_deg_s * (std::f64::consts::PI * t).sin();
            TorqueSample {
                run: 0,
                index: i,
                t_s: t,
                phi_deg: phi,
                rate_deg_s: rate,
                torque_nm: f(phi, rate),
                se_nm,
                spring_nm: 0.0,
                from_stowed_rad: 0.0,
                window,
            }
        })
        .collect()
}

/// The residual torque averaged over one bin of angle or rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bin {
    /// Lower and upper edge [deg or deg/s].
    pub range: [f64; 2],
    /// Samples in it.
    pub n: usize,
    /// Mean residual torque [N·m].
    pub mean_nm: f64,
    /// Its standard error [N·m], the correlation of neighbouring samples'
    /// errors counted.
    pub se_nm: f64,
}

/// The residual torque of one joint, all runs pooled, and where it lies.
#[derive(Clone, Debug, PartialEq)]
pub struct JointTorque {
    /// 1-based joint.
    pub joint: usize,
    /// The stowed angle of the first run's mechanism \[deg\] (the stroke runs
    /// from it to 0).
    pub stowed_deg: f64,
    /// Every sample kept.
    pub samples: Vec<TorqueSample>,
    /// Means over [`BINS`] bins of the angle the samples cover.
    pub by_angle: Vec<Bin>,
    /// Means over [`BINS`] bins of the rate the samples cover.
    pub by_rate: Vec<Bin>,
    /// `Σ (mean/se)²` over the angle bins.
    pub chi2: f64,
    /// The largest `|mean|/se` of a bin.
    pub max_z: f64,
    /// Whether the joint's residual torque is significant (χ² above
    /// [`SIGNIFICANCE_SD`] and a bin beyond [`BIN_Z`]).
    pub significant: bool,
    /// RMS of the bin means [N·m]: the size of the missing torque.
    pub rms_nm: f64,
}

impl JointTorque {
    /// The angle bin where the residual torque is largest: the largest
    /// mean among the bins clear of their band (else the clearest), since
    /// a bin of a few noisy samples says little.
    pub fn largest_bin(&self) -> Option<&Bin> {
        let used = self.by_angle.iter().filter(|b| b.n > 0);
        let z = |b: &Bin| b.mean_nm.abs() / b.se_nm.max(1e-12);
        let clear = used
            .clone()
            .filter(|b| z(b) >= CLEAR_BIN_Z)
            .max_by(|a, b| a.mean_nm.abs().total_cmp(&b.mean_nm.abs()));
        clear.or_else(|| used.max_by(|a, b| z(a).total_cmp(&z(b))))
    }

    /// Which third of the stroke (from the stowed angle to 0) holds the
    /// [`JointTorque::largest_bin`].
    pub fn stroke_third(&self) -> Option<StrokeThird> {
        let b = self.largest_bin()?;
        let mid = 0.5 * (b.range[0] + b.range[1]);
        let share = (mid - self.stowed_deg) / (-self.stowed_deg);
        let third = if share.is_finite() {
            (3.0 * share).floor().clamp(0.0, 2.0) as usize
        } else {
            1
        };
        StrokeThird::of_index(third)
    }

    /// The part of the stroke where the residual torque is largest, in
    /// words, with its size and whether it resists or drives the
    /// deployment.
    pub fn describe(&self) -> String {
        let Some(big) = self.largest_bin() else {
            return format!("joint {}: no sample to judge", self.joint);
        };
        let motion = -self.stowed_deg.signum();
        let sign = if big.mean_nm * motion < 0.0 {
            "resisting"
        } else {
            "driving"
        };
        let verdict = if self.significant {
            "significant"
        } else {
            "not significant"
        };
        format!(
            "joint {}: residual torque {verdict} (χ² {:.0} over {} bins, largest {:.1} bands), RMS {:.3} N·m, largest {sign} {:.3} N·m at {:.0}° to {:.0}°",
            self.joint,
            self.chi2,
            self.by_angle.len(),
            self.max_z,
            self.rms_nm,
            big.mean_nm.abs(),
            big.range[0],
            big.range[1]
        )
    }
}

/// The smoothed angles of one run, joint by joint, per sample: `[φ, φ̇, φ̈]`
/// [rad, rad/s, rad/s²] of the measured angle, or of its difference from
/// the model's (see [`residual_torque`]), with standard errors; `None`
/// where a window would cross a release, a latch or an impact.
#[derive(Clone, Debug, PartialEq)]
pub struct RunMotion {
    /// `[joint][sample]`: the estimates.
    pub state: Vec<Vec<Option<[f64; 3]>>>,
    /// `[joint][sample]`: whether they are of the difference from the model
    /// (else of the measured angle itself).
    pub relative: Vec<Vec<bool>>,
    /// `[joint][sample]`: their standard errors.
    pub se: Vec<Vec<[f64; 3]>>,
    /// `[joint][sample]`: the window half-width \[samples\].
    pub window: Vec<Vec<usize>>,
}

/// The sample indices where a latch state of the run or of the model
/// changes: the segment boundaries (with 0 and the length).
fn segment_cuts(latch: &[Vec<bool>], model: &[Vec<bool>], len: usize) -> Vec<usize> {
    let flips = |l: &[Vec<bool>], i: usize| l.iter().any(|x| x.get(i) != x.get(i - 1));
    let mut cuts = vec![0];
    for i in 1..len {
        if flips(latch, i) || flips(model, i) {
            cuts.push(i);
        }
    }
    cuts.push(len);
    cuts
}

/// Smooths one run against a model trajectory of it (`φ_model` with the
/// encoder offsets applied, as measured): within a segment where the model
/// and the run agree on which joints are latched, the difference
/// `φ_meas − φ_model`, which is smooth where the model is close and has
/// derivatives far smaller than the motion's, so that the smoother's bias
/// stays small; elsewhere the measured angle itself.
pub fn smooth_run(run: &crate::data::run::Run, model: &Trajectory) -> RunMotion {
    let n = run.len();
    let dt = if n > 1 {
        (run.t_s[n - 1] - run.t_s[0]) / (n - 1) as f64
    } else {
        1.0
    };
    let cuts = segment_cuts(&run.latch, &model.latched, n);
    let joints = run.joints();
    let mut out = RunMotion {
        state: vec![vec![None; n]; joints],
        relative: vec![vec![false; n]; joints],
        se: vec![vec![[f64::INFINITY; 3]; n]; joints],
        window: vec![vec![0; n]; joints],
    };
    let sigma: Vec<f64> = run
        .phi_deg
        .iter()
        .map(|p| noise_sigma(&p.iter().map(|d| d.to_radians()).collect::<Vec<_>>()))
        .collect();
    for w in cuts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let agree = (0..joints).all(|j| {
            model.latched.get(j).and_then(|l| l.get(a)) == run.latch.get(j).and_then(|l| l.get(a))
        });
        for j in 0..joints {
            let y: Vec<f64> = (a..b)
                .map(|i| {
                    let m = if agree { model.phi_deg[j][i] } else { 0.0 };
                    (run.phi_deg[j][i] - m).to_radians()
                })
                .collect();
            if let Some(s) = smooth_segment(&y, dt, sigma[j]) {
                store(&mut out, j, a, &s, agree);
            }
        }
    }
    out
}

/// Writes a smoothed segment starting at sample `at` into joint `j`.
fn store(out: &mut RunMotion, j: usize, at: usize, s: &Smoothed, relative: bool) {
    for (k, v) in s.value.iter().enumerate() {
        out.state[j][at + k] = *v;
        out.relative[j][at + k] = relative;
        out.se[j][at + k] = s.se;
        out.window[j][at + k] = s.h;
    }
}

/// The residual torque of every joint of a campaign against the model
/// `effects` (on each run's mechanism): each run is simulated with the
/// model and smoothed against it ([`smooth_run`]), then the chain
/// equations give the torque the model lacks at the measured state.
pub fn residual_torque(campaign: &Campaign, effects: &[Effect]) -> Vec<JointTorque> {
    let joints = campaign.max_joints();
    let per_run: Vec<Option<Vec<Vec<TorqueSample>>>> = (0..campaign.runs.len())
        .into_par_iter()
        .map(|r| {
            let cr = &campaign.runs[r];
            if cr.mechanism.truss.is_some() {
                return None;
            }
            let traj = campaign.simulate(r, effects).ok()?;
            if traj.t_s.len() != cr.run.len() {
                return None;
            }
            let m = smooth_run(&cr.run, &traj);
            let n = cr.mechanism.joint_count();
            let at = RunAt {
                r,
                traj: &traj,
                m: &m,
            };
            with_joints!(n, N => run_torque::<N>(&cr.mechanism, &cr.run, &at, effects), else None)
        })
        .collect();
    let mut samples: Vec<Vec<TorqueSample>> = vec![Vec::new(); joints];
    for got in per_run.into_iter().flatten() {
        for (j, s) in got.into_iter().enumerate() {
            if let Some(v) = samples.get_mut(j) {
                v.extend(s);
            }
        }
    }
    samples
        .into_iter()
        .enumerate()
        .map(|(j, s)| {
            let stowed = campaign
                .runs
                .first()
                .and_then(|r| r.mechanism.joints.get(j))
                .map_or(0.0, |jt| jt.stowed_deg);
            localise(j + 1, stowed, s)
        })
        .collect()
}

/// One run's model trajectory and smoothed motion.
struct RunAt<'a> {
    /// Index of the run in the campaign.
    r: usize,
    /// The model's trajectory (encoder offsets applied).
    traj: &'a Trajectory,
    /// The run smoothed against it.
    m: &'a RunMotion,
}

/// The state `[φ, φ̇, φ̈]` of joint `j` at sample `i` [rad, rad/s, rad/s²]:
/// the smoothed estimate, plus the model's where it is of the difference.
fn joint_state(at: &RunAt, model: &([f64; 3], bool), j: usize, i: usize) -> Option<[f64; 3]> {
    let e = at.m.state[j][i]?;
    if at.m.relative[j][i] {
        let (x, ok) = model;
        ok.then(|| [x[0] + e[0], x[1] + e[1], x[2] + e[2]])
    } else {
        Some(e)
    }
}

/// The model's true state and acceleration at sample `i` (angles without
/// the encoder offsets), joint by joint, and whether its acceleration could
/// be evaluated.
fn model_state<const N: usize>(
    chain: &HostChain<N>,
    traj: &Trajectory,
    offsets: &[f64],
    i: usize,
) -> [([f64; 3], bool); N] {
    let x = ChainState {
        phi: core::array::from_fn(|j| (traj.phi_deg[j][i] - offsets[j]).to_radians()),
        phi_dot: core::array::from_fn(|j| traj.rate_deg_s[j][i].to_radians()),
    };
    let mode = Mode {
        latched: core::array::from_fn(|j| traj.latched[j][i]),
        branch: core::array::from_fn(|j| Branch::select(x.phi[j], x.phi_dot[j])),
    };
    let acc = chain.acceleration(&x, &mode);
    let ok = acc.is_ok();
    let acc = acc.unwrap_or([0.0; N]);
    core::array::from_fn(|j| ([x.phi[j], x.phi_dot[j], acc[j]], ok))
}

/// One run's residual torque samples, joint by joint (chain of `N` joints).
fn run_torque<const N: usize>(
    mech: &Mechanism,
    run: &crate::data::run::Run,
    at: &RunAt,
    effects: &[Effect],
) -> Option<Vec<Vec<TorqueSample>>> {
    let (je, g) = effect::to_core(effects, N);
    let chain = mech.chain::<N>(&je, g)?;
    let offsets = effect::encoder_offsets_deg(effects, N);
    let mut out = vec![Vec::new(); N];
    for i in 0..run.len() {
        let latched: [bool; N] = core::array::from_fn(|j| run.latch[j].get(i) == Some(&true));
        let model = model_state(&chain, at.traj, &offsets, i);
        let mut x = ChainState {
            phi: [0.0; N],
            phi_dot: [0.0; N],
        };
        let mut acc = [0.0; N];
        let mut ok = true;
        for j in (0..N).filter(|&j| !latched[j]) {
            match joint_state(at, &model[j], j, i) {
                Some([p, v, a]) => {
                    x.phi[j] = p;
                    x.phi_dot[j] = v;
                    acc[j] = a;
                }
                None => ok = false,
            }
        }
        if !ok {
            continue;
        }
        let mode = Mode {
            latched,
            branch: core::array::from_fn(|j| Branch::select(x.phi[j], x.phi_dot[j])),
        };
        let tau = chain.missing_torque(&x, &acc, &mode);
        for j in 0..N {
            if latched[j] || x.phi[j].to_degrees().abs() < LATCH_GUARD_DEG {
                continue;
            }
            let joint = &chain.joints()[j];
            out[j].push(TorqueSample {
                run: at.r,
                index: i,
                t_s: run.t_s[i],
                phi_deg: x.phi[j].to_degrees(),
                rate_deg_s: x.phi_dot[j].to_degrees(),
                torque_nm: tau[j],
                se_nm: torque_se(&chain, &x, &mode, &at.m.se, i, j),
                spring_nm: joint.spring.torque(x.phi[j], mode.branch[j]),
                from_stowed_rad: joint.stowed_rad - x.phi[j],
                window: at.m.window[j][i],
            });
        }
    }
    Some(out)
}

/// Standard error of joint `j`'s residual torque [N·m]: the accelerations'
/// errors through the mass matrix, and the joint's own rate error through
/// the model's torque (by a central difference over one standard error, so
/// that a friction law steep at rest counts as steep).
fn torque_se<const N: usize>(
    chain: &HostChain<N>,
    x: &ChainState<f64, N>,
    mode: &Mode<N>,
    se: &[Vec<[f64; 3]>],
    i: usize,
    j: usize,
) -> f64 {
    let m = chain.mass_matrix(&x.phi);
    let mut var = 0.0;
    for l in 0..N {
        if !mode.latched[l] {
            var += (m[j][l] * se[l][i][2]).powi(2);
        }
    }
    let dv = se[j][i][1];
    let branch = mode.branch[j];
    let hi = chain.joint_torque(j, x.phi[j], x.phi_dot[j] + dv, branch);
    let lo = chain.joint_torque(j, x.phi[j], x.phi_dot[j] - dv, branch);
    var += (0.5 * (hi - lo)).powi(2);
    var.sqrt()
}

/// The share of a smoothed acceleration's variance left in the mean of `m`
/// consecutive estimates with half-window `h`: `Σ c_k² / Σ w_k²`, `c` the
/// weights of the mean (the estimates' weights averaged over the shifts).
/// The mean of accelerations is nearly a difference of two rates, so it
/// shrinks faster than `1/m`.
pub fn mean_variance_share(m: usize, h: usize) -> f64 {
    let w = CubicWeights::new(h).accel;
    let mut c = vec![0.0; w.len() + m.max(1) - 1];
    for i in 0..m.max(1) {
        for (k, wk) in w.iter().enumerate() {
            c[i + k] += wk / m.max(1) as f64;
        }
    }
    let sw: f64 = w.iter().map(|x| x * x).sum();
    c.iter().map(|x| x * x).sum::<f64>() / sw.max(1e-300)
}

/// Bins the samples over `key` into [`BINS`] equal bins of the range they
/// cover: mean and its standard error. Within a bin, each stretch of
/// consecutive samples of one run is averaged with its correlated errors
/// ([`mean_variance_share`]); stretches are independent.
pub fn bins(samples: &[TorqueSample], key: impl Fn(&TorqueSample) -> f64) -> Vec<Bin> {
    let (lo, hi) = samples
        .iter()
        .map(&key)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    if !(hi > lo) {
        return Vec::new();
    }
    let width = (hi - lo) / BINS as f64;
    let mut members: Vec<Vec<&TorqueSample>> = vec![Vec::new(); BINS];
    for s in samples {
        let k = (((key(s) - lo) / width) as usize).min(BINS - 1);
        members[k].push(s);
    }
    members
        .iter()
        .enumerate()
        .map(|(k, m)| {
            let n = m.len();
            let mean = m.iter().map(|s| s.torque_nm).sum::<f64>() / n.max(1) as f64;
            Bin {
                range: [lo + k as f64 * width, lo + (k + 1) as f64 * width],
                n,
                mean_nm: mean,
                se_nm: mean_se(m),
            }
        })
        .collect()
}

/// Standard error of the mean of a bin's samples [N·m] (see [`bins`]).
fn mean_se(m: &[&TorqueSample]) -> f64 {
    let n = m.len().max(1) as f64;
    let mut var = 0.0;
    let mut start = 0;
    for i in 1..=m.len() {
        let cut = i == m.len()
            || m[i].run != m[i - 1].run
            || m[i].index != m[i - 1].index + 1
            || m[i].window != m[i - 1].window;
        if cut {
            let stretch = &m[start..i];
            let len = stretch.len();
            let ms2 = stretch.iter().map(|s| s.se_nm * s.se_nm).sum::<f64>() / len as f64;
            let share = mean_variance_share(len, stretch[0].window.max(1));
            var += (len as f64 / n).powi(2) * ms2 * share;
            start = i;
        }
    }
    var.sqrt()
}

/// The localisation of one joint's samples: bins over angle and rate, and
/// the significance test.
fn localise(joint: usize, stowed_deg: f64, samples: Vec<TorqueSample>) -> JointTorque {
    let by_angle = bins(&samples, |s| s.phi_deg);
    let by_rate = bins(&samples, |s| s.rate_deg_s);
    let used: Vec<&Bin> = by_angle.iter().filter(|b| b.n > 0).collect();
    let z = |b: &Bin| b.mean_nm / b.se_nm.max(1e-12);
    let chi2: f64 = used.iter().map(|b| z(b).powi(2)).sum();
    let max_z = used.iter().map(|b| z(b).abs()).fold(0.0, f64::max);
    let dof = used.len() as f64;
    let significant =
        dof > 0.0 && chi2 > dof + SIGNIFICANCE_SD * (2.0 * dof).sqrt() && max_z > BIN_Z;
    let rms_nm = if used.is_empty() {
        0.0
    } else {
        (used.iter().map(|b| b.mean_nm.powi(2)).sum::<f64>() / dof).sqrt()
    };
    JointTorque {
        joint,
        stowed_deg,
        samples,
        by_angle,
        by_rate,
        chi2,
        max_z,
        significant,
        rms_nm,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A joint whose only clear bin is `range`, on a stroke from `stowed_deg`.
    fn joint_with_bin(stowed_deg: f64, range: [f64; 2]) -> JointTorque {
        let quiet = |r: [f64; 2]| Bin {
            range: r,
            n: 10,
            mean_nm: 0.001,
            se_nm: 0.01,
        };
        let loud = Bin {
            range,
            n: 10,
            mean_nm: -0.2,
            se_nm: 0.01,
        };
        JointTorque {
            joint: 2,
            stowed_deg,
            samples: Vec::new(),
            by_angle: vec![quiet([-50.0, -45.0]), loud, quiet([-30.0, -25.0])],
            by_rate: Vec::new(),
            chi2: 400.0,
            max_z: 20.0,
            significant: true,
            rms_nm: 0.1,
        }
    }

    #[test]
    fn the_stroke_third_is_the_third_of_the_largest_clear_bin() {
        let near_stowed = joint_with_bin(-90.0, [-88.0, -82.0]);
        assert_eq!(
            near_stowed.largest_bin().map(|b| b.range),
            Some([-88.0, -82.0])
        );
        assert_eq!(near_stowed.stroke_third(), Some(StrokeThird::First));
        let middle = joint_with_bin(-90.0, [-48.0, -42.0]);
        assert_eq!(middle.stroke_third(), Some(StrokeThird::Middle));
        // A wing stowed at a positive angle deploys downwards to 0.
        let near_latch = joint_with_bin(90.0, [2.0, 8.0]);
        assert_eq!(near_latch.stroke_third(), Some(StrokeThird::Last));
    }
}
