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
    /// Its name in reports where its file name alone is another run's
    /// too ([`CampaignRun::name`]); `None`: the file name.
    pub label: Option<String>,
}

impl CampaignRun {
    /// The file name of the run, for reports; runs of one campaign whose
    /// file names are the same are told apart by their folders
    /// ([`Campaign::push`] sets it).
    pub fn name(&self) -> String {
        self.label
            .clone()
            .unwrap_or_else(|| suffix(&self.source, 1))
    }
}

/// The last `k` components of `path`, joined by `/` (the whole path when
/// it has fewer).
fn suffix(path: &Path, k: usize) -> String {
    let parts: Vec<String> = path
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .filter(|c| c != "/" && c != ".")
        .collect();
    if parts.is_empty() {
        return path.display().to_string();
    }
    parts[parts.len().saturating_sub(k)..].join("/")
}

/// Each run's label: its file name, or where two runs share it, the
/// fewest trailing folders that tell them apart (`a/run.csv`,
/// `b/run.csv`), so that their report sections and plots do not collide.
fn relabel(runs: &mut [CampaignRun]) {
    let depth = |p: &Path| p.components().count().max(1);
    let names: Vec<String> = (0..runs.len())
        .map(|i| {
            let mut k = 1;
            loop {
                let mine = suffix(&runs[i].source, k);
                let clash = runs
                    .iter()
                    .enumerate()
                    .any(|(j, r)| j != i && suffix(&r.source, k) == mine);
                if !clash || k >= depth(&runs[i].source) {
                    return mine;
                }
                k += 1;
            }
        })
        .collect();
    for (r, name) in runs.iter_mut().zip(names) {
        r.label = Some(name);
    }
}

/// Runs of one campaign. The model's side of a campaign (its runs
/// simulated, the residuals) is `analysis::campaign_sim`.
#[derive(Clone, Debug, Default)]
pub struct Campaign {
    /// The runs, in the order given.
    pub runs: Vec<CampaignRun>,
    /// What was done to a run to start it at the release, one sentence
    /// each ([`from_release`]): the CLI's warnings.
    pub notes: Vec<String>,
}

/// The largest distance \[deg\] of a reading before `t = 0` from the
/// reading at the release for the rows before it to be a logger's
/// pre-trigger, the wing at rest: ten times the noise of a coarse rig
/// encoder (0.05 deg).
pub const PRETRIGGER_REST_DEG: f64 = 0.5;

/// The most sample intervals (the run's median) by which a run's first
/// sample may follow the release and still be a run from the release
/// whose sample at `t = 0` was not recorded.
pub const LOST_START_SAMPLES: f64 = 1.5;

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
    /// Two different mechanisms under one name: a run of that name could
    /// be paired with either.
    #[error("{second}: mechanism \"{name}\" is also the name of {first}, a different mechanism: a run of \"{name}\" could be paired with either; expected one mechanism file per name (give one of them, or rename the other: `name = ...`)")]
    SameNameTwice {
        /// The name.
        name: String,
        /// The file first given under it.
        first: String,
        /// The other file.
        second: String,
    },
    /// A run given twice (the same file, or a copy: the same samples).
    #[error("{file}: the same samples as {first}: a run given twice would count as new evidence and narrow every interval; give each run once")]
    SameRunTwice {
        /// The run given again.
        file: String,
        /// The run it repeats.
        first: String,
    },
    /// A run whose time stamps do not start at the release, `t = 0`
    /// ([`from_release`]).
    #[error("{file}:{line}: column `t_s` (column 1): the first sample is at t = {t0} s; a run starts at the release, t = 0: {}", shift_words(*t0))]
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

    /// Loads mechanisms and runs and pairs them; two different mechanisms
    /// under one name are refused, naming both files.
    pub fn load(mechanisms: &[PathBuf], runs: &[PathBuf]) -> Result<Campaign, CampaignError> {
        let mechs = mechanisms
            .iter()
            .map(|p| Mechanism::load(p))
            .collect::<Result<Vec<_>, _>>()?;
        for (i, m) in mechs.iter().enumerate() {
            if let Some(k) = (0..i).find(|&k| mechs[k].name == m.name && mechs[k] != *m) {
                return Err(CampaignError::SameNameTwice {
                    name: m.name.clone(),
                    first: mechanisms[k].display().to_string(),
                    second: mechanisms[i].display().to_string(),
                });
            }
        }
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
        // Glitches named at their lines in the file as read, then left out
        // of every fit (the warnings of the stored run no longer see them).
        let glitches = crate::data::glitch::warnings(&run, &file, |i| {
            crate::data::consistency::line_of_sample(&run, i)
        });
        self.notes.extend(glitches);
        let (run, note) = from_release(run, &file)?;
        self.notes.extend(note);
        let (run, _) = crate::data::glitch::without_glitches(run);
        self.runs.push(CampaignRun {
            source: source.to_path_buf(),
            run,
            mechanism,
            label: None,
        });
        relabel(&mut self.runs);
        Ok(())
    }

    /// Total number of angle samples (joints × samples, all runs).
    pub fn samples(&self) -> usize {
        self.runs.iter().map(|r| r.run.len() * r.run.joints()).sum()
    }

    /// The largest Coulomb friction its mechanisms give joint `joint`
    /// (1-based) of their own \[N·m\] (`friction.coulomb_nm`; 0 where none
    /// has the joint).
    pub fn own_coulomb_nm(&self, joint: usize) -> f64 {
        self.runs
            .iter()
            .filter_map(|r| r.mechanism.joints.get(joint.wrapping_sub(1)))
            .map(|j| j.friction.coulomb_nm)
            .fold(0.0, f64::max)
    }

    /// The largest joint count of the campaign's mechanisms.
    pub fn max_joints(&self) -> usize {
        self.runs.iter().map(|r| r.run.joints()).max().unwrap_or(0)
    }
}

/// `run` from its release at `t = 0`, where every simulation starts, with
/// what was done to it: rows before `t = 0` where every joint rests at its
/// reading at the release (within [`PRETRIGGER_REST_DEG`], switches as
/// then) are a logger's pre-trigger, left out; a first sample within
/// [`LOST_START_SAMPLES`] intervals after `t = 0` is a run whose sample at
/// the release was not recorded, taken as it is. Anything else is refused
/// ([`CampaignError::NotFromRelease`]): a logger's clock, to be shifted.
pub fn from_release(mut run: Run, file: &str) -> Result<(Run, Option<String>), CampaignError> {
    const AT_ZERO_S: f64 = 1e-9;
    let t0 = run.t_s.first().copied().unwrap_or(0.0);
    if t0.abs() <= AT_ZERO_S {
        return Ok((run, None));
    }
    // The metadata lines, then the header, then the first sample.
    let line = run.metadata.len() + 2;
    let refused = CampaignError::NotFromRelease {
        file: file.to_string(),
        line,
        t0,
    };
    let mut steps: Vec<f64> = run.t_s.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let Some(&dt) = steps.get(steps.len() / 2) else {
        return Err(refused);
    };
    if t0 > 0.0 {
        if t0 <= LOST_START_SAMPLES * dt {
            let note = format!(
                "{file}: the first sample is at t = {t0} s, not at the release (t = 0): \
                 taken as a run from the release whose first sample was not recorded"
            );
            return Ok((run, Some(note)));
        }
        return Err(refused);
    }
    let Some(k) = run.t_s.iter().position(|&t| t >= -AT_ZERO_S) else {
        return Err(refused);
    };
    let at_rest = run.phi_deg.iter().zip(&run.latch).all(|(phi, latch)| {
        phi[..k]
            .iter()
            .all(|p| (p - phi[k]).abs() <= PRETRIGGER_REST_DEG)
            && latch[..k].iter().all(|&l| l == latch[k])
    });
    if !at_rest || run.t_s[k] > LOST_START_SAMPLES * dt {
        return Err(refused);
    }
    run.t_s.drain(..k);
    for column in &mut run.phi_deg {
        column.drain(..k);
    }
    for column in &mut run.latch {
        column.drain(..k);
    }
    for column in &mut run.extra {
        column.values.drain(..k);
    }
    let note = format!(
        "{file}: {k} row{} before t = 0 (from t = {t0} s), the wing at rest: a logger's \
         pre-trigger, left out; the run is compared from the release at t = {} s",
        if k == 1 { "" } else { "s" },
        run.t_s.first().copied().unwrap_or(0.0)
    );
    Ok((run, Some(note)))
}

/// The shift that starts a run at `t = 0`, in words: what to do to every
/// `t_s` of a run whose first sample is at `t0` \[s\].
fn shift_words(t0: f64) -> String {
    if t0 > 0.0 {
        format!(
            "a logger's clock? if the release is the first sample, subtract {t0} s from every t_s"
        )
    } else {
        format!(
            "rows before t = 0 where the wing moves (a pre-trigger at rest is left out by \
             itself): a logger's clock? if the release is the first sample, add {} s to every \
             t_s",
            -t0
        )
    }
}
