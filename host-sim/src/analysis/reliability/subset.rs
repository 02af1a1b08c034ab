//! Subset simulation (Au & Beck 2001), one run per failure mode: `P(F_m)
//! = Π_k P(F_k | F_{k−1})` over nested domains `F_k = {m ≤ b_k}` of the
//! mode's margin `m`, each threshold `b_k` the `p0`-quantile of the level's
//! samples, the samples of the next level grown from the `p0 N` seeds below
//! it by the modified Metropolis algorithm in the standard normal space
//! (component-wise proposals `N(u_i, 1)`, accepted with `min(1,
//! φ(ξ)/φ(u_i))`, the candidate kept iff `m ≤ b_k`).
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
//! The c.o.v. of a mode is Au & Beck's Eq. 28–29 (`δ_k² = (1 − p_k)/(N
//! p_k)(1 + γ_k)`, `γ_k` from the correlation of the indicators along the
//! chains), summed over the levels as if they were independent; the modes
//! are independent runs beyond their shared first level.

use super::estimate::{Estimate, FailurePoint, Level, ModeResult};
use super::mc::{check_rows, draw, system};
use super::{stream, Evaluate, Problem, ReliabilityError};
use crate::report::progress::Progress;
use rand::Rng;
use rand_distr::StandardNormal;

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

/// One level's population, chain-major (sample `c · len + s` is step `s`
/// of chain `c`), with every mode's margin of each sample.
#[derive(Clone)]
struct Population {
    u: Vec<Vec<f64>>,
    x: Vec<Vec<f64>>,
    m: Vec<Vec<f64>>,
    chains: usize,
}

/// Runs subset simulation, one run per mode, the modes a level at a time
/// in turn (so that a mode already negligible against those reached stops).
pub fn run(
    problem: &Problem,
    s: &SubsetSettings,
    eval: Evaluate<'_>,
    progress: Progress<'_>,
) -> Result<Estimate, ReliabilityError> {
    let n = s.samples;
    let nc = (s.p0 * n as f64).round() as usize;
    if !(s.p0 > 0.0 && s.p0 < 0.5) || nc == 0 || n % nc != 0 || nc < 2 || s.max_levels > 63 {
        return Err(ReliabilityError::Invalid(format!(
            "subset: {n} samples per level and p0 = {}: expected p0 in (0, 0.5) and N·p0 \
             a whole number ≥ 2 dividing N (e.g. N = 1000, 2000 with p0 = 0.1)",
            s.p0
        )));
    }
    let modes = problem.modes();
    let d = problem.vary.len();
    let u: Vec<Vec<f64>> = (0..n).map(|i| draw(s.seed, 0, i as u64, d)).collect();
    let x: Vec<Vec<f64>> = u.iter().map(|u| problem.x_of(u)).collect();
    let m = eval(&x)?;
    check_rows(&m, n, modes.len())?;
    let first = Population { u, x, m, chains: n };
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
            let level = r.mi as u32 * 64 + k + 1;
            let (next, used) = grow(problem, s, level, r.mi, &r.pop, &seeds, b, eval)?;
            r.pop = next;
            r.sims += used;
            r.level_sims = used;
        }
    }
    let mut results: Vec<ModeResult> = Vec::new();
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
        let cov = r.levels.iter().map(|l| l.cov * l.cov).sum::<f64>().sqrt();
        results.push(ModeResult {
            mode: modes[mi],
            p: r.p,
            cov,
            converged: stop == Stop::Reached,
            stop: stop.name(),
            levels: r.levels,
            counted: if fails.is_empty() {
                1.0
            } else {
                new as f64 / fails.len() as f64
            },
            simulations: r.sims,
        });
    }
    let sims = n + results.iter().map(|r| r.simulations).sum::<usize>();
    Ok(combine(results, sims, failures, best))
}

/// The system's estimate from its modes' (those reached).
fn combine(
    modes: Vec<ModeResult>,
    sims: usize,
    failures: usize,
    best: Option<FailurePoint>,
) -> Estimate {
    let reached = modes.iter().filter(|r| r.converged);
    let p = reached.clone().fold(0.0, |a, r| a + r.p * r.counted);
    let var: f64 = reached.map(|r| (r.p * r.counted * r.cov).powi(2)).sum();
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
        let cov = level_cov(pop, mi, threshold, pk);
        self.p *= pk;
        self.levels.push(Level {
            threshold,
            p: pk,
            cov,
            simulations: self.level_sims,
        });
        progress(&format!(
            "subset: {mode}: level {k}: threshold {threshold:.6e}, p = {pk:.3}, {} deployments",
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

/// Au & Beck's c.o.v. of a level's conditional probability `pk` of mode
/// `mi`'s margin `≤ b` (Eq. 28–29), `γ = 0` for the independent samples of
/// the first level.
fn level_cov(pop: &Population, mi: usize, b: f64, pk: f64) -> f64 {
    let n = pop.m.len();
    let nf = n as f64;
    if pk <= 0.0 {
        return f64::INFINITY;
    }
    let base = (1.0 - pk) / (nf * pk);
    if pop.chains == n || pk >= 1.0 {
        return base.sqrt();
    }
    let len = n / pop.chains;
    let ind: Vec<f64> = pop
        .m
        .iter()
        .map(|r| f64::from(u8::from(r[mi] <= b)))
        .collect();
    let r0 = pk * (1.0 - pk);
    let mut gamma = 0.0;
    for tau in 1..len {
        let mut sum = 0.0;
        for c in 0..pop.chains {
            for s in 0..len - tau {
                sum += ind[c * len + s] * ind[c * len + s + tau];
            }
        }
        let r = sum / (n - tau * pop.chains) as f64 - pk * pk;
        gamma += 2.0 * (1.0 - (tau * pop.chains) as f64 / nf) * r / r0;
    }
    (base * (1.0 + gamma)).sqrt()
}

/// The next level of mode `mi`: from each seed a chain of `N / N_c` states
/// (the seed first) by the modified Metropolis algorithm; the draws of
/// step `s` of chain `c` come from stream (seed, level, `c · len + s`), the
/// candidates of one step go to the evaluator together.
#[allow(clippy::too_many_arguments)]
fn grow(
    problem: &Problem,
    s: &SubsetSettings,
    level: u32,
    mi: usize,
    pop: &Population,
    seeds: &[usize],
    b: f64,
    eval: Evaluate<'_>,
) -> Result<(Population, usize), ReliabilityError> {
    let n = pop.m.len();
    let chains = seeds.len();
    let len = n / chains;
    let width = pop.m[0].len();
    let mut next = Population {
        u: vec![Vec::new(); n],
        x: vec![Vec::new(); n],
        m: vec![Vec::new(); n],
        chains,
    };
    for (c, &i) in seeds.iter().enumerate() {
        next.u[c * len] = pop.u[i].clone();
        next.x[c * len] = pop.x[i].clone();
        next.m[c * len] = pop.m[i].clone();
    }
    let mut used = 0;
    for step in 1..len {
        let mut moved: Vec<(usize, Vec<f64>)> = Vec::new();
        for c in 0..chains {
            let (cur, at) = (c * len + step - 1, c * len + step);
            let mut rng = stream(s.seed, level, at as u64);
            let mut cand = next.u[cur].clone();
            for ui in cand.iter_mut() {
                let xi: f64 = *ui + rng.sample::<f64, _>(StandardNormal);
                let ratio = (0.5 * (*ui * *ui - xi * xi)).exp();
                if rng.gen::<f64>() < ratio {
                    *ui = xi;
                }
            }
            if cand != next.u[cur] {
                moved.push((c, cand));
            }
            next.u[at] = next.u[cur].clone();
            next.x[at] = next.x[cur].clone();
            next.m[at] = next.m[cur].clone();
        }
        let xs: Vec<Vec<f64>> = moved.iter().map(|(_, c)| problem.x_of(c)).collect();
        let ms = if xs.is_empty() {
            Vec::new()
        } else {
            eval(&xs)?
        };
        check_rows(&ms, xs.len(), width)?;
        used += xs.len();
        for (((c, cu), cx), cm) in moved.into_iter().zip(xs).zip(ms) {
            if cm[mi] <= b {
                let at = c * len + step;
                next.u[at] = cu;
                next.x[at] = cx;
                next.m[at] = cm;
            }
        }
    }
    Ok((next, used))
}
