//! The probability that a deployment fails, from the uncertainty of its
//! parameters: crude Monte-Carlo ([`mc`]) and subset simulation
//! ([`subset`], Au & Beck 2001, "Estimation of small failure probabilities
//! in high dimensions by subset simulation", Probabilistic Engineering
//! Mechanics 16(4)).
//!
//! A [`Problem`] is a mechanism, its uncertain parameters ([`params::Vary`],
//! independent, each mapped from a standard normal `u`) and the failure
//! criteria ([`criteria::Criterion`], a continuous limit state `g`, failure
//! iff `g ≤ 0`). The algorithms draw the points and ask an [`Evaluate`]
//! callback for their `g` by batches: locally [`Problem::g_batch`] (rayon),
//! or any other engine (the Python package sends the batches to a Dask
//! cluster). Every draw comes from its own ChaCha8 stream, numbered by
//! (seed, level, index) ([`stream`]), and every reduction runs in a fixed
//! order, so the same seed gives the same bits on any number of workers.

pub mod correlation;
pub mod criteria;
pub mod identified;
pub mod mc;
pub mod normal;
pub mod params;
pub mod subset;

use crate::model::effect::Effect;
use crate::model::mechanism::Mechanism;
use crate::simulate::deployment::{self, SimError, SimOptions, Trajectory};
use correlation::Correlation;
use criteria::{Criterion, Outcome};
use params::Vary;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Output rate of the reliability deployments [Hz]: the latch rate is
/// extrapolated from the last two samples before the latch, 1 ms apart.
pub const SAMPLE_HZ: f64 = 1000.0;

/// What a reliability analysis is about.
#[derive(Clone, Debug)]
pub struct Problem {
    /// The nominal mechanism.
    pub mech: Mechanism,
    /// The uncertain parameters (at least one).
    pub vary: Vec<Vary>,
    /// The failure criteria (at least one; any one fails).
    pub fail: Vec<Criterion>,
    /// Correlations of the parameters' standard normals ([`correlation`]).
    pub corr: Vec<Correlation>,
}

/// Why an analysis stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReliabilityError {
    /// The problem or the settings are not usable.
    #[error("{0}")]
    Invalid(String),
    /// A deployment could not be simulated.
    #[error("the deployment at {at} failed: {source}")]
    Simulation {
        /// The parameters, `name = value, ...`.
        at: String,
        /// The simulator's error.
        #[source]
        source: SimError,
    },
    /// The batch evaluator (e.g. a remote engine) failed.
    #[error("the evaluation of a batch failed: {0}")]
    Evaluator(String),
}

/// The limit-state values of a batch of parameter points (`xs[i]` has one
/// value per [`Problem::vary`]), in order.
pub type Evaluate<'a> = &'a mut dyn FnMut(&[Vec<f64>]) -> Result<Vec<f64>, ReliabilityError>;

impl Problem {
    /// Checks the problem: at least one parameter and criterion, targets
    /// that exist, `time>X` below `duration_s`.
    pub fn check(&self) -> Result<(), ReliabilityError> {
        let bad = |m: String| ReliabilityError::Invalid(m);
        if self.vary.is_empty() {
            return Err(bad("expected at least one --vary".into()));
        }
        if self.fail.is_empty() {
            return Err(bad("expected at least one --fail".into()));
        }
        for v in &self.vary {
            v.check(&self.mech).map_err(|e| bad(e.to_string()))?;
        }
        correlation::cholesky(&self.corr, self.vary.len()).map_err(bad)?;
        for c in &self.fail {
            if let Criterion::TimeAbove(x) = c {
                if *x >= self.mech.duration_s {
                    return Err(bad(format!(
                        "--fail {c}: X must be below the mechanism's duration_s ({} s); \
                         use not_latched for a deployment that does not finish",
                        self.mech.duration_s
                    )));
                }
            }
        }
        Ok(())
    }

    /// The parameter point at the independent standard normal point `u`
    /// (correlated first by [`correlation::correlate`] if there are
    /// correlations).
    pub fn x_of(&self, u: &[f64]) -> Vec<f64> {
        let l = correlation::cholesky(&self.corr, self.vary.len())
            .ok()
            .flatten();
        let z = match &l {
            Some(l) => correlation::correlate(l, u),
            None => u.to_vec(),
        };
        self.vary
            .iter()
            .zip(&z)
            .map(|(v, &z)| v.dist.at(z))
            .collect()
    }

    /// The parameters in words, `name = value, ...`.
    pub fn describe(&self, x: &[f64]) -> String {
        let parts: Vec<String> = self
            .vary
            .iter()
            .zip(x)
            .map(|(v, x)| format!("{} = {x}", v.label()))
            .collect();
        parts.join(", ")
    }

    /// The mechanism and effects at the parameter point `x`, simulated:
    /// the one call of the simulator in the reliability analysis.
    pub fn deploy(&self, x: &[f64]) -> Result<Outcome, ReliabilityError> {
        let mut mech = self.mech.clone();
        let mut effects: Vec<Effect> = Vec::new();
        for (v, &x) in self.vary.iter().zip(x) {
            v.apply(x, &mut mech, &mut effects);
        }
        let opts = SimOptions {
            sample_hz: Some(SAMPLE_HZ),
            settle_s: Some(0.0),
            ..SimOptions::default()
        };
        let traj = deployment::simulate(&mech, &effects, &opts).map_err(|source| {
            ReliabilityError::Simulation {
                at: self.describe(x),
                source,
            }
        })?;
        Ok(outcome(&traj, mech.duration_s))
    }

    /// `g` at the parameter point `x`.
    pub fn g(&self, x: &[f64]) -> Result<f64, ReliabilityError> {
        Ok(self.deploy(x)?.g(&self.fail))
    }

    /// The outcomes of a batch on every core (rayon), in the order of `xs`.
    pub fn deploy_batch(&self, xs: &[Vec<f64>]) -> Result<Vec<Outcome>, ReliabilityError> {
        xs.par_iter().map(|x| self.deploy(x)).collect()
    }

    /// `g` of a batch on every core (rayon; the order of the output is the
    /// order of `xs`, whatever the threads).
    pub fn g_batch(&self, xs: &[Vec<f64>]) -> Result<Vec<f64>, ReliabilityError> {
        xs.par_iter().map(|x| self.g(x)).collect()
    }
}

/// The outcome of a simulated deployment.
fn outcome(traj: &Trajectory, duration_s: f64) -> Outcome {
    let n = traj.joints();
    let mut rate = vec![None; n];
    for (j, r) in rate.iter_mut().enumerate() {
        let Some(tl) = traj.latch_s[j] else { continue };
        let before: Vec<usize> = (0..traj.t_s.len())
            .filter(|&i| !traj.latched[j][i] && traj.t_s[i] < tl)
            .collect();
        *r = match before[..] {
            [] => Some(0.0),
            [i] => Some(traj.rate_deg_s[j][i]),
            [.., a, b] => {
                let (ra, rb) = (traj.rate_deg_s[j][a], traj.rate_deg_s[j][b]);
                let slope = (rb - ra) / (traj.t_s[b] - traj.t_s[a]);
                Some(rb + slope * (tl - traj.t_s[b]))
            }
        };
    }
    Outcome {
        latch_s: traj.latch_s.clone(),
        latch_rate_deg_s: rate,
        end_deg: traj
            .phi_deg
            .iter()
            .map(|p| p.last().copied().unwrap_or(0.0))
            .collect(),
        stowed_deg: traj
            .phi_deg
            .iter()
            .map(|p| p.first().copied().unwrap_or(0.0))
            .collect(),
        duration_s,
    }
}

/// The random stream of one draw: ChaCha8 seeded with `seed`, stream
/// `level · 2⁴⁰ + index`, so that each draw's numbers depend on nothing
/// but (seed, level, index).
pub fn stream(seed: u64, level: u32, index: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(((level as u64) << 40) | (index & ((1 << 40) - 1)));
    rng
}

/// The failed draw of highest density: the smallest `|u|` among the
/// failures (the design point of the sample).
#[derive(Clone, Debug, PartialEq)]
pub struct FailurePoint {
    /// The standard normal point.
    pub u: Vec<f64>,
    /// The parameters there.
    pub x: Vec<f64>,
    /// `g` there (≤ 0).
    pub g: f64,
}

impl FailurePoint {
    /// `β = |u|`: the distance from the mean in standard deviations.
    pub fn beta(&self) -> f64 {
        self.u.iter().map(|u| u * u).sum::<f64>().sqrt()
    }

    /// Keeps the failure of highest density of `self` and a candidate
    /// (ties keep `self`, so the order of a sweep decides).
    pub fn keep_best(best: &mut Option<FailurePoint>, u: &[f64], x: &[f64], g: f64) {
        if g > 0.0 {
            return;
        }
        let r2: f64 = u.iter().map(|u| u * u).sum();
        let better = best
            .as_ref()
            .is_none_or(|b| r2 < b.u.iter().map(|u| u * u).sum::<f64>());
        if better {
            *best = Some(FailurePoint {
                u: u.to_vec(),
                x: x.to_vec(),
                g,
            });
        }
    }
}

/// One level of subset simulation.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    /// Threshold `b_k` of the level (0 for the last).
    pub threshold: f64,
    /// Conditional probability `P(g ≤ b_k | g ≤ b_{k−1})`.
    pub p: f64,
    /// Its coefficient of variation (Au & Beck 2001, Eq. 28–29).
    pub cov: f64,
    /// Deployments simulated for the samples of this level.
    pub simulations: usize,
}

/// The result of an analysis.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// `mc` or `subset`.
    pub method: &'static str,
    /// The failure probability.
    pub p_fail: f64,
    /// Its coefficient of variation.
    pub cov: f64,
    /// Its 95 % interval.
    pub ci95: (f64, f64),
    /// Deployments simulated.
    pub simulations: usize,
    /// Failed deployments among the samples (mc), or in the last level (subset).
    pub failures: usize,
    /// Subset only: the levels.
    pub levels: Vec<Level>,
    /// Subset: the last threshold reached 0; mc: always true.
    pub converged: bool,
    /// The failed draw of highest density, if any failed.
    pub most_likely_failure: Option<FailurePoint>,
}

impl Estimate {
    /// The result as the JSON the CLI writes and the Python package returns.
    pub fn to_json(&self, problem: &Problem, seed: u64) -> serde_json::Value {
        use serde_json::json;
        let point = self.most_likely_failure.as_ref().map(|f| {
            let params: serde_json::Map<String, serde_json::Value> = problem
                .vary
                .iter()
                .zip(&f.x)
                .map(|(v, x)| (v.label(), json!(x)))
                .collect();
            json!({"parameters": params, "u": f.u, "beta": f.beta(), "g": f.g})
        });
        let mut out = json!({
            "mechanism": problem.mech.name,
            "method": self.method,
            "seed": seed,
            "vary": problem.vary.iter().map(|v| v.to_string()).collect::<Vec<_>>(),
            "fail": problem.fail.iter().map(|c| c.to_string()).collect::<Vec<_>>(),
            "corr": problem.corr.iter().map(|c| c.to_string()).collect::<Vec<_>>(),
            "p_fail": self.p_fail,
            "cov": self.cov,
            "ci95": [self.ci95.0, self.ci95.1],
            "simulations": self.simulations,
            "failures": self.failures,
            "converged": self.converged,
            "most_likely_failure": point,
        });
        if self.method == "subset" {
            out["levels"] = self
                .levels
                .iter()
                .map(|l| {
                    json!({"threshold": l.threshold, "p": l.p, "cov": l.cov,
                           "simulations": l.simulations})
                })
                .collect();
        }
        out
    }
}
