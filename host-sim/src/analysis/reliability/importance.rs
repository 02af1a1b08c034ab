//! Importance sampling around FORM's design points ([`super::form`]): the
//! draws come from an equal mixture of unit normals centred on the design
//! points (one per distinct point; plus one at the origin when some mode
//! was not reached, so that its failures, if any, are not weighted out),
//! `q(u) = (1/K) Σ_k φ(u − c_k)`, and
//!
//! `p = (1/n) Σ_i 1[g(u_i) ≤ 0] φ(u_i)/q(u_i)`,
//!
//! `g` the system's margin (any mode failing counts, whichever centre the
//! draw came from). Draw `i` comes from centre `i mod K` (the deterministic
//! mixture: unbiased with the mixture's density in the weight) and its own
//! stream. The draws are independent, so the c.o.v. is the sample one,
//! `√(Σ (w_i − p)²/(n(n − 1)))/p` (slightly above the truth, as it ignores
//! the stratification by centre); the 95 % interval is that of a lognormal
//! estimator with that c.o.v. Melchers & Beck 2018, *Structural
//! Reliability Analysis and Prediction*, §5.4.

use super::estimate::lognormal_ci95;
use super::estimate::{Estimate, FailurePoint};
use super::form::{self, Form};
use super::mc::{binomial_cov, check_rows, system};
use super::{stream, Evaluate, Param, Problem, ReliabilityError};
use crate::report::progress::Progress;
use rand::Rng;
use rand_distr::StandardNormal;

/// The stream level of the importance draws (apart from subset's levels).
pub const IS_LEVEL: u32 = 0x00FF_0000;

/// Draws per batch handed to the evaluator when a target c.o.v. may stop
/// the run early.
pub const IS_BATCH: usize = 1000;

/// Design points nearer than this share one centre [standard deviations].
pub const SAME_CENTRE: f64 = 0.05;

/// Settings of importance sampling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IsSettings {
    /// Most draws.
    pub samples: usize,
    /// Stop after a batch of [`IS_BATCH`] once the c.o.v. is at or below
    /// this; `None`: draw all `samples`.
    pub target_cov: Option<f64>,
    /// Seed of the draws.
    pub seed: u64,
}

/// The centres of the mixture: the distinct design points, and the origin
/// when a mode was not reached.
pub fn centres(f: &Form, d: usize) -> Vec<Vec<f64>> {
    let mut c: Vec<Vec<f64>> = Vec::new();
    let far = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt()
            > SAME_CENTRE
    };
    let origin = vec![0.0; d];
    let mut all: Vec<&Vec<f64>> = f.points.iter().map(|p| &p.u).collect();
    if !f.unreached.is_empty() {
        all.push(&origin);
    }
    for u in all {
        if c.iter().all(|k| far(k, u)) {
            c.push(u.clone());
        }
    }
    c
}

/// `φ(u)/q(u)` for the mixture of unit normals at `centres`.
fn weight(u: &[f64], centres: &[Vec<f64>]) -> f64 {
    let logs: Vec<f64> = centres
        .iter()
        .map(|c| {
            let dot: f64 = u.iter().zip(c).map(|(a, b)| a * b).sum();
            let c2: f64 = c.iter().map(|a| a * a).sum();
            dot - 0.5 * c2
        })
        .collect();
    let top = logs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let sum: f64 = logs.iter().map(|l| (l - top).exp()).sum();
    centres.len() as f64 / (sum * top.exp())
}

/// Runs FORM, then importance sampling around its design points.
pub fn run(
    problem: &Problem,
    s: &IsSettings,
    eval: Evaluate<'_>,
    progress: Progress<'_>,
) -> Result<Estimate, ReliabilityError> {
    if s.samples < 2 {
        return Err(ReliabilityError::BadParam {
            param: Param::Samples,
            value: None,
            why: "expected at least 2 for importance sampling".into(),
        });
    }
    let f = form::run(problem, eval, progress)?;
    for p in &f.points {
        progress(&format!("form: {}: beta {:.4}", p.mode, p.beta));
    }
    sample(problem, s, f, eval, progress)
}

/// Importance sampling around the design points of `f`.
pub fn sample(
    problem: &Problem,
    s: &IsSettings,
    f: Form,
    eval: Evaluate<'_>,
    progress: Progress<'_>,
) -> Result<Estimate, ReliabilityError> {
    let d = problem.vary.len();
    let modes = problem.modes().len();
    let mut cs = centres(&f, d);
    if cs.is_empty() {
        cs.push(vec![0.0; d]);
    }
    let batch = if s.target_cov.is_some() {
        IS_BATCH
    } else {
        super::mc::BATCH
    };
    let (mut n, mut sum, mut sum2, mut nf) = (0usize, 0.0f64, 0.0f64, 0usize);
    let mut best: Option<FailurePoint> = None;
    while n < s.samples {
        let m = batch.min(s.samples - n);
        let us: Vec<Vec<f64>> = (n..n + m)
            .map(|i| {
                let c = &cs[i % cs.len()];
                let mut rng = stream(s.seed, IS_LEVEL, i as u64);
                c.iter()
                    .map(|ci| ci + rng.sample::<f64, _>(StandardNormal))
                    .collect()
            })
            .collect();
        let xs: Vec<Vec<f64>> = us.iter().map(|u| problem.x_of(u)).collect();
        let rows = eval(&xs)?;
        check_rows(&rows, m, modes)?;
        for ((u, x), row) in us.iter().zip(&xs).zip(&rows) {
            let g = system(row);
            if g <= 0.0 {
                let w = weight(u, &cs);
                sum += w;
                sum2 += w * w;
                nf += 1;
            }
            FailurePoint::keep_best(&mut best, u, x, g);
        }
        n += m;
        let (p, cov) = moments(sum, sum2, n);
        progress(&format!(
            "is: {n}/{} draws, {nf} failed, p = {p:.3e}, c.o.v. {cov:.3}",
            s.samples
        ));
        if s.target_cov.is_some_and(|t| nf > 0 && cov <= t) {
            break;
        }
    }
    let (p, mut cov) = moments(sum, sum2, n);
    if nf == n {
        // Every draw failed: the weights' spread cannot show the safe
        // region none of them reached (one centre at the origin weighs
        // every draw alike, no spread at all); no less uncertain than
        // the same count by crude Monte-Carlo.
        cov = cov.max(binomial_cov(nf, n));
    }
    Ok(Estimate {
        ci95: if nf > 0 {
            lognormal_ci95(p, cov)
        } else {
            (0.0, 1.0)
        },
        failures: nf,
        converged: f.unreached.is_empty() && nf > 0,
        most_likely_failure: best,
        design_points: f.points,
        unreached: f.unreached,
        ..Estimate::plain("is", p, cov, n + f.simulations)
    })
}

/// The mean of the weighted indicators and its c.o.v.
fn moments(sum: f64, sum2: f64, n: usize) -> (f64, f64) {
    let nf = n as f64;
    let p = sum / nf;
    if p <= 0.0 || n < 2 {
        return (p, f64::INFINITY);
    }
    let var = ((sum2 - nf * p * p) / (nf - 1.0)).max(0.0);
    (p, (var / nf).sqrt() / p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_weight_of_one_centre_is_the_likelihood_ratio() {
        let c = vec![vec![3.0, 0.0]];
        let u = [2.5, 0.4];
        let want = (-0.5 * (2.5f64.powi(2) + 0.16)).exp() / (-0.5 * (0.5f64.powi(2) + 0.16)).exp();
        assert!((weight(&u, &c) / want - 1.0).abs() < 1e-12);
        // Far out the sum stays finite (log space).
        assert!(weight(&[40.0, 0.0], &[vec![39.0, 0.0], vec![-39.0, 0.0]]).is_finite());
    }
}
