//! The c.o.v. of subset simulation's estimate, chain correlation and the
//! correlation between levels included, from the lineage of its samples.
//!
//! Level `k`'s conditional probability is `p_k = (1/N) Σ_j I_k(j)`, `I_k(j)
//! = 1[m_j ≤ b_k]` over the level's `N` samples. Au & Beck (2001, Eq. 27–29)
//! give its variance from the correlation of `I_k` along the level's
//! chains, `Var p_k = p_k (1 − p_k)/N · (1 + γ_k)`; as a sum over the level's
//! chains `c` it is `(1/N²) Σ_c e_k(c)²`, `e_k(c) = Σ_{j ∈ c} (I_k(j) − p_k)`
//! (the same sum of lagged covariances), [`level_covs`]. They then add the
//! levels' `δ_k²` as if the levels were independent, which they are not:
//! the chains of level `k + 1` start from samples of level `k`, so a chain
//! that happened to run deep into the failure side gives many seeds, whose
//! chains start deep too, and sibling chains start from one chain's
//! neighbouring states. Where the chains move slowly (few parameters) that
//! leaves the variance some 30 % short (docs/reliability.md §5).
//!
//! Here every sample of every level descends from one independent draw `r`
//! of the first level (its seed, that seed's seed, ...). The families of
//! different draws are independent but for the thresholds they share (an
//! `O(1/N)` coupling), so the first-order error of `ln P = Σ_k ln p_k` is a
//! sum of independent family shares,
//!
//! `ln P − ln P_true ≈ Σ_r Z_r`, `Z_r = Σ_k E_k(r)/(N p_k)`,
//!
//! `E_k(r)` the sum of `I_k − p_k` over the samples of level `k` in `r`'s
//! family, and `δ² = Var(ln P) ≈ Σ_r Z_r²` (a cluster, or sandwich,
//! variance: every correlation inside a family counts, along a chain,
//! between sibling chains and between levels, and terms that are in fact
//! independent add nothing on average). It is never taken below Au &
//! Beck's `Σ_k δ_k²`. The system's c.o.v. sums the modes' shares family by
//! family ([`super::subset`]): the modes share the first level.

/// One closed level, as the c.o.v. needs it.
#[derive(Clone, Debug, Default)]
pub(super) struct Trace {
    /// Per sample (chain-major): at or below the level's threshold.
    pub hit: Vec<bool>,
    /// Samples per chain (1 for the first level's independent draws).
    pub len: usize,
    /// Per chain: the index of its seed in the previous level's samples
    /// (empty for the first level).
    pub parent: Vec<usize>,
}

impl Trace {
    fn p(&self) -> f64 {
        self.hit.iter().filter(|&&h| h).count() as f64 / self.hit.len() as f64
    }

    /// `e(c)`: per chain, the sum of `I − p` over its samples.
    fn residuals(&self) -> Vec<f64> {
        let p = self.p();
        self.hit
            .chunks(self.len)
            .map(|c| c.iter().map(|&h| f64::from(u8::from(h)) - p).sum())
            .collect()
    }
}

/// The chain sums `sums` of level `from` summed onto the chains of level
/// `to ≤ from` they descend from.
fn down(levels: &[Trace], mut sums: Vec<f64>, from: usize, to: usize) -> Vec<f64> {
    for j in (to + 1..=from).rev() {
        let prev = &levels[j - 1];
        let mut up = vec![0.0; prev.hit.len() / prev.len];
        for (chain, &seed) in levels[j].parent.iter().enumerate() {
            up[seed / prev.len] += sums[chain];
        }
        sums = up;
    }
    sums
}

/// Per level `δ_k`, Au & Beck's c.o.v. of `p_k` from its own chains
/// (`∞` where `p_k = 0`).
pub(super) fn level_covs(levels: &[Trace]) -> Vec<f64> {
    levels
        .iter()
        .map(|t| {
            let (p, n) = (t.p(), t.hit.len() as f64);
            let var: f64 = t.residuals().iter().map(|e| e * e).sum::<f64>() / (n * n);
            if p > 0.0 {
                var.sqrt() / p
            } else {
                f64::INFINITY
            }
        })
        .collect()
}

/// `Z_r`: per draw `r` of the first level, the first-order share of its
/// family in `ln Π p_k`, `Σ_k E_k(r)/(N_k p_k)` (module doc); `None` when a
/// level has no hit.
pub(super) fn influence(levels: &[Trace]) -> Option<Vec<f64>> {
    let roots = levels.first()?.hit.len();
    let mut z = vec![0.0; roots];
    for (k, t) in levels.iter().enumerate() {
        let p = t.p();
        if p <= 0.0 {
            return None;
        }
        let scale = 1.0 / (t.hit.len() as f64 * p);
        for (zr, e) in z.iter_mut().zip(down(levels, t.residuals(), k, 0)) {
            *zr += e * scale;
        }
    }
    Some(z)
}

/// The c.o.v. of `Π p_k` from the families' shares: `√Σ_r Z_r²`, never
/// below Au & Beck's `√Σ δ_k²` (levels independent); `∞` when a level has
/// no hit.
pub(super) fn cov(levels: &[Trace]) -> f64 {
    let Some(z) = influence(levels) else {
        return f64::INFINITY;
    };
    let independent: f64 = level_covs(levels).iter().map(|d| d * d).sum();
    z.iter().map(|z| z * z).sum::<f64>().max(independent).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Independent draws: the binomial c.o.v.
    #[test]
    fn one_level_of_independent_draws_is_binomial() {
        let t = Trace {
            hit: (0..1000).map(|i| i % 10 == 0).collect(),
            len: 1,
            parent: Vec::new(),
        };
        let binomial = (0.9f64 / (1000.0 * 0.1)).sqrt();
        assert!((level_covs(std::slice::from_ref(&t))[0] - binomial).abs() < 1e-12);
        assert!((cov(&[t]) - binomial).abs() < 1e-12);
    }

    /// Chains that never move count one sample `len` times (`len` times
    /// the binomial variance), and a second level whose chains carry the
    /// first level's hits on is correlated with it: the c.o.v. is above
    /// the levels' taken as independent, and at most their sum.
    #[test]
    fn stuck_chains_and_carried_levels_add_up() {
        let first = Trace {
            hit: (0..100).map(|i| i % 10 == 0).collect(),
            len: 1,
            parent: Vec::new(),
        };
        // 10 chains of 10, seeded from the first level's samples 0, 10, ...,
        // 40 (hits) and 51, 61, ..., 91 (misses).
        let parent: Vec<usize> = (0..10)
            .map(|c| if c < 5 { 10 * c } else { 10 * c + 1 })
            .collect();
        let second = Trace {
            hit: (0..100).map(|i| i / 10 < 5).collect(),
            len: 10,
            parent,
        };
        let levels = [first, second];
        let each = level_covs(&levels);
        let b = (0.5f64 / (100.0 * 0.5)).sqrt();
        assert!((each[1] - b * 10f64.sqrt()).abs() < 1e-12, "{each:?}");
        let all = cov(&levels);
        assert!(all > (each[0].powi(2) + each[1].powi(2)).sqrt() + 0.01);
        assert!(all <= each[0] + each[1] + 1e-12, "{all} vs {each:?}");
        // The families of the ten seeds carry all of the second level.
        let z = influence(&levels).unwrap();
        assert_eq!(z.iter().filter(|&&z| z.abs() > 0.1).count(), 10);
    }
}
