//! A test campaign: measured runs, each paired with its mechanism by the
//! run's `mechanism` metadata (`docs/spec/formats.md`), and the model's
//! residuals against them. The effects of a campaign are common to all its
//! runs (same rig, same hardware); each run keeps its own mechanism.

use crate::data::run::{check_analysable, pair_runs, Run};
use crate::model::mechanism::Mechanism;
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

/// Runs of one campaign. The model's side of a campaign (its runs
/// simulated, the residuals) is `analysis::campaign_sim`.
#[derive(Clone, Debug, Default)]
pub struct Campaign {
    /// The runs, in the order given.
    pub runs: Vec<CampaignRun>,
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
    /// A run given twice (the same file, or a copy: the same samples).
    #[error("{file}: the same samples as {first}: a run given twice would count as new evidence and narrow every interval; give each run once")]
    SameRunTwice {
        /// The run given again.
        file: String,
        /// The run it repeats.
        first: String,
    },
    /// A run whose time stamps do not start at 0.
    #[error("{file}:{line}: column `t_s` (column 1): the first sample is at t = {t0} s; a run starts at the release, t = 0: a logger's clock? {} t_s", shift_words(*t0))]
    NotFromRelease {
        /// The run.
        file: String,
        /// Line of its first sample in the file.
        line: usize,
        /// Its first time stamp \[s\].
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
            let same = out
                .runs
                .iter()
                .find(|r| r.run.t_s == run.t_s && r.run.phi_deg == run.phi_deg);
            if let Some(first) = same {
                return Err(CampaignError::SameRunTwice {
                    file: path.display().to_string(),
                    first: first.source.display().to_string(),
                });
            }
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
            // The metadata lines, then the header, then the first sample.
            let line = run.metadata.len() + 2;
            return Err(CampaignError::NotFromRelease { file, line, t0 });
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

    /// The largest joint count of the campaign's mechanisms.
    pub fn max_joints(&self) -> usize {
        self.runs.iter().map(|r| r.run.joints()).max().unwrap_or(0)
    }
}

/// The shift that starts a run at `t = 0`, in words: what to do to every
/// `t_s` of a run whose first sample is at `t0` \[s\].
fn shift_words(t0: f64) -> String {
    if t0 > 0.0 {
        format!("subtract {t0} s from every")
    } else {
        format!("add {} s to every", -t0)
    }
}
