//! What the identified EFTs leave unexplained: the joints whose residual
//! stays above a multiple of the noise, with where in the stroke, and
//! synthetic runs for the tests.

use super::*;

/// `identify` warns when a joint's residual after the fit exceeds this
/// multiple of the noise RMS \[1\]: the EFT alone then leaves a systematic
/// error, as [`crate::analysis::evidence`] calls a residual "clear"
/// of the noise above 3 σ.
pub const RESIDUAL_WARN_FACTOR: f64 = 3.0;

/// The least noise RMS the warning threshold assumes \[deg\]: runs of true
/// angles (`simulate --no-noise`) have none, and a fit is never warned
/// about for residuals of a few thousandths of a degree.
pub const RESIDUAL_WARN_NOISE_FLOOR_DEG: f64 = 0.001;

/// A joint of a run that the identified EFTs do not explain down to the
/// noise: a hint that something other than Coulomb friction is at work.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ResidualWarning {
    /// The run's file name.
    pub run: String,
    /// 1-based joint.
    pub joint: usize,
    /// RMS of the residual after the fit \[deg\].
    pub rms_deg: f64,
    /// The noise RMS estimated from the runs \[deg\].
    pub noise_deg: f64,
    /// Where in the stroke the residual is largest, in words: the first,
    /// middle or last third of the measured angle's way to the latch.
    pub where_in_stroke: &'static str,
}

impl std::fmt::Display for ResidualWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} joint {}: {:.3} deg RMS ({:.1} times the noise), largest {}",
            self.run,
            self.joint,
            self.rms_deg,
            self.rms_deg / self.noise_deg.max(1e-12),
            self.where_in_stroke
        )
    }
}

/// The joints whose residual with the identified EFTs stays above
/// [`RESIDUAL_WARN_FACTOR`] × the noise RMS (estimated from the runs,
/// [`crate::analysis::evidence::noise_sigma_estimate`]), with where in the
/// stroke; none where the runs are too short to estimate their noise.
pub fn residual_warnings(campaign: &Campaign, id: &Identification) -> Vec<ResidualWarning> {
    use crate::analysis::evidence::{self, noise_sigma_estimate};
    let Some(sigma) = noise_sigma_estimate(campaign) else {
        return Vec::new();
    };
    let sigma = sigma.max(RESIDUAL_WARN_NOISE_FLOOR_DEG);
    let limit = RESIDUAL_WARN_FACTOR * sigma;
    evidence::analyse(campaign, &id.effects(), sigma)
        .into_iter()
        .filter(|e| e.rms_deg > limit)
        .map(|e| {
            let third = e
                .stroke_thirds_rms_deg
                .iter()
                .enumerate()
                .filter(|(_, v)| v.is_finite())
                .max_by(|a, b| a.1.total_cmp(b.1))
                .map_or(0, |(k, _)| k);
            ResidualWarning {
                run: e.run,
                joint: e.joint,
                rms_deg: e.rms_deg,
                noise_deg: sigma,
                where_in_stroke: [
                    "early in the stroke",
                    "in mid-stroke",
                    "late in the stroke (near the latch)",
                ][third],
            }
        })
        .collect()
}

/// A synthetic measured run: `mech` simulated with `effects` (default
/// [`crate::simulate::deployment::SimOptions`]: the run ends at the first sample at or after
/// the last latch, formats.md) and read by the reference sensor
/// ([`crate::simulate::sensor::SensorModel::REFERENCE`], N(0, 0.02°) then 14 bits)
/// with noise seed `seed`; its `mechanism` metadata names `mech`.
pub fn synthetic_run(
    mech: &crate::model::mechanism::Mechanism,
    effects: &[Effect],
    seed: u64,
) -> Result<crate::data::run::Run, crate::simulate::deployment::SimError> {
    use crate::simulate::sensor::{self, SensorModel};
    let traj = crate::simulate::deployment::simulate(
        mech,
        effects,
        &crate::simulate::deployment::SimOptions::default(),
    )?;
    let offsets = crate::model::effect::encoder_offsets_deg(effects, mech.joint_count());
    let mut run = sensor::measure(&traj, &offsets, &SensorModel::REFERENCE, seed);
    run.set_meta("mechanism", &mech.name);
    run.set_meta(
        "source",
        &format!("synthetic: reference sensor, seed {seed}"),
    );
    Ok(run)
}

/// Why [`synthetic_campaign`] failed.
#[derive(Debug, thiserror::Error)]
pub enum SyntheticError {
    /// A run's simulation failed.
    #[error(transparent)]
    Simulation(#[from] crate::simulate::deployment::SimError),
    /// A run did not join the campaign.
    #[error(transparent)]
    Campaign(#[from] crate::data::campaign::CampaignError),
}

/// A synthetic campaign with known friction: run `i` is `mechanisms[i]`
/// simulated with `coulomb_friction` of `coulomb_nm[j]` N·m at joint
/// `j + 1` and read as [`synthetic_run`] reads it with noise seed
/// `seeds[i]` (one run per mechanism and seed, as many as the shorter of
/// the two), its source named `<mechanism name>.csv`.
pub fn synthetic_campaign(
    mechanisms: &[crate::model::mechanism::Mechanism],
    coulomb_nm: &[f64],
    seeds: &[u64],
) -> Result<Campaign, SyntheticError> {
    let effects: Vec<Effect> = coulomb_nm
        .iter()
        .enumerate()
        .map(|(j, &v)| Effect::joint(EffectKind::CoulombFriction, j + 1, v))
        .collect();
    let mut campaign = Campaign::default();
    for (mech, &seed) in mechanisms.iter().zip(seeds) {
        let run = synthetic_run(mech, &effects, seed)?;
        let source = format!("{}.csv", mech.name);
        campaign.push(mechanisms, run, std::path::Path::new(&source))?;
    }
    Ok(campaign)
}
