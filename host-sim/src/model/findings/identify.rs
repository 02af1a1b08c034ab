//! The identification JSON (`deploywatch identify --json`,
//! `docs/spec/formats.md` "Findings JSON"): written by
//! [`crate::analysis::identify`], read by `margin --from` and
//! `reliability --from`. Only `method` and `joints` are required on reading.

use serde::{Deserialize, Serialize};

use super::numbers::{nan_if_null, nans_if_null, not_given};

/// Which identification method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Least squares over the trajectories (seed 001 Eq. 6 as the objective).
    Direct,
    /// Response surface on a central composite design (seed 000 Eqs. 14–16).
    Rsm,
}

/// The EFT identified at one joint.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointEft {
    /// 1-based joint.
    pub joint: usize,
    /// Equivalent friction torque `T_C` [N·m] (`physics.md` 4).
    pub coulomb_nm: f64,
    /// 95 % confidence interval [N·m] (direct method only: from the
    /// Jacobian, `p ± t₀.₉₇₅ · sd`, see `analysis::fit`); `null` for rsm.
    #[serde(default)]
    pub ci95: Option<[f64; 2]>,
    /// Standard deviation of the estimate [N·m] (direct method only).
    #[serde(default)]
    pub sd_nm: Option<f64>,
}

/// How well one run is reproduced by a model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunScore {
    /// The run's file name.
    #[serde(default)]
    pub run: String,
    /// The mechanism it was paired with.
    #[serde(default)]
    pub mechanism: String,
    /// RMS of model minus measurement over every sample and joint \[deg\]
    /// (`physics.md` 8).
    #[serde(deserialize_with = "nan_if_null")]
    pub rms_deg: f64,
    /// Trajectory error of each joint [%] (seed 000 Eq. 14, `physics.md` 8,
    /// whole run); `null` where no sample qualifies.
    #[serde(default)]
    pub trajectory_error_pct: Vec<Option<f64>>,
    /// Sum of squared residuals of each joint over the run \[deg²\].
    #[serde(skip)]
    pub joint_sse_deg2: Vec<f64>,
    /// Samples of the run.
    #[serde(skip)]
    pub samples: usize,
}

/// A model's fit to the whole campaign.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CampaignScore {
    /// RMS over every sample, joint and run \[deg\].
    #[serde(default = "not_given", deserialize_with = "nan_if_null")]
    pub rms_deg: f64,
    /// Per run.
    #[serde(default)]
    pub runs: Vec<RunScore>,
}

/// Details of a direct (least-squares) identification.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DirectDetails {
    /// Where the solver started [N·m], one value per identified joint.
    pub start_nm: Vec<f64>,
    /// How the start was chosen.
    pub start_rule: String,
    /// Sum of squared residuals at the solution \[deg²\] (seed 001 Eq. 6 over
    /// the whole runs).
    #[serde(deserialize_with = "nan_if_null")]
    pub sse_deg2: f64,
    /// Number of residuals (samples × joints, all runs).
    pub residuals: usize,
    /// The solver's verdict.
    pub termination: String,
    /// Joints whose EFT ended below 0 and were fixed at the bound 0.
    pub fixed_at_zero: Vec<usize>,
    /// Of those, the joints whose last free fit put its whole 95 %
    /// interval below 0: the runs hold less friction there than the
    /// mechanism's own, which the bound hides.
    /// Written only when there is one.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub clearly_below_zero: Vec<usize>,
}

/// One response of the design and its fitted quadratic.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResponseSurface {
    /// `te<j>_pct` (trajectory error of joint j, seed 000 Eq. 14, mean over
    /// the runs) or `mse_deg2` (mean squared angle residual, all runs).
    pub name: String,
    /// The response at each design point, in design order.
    #[serde(deserialize_with = "nans_if_null")]
    pub values: Vec<f64>,
    /// R² of the full quadratic (seed 000 Eq. 15) fitted to it.
    #[serde(deserialize_with = "nan_if_null")]
    pub r2: f64,
    /// Adjusted R².
    #[serde(deserialize_with = "nan_if_null")]
    pub adj_r2: f64,
    /// The quadratic's coefficients in coded units, seed 000 Eq. 16 order
    /// (`b0, b1..bk, b12.., b11..bkk`).
    #[serde(deserialize_with = "nans_if_null")]
    pub coded_coefficients: Vec<f64>,
}

/// Details of a response-surface identification.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RsmDetails {
    /// Design centre [N·m].
    pub centre_nm: Vec<f64>,
    /// Half-ranges [N·m]: coded ±1.
    pub half_range_nm: Vec<f64>,
    /// How the centre and half-ranges were chosen.
    pub design_rule: String,
    /// Axial distance α in coded units (1.682 for a rotatable 3-factor CCD).
    pub alpha: f64,
    /// The design points [N·m], in design order (factorial, axial, centre).
    pub points_nm: Vec<Vec<f64>>,
    /// Every response with its fitted surface.
    pub responses: Vec<ResponseSurface>,
    /// The response minimised.
    pub minimised: String,
    /// The box the surface was minimised in [N·m]: `[lower, upper]` per joint.
    pub box_nm: Vec<[f64; 2]>,
    /// The fitted surface's value at its minimum (prediction).
    #[serde(deserialize_with = "nan_if_null")]
    pub predicted: f64,
    /// The same response simulated at the minimum (check).
    #[serde(deserialize_with = "nan_if_null")]
    pub simulated: f64,
    /// Rounds of the design run (the fields above are the last round's).
    pub rounds: usize,
    /// When the surface's minimum leaves residuals above the warning level
    /// and least squares started from it explains the runs to that level:
    /// the friction it found, outside what the design reached. `None`
    /// otherwise (not needed, or friction alone does not explain them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beyond_design: Option<BeyondDesign>,
}

/// The friction that explains a campaign where a response surface's design
/// did not reach it: least squares ([`Method::Direct`]) started from the
/// surface's minimum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BeyondDesign {
    /// The EFT per identified joint [N·m], in the order of `joints`.
    pub coulomb_nm: Vec<f64>,
    /// The campaign RMS with it \[deg\].
    #[serde(deserialize_with = "nan_if_null")]
    pub rms_deg: f64,
    /// Model evaluations it took (counted in the identification's).
    pub simulations: usize,
    /// Where least squares started, in words: the surface's minimum, or
    /// the direct method's own start (its scan).
    pub start: String,
}

/// The outcome of an identification, serialisable to the JSON of
/// `deploywatch identify --json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Identification {
    /// `direct` or `rsm`.
    pub method: Method,
    /// The EFT per identified joint.
    pub joints: Vec<JointEft>,
    /// RMS of the mechanisms as given (no extra friction) against the runs \[deg\].
    #[serde(default = "not_given", deserialize_with = "nan_if_null")]
    pub rms_deg_before: f64,
    /// RMS with the identified EFTs \[deg\].
    #[serde(default = "not_given", deserialize_with = "nan_if_null")]
    pub rms_deg_after: f64,
    /// Model evaluations on the whole campaign (each one deployment of every
    /// run), everything included: start scan, solver or design, checks.
    #[serde(default)]
    pub simulations: usize,
    /// Single deployments simulated (`simulations × runs`).
    #[serde(default)]
    pub deployments: usize,
    /// Wall-clock time of the identification \[s\].
    #[serde(default = "not_given", deserialize_with = "nan_if_null")]
    pub wall_s: f64,
    /// Before: the mechanisms as given, per run.
    #[serde(default)]
    pub before: CampaignScore,
    /// After: with the identified EFTs, per run.
    #[serde(default)]
    pub after: CampaignScore,
    /// Direct method details.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direct: Option<DirectDetails>,
    /// Response-surface details.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rsm: Option<RsmDetails>,
}

impl Identification {
    /// The mechanisms its runs were of (their names, each once, in the
    /// order of the runs; empty when the file does not say).
    pub fn found_on(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for r in &self.after.runs {
            if !r.mechanism.is_empty() && !out.contains(&r.mechanism) {
                out.push(r.mechanism.clone());
            }
        }
        out
    }
}
