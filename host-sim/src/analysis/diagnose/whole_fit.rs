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

use super::outcome::{FittedSet, Outcome};
use super::policy::MIN_DELTA_BIC;
use super::Search;
use crate::analysis::campaign_sim::{fit_sim_options_for, CampaignSim};
use crate::data::campaign::Campaign;
use crate::model::effect::Effect;
use crate::report::progress::Progress;
use crate::simulate::deployment::{self, SimOptions};
use rayon::prelude::*;

/// `first`, the search on the free motion of `campaign`'s runs (`free`:
/// the runs cut to it), or the search on the whole runs (`search`) when
/// the model each finds follows the runs' latch history
/// ([`follows_history`]) and the whole runs' set explains the free motion
/// as well as `first`'s ([`explains_free_motion`]); the outcome kept says
/// which ([`Outcome::fitted_whole`]).
pub fn consider(
    campaign: &Campaign,
    free: &Campaign,
    first: Outcome,
    progress: Progress,
    search: impl FnOnce(&Campaign) -> Outcome,
) -> Outcome {
    let found = first.extended.effects();
    let sigma = first.noise_sigma_deg;
    let follows = |e: &[Effect]| follows_history(campaign, e, sigma);
    // The search on the whole runs starts from the mechanisms as given: a
    // baseline with another rebound count is no landscape to walk.
    if first.partial.is_some() || !follows(&[]) || (!found.is_empty() && !follows(&found)) {
        return first;
    }
    progress(
        "the model found closes each latch switch as often as every run does: searching again on the whole runs",
    );
    let whole = search(campaign);
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
}
