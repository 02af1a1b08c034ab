//! The Markov chains of subset simulation: adaptive conditional sampling
//! (aCS, Papaioannou, Betz, Zwirglmaier & Straub 2015, "MCMC algorithms for
//! Subset Simulation", *Probabilistic Engineering Mechanics* 41, 89–103,
//! Algorithm 5), and the c.o.v. of a level's conditional probability from
//! the correlation along its chains (Au & Beck 2001, Eq. 28–29).
//!
//! From a state `u` in `F_k = {m ≤ b_k}` the candidate is, component by
//! component, `ξ_i = ρ_i u_i + √(1 − ρ_i²) z_i`, `z_i` standard normal,
//! `σ_i = √(1 − ρ_i²) = min(1, λ σ̂_i)`, `σ̂_i` the standard deviation of
//! the level's seeds in component `i`. This conditional normal leaves the
//! standard normal law invariant, so the candidate needs no density test:
//! it is taken iff `m(ξ) ≤ b_k`. The scale `λ` is adapted after every step
//! of all the chains toward the acceptance rate [`TARGET_ACCEPTANCE`]:
//! `λ ← λ exp((a − 0.44)/√t)`, `t` the step (Papaioannou et al., Eq. 26),
//! and carried to the next level. Unlike the component-wise Metropolis
//! proposal `N(u_i, 1)` of Au & Beck, whose unit steps are rejected almost
//! always where the level is a thin shell (one parameter at `β ≈ 4.5`, the
//! conditional law 0.2 wide), the steps shrink to the level's width and
//! the chains keep moving: on a linear margin of one parameter at 1e-6
//! the spread of the estimate over 200 seeds falls from 0.69 to 0.34, the
//! smallest of them from 0.15 to 0.44 of the exact value (the subset
//! module's tests; docs/reliability.md §5). Every candidate is simulated
//! (`N − N_c` deployments a level).

use super::mc::check_rows;
use super::{stream, Evaluate, Problem, ReliabilityError};
use rand::Rng;
use rand_distr::StandardNormal;

/// The acceptance rate the chains' scale is adapted toward (Papaioannou et
/// al. 2015: 0.44, optimal for one-dimensional random walks).
pub const TARGET_ACCEPTANCE: f64 = 0.44;

/// The scale `λ` of the first level's chains.
pub const START_SCALE: f64 = 0.6;

/// The smallest `σ̂_i` a level's seeds give a component (so that chains
/// whose seeds coincide in a component still move in it).
pub const MIN_SEED_SD: f64 = 1e-3;

/// One level's population, chain-major (sample `c · len + s` is step `s`
/// of chain `c`), with every mode's margin of each sample.
#[derive(Clone)]
pub(super) struct Population {
    /// Standard normal points.
    pub u: Vec<Vec<f64>>,
    /// Parameters.
    pub x: Vec<Vec<f64>>,
    /// Every mode's margin.
    pub m: Vec<Vec<f64>>,
    /// Chains (the population's size for independent draws).
    pub chains: usize,
    /// Per chain: the index of its seed in the previous level's
    /// population (empty for the first level).
    pub parent: Vec<usize>,
}

/// Where the next level's chains start, in what domain, and how.
pub(super) struct Grow<'a> {
    /// The current level's population.
    pub pop: &'a Population,
    /// The seeds: indices into `pop`, all with `m[mode] ≤ b`.
    pub seeds: &'a [usize],
    /// The mode whose margin defines the level.
    pub mode: usize,
    /// The level's threshold `b`.
    pub b: f64,
    /// The stream level of the chains' draws.
    pub level: u32,
    /// The run's seed.
    pub seed: u64,
}

/// The next level: from each seed a chain of `N / N_c` states (the seed
/// first) by aCS (module doc), `λ` adapted along the way. Step `s` of chain
/// `c` draws from stream (seed, level, `c · len + s`), and the candidates
/// of one step go to the evaluator together, so the result does not depend
/// on how the evaluator cuts or spreads the batch. Returns the population
/// and the deployments it took.
pub(super) fn grow(
    problem: &Problem,
    g: &Grow<'_>,
    lambda: &mut f64,
    eval: Evaluate<'_>,
) -> Result<(Population, usize), ReliabilityError> {
    let n = g.pop.m.len();
    let chains = g.seeds.len();
    let len = n / chains;
    let width = g.pop.m[0].len();
    let sd = seed_sd(g.pop, g.seeds);
    let mut next = Population {
        u: vec![Vec::new(); n],
        x: vec![Vec::new(); n],
        m: vec![Vec::new(); n],
        chains,
        parent: g.seeds.to_vec(),
    };
    for (c, &i) in g.seeds.iter().enumerate() {
        next.u[c * len] = g.pop.u[i].clone();
        next.x[c * len] = g.pop.x[i].clone();
        next.m[c * len] = g.pop.m[i].clone();
    }
    let mut used = 0;
    for step in 1..len {
        let sigma: Vec<f64> = sd.iter().map(|s| (*lambda * s).min(1.0)).collect();
        let cands: Vec<Vec<f64>> = (0..chains)
            .map(|c| {
                let mut rng = stream(g.seed, g.level, (c * len + step) as u64);
                let cur = &next.u[c * len + step - 1];
                cur.iter()
                    .zip(&sigma)
                    .map(|(&u, &s)| {
                        let z: f64 = rng.sample(StandardNormal);
                        (1.0 - s * s).sqrt() * u + s * z
                    })
                    .collect()
            })
            .collect();
        let xs: Vec<Vec<f64>> = cands.iter().map(|c| problem.x_of(c)).collect();
        let ms = eval(&xs)?;
        check_rows(&ms, xs.len(), width)?;
        used += xs.len();
        let mut accepted = 0;
        for (c, ((cu, cx), cm)) in cands.into_iter().zip(xs).zip(ms).enumerate() {
            let (cur, at) = (c * len + step - 1, c * len + step);
            if cm[g.mode] <= g.b {
                accepted += 1;
                next.u[at] = cu;
                next.x[at] = cx;
                next.m[at] = cm;
            } else {
                next.u[at] = next.u[cur].clone();
                next.x[at] = next.x[cur].clone();
                next.m[at] = next.m[cur].clone();
            }
        }
        let a = accepted as f64 / chains as f64;
        *lambda *= ((a - TARGET_ACCEPTANCE) / (step as f64).sqrt()).exp();
    }
    Ok((next, used))
}

/// The standard deviation of the seeds in each component (at least
/// [`MIN_SEED_SD`]).
fn seed_sd(pop: &Population, seeds: &[usize]) -> Vec<f64> {
    let d = pop.u[0].len();
    let k = seeds.len() as f64;
    (0..d)
        .map(|i| {
            let mean = seeds.iter().map(|&s| pop.u[s][i]).sum::<f64>() / k;
            let var = seeds
                .iter()
                .map(|&s| (pop.u[s][i] - mean).powi(2))
                .sum::<f64>()
                / (k - 1.0).max(1.0);
            var.sqrt().max(MIN_SEED_SD)
        })
        .collect()
}
