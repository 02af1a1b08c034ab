//! Subset simulation (Au & Beck 2001): `P(F) = Π_k P(F_k | F_{k−1})` over
//! nested domains `F_k = {g ≤ b_k}`, each threshold `b_k` the `p0`-quantile
//! of the level's samples, the samples of the next level grown from the
//! `p0 N` seeds below it by the modified Metropolis algorithm in the
//! standard normal space (component-wise proposals `N(u_i, 1)`, accepted
//! with `min(1, φ(ξ)/φ(u_i))`, the candidate kept iff `g ≤ b_k`).
//!
//! The c.o.v. is Au & Beck's Eq. 28–29 (`δ_k² = (1 − p_k)/(N p_k)(1 + γ_k)`,
//! `γ_k` from the correlation of the indicators along the chains), summed
//! over the levels as if they were independent (a lower bound); the 95 %
//! interval is that of a lognormal estimator with that c.o.v.

use super::mc::{check_len, draw};
use super::{stream, Estimate, Evaluate, FailurePoint, Level, Problem, ReliabilityError};
use crate::analysis::fit::Z_975;
use crate::report::progress::Progress;
use rand::Rng;
use rand_distr::StandardNormal;

/// Settings of subset simulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubsetSettings {
    /// Samples per level `N` (a multiple of `1/p0`).
    pub samples: usize,
    /// Conditional probability of each level.
    pub p0: f64,
    /// Most levels (the smallest probability is `p0^max_levels`).
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
/// of chain `c`).
struct Population {
    u: Vec<Vec<f64>>,
    x: Vec<Vec<f64>>,
    g: Vec<f64>,
    chains: usize,
}

/// Runs subset simulation.
pub fn run(
    problem: &Problem,
    s: &SubsetSettings,
    eval: Evaluate<'_>,
    progress: Progress<'_>,
) -> Result<Estimate, ReliabilityError> {
    let n = s.samples;
    let nc = (s.p0 * n as f64).round() as usize;
    if !(s.p0 > 0.0 && s.p0 < 0.5) || nc == 0 || n % nc != 0 || nc < 2 {
        return Err(ReliabilityError::Invalid(format!(
            "subset: {n} samples per level and p0 = {}: expected p0 in (0, 0.5) and N·p0 \
             a whole number ≥ 2 dividing N (e.g. N = 1000, 2000 with p0 = 0.1)",
            s.p0
        )));
    }
    let d = problem.vary.len();
    let u: Vec<Vec<f64>> = (0..n).map(|i| draw(s.seed, 0, i as u64, d)).collect();
    let x: Vec<Vec<f64>> = u.iter().map(|u| problem.x_of(u)).collect();
    let g = eval(&x)?;
    check_len(&g, n)?;
    let mut pop = Population { u, x, g, chains: n };
    let mut levels: Vec<Level> = Vec::new();
    let mut sims = n;
    let mut level_sims = n;
    let mut p = 1.0;
    for k in 0..s.max_levels {
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| pop.g[a].total_cmp(&pop.g[b]).then(a.cmp(&b)));
        let b = 0.5 * (pop.g[order[nc - 1]] + pop.g[order[nc]]);
        let last = b <= 0.0;
        let threshold = if last { 0.0 } else { b };
        let hits = pop.g.iter().filter(|&&g| g <= threshold).count();
        let pk = hits as f64 / n as f64;
        let cov = level_cov(&pop, threshold, pk);
        p *= pk;
        levels.push(Level {
            threshold,
            p: pk,
            cov,
            simulations: level_sims,
        });
        progress(&format!(
            "subset: level {k}: threshold {threshold:.6e}, p = {pk:.3}, {sims} deployments so far"
        ));
        if last {
            return Ok(finish(levels, p, sims, hits, true, &pop));
        }
        if levels.len() >= 2 && !(b < levels[levels.len() - 2].threshold) {
            break;
        }
        let seeds: Vec<usize> = order[..nc].to_vec();
        let (next, used) = grow(problem, s, k + 1, &pop, &seeds, b, eval)?;
        pop = next;
        sims += used;
        level_sims = used;
    }
    let hits = pop.g.iter().filter(|&&g| g <= 0.0).count();
    Ok(finish(levels, p, sims, hits, false, &pop))
}

/// The estimate from the levels (not converged: `p` bounds `P(F)` above).
fn finish(
    levels: Vec<Level>,
    p: f64,
    sims: usize,
    hits: usize,
    converged: bool,
    pop: &Population,
) -> Estimate {
    let d2: f64 = levels.iter().map(|l| l.cov * l.cov).sum();
    let cov = d2.sqrt();
    let s = (1.0 + d2).ln().sqrt();
    let z = Z_975;
    let mut best = None;
    for i in 0..pop.g.len() {
        FailurePoint::keep_best(&mut best, &pop.u[i], &pop.x[i], pop.g[i]);
    }
    Estimate {
        method: "subset",
        p_fail: p,
        cov,
        ci95: (p * (-z * s).exp(), (p * (z * s).exp()).min(1.0)),
        simulations: sims,
        failures: hits,
        levels,
        converged,
        most_likely_failure: best,
    }
}

/// Au & Beck's c.o.v. of a level's conditional probability `pk` of
/// `g ≤ b` (Eq. 28–29), `γ = 0` for the independent samples of level 0.
fn level_cov(pop: &Population, b: f64, pk: f64) -> f64 {
    let n = pop.g.len();
    let nf = n as f64;
    if pk <= 0.0 {
        return f64::INFINITY;
    }
    let base = (1.0 - pk) / (nf * pk);
    if pop.chains == n || pk >= 1.0 {
        return base.sqrt();
    }
    let len = n / pop.chains;
    let ind: Vec<f64> = pop.g.iter().map(|&g| f64::from(u8::from(g <= b))).collect();
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

/// The next level: from each seed a chain of `N / N_c` states (the seed
/// first) by the modified Metropolis algorithm; the draws of step `s` of
/// chain `c` come from stream (seed, level, `c · len + s`), the candidates
/// of one step go to the evaluator together.
fn grow(
    problem: &Problem,
    s: &SubsetSettings,
    level: u32,
    pop: &Population,
    seeds: &[usize],
    b: f64,
    eval: Evaluate<'_>,
) -> Result<(Population, usize), ReliabilityError> {
    let n = pop.g.len();
    let chains = seeds.len();
    let len = n / chains;
    let d = problem.vary.len();
    let mut u = vec![Vec::new(); n];
    let mut x = vec![Vec::new(); n];
    let mut g = vec![0.0; n];
    for (c, &i) in seeds.iter().enumerate() {
        u[c * len] = pop.u[i].clone();
        x[c * len] = pop.x[i].clone();
        g[c * len] = pop.g[i];
    }
    let mut used = 0;
    for step in 1..len {
        let mut moved: Vec<(usize, Vec<f64>)> = Vec::new();
        for c in 0..chains {
            let (cur, at) = (c * len + step - 1, c * len + step);
            let mut rng = stream(s.seed, level, at as u64);
            let mut cand = u[cur].clone();
            for ui in cand.iter_mut().take(d) {
                let xi: f64 = *ui + rng.sample::<f64, _>(StandardNormal);
                let ratio = (0.5 * (*ui * *ui - xi * xi)).exp();
                if rng.gen::<f64>() < ratio {
                    *ui = xi;
                }
            }
            if cand != u[cur] {
                moved.push((c, cand));
            }
            u[at] = u[cur].clone();
            x[at] = x[cur].clone();
            g[at] = g[cur];
        }
        let xs: Vec<Vec<f64>> = moved.iter().map(|(_, c)| problem.x_of(c)).collect();
        let gs = if xs.is_empty() {
            Vec::new()
        } else {
            eval(&xs)?
        };
        check_len(&gs, xs.len())?;
        used += xs.len();
        for (((c, cu), cx), cg) in moved.into_iter().zip(xs).zip(gs) {
            if cg <= b {
                let at = c * len + step;
                u[at] = cu;
                x[at] = cx;
                g[at] = cg;
            }
        }
    }
    Ok((Population { u, x, g, chains }, used))
}
