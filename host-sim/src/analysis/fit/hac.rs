//! The heteroskedasticity-and-autocorrelation consistent (HAC) covariance
//! of a least-squares fit whose residuals are time series: the sandwich
//!
//! ```text
//! Cov(p) ≈ (JᵀJ)⁺ S (JᵀJ)⁺,   S = Σ_series Σ_{|l|≤L} (1 − |l|/(L+1)) Σ_t g_t g_{t−l}ᵀ,   g_t = J_tᵀ r_t
//! ```
//!
//! with the Bartlett kernel (Newey & West, *Econometrica* 55, 1987), lags
//! taken only within one contiguous series (one joint of one run), the
//! window `L + 1` from the data by Andrews' AR(1) plug-in rule (Andrews,
//! *Econometrica* 59, 1991, §6: `Ŝ_T = 1.1447 (α̂(1) T)^{1/3}`), and the
//! interval's critical value from the fixed-b asymptotics of Kiefer &
//! Vogelsang (*Econometric Theory* 21, 2005), which hold when the window
//! is a sizeable fraction `b` of the series — as it is for the smooth
//! residual a slightly wrong model leaves.
//!
//! The Bartlett sum is computed as the sum of outer products of the
//! scores' sums over every window of `L + 1` samples (zero outside the
//! series), divided by `L + 1`: the pair `(s, u)` lies in `L + 1 − |s − u|`
//! such windows, which is the kernel's weight. That makes it positive
//! semi-definite by construction and `O(m n²)` whatever the window.

use nalgebra::DMatrix;

/// Andrews' constant of the Bartlett kernel's optimal bandwidth
/// `Ŝ_T = 1.1447 (α̂(1) T)^{1/3}` (Andrews 1991, eq. 6.2) \[1\].
pub const ANDREWS_BARTLETT: f64 = 1.1447;

/// The largest AR(1) coefficient the plug-in rule takes \[1\]: nearer 1 the
/// window is the whole series anyway.
const RHO_MAX: f64 = 0.999_999;

/// The HAC estimate of a fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Hac {
    /// The sandwich covariance of the parameters (their units squared).
    pub cov: DMatrix<f64>,
    /// The Bartlett window `L + 1` \[samples\].
    pub window: usize,
    /// The window over the mean series length, `b` of the fixed-b theory
    /// \[1\] (at most 1).
    pub b: f64,
}

impl Hac {
    /// The two-sided 95 % critical value of a t statistic studentised by
    /// this estimate ([`critical_975`] at [`Hac::b`]).
    pub fn critical_975(&self) -> f64 {
        critical_975(self.b)
    }
}

/// The 0.975 quantile of the fixed-b limit of a t statistic studentised
/// with the Bartlett kernel at window fraction `b` (Kiefer & Vogelsang
/// 2005, the cubic fitted to their simulated quantiles:
/// `1.9600 + 2.9694 b + 0.4160 b² − 0.5324 b³`); the normal's 1.96 at
/// `b = 0`.
pub fn critical_975(b: f64) -> f64 {
    let b = b.clamp(0.0, 1.0);
    1.9600 + b * (2.9694 + b * (0.4160 - 0.5324 * b))
}

/// The scores `g_t = J_t r_t` (one row per residual, one column per
/// parameter).
pub fn scores(j: &DMatrix<f64>, r: &[f64]) -> DMatrix<f64> {
    let mut g = j.clone();
    for (t, &rt) in r.iter().enumerate().take(g.nrows()) {
        for a in 0..g.ncols() {
            g[(t, a)] *= rt;
        }
    }
    g
}

/// The start of each series of `lengths` and its length, in order.
fn spans(lengths: &[usize]) -> impl Iterator<Item = (usize, usize)> + '_ {
    lengths.iter().scan(0, |start, &len| {
        let s = *start;
        *start += len;
        Some((s, len))
    })
}

/// Andrews' (1991) AR(1) plug-in window `L + 1` \[samples\] of the Bartlett
/// kernel for scores `g` in series of `lengths`: an AR(1) fitted to each
/// parameter's score series (lags within a series), `α̂_a = 4ρ̂²/((1 − ρ̂)²
/// (1 + ρ̂)²)`, averaged over the parameters whose scores are not all zero
/// (each parameter counts alike, whatever its unit), and
/// `1.1447 (α̂ T)^{1/3}` with `T` the mean series length; at least 1, at
/// most the longest series.
pub fn andrews_window(g: &DMatrix<f64>, lengths: &[usize]) -> usize {
    let mut alphas = Vec::new();
    for a in 0..g.ncols() {
        let (mut lag1, mut lag0) = (0.0, 0.0);
        for (s, len) in spans(lengths) {
            for t in s + 1..s + len {
                lag1 += g[(t, a)] * g[(t - 1, a)];
                lag0 += g[(t - 1, a)] * g[(t - 1, a)];
            }
        }
        if lag0 > 0.0 && lag0.is_finite() {
            let rho = (lag1 / lag0).clamp(-RHO_MAX, RHO_MAX);
            alphas.push(4.0 * rho * rho / ((1.0 - rho).powi(2) * (1.0 + rho).powi(2)));
        }
    }
    let longest = lengths.iter().copied().max().unwrap_or(1).max(1);
    if alphas.is_empty() {
        return 1;
    }
    let alpha = alphas.iter().sum::<f64>() / alphas.len() as f64;
    let t = lengths.iter().sum::<usize>() as f64 / lengths.len().max(1) as f64;
    let w = ANDREWS_BARTLETT * (alpha * t).cbrt();
    if w.is_finite() {
        (w.round() as usize).clamp(1, longest)
    } else {
        longest
    }
}

/// The Bartlett long-run covariance `S` of scores `g` in series of
/// `lengths` with window `window` (`L + 1`): `Σ` over every window
/// position of the outer product of the window's score sum, over `window`.
/// `window = 1` is White's (1980) heteroskedasticity-consistent `Σ g_t g_tᵀ`.
pub fn long_run(g: &DMatrix<f64>, lengths: &[usize], window: usize) -> DMatrix<f64> {
    let n = g.ncols();
    let w = window.max(1);
    let mut s = DMatrix::zeros(n, n);
    let mut sum = vec![0.0; n];
    for (start, len) in spans(lengths) {
        sum.iter_mut().for_each(|x| *x = 0.0);
        // Window positions ending at k = start .. start + len + w − 2: the
        // sum of g over [k − w + 1, k] ∩ the series.
        for k in start..start + len + w - 1 {
            if k < start + len {
                for a in 0..n {
                    sum[a] += g[(k, a)];
                }
            }
            if k >= start + w {
                let out = k - w;
                for a in 0..n {
                    sum[a] -= g[(out, a)];
                }
            }
            for a in 0..n {
                for c in a..n {
                    s[(a, c)] += sum[a] * sum[c];
                }
            }
        }
    }
    for a in 0..n {
        for c in a..n {
            let v = s[(a, c)] / w as f64;
            s[(a, c)] = v;
            s[(c, a)] = v;
        }
    }
    s
}

/// The HAC covariance of a fit with Jacobian `j`, residuals `r` and the
/// pseudo-inverse `bread = (JᵀJ)⁺`, the residuals in contiguous series of
/// `lengths` (summing to `r.len()`); `None` when they do not.
pub fn hac(j: &DMatrix<f64>, r: &[f64], bread: &DMatrix<f64>, lengths: &[usize]) -> Option<Hac> {
    if lengths.iter().sum::<usize>() != r.len() || r.len() != j.nrows() || lengths.is_empty() {
        return None;
    }
    let g = scores(j, r);
    let window = andrews_window(&g, lengths);
    let s = long_run(&g, lengths, window);
    let mean_len = r.len() as f64 / lengths.len() as f64;
    Some(Hac {
        cov: bread * s * bread,
        window,
        b: (window as f64 / mean_len).min(1.0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Standard normal draws (splitmix64 and Box–Muller; deterministic).
    fn normals(seed: u64, n: usize) -> Vec<f64> {
        let mut state = seed;
        let mut uniform = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| {
                let (u, v) = (uniform().max(1e-300), uniform());
                (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
            })
            .collect()
    }

    /// The variance of a mean's estimate, HAC over OLS, for errors `e`
    /// (model: a constant; `J` a column of ones).
    fn inflation(e: &[f64], lengths: &[usize]) -> (f64, usize) {
        let m = e.len();
        let mean = e.iter().sum::<f64>() / m as f64;
        let r: Vec<f64> = e.iter().map(|x| x - mean).collect();
        let j = DMatrix::from_element(m, 1, 1.0);
        let bread = DMatrix::from_element(1, 1, 1.0 / m as f64);
        let h = hac(&j, &r, &bread, lengths).unwrap();
        let ols = r.iter().map(|x| x * x).sum::<f64>() / (m - 1) as f64 / m as f64;
        (h.cov[(0, 0)] / ols, h.window)
    }

    #[test]
    fn white_noise_gives_about_the_ols_variance() {
        for seed in 1..4 {
            let e = normals(seed, 20_000);
            let (ratio, window) = inflation(&e, &[20_000]);
            assert!((0.85..1.15).contains(&ratio), "seed {seed}: {ratio}");
            assert!(window < 20, "seed {seed}: window {window}");
        }
    }

    #[test]
    fn ar1_inflates_the_variance_by_its_long_run_factor() {
        for (rho, seed) in [(0.5, 7u64), (0.8, 8), (-0.4, 9)] {
            let z = normals(seed, 40_000);
            let mut e = Vec::with_capacity(z.len());
            let mut x = 0.0;
            for v in z {
                x = rho * x + v;
                e.push(x);
            }
            // Four series of 10 000: lags never cross their joins.
            let (ratio, _) = inflation(&e, &[10_000; 4]);
            let want = (1.0 + rho) / (1.0 - rho);
            assert!(
                (ratio / want - 1.0).abs() < 0.2,
                "rho {rho}: inflation {ratio}, (1+ρ)/(1−ρ) = {want}"
            );
        }
    }

    #[test]
    fn window_one_is_whites_estimator_and_lags_stay_in_their_series() {
        let g = DMatrix::from_row_slice(4, 1, &[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(long_run(&g, &[4], 1)[(0, 0)], 30.0);
        // Window 2 within one series: Σ g² + Σ g_t g_{t−1} = 30 + 20.
        assert_eq!(long_run(&g, &[4], 2)[(0, 0)], 50.0);
        // Two series of two: the pair (2, 3) is not neighbours: 30 + 2 + 12.
        assert_eq!(long_run(&g, &[2, 2], 2)[(0, 0)], 44.0);
    }

    #[test]
    fn fixed_b_critical_values() {
        assert!((critical_975(0.0) - 1.96).abs() < 1e-12);
        assert!(critical_975(0.5) > critical_975(0.1));
        assert!((critical_975(1.0) - 4.8130).abs() < 1e-3);
    }
}
