//! Crude Monte-Carlo: `p = n_f / n`, c.o.v. `√((1 − p)/(n p))`, the 95 %
//! interval of Wilson (1927), which stays meaningful with no failure.

use super::estimate::{Estimate, FailurePoint};
use super::{stream, Evaluate, Param, Problem, ReliabilityError};
use crate::analysis::fit::Z_975;
use crate::report::progress::Progress;
use rand::Rng;
use rand_distr::StandardNormal;

/// Draws per batch handed to the evaluator.
pub const BATCH: usize = 10_000;

/// Draws in the first batch when a target c.o.v. may end the run: the
/// batches double from it up to [`BATCH`], so that a target a thousand
/// deployments meet does not wait for ten thousand (on a physical-latch
/// wing, minutes). The draws are those of their index whatever the
/// batches, so a run to `samples` gives the same estimate.
pub const FIRST_TARGET_BATCH: usize = 1_000;

/// Settings of a crude Monte-Carlo run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct McSettings {
    /// Most deployments.
    pub samples: usize,
    /// Stop after a batch once the c.o.v. is at or below this (with at
    /// least one failure), the batches growing from
    /// [`FIRST_TARGET_BATCH`]; `None`: run all `samples`.
    pub target_cov: Option<f64>,
    /// Seed of the draws.
    pub seed: u64,
}

/// The standard normal point of draw `index` at `level` (d components).
pub fn draw(seed: u64, level: u32, index: u64, d: usize) -> Vec<f64> {
    let mut rng = stream(seed, level, index);
    (0..d).map(|_| rng.sample(StandardNormal)).collect()
}

/// Wilson's 95 % interval of a proportion `k/n`.
pub fn wilson95(k: usize, n: usize) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let (none, all) = (k == 0, k >= n);
    let (z, n) = (Z_975, n as f64);
    let p = k as f64 / n;
    let d = 1.0 + z * z / n;
    let c = (p + z * z / (2.0 * n)) / d;
    let h = z / d * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt();
    // No failure: the lower bound is 0 exactly (`c − h` rounds to ~1e-18);
    // every draw failed: the upper bound is 1.
    let lo = if none { 0.0 } else { (c - h).max(0.0) };
    let hi = if all { 1.0 } else { (c + h).min(1.0) };
    (lo, hi)
}

/// Runs crude Monte-Carlo.
pub fn run(
    problem: &Problem,
    s: &McSettings,
    eval: Evaluate<'_>,
    progress: Progress<'_>,
) -> Result<Estimate, ReliabilityError> {
    if s.samples == 0 {
        return Err(ReliabilityError::BadParam {
            param: Param::Samples,
            value: None,
            why: "expected at least 1".into(),
        });
    }
    let d = problem.vary.len();
    let (mut n, mut nf) = (0usize, 0usize);
    let mut best: Option<FailurePoint> = None;
    let mut size = match s.target_cov {
        Some(_) => FIRST_TARGET_BATCH,
        None => BATCH,
    };
    while n < s.samples {
        let m = size.min(s.samples - n);
        size = (2 * size).min(BATCH);
        let us: Vec<Vec<f64>> = (n..n + m).map(|i| draw(s.seed, 0, i as u64, d)).collect();
        let xs: Vec<Vec<f64>> = us.iter().map(|u| problem.x_of(u)).collect();
        let ms = eval(&xs)?;
        check_rows(&ms, m, problem.modes().len())?;
        for ((u, x), row) in us.iter().zip(&xs).zip(&ms) {
            let g = system(row);
            if g <= 0.0 {
                nf += 1;
            }
            FailurePoint::keep_best(&mut best, u, x, g);
        }
        n += m;
        let cov = cov(nf, n);
        progress(&format!(
            "mc: {n}/{} deployments, {nf} failed, p = {:.3e}, c.o.v. {cov:.3}",
            s.samples,
            nf as f64 / n as f64
        ));
        if s.target_cov.is_some_and(|t| nf > 0 && cov <= t) {
            break;
        }
    }
    Ok(Estimate {
        ci95: wilson95(nf, n),
        failures: nf,
        most_likely_failure: best,
        ..Estimate::plain("mc", nf as f64 / n as f64, cov(nf, n), n)
    })
}

/// The system's margin of a row of mode margins: the smallest (any mode
/// fails the wing).
pub fn system(row: &[f64]) -> f64 {
    row.iter().copied().fold(f64::INFINITY, f64::min)
}

/// `√((1 − p)/(n p))`, infinite with no failure ([`binomial_cov`]).
fn cov(nf: usize, n: usize) -> f64 {
    binomial_cov(nf, n)
}

/// The c.o.v. of a proportion `k/n`: `√((1 − p)/(n p))`, infinite with no
/// failure; with every draw failed, `p` is Wilson's centre `(k + z²/2)/(n +
/// z²)` instead of 1, whose c.o.v. would be 0 (twenty failures in twenty
/// draws do not make a probability of 1 certain).
pub fn binomial_cov(k: usize, n: usize) -> f64 {
    if k == 0 || n == 0 {
        return f64::INFINITY;
    }
    let (k, n) = (k as f64, n as f64);
    let p = if k >= n {
        (k + Z_975 * Z_975 / 2.0) / (n + Z_975 * Z_975)
    } else {
        k / n
    };
    ((1.0 - p) / (n * p)).sqrt()
}

/// The evaluator answered every point with one margin per mode, none NaN.
pub(super) fn check_rows(
    rows: &[Vec<f64>],
    m: usize,
    modes: usize,
) -> Result<(), ReliabilityError> {
    check_len(rows, m)?;
    if let Some(r) = rows.iter().find(|r| r.len() != modes) {
        return Err(ReliabilityError::Evaluator(format!(
            "a row of {} margins; expected one per failure mode ({modes})",
            r.len()
        )));
    }
    // A NaN compares false both ways: counted neither failed nor safe, it
    // would pass for a margin and lower the probability without a word.
    match rows.iter().position(|r| r.iter().any(|g| g.is_nan())) {
        Some(i) => Err(ReliabilityError::Evaluator(format!(
            "row {i} of the batch has a margin NaN; expected a number per failure mode \
             (≤ 0: failed)"
        ))),
        None => Ok(()),
    }
}

/// The evaluator answered every point.
pub(super) fn check_len<T>(gs: &[T], m: usize) -> Result<(), ReliabilityError> {
    if gs.len() == m {
        Ok(())
    } else {
        Err(ReliabilityError::Evaluator(format!(
            "{} values for a batch of {m} points",
            gs.len()
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilson_brackets_the_proportion() {
        let (lo, hi) = wilson95(100, 10_000);
        assert!(lo < 0.01 && hi > 0.01 && lo > 0.008 && hi < 0.0125);
        let (lo, hi) = wilson95(0, 1000);
        assert!(lo == 0.0 && hi > 0.0 && hi < 0.005);
        let (lo, hi) = wilson95(20, 20);
        assert!(lo > 0.8 && lo < 0.85 && hi == 1.0);
    }

    #[test]
    fn every_draw_failed_is_not_a_certainty() {
        // 20 of 20: the c.o.v. of Wilson's centre (20 + 1.92)/(20 + 3.84),
        // not the 0 of p = 1.
        let c = binomial_cov(20, 20);
        let p = (20.0 + Z_975 * Z_975 / 2.0) / (20.0 + Z_975 * Z_975);
        assert!((c - ((1.0 - p) / (20.0 * p)).sqrt()).abs() < 1e-15 && c > 0.05);
        assert!((binomial_cov(100, 10_000) - (0.99f64 / 100.0).sqrt()).abs() < 1e-15);
        assert!(binomial_cov(0, 10).is_infinite());
    }

    #[test]
    fn draws_depend_on_seed_level_and_index_only() {
        assert_eq!(draw(7, 2, 5, 3), draw(7, 2, 5, 3));
        assert_ne!(draw(7, 2, 5, 3), draw(7, 2, 6, 3));
        assert_ne!(draw(7, 1, 5, 3), draw(7, 2, 5, 3));
        assert_ne!(draw(8, 2, 5, 3), draw(7, 2, 5, 3));
    }
}
