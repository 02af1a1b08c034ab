//! Subset simulation (Au & Beck 2001), one run per failure mode: `P(F_m)
//! = Π_k P(F_k | F_{k−1})` over nested domains `F_k = {m ≤ b_k}` of the
//! mode's margin `m`, each threshold `b_k` the `p0`-quantile of the level's
//! samples, the samples of the next level grown from the `p0 N` seeds below
//! it by Markov chains in the standard normal space, adaptive conditional
//! sampling ([`super::chains`]: Papaioannou et al. 2015), the candidate
//! kept iff `m ≤ b_k`.
//!
//! Every mode's levels start from the same first level (`N` independent
//! draws, simulated once) and follow that mode's margin only, so a joint
//! that fails in one direction of the parameters is not hidden by another
//! failing in another (several joints make a series system). The system's
//! probability is the sum of the modes' probabilities of the failures no
//! earlier mode has: `P(F) = Σ_m P(F_m) · P(no earlier mode | F_m)`, the
//! second factor the share of the mode's last level that fails it and no
//! earlier mode.
//!
//! A mode whose thresholds stop falling (twice less than
//! [`STALL_RELATIVE`] of the threshold, or not at all) or that does not
//! reach 0 in `max_levels` levels is *not reached*: its failure domain may
//! be empty or out of the chains' reach, and the probability of its last
//! level is an estimate of `P(m ≤ b)`, not a bound on the mode (a domain
//! the chains never entered is missing from it). The system's estimate then
//! counts the modes reached only and says so (`converged = false`).
//!
//! The c.o.v. of a level is Au & Beck's Eq. 28–29 (`δ_k² = (1 − p_k)/(N
//! p_k)(1 + γ_k)`, `γ_k` from the correlation of the indicators along the
//! chains); that of a mode and of the system counts the correlation
//! between levels and between modes too, from the lineage of the samples:
//! each descends from one independent draw of the shared first level
//! ([`super::lineage`]).

use super::chains::{self, Grow, Population};
use super::estimate::{Estimate, FailurePoint, Level, ModeResult};
use super::lineage::{self, Trace};
use super::mc::{binomial_cov, check_rows, draw, system, wilson95};
use super::text::quantity;
use super::{Evaluate, Problem, ReliabilityError};
use crate::report::progress::Progress;

/// A threshold that falls by less than this fraction of itself, two levels
/// running, has stalled: the margin has a floor there.
pub const STALL_RELATIVE: f64 = 1e-3;

/// Settings of subset simulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubsetSettings {
    /// Samples per level `N` (a multiple of `1/p0`).
    pub samples: usize,
    /// Conditional probability of each level.
    pub p0: f64,
    /// Most levels per mode (the smallest probability is `p0^max_levels`;
    /// at most 63).
    pub max_levels: u32,
    /// Seed of the draws.
    pub seed: u64,
}

impl Default for SubsetSettings {
    fn default() -> Self {
        SubsetSettings {
            samples: 2000,
            p0: 0.1,
            max_levels: 20,
            seed: 0,
        }
    }
}

impl SubsetSettings {
    /// The settings' own check, made before any deployment (by [`run`] and
    /// by `auto` before its importance sampling): `p0` in (0, 0.5) and
    /// `N·p0` seeds a whole number ≥ 2 dividing `N`.
    pub fn check(&self) -> Result<(), ReliabilityError> {
        let n = self.samples;
        let p0 = self.p0;
        if !(p0 > 0.0 && p0 < 0.5) {
            return Err(ReliabilityError::Invalid(format!(
                "subset: p0 = {p0}: expected p0 in (0, 0.5) (0.1 by default)"
            )));
        }
        if self.max_levels > 63 {
            return Err(ReliabilityError::Invalid(format!(
                "subset: {} levels at most: expected at most 63",
                self.max_levels
            )));
        }
        let seeds = p0 * n as f64;
        let nc = seeds.round() as usize;
        if nc < 2 || (seeds - nc as f64).abs() > 1e-9 || n % nc != 0 {
            let step = (1.0 / p0).round();
            let seeds = (seeds * 1e6).round() / 1e6;
            return Err(ReliabilityError::Invalid(format!(
                "subset: {n} samples per level keep N·p0 = {seeds} of each level (p0 = {p0}) \
                 as the next level's seeds: expected a whole number of seeds, at least 2, \
                 dividing N (with p0 = {p0}: N a multiple of {step} and at least {}, e.g. 1000 \
                 or 2000)",
                2.0 * step
            )));
        }
        Ok(())
    }
}

/// Runs subset simulation, one run per mode, the modes a level at a time
/// in turn (so that a mode already negligible against those reached stops).
pub fn run(
    problem: &Problem,
    s: &SubsetSettings,
    eval: Evaluate<'_>,
    progress: Progress<'_>,
) -> Result<Estimate, ReliabilityError> {
    s.check()?;
    let n = s.samples;
    let modes = problem.modes();
    let d = problem.vary.len();
    let u: Vec<Vec<f64>> = (0..n).map(|i| draw(s.seed, 0, i as u64, d)).collect();
    let x: Vec<Vec<f64>> = u.iter().map(|u| problem.x_of(u)).collect();
    let m = eval(&x)?;
    check_rows(&m, n, modes.len())?;
    let first = Population {
        u,
        x,
        m,
        chains: n,
        parent: Vec::new(),
    };
    let mut runs: Vec<ModeRun> = (0..modes.len())
        .map(|mi| ModeRun::new(mi, first.clone(), n))
        .collect();
    let mut reached = 0.0;
    for k in 0..s.max_levels {
        for r in runs.iter_mut().filter(|r| r.stop.is_none()) {
            let Some((seeds, b)) = r.close_level(s, k, reached, modes[r.mi], progress) else {
                if r.stop == Some(Stop::Reached) {
                    reached += r.p;
                }
                continue;
            };
            let g = Grow {
                pop: &r.pop,
                seeds: &seeds,
                mode: r.mi,
                b,
                level: r.mi as u32 * 64 + k + 1,
                seed: s.seed,
            };
            let (next, used) = chains::grow(problem, &g, &mut r.lambda, eval)?;
            r.pop = next;
            r.sims += used;
            r.level_sims = used;
        }
    }
    Ok(finish(runs, &modes, n))
}

/// The modes' results and the system's estimate from their runs.
fn finish(runs: Vec<ModeRun>, modes: &[super::criteria::Mode], n: usize) -> Estimate {
    let mut results: Vec<ModeResult> = Vec::new();
    let mut shares: Vec<Option<Vec<f64>>> = Vec::new();
    let mut best = None;
    let mut failures = 0;
    for r in runs {
        let mi = r.mi;
        let fails: Vec<&Vec<f64>> = r.pop.m.iter().filter(|row| row[mi] <= 0.0).collect();
        let new = fails
            .iter()
            .filter(|row| row[..mi].iter().all(|&g| g > 0.0))
            .count();
        for i in 0..r.pop.u.len() {
            FailurePoint::keep_best(&mut best, &r.pop.u[i], &r.pop.x[i], system(&r.pop.m[i]));
        }
        let stop = r.stop.unwrap_or(Stop::Levels);
        if stop == Stop::Reached {
            failures += fails.len();
        }
        let mut levels = r.levels;
        for (l, c) in levels.iter_mut().zip(lineage::level_covs(&r.traces)) {
            l.cov = c;
        }
        shares.push(lineage::influence(&r.traces));
        // A mode reached at the first level is a crude Monte-Carlo count.
        let first_only = stop == Stop::Reached && levels.len() == 1;
        let hits = (r.p * n as f64).round() as usize;
        results.push(ModeResult {
            mode: modes[mi],
            p: r.p,
            cov: if first_only {
                binomial_cov(hits, n)
            } else {
                lineage::cov(&r.traces)
            },
            converged: stop == Stop::Reached,
            stop: stop.name(),
            levels,
            counted: if fails.is_empty() {
                1.0
            } else {
                new as f64 / fails.len() as f64
            },
            simulations: r.sims,
        });
    }
    let sims = n + results.iter().map(|r| r.simulations).sum::<usize>();
    let mut e = combine(results, &shares, sims, failures, best);
    let reached = e.modes.iter().filter(|m| m.converged);
    if e.p_fail > 0.0 && reached.map(|m| m.levels.len()).all(|l| l == 1) {
        // Every mode reached at the first level: the estimate is the first
        // level's crude Monte-Carlo count, with its binomial c.o.v. and
        // Wilson's interval (which stay meaningful at p = 1).
        let k = (e.p_fail * n as f64).round() as usize;
        e.cov = binomial_cov(k, n);
        e.ci95 = wilson95(k, n);
    }
    e
}

/// The system's estimate from its modes' (those reached): `P = Σ_m P_m
/// c_m`, `c_m` the share counted; its c.o.v. from the families of the
/// shared first level, `Z_r = Σ_m P_m c_m Z_{m,r} / P` ([`lineage`]),
/// never below the modes' taken as independent.
fn combine(
    modes: Vec<ModeResult>,
    shares: &[Option<Vec<f64>>],
    sims: usize,
    failures: usize,
    best: Option<FailurePoint>,
) -> Estimate {
    let reached: Vec<(&ModeResult, &Option<Vec<f64>>)> = modes
        .iter()
        .zip(shares)
        .filter(|(r, _)| r.converged)
        .collect();
    // `+ 0.0`: an empty sum of f64 is −0, printed `-0.0000e0`.
    let p: f64 = reached.iter().map(|(r, _)| r.p * r.counted).sum::<f64>() + 0.0;
    let independent: f64 = reached
        .iter()
        .map(|(r, _)| (r.p * r.counted * r.cov).powi(2))
        .sum();
    let mut z: Vec<f64> = Vec::new();
    for (r, share) in &reached {
        let Some(share) = share else { continue };
        z.resize(share.len(), 0.0);
        for (a, b) in z.iter_mut().zip(share) {
            *a += r.p * r.counted * b;
        }
    }
    let var = z.iter().map(|z| z * z).sum::<f64>().max(independent);
    let cov = if p > 0.0 {
        var.sqrt() / p
    } else {
        f64::INFINITY
    };
    Estimate {
        failures,
        converged: modes
            .iter()
            .all(|r| r.converged || r.stop == Stop::Negligible.name()),
        most_likely_failure: best,
        modes,
        ..Estimate::plain("subset", p, cov, sims)
    }
}

/// Why a mode's levels stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stop {
    /// The threshold reached 0: the mode's probability is estimated.
    Reached,
    /// The thresholds stopped falling ([`stalled`]).
    Stalled,
    /// The level's probability fell below [`NEGLIGIBLE`] of the modes
    /// reached.
    Negligible,
    /// `max_levels` levels.
    Levels,
}

impl Stop {
    fn name(self) -> &'static str {
        match self {
            Stop::Reached => "reached",
            Stop::Stalled => "stalled",
            Stop::Negligible => "negligible",
            Stop::Levels => "levels",
        }
    }
}

/// A mode whose last level's probability is below this fraction of the
/// modes already reached stops: it would add less than 1 % to the system.
pub const NEGLIGIBLE: f64 = 0.01;

/// The levels of one mode so far.
struct ModeRun {
    mi: usize,
    pop: Population,
    levels: Vec<Level>,
    p: f64,
    sims: usize,
    level_sims: usize,
    stop: Option<Stop>,
    /// The scale of the chains' proposals ([`chains`]).
    lambda: f64,
    /// The closed levels' hits and lineage ([`lineage`]).
    traces: Vec<Trace>,
}

impl ModeRun {
    fn new(mi: usize, pop: Population, n: usize) -> Self {
        ModeRun {
            mi,
            pop,
            levels: Vec::new(),
            p: 1.0,
            sims: 0,
            level_sims: n,
            stop: None,
            lambda: chains::START_SCALE,
            traces: Vec::new(),
        }
    }

    /// Closes level `k`: its threshold and probability; the seeds of the
    /// next level and its threshold, or `None` when the mode stops
    /// (`reached`: the probability of the modes reached so far).
    fn close_level(
        &mut self,
        s: &SubsetSettings,
        k: u32,
        reached: f64,
        mode: super::criteria::Mode,
        progress: Progress<'_>,
    ) -> Option<(Vec<usize>, f64)> {
        let (pop, mi) = (&self.pop, self.mi);
        let n = pop.m.len();
        let nc = (s.p0 * n as f64).round() as usize;
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| pop.m[a][mi].total_cmp(&pop.m[b][mi]).then(a.cmp(&b)));
        let b = 0.5 * (pop.m[order[nc - 1]][mi] + pop.m[order[nc]][mi]);
        let threshold = b.max(0.0);
        let hits = pop.m.iter().filter(|r| r[mi] <= threshold).count();
        let pk = hits as f64 / n as f64;
        self.traces.push(Trace {
            hit: pop.m.iter().map(|r| r[mi] <= threshold).collect(),
            len: n / pop.chains,
            parent: pop.parent.clone(),
        });
        self.p *= pk;
        self.levels.push(Level {
            threshold,
            p: pk,
            cov: f64::NAN,
            simulations: self.level_sims,
        });
        progress(&format!(
            "subset: {mode}: level {k}: threshold {}, p = {pk:.3}, {} deployments",
            quantity(threshold, mode.criterion.margin_unit()),
            self.level_sims
        ));
        self.stop = if b <= 0.0 {
            Some(Stop::Reached)
        } else if stalled(&self.levels) {
            Some(Stop::Stalled)
        } else if reached > 0.0 && self.p < NEGLIGIBLE * reached {
            Some(Stop::Negligible)
        } else if k + 1 >= s.max_levels {
            Some(Stop::Levels)
        } else {
            None
        };
        self.stop.is_none().then(|| (order[..nc].to_vec(), b))
    }
}

/// The thresholds stopped falling: not lower than the one before, or
/// twice running lower by less than [`STALL_RELATIVE`] of themselves.
fn stalled(levels: &[Level]) -> bool {
    let t: Vec<f64> = levels.iter().map(|l| l.threshold).collect();
    let small = |a: f64, b: f64| a - b < STALL_RELATIVE * a.abs();
    match t[..] {
        [.., a, b, c] if small(a, b) && small(b, c) => true,
        [.., a, b] => !(b < a),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::reliability::criteria::Criterion;
    use crate::analysis::reliability::normal;
    use crate::model::mechanism::Mechanism;

    /// `d` standard normal parameters (the mechanism is not simulated:
    /// the margins below are functions of `x`).
    fn problem(d: usize) -> Problem {
        let mech = Mechanism::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../data/mechanisms/reliability_one_panel.toml"
        )))
        .unwrap();
        Problem {
            mech,
            vary: (0..d)
                .map(|_| "coulomb_friction:joint=1:normal(0,1)".parse().unwrap())
                .collect(),
            fixed: Vec::new(),
            fail: vec![Criterion::NotLatched],
            corr: Vec::new(),
        }
    }

    /// Subset simulation over `seeds` seeds of a linear margin `β − a·u`
    /// (`a` the unit diagonal in `d` parameters): the ratios to the exact
    /// `Φ(−β)` and the printed c.o.v.s.
    fn sweep(d: usize, p: f64, seeds: u64) -> (Vec<f64>, Vec<f64>) {
        let beta = -normal::inverse_cdf(p);
        let pr = problem(d);
        let mut ratios = Vec::new();
        let mut covs = Vec::new();
        for seed in 0..seeds {
            let mut eval = |xs: &[Vec<f64>]| -> Result<Vec<Vec<f64>>, ReliabilityError> {
                Ok(xs
                    .iter()
                    .map(|x| vec![beta - x.iter().sum::<f64>() / (d as f64).sqrt()])
                    .collect())
            };
            let s = SubsetSettings {
                seed,
                ..SubsetSettings::default()
            };
            let e = run(&pr, &s, &mut eval, &crate::report::progress::quiet).unwrap();
            assert!(e.converged);
            ratios.push(e.p_fail / normal::tail(beta));
            covs.push(e.cov);
        }
        (ratios, covs)
    }

    /// The spread over seeds (sample c.o.v.) and the mean printed c.o.v.
    fn spread(ratios: &[f64], covs: &[f64]) -> (f64, f64) {
        let n = ratios.len() as f64;
        let mean = ratios.iter().sum::<f64>() / n;
        let var = ratios.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0);
        (var.sqrt() / mean, covs.iter().sum::<f64>() / n)
    }

    /// At 1e-6 on one parameter, where the levels are thin shells: no bias,
    /// and the printed c.o.v. is the spread over seeds (within 25 %).
    #[test]
    fn one_parameter_at_1e_6_is_unbiased_and_its_cov_is_the_spread() {
        let (mut ratios, covs) = sweep(1, 1e-6, 60);
        let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
        let (spread, printed) = spread(&ratios, &covs);
        ratios.sort_by(f64::total_cmp);
        let median = ratios[ratios.len() / 2];
        assert!((0.85..1.15).contains(&mean), "mean {mean}");
        assert!((0.8..1.25).contains(&median), "median {median}");
        assert!(
            ratios[0] > 1.0 / 3.0 && ratios[ratios.len() - 1] < 3.0,
            "{ratios:?}"
        );
        assert!(
            printed > spread / 1.25 && printed < spread * 1.25,
            "printed {printed} vs spread {spread}"
        );
    }
}
