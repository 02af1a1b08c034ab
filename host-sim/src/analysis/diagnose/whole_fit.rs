//! Runs of a physical latch fitted whole where the model follows their
//! latch history (`docs/diagnosis.md`, "Runs of a physical latch", 5).
//!
//! The search fits runs of a physical latch on their free motion
//! ([`super::latch_window`]) because the impact sequence at a latch changes
//! with the smallest difference: a model whose latches rebound once more
//! than the runs' cannot be compared with them sample by sample. Where the
//! model found, simulated over the whole runs from the release, closes every
//! latch switch exactly as often as each run does, it does follow their
//! impact sequence: the rebounds are the same rebounds, their instants and
//! heights move continuously with the effects, and the motion after the
//! first contact is evidence like the motion before it. An effect that acts
//! mostly after the first contact (a harness at a joint still swinging when
//! another has latched, damping that shows in the rebounds) is then fitted
//! on the whole runs. [`follows_history`] decides, for the mechanisms as
//! given (where the search starts) and the set found on the free motion
//! before, and for the set found on the whole runs after.
//!
//! Where the model follows the runs only part of the way (a switch closes
//! once more or less late in the run, or the integration's tolerance moves
//! a late rebound), each run is fitted up to its [`horizon`], the first
//! sample where model and run part (`docs/diagnosis.md`, "Runs of a
//! physical latch", 6).

use super::latch_window::{self, RunWindow};
use super::outcome::{FittedSet, Outcome};
use super::policy::MIN_DELTA_BIC;
use super::Search;
use crate::analysis::campaign_sim::{fit_sim_options_for, CampaignSim};
use crate::data::campaign::{Campaign, CampaignRun};
use crate::model::effect::Effect;
use crate::report::progress::Progress;
use crate::simulate::deployment::{self, SimOptions};
use rayon::prelude::*;

/// `first`, the search on the free motion of `campaign`'s runs (`free`:
/// the runs cut to it), or the search on the whole runs (`search`) when
/// the model each finds follows the runs' latch history
/// ([`follows_history`]) and the whole runs' set explains the free motion
/// as well as `first`'s ([`explains_free_motion`]), or else the search on
/// each run up to where the model follows it ([`to_horizon`]); the outcome
/// kept says which ([`Outcome::fitted_whole`], [`Outcome::fitted_to`]).
/// `search(runs, named_only)`: the search on those runs, its discovery of
/// unnamed torques left out when `named_only`.
pub fn consider(
    campaign: &Campaign,
    free: &Campaign,
    first: Outcome,
    progress: Progress,
    search: impl FnOnce(&Campaign, bool) -> Outcome,
) -> Outcome {
    let found = first.extended.effects();
    let sigma = first.noise_sigma_deg;
    let follows = |e: &[Effect]| follows_history(campaign, e, sigma);
    // The search on the whole runs starts from the mechanisms as given: a
    // baseline with another rebound count is no landscape to walk.
    if first.partial.is_some() {
        return first;
    }
    if !follows(&[]) || (!found.is_empty() && !follows(&found)) {
        return to_horizon(campaign, free, first, progress, search);
    }
    progress(
        "the model found closes each latch switch as often as every run does: searching again on the whole runs",
    );
    let whole = search(campaign, false);
    let simulations = first.simulations + whole.simulations;
    let kept = whole.partial.is_none()
        && follows(&whole.extended.effects())
        && explains_free_motion(free, &whole.extended, &first.extended);
    if kept {
        return Outcome {
            fitted_whole: true,
            simulations,
            ..whole
        };
    }
    progress("the set found on the whole runs does not follow their latch history, or misses their free motion: the free motion's kept");
    Outcome {
        simulations,
        ..first
    }
}

/// The runs are fitted up to where the model follows them
/// ([`to_horizon`]) only when that gives at least this many times the free
/// motion's samples \[1\]: fewer add little evidence for a search run again.
pub const MORE_THAN_FREE: f64 = 1.5;

/// Where the whole runs are refused ([`consider`]): `first`, or the search
/// on each run cut where the model stops following it (`search` on the
/// runs cut at [`horizon`] of the mechanisms as given and of `first`'s set,
/// the earlier, never before the free motion's end; named effects only:
/// beyond the free motion a torque table of many knots fits what the
/// rebounds make of the tolerance) when that is at least
/// [`MORE_THAN_FREE`] times the free motion and the set found there leaves
/// the runs so cut at the noise (unless `first` left the free motion above
/// it), follows the runs as far and explains the free motion as well as
/// `first`'s ([`explains_free_motion`]); the outcome kept gives the windows
/// ([`Outcome::fitted_to`]).
fn to_horizon(
    campaign: &Campaign,
    free: &Campaign,
    first: Outcome,
    progress: Progress,
    search: impl FnOnce(&Campaign, bool) -> Outcome,
) -> Outcome {
    let sigma = first.noise_sigma_deg;
    let found = first.extended.effects();
    let Some(base) = horizons(campaign, &[], sigma) else {
        return first;
    };
    let with_found = if found.is_empty() {
        Some(base.clone())
    } else {
        horizons(campaign, &found, sigma)
    };
    let Some(with_found) = with_found else {
        return first;
    };
    let windows: Vec<RunWindow> = (0..campaign.runs.len())
        .map(|i| {
            let w = if with_found[i].kept < base[i].kept {
                &with_found[i]
            } else {
                &base[i]
            };
            let at_least = free.runs.get(i).map_or(0, |f| f.run.len());
            let t_s = &campaign.runs[i].run.t_s;
            window_to(w.kept.max(at_least), w.of, t_s, w.joint)
        })
        .collect();
    let kept: usize = windows.iter().map(|w| w.kept).sum();
    let free_samples: usize = free.runs.iter().map(|r| r.run.len()).sum();
    if (kept as f64) < MORE_THAN_FREE * free_samples as f64 {
        return first;
    }
    progress(&format!(
        "the model follows the runs' latch history beyond their free motion ({kept} of {} samples): searching again on them up to where it stops",
        windows.iter().map(|w| w.of).sum::<usize>()
    ));
    let cut = latch_window::apply(campaign, &windows);
    let there = search(&cut, true);
    let simulations = first.simulations + there.simulations;
    // Switches that change state alike do not make rebounds of the same
    // height (a latch as built within its tolerances): the set must leave
    // the runs so cut at the noise where the free motion's did.
    let kept = there.partial.is_none()
        && (there.unexplained.is_none() || first.unexplained.is_some())
        && horizons(campaign, &there.extended.effects(), sigma)
            .is_some_and(|h| h.iter().zip(&windows).all(|(a, w)| a.kept >= w.kept))
        && explains_free_motion(free, &there.extended, &first.extended);
    if kept {
        return Outcome {
            fitted_to: Some(windows),
            simulations,
            ..there
        };
    }
    progress("the set found up to where the model follows the runs does not follow them as far, or misses their free motion: the free motion's kept");
    Outcome {
        simulations,
        ..first
    }
}

/// Each run's [`horizon`] with `effects`; `None` when one has none.
fn horizons(campaign: &Campaign, effects: &[Effect], sigma: f64) -> Option<Vec<RunWindow>> {
    (0..campaign.runs.len())
        .into_par_iter()
        .map(|i| horizon(&campaign.runs[i], effects, sigma))
        .collect()
}

/// The window of the first `kept` of `of` samples at stamps `t_s`, ended
/// at `joint` (1-based).
fn window_to(kept: usize, of: usize, t_s: &[f64], joint: Option<usize>) -> RunWindow {
    RunWindow {
        kept,
        of,
        end_s: (kept < of).then(|| t_s.get(kept).copied()).flatten(),
        joint,
    }
}

/// True when `whole`, the set found on the whole runs at its values, does
/// not miss the free motion (`free`: the runs cut to it) by more than
/// `first`, the set fitted there: its BIC on the free windows (its
/// parameters counted, not refitted) within [`MIN_DELTA_BIC`] of
/// `first`'s. The motion before the first contact is where the model is
/// surest; a set that misses it to fit the rest (where the stick of a
/// friction or a late rebound can turn on the integration's tolerance)
/// is not the answer.
pub fn explains_free_motion(free: &Campaign, whole: &FittedSet, first: &FittedSet) -> bool {
    let bic = |f: &FittedSet| {
        let r = free.residual_vector(&f.effects())?;
        let m = r.len().max(1) as f64;
        let sse: f64 = r.iter().map(|x| x * x).sum();
        let k = f.params().len() as f64;
        Some(m * (sse.max(1e-300) / m).ln() + k * m.ln())
    };
    match (bic(whole), bic(first)) {
        (Some(w), Some(f)) => w <= f + MIN_DELTA_BIC,
        _ => false,
    }
}

/// On the whole runs a member of the set found whose loss moves the
/// model's runs by less than this share of the noise σ̂ (RMS over every
/// sample, the others as fitted) is dropped ([`Search::drop_negligible`])
/// \[1\]. Through the rebounds the fit's landscape is rough at that scale
/// (an impact instant moves by a fraction of a sample with the integration
/// tolerance), and a nuisance there can earn its BIC without being seen:
/// on a generated wing with viscous damping hidden (`tests/examples/after_contact.rs`,
/// seed 14034) a rig tilt of 2e-5 rad that moved the runs by 0.0016° (σ̂
/// 0.022°) beat the set without it by 10 in BIC.
pub const NEGLIGIBLE_SHARE: f64 = 0.25;

impl Search<'_, '_> {
    /// On the whole runs: drops, one at a time and the smallest first, each
    /// member whose loss moves the model's runs by less than
    /// [`NEGLIGIBLE_SHARE`]·σ̂ RMS, the others refitted.
    pub(super) fn drop_negligible(&mut self) {
        let eng = self.eng;
        while !self.current.members.is_empty() && !eng.halt.now() {
            let runs = |e: &[Effect]| {
                (0..eng.campaign.runs.len())
                    .into_par_iter()
                    .map(|i| eng.campaign.simulate(i, e).ok().map(|t| t.phi_deg))
                    .collect::<Option<Vec<_>>>()
            };
            let effects = self.current.effects();
            if effects.len() != self.current.members.len() {
                return;
            }
            let Some(all) = runs(&effects) else { return };
            let moves = |k: usize| {
                let mut less = effects.clone();
                less.remove(k);
                let other = runs(&less)?;
                let (mut ss, mut n) = (0.0, 0usize);
                for (a, b) in all.iter().flatten().zip(other.iter().flatten()) {
                    ss += a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>();
                    n += a.len().min(b.len());
                }
                Some((ss / n.max(1) as f64).sqrt())
            };
            let smallest = (0..effects.len())
                .filter_map(|k| moves(k).map(|m| (k, m)))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            let Some((k, m)) = smallest.filter(|(_, m)| *m < NEGLIGIBLE_SHARE * self.sigma) else {
                return;
            };
            let Some(less) = eng.refit(eng.campaign, &self.current.without(k)) else {
                return;
            };
            eng.say(format!(
                "  dropped {}: on the whole runs it moves them by {m:.4} deg, under a quarter of the noise",
                self.current.members[k].candidate.words()
            ));
            self.current_held = eng.held_out(&less);
            self.current = less;
        }
    }
}

/// Closings of one switch over a run: each open-to-closed transition, and
/// one more when it is closed at the first sample.
pub fn closings(switch: &[bool]) -> usize {
    switch.windows(2).filter(|w| !w[0] && w[1]).count() + usize::from(switch.first() == Some(&true))
}

/// Each run's closings, joint by joint (`[run][joint]`), of the joints
/// whose switch column the run has; `None` when a run of a mechanism with a
/// physical latch lacks one of them (its latch history is not read).
pub fn measured_history(campaign: &Campaign) -> Option<Vec<Vec<Option<usize>>>> {
    campaign
        .runs
        .iter()
        .map(|cr| {
            let len = cr.run.len();
            (0..cr.mechanism.joint_count())
                .map(|j| {
                    let physical = cr.mechanism.latch(j).is_some();
                    match cr.run.latch.get(j).filter(|s| s.len() == len) {
                        Some(s) => Some(Some(closings(s))),
                        None if physical => None,
                        None => Some(None),
                    }
                })
                .collect()
        })
        .collect()
}

/// The model's runs are settled when the same model at a tenth of the
/// fit's integration tolerance moves them by less than this share of the
/// noise σ̂ (RMS over every sample) \[1\]. Where a latch's rebounds amplify
/// a difference of the integration's size into one of degrees, the whole
/// runs are chaotic at that scale: no simulation follows them, an effect
/// as much as the tolerance moves them by anything, and only the free
/// windows can be fitted (a generated wing with Coulomb friction of 0.01
/// N·m hidden at a joint latched in 0.17 s, seed 14948 of
/// `tests/examples/after_contact.rs`: the free windows find it, while
/// over the whole runs the model without it matches them at the noise).
pub const SETTLED_SHARE: f64 = 0.5;

/// The integration tolerance of the check of [`SETTLED_SHARE`], relative
/// to the fit's \[1\].
const TIGHTER: f64 = 0.1;

/// True when the model with `effects`, simulated over each whole run at its
/// stamps, closes every switch the runs record exactly as often as each run
/// does and is settled ([`SETTLED_SHARE`] of the noise σ̂ `sigma` \[deg\]),
/// on a campaign with a physical latch; false when any run differs, lacks
/// a physical latch's switch, or cannot be simulated.
pub fn follows_history(campaign: &Campaign, effects: &[Effect], sigma: f64) -> bool {
    if !campaign
        .runs
        .iter()
        .any(|r| r.mechanism.has_physical_latch())
    {
        return false;
    }
    let Some(measured) = measured_history(campaign) else {
        return false;
    };
    let settled: Vec<Option<(f64, usize)>> = (0..campaign.runs.len())
        .into_par_iter()
        .map(|i| {
            let cr = &campaign.runs[i];
            // The switches and the settling, not the angles against the
            // runs: no encoder offset applied to either.
            let base = fit_sim_options_for(&cr.mechanism);
            let traj = deployment::simulate_at(&cr.mechanism, effects, &base, &cr.run.t_s).ok()?;
            let same = measured[i].iter().enumerate().all(|(j, m)| match m {
                Some(n) => traj.latched.get(j).is_some_and(|l| closings(l) == *n),
                None => true,
            });
            if !same {
                return None;
            }
            let tight = SimOptions {
                rtol: base.rtol * TIGHTER,
                atol: base.atol * TIGHTER,
                ..base
            };
            let fine = deployment::simulate_at(&cr.mechanism, effects, &tight, &cr.run.t_s).ok()?;
            let (mut ss, mut n) = (0.0, 0usize);
            for (a, b) in traj.phi_deg.iter().zip(&fine.phi_deg) {
                ss += a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>();
                n += a.len().min(b.len());
            }
            Some((ss, n))
        })
        .collect();
    let Some(all) = settled.into_iter().collect::<Option<Vec<_>>>() else {
        return false;
    };
    let (ss, n) = all.iter().fold((0.0, 0), |(s, k), (a, b)| (s + a, k + b));
    n > 0 && (ss / n as f64).sqrt() < SETTLED_SHARE * sigma
}

/// A switch transition of the model is paired with the run's when the two
/// lie within this time of each other \[s\]: an effect moves an impact
/// continuously, by a few samples at most, while a rebound more or less
/// puts the sequences out of step by the whole rebound.
pub const SWITCH_SLACK_S: f64 = 0.05;

/// Each state change of a switch (its sample index): open to closed and
/// closed to open, and the first sample when it is closed there.
fn transitions(switch: &[bool]) -> Vec<usize> {
    let mut v: Vec<usize> = (1..switch.len())
        .filter(|&i| switch[i] != switch[i - 1])
        .collect();
    if switch.first() == Some(&true) {
        v.insert(0, 0);
    }
    v
}

/// The first sample at which two switch histories (`run`, `model`, at the
/// same stamps `t_s`) part: the earlier of the first pair of the n-th state
/// changes more than [`SWITCH_SLACK_S`] apart, or of a change without a
/// counterpart; `None` when they change alike throughout.
fn parting(run: &[bool], model: &[bool], t_s: &[f64]) -> Option<usize> {
    let (a, b) = (transitions(run), transitions(model));
    let at = |i: usize| t_s.get(i).copied().unwrap_or(f64::INFINITY);
    (0..a.len().max(b.len())).find_map(|n| match (a.get(n), b.get(n)) {
        (Some(&x), Some(&y)) if (at(x) - at(y)).abs() <= SWITCH_SLACK_S => None,
        (Some(&x), Some(&y)) => Some(x.min(y)),
        (Some(&x), None) | (None, Some(&x)) => Some(x),
        (None, None) => None,
    })
}

/// The window of run `cr` the model with `effects` follows
/// (`docs/diagnosis.md`, "Runs of a physical latch", 6): up to the first
/// sample where a switch of a physical latch changes state without its
/// counterpart in the model within [`SWITCH_SLACK_S`], or where the same
/// model at a tenth of the fit's integration tolerance moves a joint by
/// [`SETTLED_SHARE`] of the noise σ̂ `sigma` \[deg\] or more (the window's
/// joint: the one that parts there); `None` when the run lacks a physical
/// latch's switch or cannot be simulated.
pub fn horizon(cr: &CampaignRun, effects: &[Effect], sigma: f64) -> Option<RunWindow> {
    let len = cr.run.len();
    let base = fit_sim_options_for(&cr.mechanism);
    let traj = deployment::simulate_at(&cr.mechanism, effects, &base, &cr.run.t_s).ok()?;
    let tight = SimOptions {
        rtol: base.rtol * TIGHTER,
        atol: base.atol * TIGHTER,
        ..base
    };
    let fine = deployment::simulate_at(&cr.mechanism, effects, &tight, &cr.run.t_s).ok()?;
    // (first sample not followed, its joint 1-based)
    let mut h: (usize, Option<usize>) = (len, None);
    let mut part = |i: usize, j: usize| {
        if i < h.0 {
            h = (i, Some(j + 1));
        }
    };
    for (j, (a, b)) in traj.phi_deg.iter().zip(&fine.phi_deg).enumerate() {
        let mut unsettled = a.iter().zip(b);
        if let Some(i) = unsettled.position(|(x, y)| (x - y).abs() >= SETTLED_SHARE * sigma) {
            part(i, j);
        }
    }
    for j in 0..cr.mechanism.joint_count() {
        if cr.mechanism.latch(j).is_none() {
            continue;
        }
        let run = cr.run.latch.get(j).filter(|s| s.len() == len)?;
        let model = traj.latched.get(j)?;
        if let Some(i) = parting(run, model, &cr.run.t_s) {
            part(i, j);
        }
    }
    Some(window_to(h.0, len, &cr.run.t_s, h.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closings_count_each_closing_and_a_switch_closed_at_the_start() {
        assert_eq!(closings(&[]), 0);
        assert_eq!(closings(&[false, false]), 0);
        assert_eq!(closings(&[true, true, false]), 1);
        assert_eq!(closings(&[false, true, false, true, true]), 2);
        assert_eq!(closings(&[true, false, true]), 2);
    }

    #[test]
    fn switches_part_at_the_first_change_without_its_counterpart() {
        let t: Vec<f64> = (0..40).map(|i| f64::from(i) * 0.01).collect();
        let at = |on: &[usize]| (0..40).map(|i| on.contains(&i)).collect::<Vec<bool>>();
        // The same closing, 2 samples apart: followed.
        let run = at(&[10, 11, 12, 13]);
        assert_eq!(parting(&run, &at(&[12, 13, 14, 15]), &t), None);
        // 8 samples apart (0.08 s > 0.05 s): parted at the earlier.
        assert_eq!(parting(&run, &at(&[18, 19, 20, 21]), &t), Some(10));
        // A closing more in the model: its closing at 25 has no
        // counterpart in the run.
        let model = at(&[10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 25, 26]);
        let run = at(&[10, 11, 12, 13, 14, 15, 16, 17, 18, 19]);
        assert_eq!(parting(&run, &model, &t), Some(25));
        // A switch closed at the first sample counts as a change there.
        assert_eq!(parting(&at(&[0, 1]), &at(&[8]), &t), Some(0));
        assert_eq!(transitions(&at(&[0, 1, 5])), vec![0, 2, 5, 6]);
    }
}
