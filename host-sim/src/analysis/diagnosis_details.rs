//! What a diagnosis's report and JSON show beside the search's
//! [`Outcome`]: the evidence before and after the extension, the residual
//! torque of both models, the monitor's export of each discovered table,
//! the trajectory error per joint, and every run simulated with and
//! without the effects found; with the thresholds those views apply.
//!
//! Computed here, once, so that the report writers (`report::diagnosis`)
//! only write what they are given.

use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::diagnose::{Candidate, Outcome, MIN_DELTA_BIC};
use crate::analysis::evidence::{self, JointEvidence};
use crate::analysis::metrics::{self, TimeWindow};
use crate::analysis::residual_torque::{self, JointTorque};
use crate::analysis::table_export::{self, TableExport};
use crate::data::campaign::Campaign;
use crate::simulate::deployment::Trajectory;

/// A joint's baseline residual is named in the evidence of an
/// `"unexplained"` effect when its RMS exceeds this many noise standard
/// deviations (ratio): above what noise alone leaves.
pub const UNEXPLAINED_NOISE_FACTOR: f64 = 3.0;

/// Smallest extended RMS the gain's ratio divides by \[deg\]: a perfect fit
/// gives a large finite ratio, not infinity.
pub const MIN_RMS_DEG: f64 = 1e-12;

/// The gain of the extended model: baseline RMS / extended RMS (ratio),
/// finite for a perfect fit ([`MIN_RMS_DEG`]).
pub fn gain_ratio(o: &Outcome) -> f64 {
    o.baseline.rms() / o.extended.rms().max(MIN_RMS_DEG)
}

/// The joints of `before` whose residual is above the noise
/// ([`UNEXPLAINED_NOISE_FACTOR`] × σ̂): what an `"unexplained"` effect
/// points at.
pub fn above_noise(
    before: &[JointEvidence],
    noise_sigma_deg: f64,
) -> impl Iterator<Item = &JointEvidence> {
    before
        .iter()
        .filter(move |e| e.rms_deg > UNEXPLAINED_NOISE_FACTOR * noise_sigma_deg)
}

/// Other candidates that explained the data as well (ΔBIC within
/// [`MIN_DELTA_BIC`] of the chosen one) in the round that chose `c`, each
/// with how much worse its BIC is.
pub fn alternatives(o: &Outcome, c: Candidate) -> Vec<(Candidate, f64)> {
    for r in &o.rounds {
        if let Some(win) = r.scores.iter().find(|s| s.accepted() && s.candidate == c) {
            return r
                .scores
                .iter()
                .filter(|s| s.candidate != c && win.delta_bic - s.delta_bic < MIN_DELTA_BIC)
                .map(|s| (s.candidate, win.delta_bic - s.delta_bic))
                .collect();
        }
    }
    Vec::new()
}

/// One run simulated with the baseline (no effect) and with the extended
/// model; `None` where the simulation fails.
#[derive(Clone, Debug)]
pub struct RunModels {
    /// The mechanisms as given.
    pub baseline: Option<Trajectory>,
    /// With the effects found.
    pub extended: Option<Trajectory>,
}

/// Everything a diagnosis report shows beside the [`Outcome`].
#[derive(Clone, Debug)]
pub struct Details {
    /// The evidence of each run and joint against the baseline.
    pub before: Vec<JointEvidence>,
    /// The same against the extended model.
    pub after: Vec<JointEvidence>,
    /// The residual torque of each joint: `[baseline, extended]`.
    pub torque: [Vec<JointTorque>; 2],
    /// The monitor's export of each discovered table.
    pub exports: Vec<TableExport>,
    /// Trajectory error per joint [%] (seed 000 Eq. 14), averaged over the
    /// runs: `[baseline, extended]`.
    pub trajectory_error_pct: [Vec<Option<f64>>; 2],
    /// Each run simulated with both models, in campaign order.
    pub runs: Vec<RunModels>,
}

/// The details of `outcome` on `campaign` (the campaign the effects were
/// fitted on: for runs of a physical latch, their free motion).
pub fn details(campaign: &Campaign, outcome: &Outcome) -> Details {
    let sigma = outcome.noise_sigma_deg;
    let ext = outcome.extended.effects();
    let runs: Vec<RunModels> = (0..campaign.runs.len())
        .map(|i| RunModels {
            baseline: campaign.simulate(i, &[]).ok(),
            extended: campaign.simulate(i, &ext).ok(),
        })
        .collect();
    Details {
        before: evidence::analyse(campaign, &[], sigma),
        after: evidence::analyse(campaign, &ext, sigma),
        torque: [
            residual_torque::residual_torque(campaign, &[]),
            residual_torque::residual_torque(campaign, &ext),
        ],
        exports: table_export::export_tables(campaign, &ext),
        trajectory_error_pct: [
            te_per_joint(campaign, &runs, |r| r.baseline.as_ref()),
            te_per_joint(campaign, &runs, |r| r.extended.as_ref()),
        ],
        runs,
    }
}

/// Trajectory error per joint (seed 000 Eq. 14) of one model, averaged
/// over the runs it simulates.
fn te_per_joint(
    c: &Campaign,
    runs: &[RunModels],
    model: impl Fn(&RunModels) -> Option<&Trajectory>,
) -> Vec<Option<f64>> {
    let n = c.max_joints();
    let mut acc = vec![(0.0, 0usize); n];
    for (cr, m) in c.runs.iter().zip(runs) {
        let Some(traj) = model(m) else {
            continue;
        };
        let r = &cr.run;
        if let Ok(te) = metrics::trajectory_errors_pct(
            &r.t_s,
            &traj.phi_deg,
            &r.phi_deg,
            &r.latch,
            TimeWindow::ALL,
        ) {
            for (j, v) in te.iter().enumerate() {
                if let Some(v) = v {
                    acc[j].0 += v;
                    acc[j].1 += 1;
                }
            }
        }
    }
    acc.iter()
        .map(|(s, k)| (*k > 0).then(|| s / *k as f64))
        .collect()
}
