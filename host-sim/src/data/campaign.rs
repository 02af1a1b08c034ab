//! A test campaign: measured runs, each paired with its mechanism by the
//! run's `mechanism` metadata (`docs/spec/formats.md`), and the model's
//! residuals against them. The effects of a campaign are common to all its
//! runs (same rig, same hardware); each run keeps its own mechanism.

use crate::data::run::{check_analysable, pair_runs, Run};
use crate::model::effect::{self, Effect};
use crate::model::mechanism::Mechanism;
use crate::simulate::deployment::{self, SimOptions, Trajectory};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// One measured run with its mechanism.
#[derive(Clone, Debug)]
pub struct CampaignRun {
    /// Where the run came from (for reports).
    pub source: PathBuf,
    /// The measurements.
    pub run: Run,
    /// The mechanism it was measured on, as given (nominal).
    pub mechanism: Mechanism,
}

impl CampaignRun {
    /// The file name of the run, for reports.
    pub fn name(&self) -> String {
        self.source
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| self.source.display().to_string())
    }
}

/// Runs of one campaign.
#[derive(Clone, Debug)]
pub struct Campaign {
    /// The runs, in the order given.
    pub runs: Vec<CampaignRun>,
    /// Integration settings of the model runs. Fits use rtol 1e-7: the
    /// angles are then within about 1e-5 deg of the converged solution,
    /// three orders below the sensor noise, at two thirds of the cost.
    pub sim: SimOptions,
}

impl Default for Campaign {
    fn default() -> Self {
        Campaign {
            runs: Vec::new(),
            sim: SimOptions {
                rtol: 1e-7,
                atol: 1e-9,
                stop_when_deployed: false,
                ..SimOptions::default()
            },
        }
    }
}

/// Why a campaign could not be assembled.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CampaignError {
    /// A mechanism file is invalid.
    #[error(transparent)]
    Mechanism(#[from] crate::model::mechanism_toml::MechanismError),
    /// A run file is invalid or cannot be paired.
    #[error(transparent)]
    Run(#[from] crate::data::run::RunError),
    /// Nothing to work on.
    #[error("no runs given")]
    NoRuns,
    /// A run whose time stamps do not start at 0.
    #[error("{file}: the first sample is at t = {t0} s; a run starts at the release, t = 0")]
    NotFromRelease {
        /// The run.
        file: String,
        /// Its first time stamp [s].
        t0: f64,
    },
}

impl Campaign {
    /// The joints an effect or EFT may name in every run's mechanism: the
    /// hinges, then a truss wing's friction nodes
    /// ([`Mechanism::effect_joints`](crate::model::mechanism::Mechanism::effect_joints));
    /// the least over the runs.
    pub fn effect_joints(&self) -> usize {
        self.runs
            .iter()
            .map(|r| r.mechanism.effect_joints())
            .min()
            .unwrap_or(0)
    }

    /// Loads mechanisms and runs and pairs them.
    pub fn load(mechanisms: &[PathBuf], runs: &[PathBuf]) -> Result<Campaign, CampaignError> {
        let mechs = mechanisms
            .iter()
            .map(|p| Mechanism::load(p))
            .collect::<Result<Vec<_>, _>>()?;
        let mut out = Campaign::default();
        for path in runs {
            let run = Run::load(path)?;
            out.push(&mechs, run, path)?;
        }
        if out.runs.is_empty() {
            return Err(CampaignError::NoRuns);
        }
        Ok(out)
    }

    /// Adds a run already in memory, pairing it with one of `mechanisms`.
    pub fn push(
        &mut self,
        mechanisms: &[Mechanism],
        run: Run,
        source: &Path,
    ) -> Result<(), CampaignError> {
        let file = source.display().to_string();
        let mechanism = pair_runs(mechanisms, &run, &file)?.clone();
        // Units, signs and switches against the mechanism, before any work.
        crate::data::consistency::check(&run, &mechanism, &file)?;
        // A run that never moves, or that stops before its joints latched
        // and before the mechanism's duration, is refused, not fitted.
        check_analysable(&run, &mechanism, &file)?;
        let t0 = run.t_s.first().copied().unwrap_or(0.0);
        if t0.abs() > 1e-9 {
            return Err(CampaignError::NotFromRelease { file, t0 });
        }
        self.runs.push(CampaignRun {
            source: source.to_path_buf(),
            run,
            mechanism,
        });
        Ok(())
    }

    /// Total number of angle samples (joints × samples, all runs).
    pub fn samples(&self) -> usize {
        self.runs.iter().map(|r| r.run.len() * r.run.joints()).sum()
    }

    /// Simulates run `i` with `effects`, sampled at the run's own time stamps
    /// over its whole length (encoder offsets applied to the angles).
    pub fn simulate(
        &self,
        i: usize,
        effects: &[Effect],
    ) -> Result<Trajectory, deployment::SimError> {
        let r = &self.runs[i];
        let mut traj = deployment::simulate_at(&r.mechanism, effects, &self.sim, &r.run.t_s)?;
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

    /// Model minus measurement [deg] of run `i`, joint by joint
    /// (`[joint][sample]`).
    pub fn residuals(&self, i: usize, effects: &[Effect]) -> Option<Vec<Vec<f64>>> {
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

    /// All residuals of all runs, flattened (runs simulated in parallel).
    pub fn residual_vector(&self, effects: &[Effect]) -> Option<Vec<f64>> {
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

    /// RMS of the residuals of all runs [deg], `None` if a simulation fails.
    pub fn rms(&self, effects: &[Effect]) -> Option<f64> {
        let r = self.residual_vector(effects)?;
        Some((r.iter().map(|x| x * x).sum::<f64>() / r.len().max(1) as f64).sqrt())
    }

    /// The largest joint count of the campaign's mechanisms.
    pub fn max_joints(&self) -> usize {
        self.runs.iter().map(|r| r.run.joints()).max().unwrap_or(0)
    }
}
