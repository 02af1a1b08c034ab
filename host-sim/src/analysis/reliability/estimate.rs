//! What an analysis found: the estimate, its c.o.v. and interval, and per
//! method what it rests on (the levels of each mode for subset
//! simulation, the design points for importance sampling, both estimates
//! for `auto`), and its JSON.

use super::criteria::Mode;
use super::Problem;
use crate::analysis::fit::Z_975;
use serde_json::{json, Value};

/// The failed draw of highest density: the smallest `|u|` among the
/// failures (the design point of the sample).
#[derive(Clone, Debug, PartialEq)]
pub struct FailurePoint {
    /// The standard normal point.
    pub u: Vec<f64>,
    /// The parameters there.
    pub x: Vec<f64>,
    /// The system's margin there (≤ 0).
    pub g: f64,
}

impl FailurePoint {
    /// `β = |u|`: the distance from the mean in standard deviations.
    pub fn beta(&self) -> f64 {
        self.u.iter().map(|u| u * u).sum::<f64>().sqrt()
    }

    /// Keeps the failure of highest density of `best` and a candidate
    /// (ties keep `best`, so the order of a sweep decides).
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
    /// Conditional probability `P(m ≤ b_k | m ≤ b_{k−1})`.
    pub p: f64,
    /// Its coefficient of variation (Au & Beck 2001, Eq. 28–29).
    pub cov: f64,
    /// Deployments simulated for the samples of this level.
    pub simulations: usize,
}

/// Subset simulation of one failure mode.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeResult {
    /// The mode.
    pub mode: Mode,
    /// Reached: the estimate of `P(F_m)`; not reached: of the probability
    /// of the last level, `P(m ≤ b)`.
    pub p: f64,
    /// The c.o.v. of `p`.
    pub cov: f64,
    /// The thresholds reached the mode's failure domain (0).
    pub converged: bool,
    /// Why its levels stopped: `reached` (0), `stalled` (the thresholds
    /// stopped falling), `negligible` (the last level's probability below
    /// 1 % of the modes reached), `levels` (`max_levels`).
    pub stop: &'static str,
    /// The levels.
    pub levels: Vec<Level>,
    /// The share of the mode's failures that no earlier mode has (from its
    /// last level): the system counts `p · counted`.
    pub counted: f64,
    /// Deployments simulated for this mode.
    pub simulations: usize,
}

/// A design point of FORM: the most likely point of a mode's failure
/// domain (the point of its boundary nearest the origin of `u`).
#[derive(Clone, Debug, PartialEq)]
pub struct DesignPoint {
    /// The mode.
    pub mode: Mode,
    /// The standard normal point.
    pub u: Vec<f64>,
    /// The parameters there.
    pub x: Vec<f64>,
    /// `β = |u|`.
    pub beta: f64,
    /// Deployments the search took.
    pub simulations: usize,
}

/// The result of an analysis.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// `mc`, `subset`, `is` or `auto`.
    pub method: &'static str,
    /// The failure probability.
    pub p_fail: f64,
    /// Its coefficient of variation.
    pub cov: f64,
    /// Its 95 % interval.
    pub ci95: (f64, f64),
    /// Deployments simulated.
    pub simulations: usize,
    /// Failed deployments among the samples (mc, is), or in the modes'
    /// last levels (subset).
    pub failures: usize,
    /// Every mode's failure domain was reached (subset: every mode's
    /// thresholds reached 0; is: a design point of every mode that can
    /// fail was found and the sample failed); mc: always true.
    pub converged: bool,
    /// The failed draw of highest density, if any failed.
    pub most_likely_failure: Option<FailurePoint>,
    /// Subset: each mode.
    pub modes: Vec<ModeResult>,
    /// Importance sampling: the design points sampled around.
    pub design_points: Vec<DesignPoint>,
    /// Importance sampling: the modes whose boundary FORM did not find.
    pub unreached: Vec<Mode>,
    /// `auto`: the estimates of importance sampling and subset simulation.
    pub checks: Vec<Estimate>,
    /// `auto`: whether they agree within their 95 % intervals (`None`
    /// when neither saw a failure: nothing to compare).
    pub agree: Option<bool>,
}

impl Estimate {
    /// An estimate of `method` with no detail.
    pub fn plain(method: &'static str, p: f64, cov: f64, simulations: usize) -> Estimate {
        Estimate {
            method,
            p_fail: p,
            cov,
            ci95: lognormal_ci95(p, cov),
            simulations,
            failures: 0,
            converged: true,
            most_likely_failure: None,
            modes: Vec::new(),
            design_points: Vec::new(),
            unreached: Vec::new(),
            checks: Vec::new(),
            agree: None,
        }
    }

    /// The result as the JSON the CLI writes and the Python package returns.
    pub fn to_json(&self, problem: &Problem, seed: u64) -> Value {
        let mut out = json!({
            "mechanism": problem.mech.name,
            "method": self.method,
            "seed": seed,
            "vary": problem.vary.iter().map(|v| v.to_string()).collect::<Vec<_>>(),
            "fail": problem.fail.iter().map(|c| c.to_string()).collect::<Vec<_>>(),
            "corr": problem.corr.iter().map(|c| c.to_string()).collect::<Vec<_>>(),
            "fixed": problem.fixed.iter()
                .map(|f| json!({"effect": f.effect.to_string(), "source": f.source}))
                .collect::<Vec<_>>(),
        });
        let body = self.body(problem);
        if let (Value::Object(o), Value::Object(b)) = (&mut out, body) {
            o.extend(b);
        }
        out
    }

    /// The method's part of the JSON.
    fn body(&self, problem: &Problem) -> Value {
        let labels = super::params::unique_labels(&problem.vary);
        let params = |x: &[f64]| -> Value {
            labels
                .iter()
                .zip(x)
                .map(|(label, x)| (label.clone(), json!(x)))
                .collect::<serde_json::Map<_, _>>()
                .into()
        };
        let point = self
            .most_likely_failure
            .as_ref()
            .map(|f| json!({"parameters": params(&f.x), "u": f.u, "beta": f.beta(), "g": f.g}));
        let mut out = json!({
            "method": self.method,
            "p_fail": self.p_fail,
            "cov": self.cov,
            "ci95": [self.ci95.0, self.ci95.1],
            "simulations": self.simulations,
            "failures": self.failures,
            "converged": self.converged,
            "most_likely_failure": point,
        });
        if !self.modes.is_empty() {
            out["modes"] = self.modes.iter().map(mode_json).collect();
        }
        if self.method == "is" {
            out["design_points"] = self
                .design_points
                .iter()
                .map(|d| {
                    json!({"mode": d.mode.to_string(), "beta": d.beta, "u": d.u,
                           "parameters": params(&d.x), "simulations": d.simulations})
                })
                .collect();
            out["unreached"] = self.unreached.iter().map(|m| m.to_string()).collect();
        }
        if !self.checks.is_empty() {
            let checks: serde_json::Map<String, Value> = self
                .checks
                .iter()
                .map(|c| (c.method.to_string(), c.body(problem)))
                .collect();
            out["estimates"] = checks.into();
            out["agree"] = json!(self.agree);
        }
        out
    }
}

fn mode_json(m: &ModeResult) -> Value {
    json!({
        "mode": m.mode.to_string(),
        "p": m.p,
        "cov": m.cov,
        "converged": m.converged,
        "stop": m.stop,
        "counted": m.counted,
        "simulations": m.simulations,
        "levels": m.levels.iter().map(|l| json!({"threshold": l.threshold, "p": l.p,
            "cov": l.cov, "simulations": l.simulations})).collect::<Vec<_>>(),
    })
}

/// The 95 % interval of a lognormal estimator of median-ish `p` and
/// c.o.v. `cov` (`σ_ln = √ln(1 + cov²)`), capped at 1.
pub fn lognormal_ci95(p: f64, cov: f64) -> (f64, f64) {
    if !(p > 0.0) || !cov.is_finite() {
        return (0.0, 1.0);
    }
    let s = (1.0 + cov * cov).ln().sqrt();
    (p * (-Z_975 * s).exp(), (p * (Z_975 * s).exp()).min(1.0))
}
