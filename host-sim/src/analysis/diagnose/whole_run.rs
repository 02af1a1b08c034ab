//! The whole run of runs of a physical latch (`docs/diagnosis.md`, "Runs of
//! a physical latch", "The whole run"): the effects are fitted on each
//! run's free motion ([`super::latch_window`]), up to the first instant any
//! joint enters its latch's reach; this check compares the model found with
//! the motion after it.
//!
//! After the first contact the run cannot be simulated from the release:
//! the impact sequence at a latch changes with the smallest difference. The
//! motion between contacts can: each stretch where no joint is in a
//! contact transient (every joint of a latch either clear of its reach or
//! held in it, its switch closed for [`HELD_S`] or longer) is cut into shots of at most [`SHOT_S`], and each
//! shot is simulated from the measured state at its start (multiple
//! shooting from the measured state, Bock 1981; Baake et al. 1992). The
//! angles and rates at a shot's start are the smoother's
//! ([`smooth_segment`]), then fitted to the shot by Gauss–Newton (the
//! start's nuisance parameters, so that a shot's residual is what the
//! model's torques miss, not the start's error). A joint swinging free
//! after the first contact whose residual over the shots stays above
//! [`AFTER_CONTACT_FACTOR`]·σ̂ is not followed by the model found: the
//! report says so at that joint. It is a finding of the fit, not a cause:
//! on runs of latches as built (within their tolerances, no effect hidden)
//! a shot started beside a joint whose latch differs from the drawing's
//! misses too (`docs/diagnosis.md`, "Runs of a physical latch", 4).

use super::latch_window::{RunWindow, FREE_MARGIN_DEG};
use super::smoothing::smooth_segment;
use crate::analysis::latch_events::{travel_deg, zone_deg};
use crate::data::campaign::{Campaign, CampaignRun};
use crate::model::effect::{self, Effect};
use crate::simulate::latch_deployment::{simulate_physical_from, StartState};
use crate::simulate::trajectory::{Samples, SimOptions};
use deploywatch_core::Branch;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// Longest shot \[s\]: the error of a start state grows over a shot, and
/// a shot much longer than a panel's swing gains little.
pub const SHOT_S: f64 = 1.0;

/// Fewest samples in a shot: its start's rates are fitted to it.
pub const MIN_SHOT_SAMPLES: usize = 40;

/// Time kept clear of a contact transient on either side \[s\] (at least
/// the smoother's half-width: a shot's start state is the smoother's).
pub const CONTACT_GUARD_S: f64 = 0.05;

/// How long a joint must have been held for the shots to count it held
/// \[s\]: its switch closed throughout (without a switch: its travel within
/// the latch's hold limit throughout). A joint within its latch's reach
/// and not held is in a contact transient: entering, rebounding, or
/// rattling off its stop, whose impacts change the motion of every panel
/// it carries. A joint of a pawl within its reach is never counted held:
/// where it sits in the notch, and whether the pawl is engaged, is not
/// read from the angle.
pub const HELD_S: f64 = 0.2;

/// A joint swinging free after the first contact is not followed by the
/// model when its residual RMS over the shots exceeds this many σ̂ \[1\]:
/// the shots' residual of a right model with the drawing's latches is the
/// noise plus what a fitted start leaves (the shots of
/// `tests/diagnosis_physical_latch.rs`'s clean campaign).
pub const AFTER_CONTACT_FACTOR: f64 = 2.0;

/// Fewest residual samples of a joint over the shots for it to be judged.
pub const MIN_JUDGED_SAMPLES: usize = 200;

/// Rate step of the start's sensitivities \[rad/s\].
const RATE_STEP_RAD_S: f64 = 1e-3;

/// Angle step of the start's sensitivities \[rad\].
const ANGLE_STEP_RAD: f64 = 1e-4;

/// Gauss–Newton steps on a shot's start (each kept only when it lowers the
/// shot's sum of squares).
const GAUSS_NEWTON_STEPS: usize = 2;

/// One shot: samples `start..end` of run `run` (0-based), simulated from
/// the measured state at `start`.
#[derive(Clone, Debug, PartialEq)]
pub struct Shot {
    /// The run (0-based).
    pub run: usize,
    /// First sample.
    pub start: usize,
    /// One past the last sample.
    pub end: usize,
    /// Its length \[s\].
    pub length_s: f64,
    /// Its start \[s\].
    pub start_s: f64,
    /// Each joint's residual RMS over the shot where it is clear of its
    /// latch \[deg\] (`None`: in its latch throughout, or not simulated).
    pub rms_deg: Vec<Option<f64>>,
}

/// One joint over the whole run.
#[derive(Clone, Debug, PartialEq)]
pub struct JointAfter {
    /// 1-based joint.
    pub joint: usize,
    /// Residual RMS over the free windows \[deg\].
    pub free_rms_deg: f64,
    /// Residual RMS over the shots where the joint swings clear of its
    /// latch \[deg\] (`None`: fewer than [`MIN_JUDGED_SAMPLES`]).
    pub after_rms_deg: Option<f64>,
    /// Samples behind `after_rms_deg`.
    pub after_samples: usize,
}

/// The whole-run check of a campaign of physical latches.
#[derive(Clone, Debug, PartialEq)]
pub struct WholeRun {
    /// The shots simulated.
    pub shots: Vec<Shot>,
    /// Each joint's fit over the free window and after it.
    pub joints: Vec<JointAfter>,
    /// The noise floor σ̂ it is judged against \[deg\].
    pub noise_sigma_deg: f64,
}

impl WholeRun {
    /// The joint the model misses most after the first contact, when its
    /// residual there exceeds [`AFTER_CONTACT_FACTOR`]·σ̂: its 1-based
    /// number, RMS \[deg\] and samples.
    pub fn missed(&self) -> Option<&JointAfter> {
        self.joints
            .iter()
            .filter(|j| {
                j.after_rms_deg
                    .is_some_and(|r| r > AFTER_CONTACT_FACTOR * self.noise_sigma_deg)
            })
            .max_by(|a, b| {
                a.after_rms_deg
                    .unwrap_or(0.0)
                    .total_cmp(&b.after_rms_deg.unwrap_or(0.0))
            })
    }

    /// [`WholeRun::missed`] in words, for the progress.
    pub fn missed_words(&self) -> Option<String> {
        self.missed().map(|m| {
            format!(
                "after the first contact the model found does not follow joint {} ({:.4} deg RMS)",
                m.joint,
                m.after_rms_deg.unwrap_or(0.0)
            )
        })
    }

    /// Seconds of the runs the shots cover.
    pub fn shot_seconds(&self) -> f64 {
        self.shots.iter().map(|s| s.length_s).sum::<f64>().max(0.0)
    }
}

/// Median sample period of `t` \[s\].
fn period(t: &[f64]) -> Option<f64> {
    let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    if d.is_empty() {
        return None;
    }
    d.sort_by(f64::total_cmp);
    Some(d[d.len() / 2]).filter(|p| *p > 0.0)
}

/// The measured angles of run `cr` less the encoder offsets of `effects`
/// \[deg\], and their smoothed value and rate (`None` near the ends).
struct Measured {
    phi: Vec<Vec<f64>>,
    smooth: Vec<Vec<Option<[f64; 3]>>>,
    /// The widest smoother half-width of the joints \[samples\]: a start
    /// this near a contact sees the impact's kink.
    h: usize,
}

fn measured(cr: &CampaignRun, effects: &[Effect], sigma: f64) -> Option<Measured> {
    let n = cr.mechanism.joint_count().min(cr.run.joints());
    let dt = period(&cr.run.t_s)?;
    let off = effect::encoder_offsets_deg(effects, n);
    let phi: Vec<Vec<f64>> = (0..n)
        .map(|j| cr.run.phi_deg[j].iter().map(|x| x - off[j]).collect())
        .collect();
    let fits = phi
        .iter()
        .map(|y| smooth_segment(y, dt, sigma))
        .collect::<Option<Vec<_>>>()?;
    let h = fits.iter().map(|f| f.h).max().unwrap_or(0);
    let smooth = fits.into_iter().map(|f| f.value).collect();
    Some(Measured { phi, smooth, h })
}

/// Per sample of run `cr`: whether any joint is in a contact transient
/// there (within [`CONTACT_GUARD_S`]), and per joint whether it is within
/// its latch's reach.
fn contact_mask(cr: &CampaignRun, m: &Measured) -> (Vec<bool>, Vec<Vec<bool>>) {
    let len = cr.run.len();
    let t = &cr.run.t_s;
    let mech = &cr.mechanism;
    let n = m.phi.len();
    let mut near = vec![vec![false; len]; n];
    let mut transient = vec![false; len];
    for j in 0..n {
        let stowed = mech.joints[j].stowed_deg;
        let reach = match mech.latch(j) {
            Some(l) => zone_deg(l) + FREE_MARGIN_DEG,
            None => FREE_MARGIN_DEG,
        };
        let hold_deg = mech
            .latch(j)
            .map_or(FREE_MARGIN_DEG, |l| l.hold_limit_deg(stowed));
        let switch = cr.run.latch.get(j).filter(|s| s.len() == len);
        let mut held_since: Option<f64> = None;
        for i in 0..len {
            near[j][i] = travel_deg(stowed, m.phi[j][i]) <= reach;
            let in_hold = match switch {
                Some(s) => s[i],
                None => travel_deg(stowed, m.phi[j][i]) <= hold_deg,
            };
            held_since = if in_hold {
                held_since.or(Some(t[i]))
            } else {
                None
            };
            // A pawl's notch contact (riding, engaged, where in the notch)
            // is not read from the angle: a shot cannot start from it.
            let pawl = mech.latch(j).is_some_and(|l| l.pawl.is_some());
            let held = !pawl && held_since.is_some_and(|s| t[i] - s >= HELD_S);
            if near[j][i] && !held {
                transient[i] = true;
            }
        }
    }
    // Each transient sample marks the samples within the guard.
    let g = period(t)
        .map_or(0, |dt| (CONTACT_GUARD_S / dt).ceil() as usize)
        .max(m.h);
    let mut marks = vec![0i64; len + 1];
    for i in (0..len).filter(|&i| transient[i]) {
        marks[i.saturating_sub(g)] += 1;
        marks[(i + g + 1).min(len)] -= 1;
    }
    let mut open = 0;
    let guarded = marks[..len]
        .iter()
        .map(|d| {
            open += d;
            open > 0
        })
        .collect();
    (guarded, near)
}

/// The shots of run `run` after its free window `w`.
fn shots_of(run: usize, cr: &CampaignRun, w: &RunWindow, busy: &[bool]) -> Vec<Shot> {
    let t = &cr.run.t_s;
    let mut out = Vec::new();
    let mut i = w.kept;
    while i < busy.len() {
        if busy[i] {
            i += 1;
            continue;
        }
        let start = i;
        while i < busy.len() && !busy[i] && t[i] - t[start] < SHOT_S {
            i += 1;
        }
        if i - start >= MIN_SHOT_SAMPLES {
            out.push(Shot {
                run,
                start,
                end: i,
                length_s: t[i - 1] - t[start],
                start_s: t[start],
                rms_deg: Vec::new(),
            });
        }
    }
    out
}

/// The residual (model minus measured, offsets removed) \[deg\] of `shot`
/// from `start`, joint by joint, or `None` when the simulation fails.
fn shot_residual(
    cr: &CampaignRun,
    m: &Measured,
    effects: &[Effect],
    shot: &Shot,
    start: &StartState,
    opts: &SimOptions,
) -> Option<Vec<Vec<f64>>> {
    let t = &cr.run.t_s;
    let times: Vec<f64> = (shot.start..shot.end)
        .map(|i| t[i] - t[shot.start])
        .collect();
    let run = simulate_physical_from(&cr.mechanism, effects, opts, start, Samples::Listed(&times))
        .ok()?;
    let traj = run.traj;
    (0..m.phi.len())
        .map(|j| {
            let model = traj.phi_deg.get(j)?;
            (model.len() == times.len()).then(|| {
                model
                    .iter()
                    .zip(&m.phi[j][shot.start..shot.end])
                    .map(|(a, b)| a - b)
                    .collect()
            })
        })
        .collect()
}

/// The shot's residual from the smoother's start, its angles and rates
/// then fitted by at most [`GAUSS_NEWTON_STEPS`] Gauss–Newton steps, or
/// `None`.
fn fitted_shot(
    cr: &CampaignRun,
    m: &Measured,
    effects: &[Effect],
    shot: &Shot,
    opts: &SimOptions,
) -> Option<Vec<Vec<f64>>> {
    let n = m.phi.len();
    let stowed: Vec<f64> = (0..n).map(|j| cr.mechanism.joints[j].stowed_deg).collect();
    let at = |j: usize| m.smooth[j][shot.start];
    let held: Vec<bool> = (0..n)
        .map(|j| {
            cr.mechanism.latch(j).is_none()
                && travel_deg(stowed[j], m.phi[j][shot.start]) <= FREE_MARGIN_DEG
        })
        .collect();
    let mut start = StartState {
        q_rad: (0..n)
            .map(|j| at(j).map(|v| v[0].to_radians()))
            .collect::<Option<_>>()?,
        v_rad_s: (0..n)
            .map(|j| at(j).map(|v| v[1].to_radians()))
            .collect::<Option<_>>()?,
        held,
        branch: vec![None; n],
    };
    let free: Vec<usize> = (0..n).filter(|&j| !start.held[j]).collect();
    let mut best = shot_residual(cr, m, effects, shot, &start, opts)?;
    // A spring with hysteresis keeps its branch over a small loop: each
    // such joint's other branch is tried, kept when the shot fits better.
    for &j in free.iter().filter(|&&j| has_hysteresis(cr, j)) {
        let mut other = start.clone();
        let rate_branch = if other.q_rad[j] * other.v_rad_s[j] < 0.0 {
            Branch::Unfold
        } else {
            Branch::Fold
        };
        other.branch[j] = Some(match rate_branch {
            Branch::Fold => Branch::Unfold,
            Branch::Unfold => Branch::Fold,
        });
        if let Some(r) = shot_residual(cr, m, effects, shot, &other, opts) {
            if sum_sq(&r) < sum_sq(&best) {
                (start, best) = (other, r);
            }
        }
    }
    for _ in 0..GAUSS_NEWTON_STEPS {
        let Some((next, r)) = gauss_newton(cr, m, effects, shot, opts, &start, &best, &free) else {
            break;
        };
        if sum_sq(&r) >= sum_sq(&best) {
            break;
        }
        (start, best) = (next, r);
    }
    Some(best)
}

/// True when joint `j`'s spring has hysteresis (a tape spring's fold).
fn has_hysteresis(cr: &CampaignRun, j: usize) -> bool {
    cr.mechanism.joints.get(j).is_some_and(|jt| {
        jt.spring
            .to_spring::<f64>()
            .is_ok_and(|s| s.hysteresis_below_rad().is_some())
    })
}

/// Sum of squares of a residual `[joint][sample]`.
fn sum_sq(r: &[Vec<f64>]) -> f64 {
    r.iter().flatten().map(|x| x * x).sum()
}

/// One Gauss–Newton step on the angles and rates of the `free` joints at
/// the shot's start, from `start` whose residual is `r0`: the new start and
/// its residual.
#[allow(clippy::too_many_arguments)]
fn gauss_newton(
    cr: &CampaignRun,
    m: &Measured,
    effects: &[Effect],
    shot: &Shot,
    opts: &SimOptions,
    start: &StartState,
    r0: &[Vec<f64>],
    free: &[usize],
) -> Option<(StartState, Vec<Vec<f64>>)> {
    let flat = |r: &[Vec<f64>]| -> Vec<f64> { r.iter().flatten().copied().collect() };
    let base = flat(r0);
    // Columns: each free joint's angle, then its rate.
    let params: Vec<(usize, bool)> = free.iter().flat_map(|&j| [(j, false), (j, true)]).collect();
    if params.is_empty() {
        return None;
    }
    let cols: Vec<Vec<f64>> = params
        .par_iter()
        .map(|&(j, rate)| {
            let mut s = start.clone();
            let d = if rate {
                RATE_STEP_RAD_S
            } else {
                ANGLE_STEP_RAD
            };
            if rate {
                s.v_rad_s[j] += d;
            } else {
                s.q_rad[j] += d;
            }
            let r = shot_residual(cr, m, effects, shot, &s, opts)?;
            Some(
                flat(&r)
                    .iter()
                    .zip(&base)
                    .map(|(a, b)| (a - b) / d)
                    .collect(),
            )
        })
        .collect::<Option<_>>()?;
    let jac = DMatrix::from_fn(base.len(), cols.len(), |r, c| cols[c][r]);
    let rhs = -DVector::from_column_slice(&base);
    let step = jac.svd(true, true).solve(&rhs, 1e-12).ok()?;
    let mut next = start.clone();
    for (k, &(j, rate)) in params.iter().enumerate() {
        if rate {
            next.v_rad_s[j] += step[k];
        } else {
            next.q_rad[j] += step[k];
        }
    }
    let r = shot_residual(cr, m, effects, shot, &next, opts)?;
    Some((next, r))
}

/// The whole-run check of `campaign` (its runs whole) against `effects`,
/// fitted on the free windows `windows`, at the noise floor σ̂ `sigma`
/// \[deg\]; `free_residuals` gives the free window's residuals of run `i`
/// (`[joint][sample]`). `None` when no run goes on after its free window;
/// no shots when none of the rest is clear of a contact transient.
pub fn check(
    campaign: &Campaign,
    windows: &[RunWindow],
    effects: &[Effect],
    sigma: f64,
    opts: &SimOptions,
    free_residuals: impl Fn(usize) -> Option<Vec<Vec<f64>>>,
) -> Option<WholeRun> {
    let joints = campaign.max_joints();
    let mut free_ss = vec![(0.0, 0usize); joints];
    let mut after_ss = vec![(0.0, 0usize); joints];
    let mut shots = Vec::new();
    for (i, (cr, w)) in campaign.runs.iter().zip(windows).enumerate() {
        if let Some(r) = free_residuals(i) {
            for (j, s) in r.iter().enumerate().take(joints) {
                free_ss[j].0 += s.iter().map(|x| x * x).sum::<f64>();
                free_ss[j].1 += s.len();
            }
        }
        if w.kept >= w.of {
            continue;
        }
        let Some(m) = measured(cr, effects, sigma) else {
            continue;
        };
        let (busy, near) = contact_mask(cr, &m);
        let run_shots = shots_of(i, cr, w, &busy);
        let results: Vec<Option<Vec<Vec<f64>>>> = run_shots
            .iter()
            .map(|s| fitted_shot(cr, &m, effects, s, opts))
            .collect();
        for (s, r) in run_shots.iter().zip(results) {
            let Some(r) = r else { continue };
            let mut shot = s.clone();
            for (j, res) in r.iter().enumerate().take(joints) {
                let (mut ss, mut k_n) = (0.0, 0usize);
                for (k, x) in res.iter().enumerate() {
                    if !near[j][s.start + k] {
                        ss += x * x;
                        k_n += 1;
                    }
                }
                after_ss[j].0 += ss;
                after_ss[j].1 += k_n;
                shot.rms_deg
                    .push((k_n > 0).then(|| (ss / k_n as f64).sqrt()));
            }
            shots.push(shot);
        }
    }
    if windows.iter().all(|w| w.kept >= w.of) {
        return None;
    }
    let rms = |(ss, n): (f64, usize)| if n == 0 { 0.0 } else { (ss / n as f64).sqrt() };
    Some(WholeRun {
        shots,
        joints: (0..joints)
            .map(|j| JointAfter {
                joint: j + 1,
                free_rms_deg: rms(free_ss[j]),
                after_rms_deg: (after_ss[j].1 >= MIN_JUDGED_SAMPLES).then(|| rms(after_ss[j])),
                after_samples: after_ss[j].1,
            })
            .collect(),
        noise_sigma_deg: sigma,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_period_is_the_median_step() {
        assert_eq!(period(&[0.0, 0.001, 0.002, 0.0035, 0.0045]), Some(0.001));
        assert_eq!(period(&[0.0]), None);
    }

    #[test]
    fn the_joint_missed_most_is_named_only_above_the_factor() {
        let j = |joint, after: Option<f64>| JointAfter {
            joint,
            free_rms_deg: 0.02,
            after_rms_deg: after,
            after_samples: 1000,
        };
        let w = WholeRun {
            shots: Vec::new(),
            joints: vec![
                j(1, Some(0.03)),
                j(2, None),
                j(3, Some(0.35)),
                j(4, Some(0.1)),
            ],
            noise_sigma_deg: 0.02,
        };
        assert_eq!(w.missed().map(|m| m.joint), Some(3));
        let clean = WholeRun {
            joints: vec![j(1, Some(0.039)), j(2, None)],
            ..w
        };
        assert_eq!(clean.missed(), None);
    }
}
