//! The model's side of a campaign: each run simulated at its own time
//! stamps with the campaign's effects, and the residuals (model minus
//! measurement) that identification and diagnosis fit.

use crate::data::campaign::Campaign;
use crate::model::effect::{self, Effect};
use crate::simulate::deployment::{self, SimOptions, Trajectory};
use rayon::prelude::*;

/// Relative tolerance of the model runs of a fit: the angles are then
/// within about 1e-5 deg of the converged solution, three orders below the
/// sensor noise, at two thirds of the cost of the default 1e-8.
pub const FIT_RTOL: f64 = 1e-7;

/// Absolute tolerance of the model runs of a fit [rad, rad/s].
pub const FIT_ATOL: f64 = 1e-9;

/// The integration settings of a campaign's model runs: [`FIT_RTOL`],
/// [`FIT_ATOL`], the whole run length (no stop at the last latch), and the
/// energy ledger booked but not enforced (`max_drift` infinite). A fit is
/// judged by its residuals, at the accuracy `FIT_RTOL` sets: the ledger's
/// step budget would retake the steps that tolerance relaxes (holding each
/// model run to the default accuracy, several times the cost), and a run
/// stopped on drift would leave a hole in the cost the optimiser walks
/// (`docs/diagnosis.md`, "Method", 1).
pub fn fit_sim_options() -> SimOptions {
    SimOptions {
        rtol: FIT_RTOL,
        atol: FIT_ATOL,
        stop_when_deployed: false,
        max_drift: f64::INFINITY,
        ..SimOptions::default()
    }
}

/// A campaign's runs simulated: implemented for [`Campaign`].
pub trait CampaignSim {
    /// Simulates run `i` with `effects`, sampled at the run's own time stamps
    /// over its whole length (encoder offsets applied to the angles).
    fn simulate(&self, i: usize, effects: &[Effect]) -> Result<Trajectory, deployment::SimError>;
    /// [`CampaignSim::simulate`] with the settings `opts` instead of the
    /// fit's ([`fit_sim_options_for`]).
    fn simulate_with(
        &self,
        i: usize,
        effects: &[Effect],
        opts: &SimOptions,
    ) -> Result<Trajectory, deployment::SimError>;
    /// Model minus measurement \[deg\] of run `i`, joint by joint
    /// (`[joint][sample]`).
    fn residuals(&self, i: usize, effects: &[Effect]) -> Option<Vec<Vec<f64>>>;
    /// All residuals of all runs, flattened (runs simulated in parallel).
    fn residual_vector(&self, effects: &[Effect]) -> Option<Vec<f64>>;
    /// RMS of the residuals of all runs \[deg\], `None` if a simulation fails.
    fn rms(&self, effects: &[Effect]) -> Option<f64>;
    /// The lengths of the contiguous time series of
    /// [`CampaignSim::residual_vector`], in its order: one per joint of each
    /// run (the run's sample count) — what an autocorrelation-consistent
    /// interval lags within ([`crate::analysis::fit::Residuals::series`]).
    fn series_lengths(&self) -> Vec<usize>;
}

/// Relative tolerance of the model runs of a fit on a wing with flexible
/// panels: their angles are then within about 1e-6 deg of the converged
/// solution (`cargo run --release -p deploywatch-sim --example
/// flexible_cost`), closer than a rigid wing's at [`FIT_RTOL`], whose
/// steps the panels' ringing would otherwise keep short.
pub const FLEXIBLE_FIT_RTOL: f64 = 1e-6;

/// Absolute tolerance of the model runs of a fit on a flexible wing [rad,
/// rad/s].
pub const FLEXIBLE_FIT_ATOL: f64 = 1e-7;

/// [`fit_sim_options`] for `mech`: with flexible panels at
/// [`FLEXIBLE_FIT_RTOL`] and [`FLEXIBLE_FIT_ATOL`].
pub fn fit_sim_options_for(mech: &crate::model::mechanism::Mechanism) -> SimOptions {
    match mech.flexible {
        Some(_) => SimOptions {
            rtol: FLEXIBLE_FIT_RTOL,
            atol: FLEXIBLE_FIT_ATOL,
            ..fit_sim_options()
        },
        None => fit_sim_options(),
    }
}

impl CampaignSim for Campaign {
    fn simulate(&self, i: usize, effects: &[Effect]) -> Result<Trajectory, deployment::SimError> {
        self.simulate_with(i, effects, &fit_sim_options_for(&self.runs[i].mechanism))
    }

    fn simulate_with(
        &self,
        i: usize,
        effects: &[Effect],
        opts: &SimOptions,
    ) -> Result<Trajectory, deployment::SimError> {
        let r = &self.runs[i];
        let mut traj = deployment::simulate_at(&r.mechanism, effects, opts, &r.run.t_s)?;
        let offsets = effect::encoder_offsets_deg(effects, r.mechanism.joint_count());
        for (j, b) in offsets.iter().enumerate() {
            if *b != 0.0 {
                for x in traj.phi_deg[j].iter_mut() {
                    *x += b;
                }
            }
        }
        Ok(traj)
    }

    fn residuals(&self, i: usize, effects: &[Effect]) -> Option<Vec<Vec<f64>>> {
        let traj = self.simulate(i, effects).ok()?;
        let run = &self.runs[i].run;
        if traj.t_s.len() != run.len() {
            return None;
        }
        Some(
            (0..run.joints())
                .map(|j| {
                    traj.phi_deg[j]
                        .iter()
                        .zip(&run.phi_deg[j])
                        .map(|(m, y)| m - y)
                        .collect()
                })
                .collect(),
        )
    }

    fn residual_vector(&self, effects: &[Effect]) -> Option<Vec<f64>> {
        let per_run: Vec<Option<Vec<Vec<f64>>>> = (0..self.runs.len())
            .into_par_iter()
            .map(|i| self.residuals(i, effects))
            .collect();
        let mut out = Vec::with_capacity(self.samples());
        for r in per_run {
            for joint in r? {
                out.extend(joint);
            }
        }
        Some(out)
    }

    fn series_lengths(&self) -> Vec<usize> {
        self.runs
            .iter()
            .flat_map(|r| std::iter::repeat_n(r.run.len(), r.run.joints()))
            .collect()
    }

    fn rms(&self, effects: &[Effect]) -> Option<f64> {
        let r = self.residual_vector(effects)?;
        Some((r.iter().map(|x| x * x).sum::<f64>() / r.len().max(1) as f64).sqrt())
    }
}
