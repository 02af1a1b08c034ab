//! Identification of the equivalent friction torque (EFT) of each joint from
//! measured deployments: the papers' quantity (`physics.md` 4, the Coulomb
//! torque `T_C` with `T_brk = T_C`, `f = 0`), common to every run of a
//! campaign (same hinges, same rig), each run keeping its own mechanism.
//!
//! Two methods, both over simulations of every run of the campaign:
//!
//! - **direct** ([`direct::identify_direct`]): minimise the sum of squared angle
//!   residuals of all runs at once (seed 001 Eq. 6 over the whole runs,
//!   model minus measurement at every sample) over the EFTs with a
//!   derivative-based least-squares solver ([`crate::analysis::fit::least_squares`],
//!   Levenberg–Marquardt, finite-difference Jacobian with one parallel
//!   simulation per column), lower bound 0, 95 % confidence intervals from
//!   the Jacobian at the solution.
//! - **rsm** ([`by_rsm::identify_rsm`]): the method of seed 000 (section 4.3,
//!   Eqs. 14–16, Table 9): a central composite design (CCD) of EFTs around a
//!   centre, every design point simulated (in parallel), a full quadratic
//!   (Eq. 15) fitted to each response with its R², and the fitted surface
//!   minimised inside the box the design explored ([`crate::analysis::identify::rsm`]).
//!
//! A *simulation* in the counts below is one evaluation of the model on the
//! whole campaign, i.e. one deployment of every run; `deployments` counts
//! the single deployments (`simulations × runs`).

pub mod by_rsm;
pub mod direct;
pub mod residual_check;
pub mod rsm;
pub mod rsm_box;

use self::rsm::{CcdKind, Coding, Quadratic};
use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::fit::{self, FitOptions};
use crate::analysis::metrics::{self, TimeWindow};
use crate::data::campaign::Campaign;
use crate::model::effect::{Effect, EffectKind};
pub use crate::model::findings::identify::{
    BeyondDesign, CampaignScore, DirectDetails, Identification, JointEft, Method, ResponseSurface,
    RsmDetails, RunScore,
};
use crate::report::progress::Progress;
use crate::report::text::list;
use crate::simulate::deployment::Trajectory;
use rayon::prelude::*;
use serde::Serialize;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// The uniform EFTs tried by the start scan [N·m]: a geometric grid with
/// ratio √2 from 0.025 to 3.2 N·m (15 values), plus 0.
pub const SCAN_GRID_NM: [f64; 16] = [
    0.0, 0.025, 0.035355, 0.05, 0.070711, 0.1, 0.141421, 0.2, 0.282843, 0.4, 0.565685, 0.8,
    1.131371, 1.6, 2.262742, 3.2,
];

impl Method {
    /// The name used on the command line and in the JSON.
    pub fn name(self) -> &'static str {
        match self {
            Method::Direct => "direct",
            Method::Rsm => "rsm",
        }
    }
}

/// A name on the command line that is not a [`Method`] or an [`RsmResponse`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ParseNameError {
    /// Not one of the accepted names.
    #[error("unknown {what} `{name}`: expected {expected}")]
    UnknownName {
        /// What was being named (`method`, `response`).
        what: &'static str,
        /// The name given.
        name: String,
        /// The accepted names, in words.
        expected: &'static str,
    },
}

impl std::str::FromStr for Method {
    type Err = ParseNameError;
    fn from_str(s: &str) -> Result<Self, ParseNameError> {
        match s {
            "direct" => Ok(Method::Direct),
            "rsm" => Ok(Method::Rsm),
            _ => Err(ParseNameError::UnknownName {
                what: "method",
                name: s.to_string(),
                expected: "`direct` or `rsm`",
            }),
        }
    }
}

impl CampaignScore {
    /// Trajectory error of joint `joint` (1-based) averaged over the runs
    /// where it is defined [%]; `None` if it is defined in none.
    pub fn mean_te_pct(&self, joint: usize) -> Option<f64> {
        let v: Vec<f64> = self
            .runs
            .iter()
            .filter_map(|r| r.trajectory_error_pct.get(joint - 1).copied().flatten())
            .collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    }
}

impl Identification {
    /// The identified EFTs as `coulomb_friction` effects.
    pub fn effects(&self) -> Vec<Effect> {
        self.joints
            .iter()
            .map(|j| Effect::joint(EffectKind::CoulombFriction, j.joint, j.coulomb_nm))
            .collect()
    }

    /// The EFT identified at joint `joint` (1-based) [N·m].
    pub fn eft(&self, joint: usize) -> Option<f64> {
        self.joints
            .iter()
            .find(|j| j.joint == joint)
            .map(|j| j.coulomb_nm)
    }

    /// The parts every method fills the same way: the scores before and
    /// after, the cost; no EFT and no details yet.
    fn scored(
        method: Method,
        model: &Model,
        t0: Instant,
        before: CampaignScore,
        after: CampaignScore,
    ) -> Self {
        Identification {
            method,
            joints: Vec::new(),
            rms_deg_before: before.rms_deg,
            rms_deg_after: after.rms_deg,
            simulations: model.count(),
            deployments: model.count() * model.campaign.runs.len(),
            wall_s: t0.elapsed().as_secs_f64(),
            before,
            after,
            direct: None,
            rsm: None,
        }
    }

    /// Pretty-printed JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }
}

/// Why an identification failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IdentifyError {
    /// No joint selected.
    #[error("no joint to identify")]
    NoJoints,
    /// A joint that some run's mechanism does not have.
    #[error("joint {joint} does not exist in every run (the campaign's mechanisms have joints 1 to {joints})")]
    BadJoint {
        /// The joint asked for (1-based).
        joint: usize,
        /// Joints every mechanism has.
        joints: usize,
    },
    /// A joint selected twice.
    #[error("joint {0} is selected twice")]
    DuplicateJoint(usize),
    /// A vector option of the wrong length or with bad values.
    #[error("{0}")]
    BadOption(String),
    /// The model cannot be simulated (e.g. at the start or at a design point).
    #[error("the model cannot be simulated {0}")]
    Simulation(String),
    /// The least-squares solver failed.
    #[error(transparent)]
    Fit(#[from] fit::FitError),
    /// The response surface could not be fitted or minimised.
    #[error("response surface: {0}")]
    Rsm(#[from] rsm::RsmError),
}

/// Settings of [`direct::identify_direct`].
#[derive(Clone, Debug, PartialEq)]
pub struct DirectOptions {
    /// Start [N·m], one value per identified joint; `None`: the per-joint
    /// best of the start scan ([`SCAN_GRID_NM`]).
    pub start_nm: Option<Vec<f64>>,
    /// Smallest finite-difference step [N·m] (the step is
    /// `max(min_step, JACOBIAN_REL_STEP·|T_C|)`, `analysis::fit`).
    pub min_step_nm: f64,
    /// Upper bound of every EFT [N·m].
    pub upper_nm: f64,
    /// Residual evaluations per parameter the solver may use.
    pub patience: usize,
}

impl Default for DirectOptions {
    fn default() -> Self {
        DirectOptions {
            start_nm: None,
            min_step_nm: DEFAULT_MIN_STEP_NM,
            upper_nm: 100.0,
            patience: 40,
        }
    }
}

/// The response a response-surface identification minimises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RsmResponse {
    /// The sum over the identified joints of their trajectory errors
    /// (seed 000 Eq. 14, each the mean over the runs): the paper's responses
    /// with equal weights (the paper does not say how it combined them).
    TeSum,
    /// The mean squared angle residual over every sample, joint and run
    /// \[deg²\] (seed 001 Eq. 6 divided by the number of residuals).
    Mse,
}

impl RsmResponse {
    /// The name used on the command line and in the JSON.
    pub fn name(self) -> &'static str {
        match self {
            RsmResponse::TeSum => "te",
            RsmResponse::Mse => "mse",
        }
    }
}

impl std::str::FromStr for RsmResponse {
    type Err = ParseNameError;
    fn from_str(s: &str) -> Result<Self, ParseNameError> {
        match s {
            "te" => Ok(RsmResponse::TeSum),
            "mse" => Ok(RsmResponse::Mse),
            _ => Err(ParseNameError::UnknownName {
                what: "response",
                name: s.to_string(),
                expected: "`te` or `mse`",
            }),
        }
    }
}

/// Settings of [`by_rsm::identify_rsm`].
#[derive(Clone, Debug, PartialEq)]
pub struct RsmOptions {
    /// Design centre [N·m] per identified joint; `None`: the per-joint best
    /// of the start scan ([`SCAN_GRID_NM`]), at least 0.025 N·m.
    pub centre_nm: Option<Vec<f64>>,
    /// Half-ranges [N·m] per identified joint (coded ±1); `None`:
    /// `half_range_fraction × centre`.
    pub half_range_nm: Option<Vec<f64>>,
    /// Half-range as a fraction of the centre when `half_range_nm` is
    /// `None` \[1\]. Default 0.5, the relative half-ranges of seed 000
    /// Table 9 for EFT2 and EFT3 (0.3 of 0.6, 0.05 of 0.1): with α = 1.682
    /// the design spans `centre × (1 ± 0.84)`.
    pub half_range_fraction: f64,
    /// The kind of CCD (seed 000 Table 9: circumscribed, rotatable).
    pub kind: CcdKind,
    /// Centre runs (1 in seed 000 Table 9; more add nothing for a
    /// deterministic simulation).
    pub centre_runs: usize,
    /// The response minimised.
    pub response: RsmResponse,
    /// Rounds of the design \[1\]: 1 is seed 000's single CCD; each further
    /// round re-centres the design on the last surface minimum and halves
    /// its half-ranges ([`RSM_ROUND_SHRINK`]), the sequential
    /// response-surface method of Box and Wilson (1951) (Myers,
    /// Montgomery and Anderson-Cook, *Response Surface Methodology*, ch. 5–6).
    pub rounds: usize,
}

/// Default smallest finite-difference step of an EFT [N·m]
/// ([`DirectOptions::min_step_nm`]): the Jacobian's step is
/// `max(min_step, JACOBIAN_REL_STEP·|T_C|)` (`analysis::fit`); 10⁻⁴ N·m is
/// a tenth of the smallest friction the papers identify (0.001 N·m), far
/// above the simulation's error at its tolerances.
pub const DEFAULT_MIN_STEP_NM: f64 = 1e-4;

/// Factor on the half-ranges from one round of a sequential response-surface
/// design to the next \[1\].
pub const RSM_ROUND_SHRINK: f64 = 0.5;

/// A later round's half-range stays below this fraction of the distance
/// from its centre to 0 N·m over the design's reach (ratio): the axial
/// points stay strictly above 0, where the effect is defined.
pub const RSM_REACH_MARGIN: f64 = 0.999;

/// A design point below 0 N·m by less than this fraction of its half-range
/// (ratio) is rounding and is set to 0; further below, the plan is refused.
pub const RSM_ZERO_SLACK: f64 = 1e-9;

/// Least design centre of a later round [N·m]: a minimum at 0 N·m is
/// re-centred here so the next design has a positive extent.
const RSM_MIN_CENTRE_NM: f64 = 1e-3;

impl Default for RsmOptions {
    fn default() -> Self {
        RsmOptions {
            centre_nm: None,
            half_range_nm: None,
            half_range_fraction: 0.5,
            kind: CcdKind::Circumscribed,
            centre_runs: 1,
            response: RsmResponse::TeSum,
            rounds: 1,
        }
    }
}

/// The model on a campaign with the EFTs of some joints as parameters,
/// counting its evaluations.
struct Model<'a> {
    campaign: &'a Campaign,
    joints: &'a [usize],
    /// The identified joints that are measured (hinges): the responses of
    /// a response surface (a truss's friction node has no angle of its own;
    /// seed 000 Table 9 has TE1, TE2 for EFT1..3).
    te_joints: Vec<usize>,
    evaluations: AtomicUsize,
}

impl<'a> Model<'a> {
    fn new(campaign: &'a Campaign, joints: &'a [usize]) -> Self {
        let measured = measured_joints(campaign);
        Model {
            campaign,
            joints,
            te_joints: joints.iter().copied().filter(|&j| j <= measured).collect(),
            evaluations: AtomicUsize::new(0),
        }
    }

    fn effects(&self, p: &[f64]) -> Vec<Effect> {
        self.joints
            .iter()
            .zip(p)
            .map(|(&j, &v)| Effect::joint(EffectKind::CoulombFriction, j, v))
            .collect()
    }

    fn residuals(&self, p: &[f64]) -> Option<Vec<f64>> {
        self.evaluations.fetch_add(1, Ordering::Relaxed);
        self.campaign.residual_vector(&self.effects(p))
    }

    /// Every run simulated (in parallel), scored.
    fn score(&self, p: &[f64]) -> Option<(CampaignScore, Vec<Trajectory>)> {
        self.evaluations.fetch_add(1, Ordering::Relaxed);
        score(self.campaign, &self.effects(p))
    }

    fn count(&self) -> usize {
        self.evaluations.load(Ordering::Relaxed)
    }
}

/// Simulates every run of `campaign` with `effects` (in parallel) and scores
/// them: RMS \[deg\] (`physics.md` 8) and the trajectory error of every joint
/// (seed 000 Eq. 14, whole run). `None` if a simulation fails.
pub fn score(campaign: &Campaign, effects: &[Effect]) -> Option<(CampaignScore, Vec<Trajectory>)> {
    let trajs: Vec<Option<Trajectory>> = (0..campaign.runs.len())
        .into_par_iter()
        .map(|i| campaign.simulate(i, effects).ok())
        .collect();
    let trajs: Vec<Trajectory> = trajs.into_iter().collect::<Option<_>>()?;
    let mut runs = Vec::with_capacity(trajs.len());
    let (mut sse, mut count) = (0.0, 0usize);
    for (cr, traj) in campaign.runs.iter().zip(&trajs) {
        let run = &cr.run;
        if traj.t_s.len() != run.len() || traj.joints() != run.joints() {
            return None;
        }
        let s = metrics::sse_deg2(&run.t_s, &traj.phi_deg, &run.phi_deg, TimeWindow::ALL).ok()?;
        sse += s.sse_deg2;
        count += s.samples * s.joints;
        let te = metrics::trajectory_errors_pct(
            &run.t_s,
            &traj.phi_deg,
            &run.phi_deg,
            &run.latch,
            TimeWindow::ALL,
        )
        .ok()?;
        let joint_sse_deg2 = (0..run.joints())
            .map(|j| {
                traj.phi_deg[j]
                    .iter()
                    .zip(&run.phi_deg[j])
                    .map(|(a, e)| (a - e) * (a - e))
                    .sum()
            })
            .collect();
        runs.push(RunScore {
            run: cr.name(),
            mechanism: cr.mechanism.name.clone(),
            rms_deg: s.rms_deg(),
            trajectory_error_pct: te,
            joint_sse_deg2,
            samples: run.len(),
        });
    }
    Some((
        CampaignScore {
            rms_deg: metrics::rms_deg(sse, count, 1),
            runs,
        },
        trajs,
    ))
}

/// Checks a joint selection against a campaign: not empty, no duplicates,
/// every joint present in every run.
pub fn check_joints(campaign: &Campaign, joints: &[usize]) -> Result<(), IdentifyError> {
    if joints.is_empty() {
        return Err(IdentifyError::NoJoints);
    }
    let n = campaign.effect_joints();
    for (i, &j) in joints.iter().enumerate() {
        if j == 0 || j > n {
            return Err(IdentifyError::BadJoint {
                joint: j,
                joints: n,
            });
        }
        if joints[..i].contains(&j) {
            return Err(IdentifyError::DuplicateJoint(j));
        }
    }
    Ok(())
}

/// The joints every run of the campaign has: `1..=n`, counting a truss
/// wing's friction nodes after its hinges
/// ([`crate::model::mechanism::Mechanism::effect_joints`]: EFT1..3 of the
/// seed 000 truss wing are joints 1, 2 and 3, joint 3 the pins at F).
pub fn all_joints(campaign: &Campaign) -> Vec<usize> {
    (1..=campaign.effect_joints()).collect()
}

/// The joints every run measures (its angle columns).
fn measured_joints(campaign: &Campaign) -> usize {
    campaign
        .runs
        .iter()
        .map(|r| r.run.joints())
        .min()
        .unwrap_or(0)
}

fn check_vector(what: &str, v: &[f64], n: usize, nonnegative: bool) -> Result<(), IdentifyError> {
    if v.len() != n {
        return Err(IdentifyError::BadOption(format!(
            "{what}: {} values given, expected one per identified joint ({n})",
            v.len()
        )));
    }
    if v.iter()
        .any(|x| !x.is_finite() || (nonnegative && *x < 0.0))
    {
        return Err(IdentifyError::BadOption(format!(
            "{what}: expected finite{} values in N·m, got {}",
            if nonnegative { " non-negative" } else { "" },
            list(v)
        )));
    }
    Ok(())
}

/// The result of the start scan ([`SCAN_GRID_NM`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Scan {
    /// The uniform EFT (the same at every identified joint) with the lowest
    /// campaign RMS [N·m].
    pub uniform_best_nm: f64,
    /// Its campaign RMS \[deg\].
    pub uniform_best_rms_deg: f64,
    /// Per identified joint, the grid value whose uniform EFT gives that
    /// joint's lowest RMS (over the runs) [N·m]: a separable first guess.
    pub per_joint_best_nm: Vec<f64>,
}

/// The start scan: the same EFT at every identified joint, for each value
/// of [`SCAN_GRID_NM`] (simulated in parallel); keeps the best value for the
/// whole campaign and, per joint, the value that fits that joint best.
fn scan_with(model: &Model, progress: Progress) -> Result<Scan, IdentifyError> {
    progress(&format!(
        "scan: the same EFT at joints {} ({} values from 0 to {} N·m)",
        list(model.joints),
        SCAN_GRID_NM.len(),
        SCAN_GRID_NM[SCAN_GRID_NM.len() - 1]
    ));
    let k = model.joints.len();
    // Per grid value: SSE and count of each identified joint, then of all joints.
    let rows: Vec<Option<(Vec<f64>, f64)>> = SCAN_GRID_NM
        .par_iter()
        .map(|&c| {
            let (score, _) = model.score(&vec![c; k])?;
            let per_joint = model
                .joints
                .iter()
                .map(|&j| {
                    let (sse, n) = score.runs.iter().fold((0.0, 0usize), |(s, n), r| {
                        let v = r.joint_sse_deg2.get(j - 1).copied().unwrap_or(0.0);
                        (s + v, n + r.samples)
                    });
                    (sse / n.max(1) as f64).sqrt()
                })
                .collect();
            Some((per_joint, score.rms_deg))
        })
        .collect();
    let ok: Vec<(f64, &(Vec<f64>, f64))> = SCAN_GRID_NM
        .iter()
        .zip(&rows)
        .filter_map(|(c, r)| r.as_ref().map(|r| (*c, r)))
        .collect();
    let best = ok
        .iter()
        .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
        .ok_or_else(|| IdentifyError::Simulation("at any EFT of the start scan".into()))?;
    let measured = measured_joints(model.campaign);
    let per_joint: Vec<f64> = (0..k)
        .map(|i| {
            if model.joints[i] > measured {
                // A truss friction node has no angle of its own.
                return best.0;
            }
            ok.iter()
                .min_by(|a, b| a.1 .0[i].total_cmp(&b.1 .0[i]))
                .map(|r| r.0)
                .unwrap_or(best.0)
        })
        .collect();
    progress(&format!(
        "scan: best uniform EFT {} N·m (RMS {:.4} deg); best per joint {} N·m",
        best.0,
        best.1 .1,
        list(&per_joint)
    ));
    Ok(Scan {
        uniform_best_nm: best.0,
        uniform_best_rms_deg: best.1 .1,
        per_joint_best_nm: per_joint,
    })
}

/// The campaign scored with the mechanisms as given (no extra friction).
fn score_as_given(model: &Model, progress: Progress) -> Result<CampaignScore, IdentifyError> {
    let (before, _) = model
        .score(&vec![0.0; model.joints.len()])
        .ok_or_else(|| IdentifyError::Simulation("as given (no extra friction)".into()))?;
    progress(&format!(
        "before: RMS {:.4} deg over {} runs",
        before.rms_deg,
        model.campaign.runs.len()
    ));
    Ok(before)
}

#[cfg(test)]
mod tests;
