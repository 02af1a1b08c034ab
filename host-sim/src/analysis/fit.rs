//! Nonlinear least squares over simulations: Levenberg–Marquardt (the
//! MINPACK algorithm as ported by the `levenberg-marquardt` crate) with a
//! finite-difference Jacobian whose columns are simulated in parallel
//! (rayon), bounds by projection, and 95 % confidence intervals from the
//! Jacobian at the solution. The ordinary (white-noise) interval
//!
//! ```text
//! s² = SSE / (m − n),   Cov(p) ≈ s² (JᵀJ)⁻¹,   CI95 = p ± t₀.₉₇₅,ₘ₋ₙ · sd
//! ```
//!
//! (Bates & Watts, *Nonlinear Regression Analysis*, 1988, §2.3), and, when
//! the model says its residuals are time series ([`Residuals::series`]),
//! the wider of it and the autocorrelation-consistent interval of [`hac`]
//! (`p ± c(b) · sd_HAC`, the sandwich of Newey & West 1987 with the fixed-b
//! critical value `c(b)` of Kiefer & Vogelsang 2005). Used by
//! `identify --method direct` and by `diagnose`.

pub mod hac;

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{DMatrix, DVector, Dyn, Owned};
use rayon::prelude::*;
use std::sync::Mutex;

/// A least-squares problem: parameters (natural units) → residuals.
pub trait Residuals: Sync {
    /// The residual vector at `p`, `None` where the model cannot be evaluated
    /// (e.g. a simulation failed). Its length must not depend on `p`.
    fn residuals(&self, p: &[f64]) -> Option<Vec<f64>>;
    /// The lengths of the contiguous time series the residual vector is
    /// made of, in order (e.g. one joint of one run), summing to its
    /// length; `None` (the default): the residuals are not series, and the
    /// fit reports the ordinary intervals only.
    fn series(&self) -> Option<&[usize]> {
        None
    }
}

/// A model whose residual vector is the concatenation of contiguous time
/// series of the given lengths ([`Residuals::series`]).
pub struct InSeries<'a> {
    /// The model.
    pub model: &'a dyn Residuals,
    /// The series' lengths, in the order of the residual vector.
    pub lengths: Vec<usize>,
}

impl Residuals for InSeries<'_> {
    fn residuals(&self, p: &[f64]) -> Option<Vec<f64>> {
        self.model.residuals(p)
    }
    fn series(&self) -> Option<&[usize]> {
        Some(&self.lengths)
    }
}

impl<F: Fn(&[f64]) -> Option<Vec<f64>> + Sync> Residuals for F {
    fn residuals(&self, p: &[f64]) -> Option<Vec<f64>> {
        self(p)
    }
}

/// Settings of a fit.
#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// Lower bound of each parameter.
    pub lower: Vec<f64>,
    /// Upper bound of each parameter.
    pub upper: Vec<f64>,
    /// Smallest finite-difference step of each parameter (natural units); the
    /// step is `max(min_step, 1e-4·|p|)`.
    pub min_step: Vec<f64>,
    /// Most residual evaluations per parameter the solver may use (MINPACK
    /// "patience").
    pub patience: usize,
}

impl FitOptions {
    /// Unbounded above, `lower` below, with the given steps.
    pub fn new(lower: Vec<f64>, min_step: Vec<f64>) -> Self {
        let n = lower.len();
        FitOptions {
            lower,
            upper: vec![f64::INFINITY; n],
            min_step,
            patience: 30,
        }
    }
}

/// The outcome of a fit.
#[derive(Clone, Debug, PartialEq)]
pub struct FitResult {
    /// Best parameters.
    pub params: Vec<f64>,
    /// Standard deviation of each parameter that [`FitResult::ci95`]
    /// implies: its half width over `t₀.₉₇₅,ₘ₋ₙ`.
    pub sd: Vec<f64>,
    /// 95 % confidence interval of each parameter: the wider of the
    /// ordinary one ([`FitResult::ci95_ols`]) and, for residuals in series,
    /// the autocorrelation-consistent one ([`hac`]).
    pub ci95: Vec<[f64; 2]>,
    /// The ordinary 95 % interval `p ± t₀.₉₇₅,ₘ₋ₙ s √((JᵀJ)⁺)ᵢᵢ`, which
    /// holds when the residuals are independent noise of one variance: a
    /// statistic of the fit (the diagnosis's "clear of zero" rule), not
    /// what the data say about the parameter when the model is wrong.
    pub ci95_ols: Vec<[f64; 2]>,
    /// The Bartlett window of the autocorrelation-consistent interval
    /// \[samples\]; `None` when only the ordinary one was computed.
    pub hac_window: Option<usize>,
    /// Sum of squared residuals at the solution.
    pub sse: f64,
    /// Number of residuals `m`.
    pub residuals: usize,
    /// Residual evaluations (simulations per run) used.
    pub evaluations: usize,
    /// The solver's verdict.
    pub termination: String,
}

impl FitResult {
    /// Root mean square of the residuals.
    pub fn rms(&self) -> f64 {
        (self.sse / self.residuals.max(1) as f64).sqrt()
    }
}

/// Why a fit failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FitError {
    /// The model could not be evaluated at the starting point.
    #[error("the model cannot be evaluated at the starting point {}", crate::report::text::list(.0))]
    BadStart(Vec<f64>),
    /// The model could not be evaluated at the point the solver ended on.
    #[error("the model cannot be evaluated at the solver's end point {}", crate::report::text::list(.0))]
    BadEnd(Vec<f64>),
    /// More parameters than residuals.
    #[error("{params} parameters but only {residuals} residuals")]
    TooFewResiduals {
        /// Parameters.
        params: usize,
        /// Residuals.
        residuals: usize,
    },
}

/// MINUIT's bound transformations (James, *MINUIT Tutorial*, CERN 2004,
/// §1.3): the solver works on an unbounded `u`, the model sees `p(u)`
/// inside its bounds. (Projecting `p` instead stalls: the LM iterate leaves
/// the box and the projected model stops responding.)
#[derive(Clone, Copy, Debug)]
enum Bound {
    Free,
    Lower(f64),
    Upper(f64),
    Both(f64, f64),
}

impl Bound {
    fn new(lo: f64, hi: f64) -> Self {
        match (lo.is_finite(), hi.is_finite()) {
            (true, true) => Bound::Both(lo, hi),
            (true, false) => Bound::Lower(lo),
            (false, true) => Bound::Upper(hi),
            (false, false) => Bound::Free,
        }
    }
    /// `p(u)`.
    fn p(self, u: f64) -> f64 {
        match self {
            Bound::Free => u,
            Bound::Lower(lo) => lo - 1.0 + (u * u + 1.0).sqrt(),
            Bound::Upper(hi) => hi + 1.0 - (u * u + 1.0).sqrt(),
            Bound::Both(lo, hi) => lo + 0.5 * (hi - lo) * (u.sin() + 1.0),
        }
    }
    /// `dp/du`.
    fn dp(self, u: f64) -> f64 {
        match self {
            Bound::Free => 1.0,
            Bound::Lower(_) => u / (u * u + 1.0).sqrt(),
            Bound::Upper(_) => -u / (u * u + 1.0).sqrt(),
            Bound::Both(lo, hi) => 0.5 * (hi - lo) * u.cos(),
        }
    }
    /// `u(p)` for a `p` inside the bounds (clamped, and nudged off a bound
    /// where `dp/du` would vanish).
    fn u(self, p: f64) -> f64 {
        match self {
            Bound::Free => p,
            Bound::Lower(lo) => {
                let d = (p - lo).max(1e-9) + 1.0;
                (d * d - 1.0).sqrt()
            }
            Bound::Upper(hi) => {
                let d = (hi - p).max(1e-9) + 1.0;
                -(d * d - 1.0).sqrt()
            }
            Bound::Both(lo, hi) => {
                let x = (2.0 * (p - lo) / (hi - lo) - 1.0).clamp(-1.0 + 1e-9, 1.0 - 1e-9);
                x.asin()
            }
        }
    }
}

struct Problem<'a> {
    model: &'a dyn Residuals,
    opts: &'a FitOptions,
    bounds: Vec<Bound>,
    /// The solver's unbounded variables `u`.
    u: DVector<f64>,
    m: usize,
    /// The residuals at `p`, computed once per point.
    cache: Mutex<Option<(Vec<f64>, Vec<f64>)>>,
    evaluations: Mutex<usize>,
    /// Each residual the solver is given at a trial point the model cannot
    /// evaluate \[residual units\]: large enough that the trial's norm is
    /// over ten times the start's, so the solver rejects the step and
    /// shortens it (levenberg-marquardt's trust region), where a `None`
    /// would end the fit on that point.
    penalty: f64,
}

impl Problem<'_> {
    fn clamp(&self, p: &[f64]) -> Vec<f64> {
        p.iter()
            .enumerate()
            .map(|(i, &x)| x.max(self.opts.lower[i]).min(self.opts.upper[i]))
            .collect()
    }

    /// The model's parameters at the solver's variables.
    fn p_of(&self, u: &[f64]) -> Vec<f64> {
        u.iter().zip(&self.bounds).map(|(&u, b)| b.p(u)).collect()
    }

    fn eval(&self, p: &[f64]) -> Option<Vec<f64>> {
        if let Ok(mut e) = self.evaluations.lock() {
            *e += 1;
        }
        let r = self.model.residuals(p)?;
        (r.len() == self.m && r.iter().all(|x| x.is_finite())).then_some(r)
    }

    fn residuals_at(&self, p: &[f64]) -> Option<Vec<f64>> {
        if let Ok(c) = self.cache.lock() {
            if let Some((cp, r)) = c.as_ref() {
                if cp.as_slice() == p {
                    return Some(r.clone());
                }
            }
        }
        let r = self.eval(p)?;
        if let Ok(mut c) = self.cache.lock() {
            *c = Some((p.to_vec(), r.clone()));
        }
        Some(r)
    }

    /// Forward differences, one parallel simulation per column, stepping
    /// inwards at a bound, and backwards where the model cannot be
    /// evaluated a step forwards.
    fn jacobian_at(&self, p: &[f64]) -> Option<DMatrix<f64>> {
        let r0 = self.residuals_at(p)?;
        let n = p.len();
        let cols: Vec<Option<Vec<f64>>> = (0..n)
            .into_par_iter()
            .map(|j| {
                let mut h = self.opts.min_step[j].max(JACOBIAN_REL_STEP * p[j].abs());
                if p[j] + h > self.opts.upper[j] {
                    h = -h;
                }
                let column = |h: f64| {
                    let mut q = p.to_vec();
                    q[j] += h;
                    let r = self.eval(&q)?;
                    Some(
                        r.iter()
                            .zip(&r0)
                            .map(|(a, b)| (a - b) / h)
                            .collect::<Vec<f64>>(),
                    )
                };
                let back_inside = p[j] - h >= self.opts.lower[j] && p[j] - h <= self.opts.upper[j];
                column(h).or_else(|| back_inside.then(|| column(-h)).flatten())
            })
            .collect();
        let mut jac = DMatrix::zeros(self.m, n);
        for (j, c) in cols.into_iter().enumerate() {
            let c = c?;
            for (i, v) in c.into_iter().enumerate() {
                jac[(i, j)] = v;
            }
        }
        Some(jac)
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.u = x.clone();
    }

    fn params(&self) -> DVector<f64> {
        self.u.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let p = self.clamp(&self.p_of(self.u.as_slice()));
        let r = self
            .residuals_at(&p)
            .or_else(|| (self.penalty > 0.0).then(|| vec![self.penalty; self.m]))?;
        Some(DVector::from_vec(r))
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        // Chain rule: ∂r/∂u = ∂r/∂p · diag(dp/du).
        let p = self.clamp(&self.p_of(self.u.as_slice()));
        let mut j = self.jacobian_at(&p)?;
        for (c, (b, &u)) in self.bounds.iter().zip(self.u.iter()).enumerate() {
            let d = b.dp(u);
            for r in 0..j.nrows() {
                j[(r, c)] *= d;
            }
        }
        Some(j)
    }
}

/// Forward-difference step of the Jacobian relative to the parameter
/// (ratio), above the options' `min_step`: about the square root of the
/// simulation's relative tolerance (10⁻⁸), where truncation and the
/// simulation's own error balance.
pub const JACOBIAN_REL_STEP: f64 = 1e-4;

/// Singular values of `JᵀJ` below this fraction of its norm count as zero
/// in the covariance's pseudo-inverse (ratio): about 10⁴ ulps, a parameter
/// the data cannot see.
pub const PINV_REL_TOL: f64 = 1e-12;

/// Levenberg–Marquardt's relative tolerance on the parameters (ratio):
/// finer than any interval the fit reports.
pub const LM_XTOL: f64 = 1e-8;

/// Levenberg–Marquardt's relative tolerance on the sum of squares (ratio).
pub const LM_FTOL: f64 = 1e-10;

/// The standard normal's 0.975 quantile: a two-sided 95 % interval is
/// `± Z_975` standard deviations.
pub const Z_975: f64 = 1.959_963_984_540_054;

/// Student-t 0.975 quantile for `dof` degrees of freedom (Cornish–Fisher
/// expansion; exact to 1e-3 for dof ≥ 3, [`Z_975`] in the limit).
pub fn t975(dof: usize) -> f64 {
    let z = Z_975;
    let v = dof.max(1) as f64;
    let z3 = z * z * z;
    let z5 = z3 * z * z;
    let z7 = z5 * z * z;
    z + (z3 + z) / (4.0 * v)
        + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * v * v)
        + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * v * v * v)
}

/// The intervals of a fit ([`intervals`]).
struct Intervals {
    sd: Vec<f64>,
    ci95: Vec<[f64; 2]>,
    ci95_ols: Vec<[f64; 2]>,
    hac_window: Option<usize>,
}

/// The 95 % intervals of the parameters `p` of a fit with Jacobian `j`
/// (`None`: unknown, infinite intervals) and residuals `r`: the ordinary
/// `cov = s² (JᵀJ)⁺`, `s² = SSE/(m − n)`, interval `p ± t₀.₉₇₅(m − n) · sd`;
/// with `series` (the residuals' contiguous series), the reported interval
/// is the wider of it and `p ± c(b) · sd_HAC` ([`hac::hac`]).
fn intervals(j: Option<DMatrix<f64>>, p: &[f64], r: &[f64], series: Option<&[usize]>) -> Intervals {
    let n = p.len();
    let m = r.len();
    let Some(j) = j else {
        let open: Vec<[f64; 2]> = p
            .iter()
            .map(|_| [f64::NEG_INFINITY, f64::INFINITY])
            .collect();
        return Intervals {
            sd: vec![f64::INFINITY; n],
            ci95: open.clone(),
            ci95_ols: open,
            hac_window: None,
        };
    };
    let jtj = j.transpose() * &j;
    let sse: f64 = r.iter().map(|x| x * x).sum();
    let s2 = sse / (m - n) as f64;
    let t = t975(m - n);
    // Pseudo-inverse: a parameter the data cannot see gets an
    // infinite interval rather than a failure.
    let cov = jtj
        .clone()
        .pseudo_inverse(PINV_REL_TOL * jtj.norm().max(f64::MIN_POSITIVE))
        .unwrap_or_else(|_| DMatrix::from_element(n, n, f64::INFINITY));
    let unseen = |i: usize| jtj[(i, i)] <= 0.0;
    let sd_ols: Vec<f64> = (0..n)
        .map(|i| {
            if unseen(i) {
                f64::INFINITY
            } else {
                (s2 * cov[(i, i)]).max(0.0).sqrt()
            }
        })
        .collect();
    let hac = series.and_then(|lengths| hac::hac(&j, r, &cov, lengths));
    // Half widths: the ordinary one, widened to the HAC one where wider.
    let half: Vec<f64> = (0..n)
        .map(|i| {
            let ols = t * sd_ols[i];
            match &hac {
                Some(h) if !unseen(i) => {
                    let w = h.critical_975() * h.cov[(i, i)].max(0.0).sqrt();
                    if w.is_finite() {
                        ols.max(w)
                    } else {
                        ols
                    }
                }
                _ => ols,
            }
        })
        .collect();
    let band =
        |h: &[f64]| -> Vec<[f64; 2]> { h.iter().zip(p).map(|(h, x)| [x - h, x + h]).collect() };
    let ols_half: Vec<f64> = sd_ols.iter().map(|s| t * s).collect();
    Intervals {
        sd: half.iter().map(|h| h / t).collect(),
        ci95: band(&half),
        ci95_ols: band(&ols_half),
        hac_window: hac.map(|h| h.window),
    }
}

/// Minimises `Σ r(p)²` from `p0` within the bounds of `opts`.
pub fn least_squares(
    model: &dyn Residuals,
    p0: &[f64],
    opts: &FitOptions,
) -> Result<FitResult, FitError> {
    let n = p0.len();
    let bounds: Vec<Bound> = (0..n)
        .map(|i| Bound::new(opts.lower[i], opts.upper[i]))
        .collect();
    let mut problem = Problem {
        model,
        opts,
        bounds: bounds.clone(),
        u: DVector::zeros(n),
        m: 0,
        cache: Mutex::new(None),
        evaluations: Mutex::new(0),
        penalty: 0.0,
    };
    let start = problem.clamp(p0);
    let r0 = model
        .residuals(&start)
        .ok_or_else(|| FitError::BadStart(start.clone()))?;
    problem.m = r0.len();
    let r0_norm = r0.iter().map(|x| x * x).sum::<f64>().sqrt();
    problem.penalty = 20.0 * (r0_norm / (problem.m.max(1) as f64).sqrt() + 1.0);
    if problem.m <= n {
        return Err(FitError::TooFewResiduals {
            params: n,
            residuals: problem.m,
        });
    }
    problem.u = DVector::from_iterator(n, start.iter().zip(&bounds).map(|(&p, b)| b.u(p)));
    let (problem, report) = LevenbergMarquardt::new()
        .with_patience(opts.patience)
        .with_xtol(LM_XTOL)
        .with_ftol(LM_FTOL)
        .minimize(problem);
    let p = problem.clamp(&problem.p_of(problem.u.as_slice()));
    let r = problem
        .residuals_at(&p)
        .ok_or_else(|| FitError::BadEnd(p.clone()))?;
    let sse: f64 = r.iter().map(|x| x * x).sum();
    let m = problem.m;
    let ci = intervals(problem.jacobian_at(&p), &p, &r, model.series());
    let evaluations = problem.evaluations.lock().map(|e| *e).unwrap_or(0) + 1;
    Ok(FitResult {
        params: p,
        sd: ci.sd,
        ci95: ci.ci95,
        ci95_ols: ci.ci95_ols,
        hac_window: ci.hac_window,
        sse,
        residuals: m,
        evaluations,
        termination: termination_words(&report.termination),
    })
}

/// Why the solver stopped, in words (the solver's verdict as printed and
/// stored in the JSON).
pub fn termination_words(t: &levenberg_marquardt::TerminationReason) -> String {
    use levenberg_marquardt::TerminationReason as T;
    match t {
        T::Converged { ftol, xtol } => {
            let mut why = Vec::new();
            if *ftol {
                why.push("the sum of squares stopped decreasing (ftol)");
            }
            if *xtol {
                why.push("the parameters stopped moving (xtol)");
            }
            format!("converged: {}", why.join(" and "))
        }
        T::ResidualsZero => "converged: the residuals are zero".into(),
        T::Orthogonal => "converged: the residuals are orthogonal to the Jacobian (gtol)".into(),
        T::LostPatience => "stopped: the evaluation budget ran out".into(),
        T::NoImprovementPossible(what) => {
            format!("stopped: no improvement possible at machine precision ({what})")
        }
        T::User(what) => format!("stopped: the model could not be evaluated ({what})"),
        T::Numerical(what) => format!("stopped: a number became NaN or infinite ({what})"),
        T::NoParameters => "stopped: no parameter to fit".into(),
        T::NoResiduals => "stopped: no residual".into(),
        T::WrongDimensions(what) => format!("stopped: wrong dimensions ({what})"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_an_exponential_with_honest_intervals() {
        // y = a exp(−b t) + noise (deterministic pseudo-noise, σ ≈ 0.01).
        let t: Vec<f64> = (0..200).map(|i| i as f64 * 0.05).collect();
        let noise: Vec<f64> = (0..200)
            .map(|i| 0.01 * ((i as f64 * 12.9898).sin() * 43758.5453).fract())
            .collect();
        let y: Vec<f64> = t
            .iter()
            .zip(&noise)
            .map(|(t, e)| 2.0 * (-0.7 * t).exp() + e)
            .collect();
        let model = |p: &[f64]| -> Option<Vec<f64>> {
            Some(
                t.iter()
                    .zip(&y)
                    .map(|(t, y)| p[0] * (-p[1] * t).exp() - y)
                    .collect(),
            )
        };
        let fit = least_squares(
            &model,
            &[1.0, 0.1],
            &FitOptions::new(vec![0.0, 0.0], vec![1e-6; 2]),
        )
        .unwrap();
        assert!((fit.params[0] - 2.0).abs() < 0.02, "{:?}", fit);
        assert!((fit.params[1] - 0.7).abs() < 0.01, "{:?}", fit);
        for (i, truth) in [2.0, 0.7].iter().enumerate() {
            let [lo, hi] = fit.ci95[i];
            assert!(lo < *truth && *truth < hi, "{i}: {lo}..{hi}");
            assert!(hi - lo < 0.05);
        }
    }

    #[test]
    fn bounds_hold() {
        let model = |p: &[f64]| -> Option<Vec<f64>> { Some(vec![p[0] + 1.0, 2.0 * (p[0] + 1.0)]) };
        let fit = least_squares(&model, &[0.5], &FitOptions::new(vec![0.0], vec![1e-6])).unwrap();
        assert!(
            fit.params[0] >= 0.0 && fit.params[0] < 1e-6,
            "{:?}",
            fit.params
        );
    }

    #[test]
    fn a_trial_point_the_model_cannot_evaluate_is_a_step_rejected() {
        // r = w (p² − 4), evaluable only below p = 5: the first trial from
        // p = 0.1 is the trust region's 10 (Gauss–Newton would go to 19.9).
        let model = |p: &[f64]| -> Option<Vec<f64>> {
            (p[0] < 5.0).then(|| (1..=5).map(|w| w as f64 * (p[0] * p[0] - 4.0)).collect())
        };
        let opts = FitOptions::new(vec![f64::NEG_INFINITY], vec![1e-9]);
        let fit = least_squares(&model, &[0.1], &opts).unwrap();
        assert!((fit.params[0] - 2.0).abs() < 1e-6, "{fit:?}");
        assert!(fit.termination.starts_with("converged"), "{fit:?}");
    }

    #[test]
    fn residuals_in_series_widen_the_interval_never_narrow_it() {
        // y = 1 + AR(1) noise (ρ = 0.9, uniform innovations from
        // splitmix64) in four series of 2 000: the variance of the mean is
        // about (1 + ρ)/(1 − ρ) = 19 times the white-noise one.
        let (mut x, mut state) = (0.0, 11u64);
        let y: Vec<f64> = (0..8000)
            .map(|_| {
                state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
                let mut z = state;
                z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
                let u = ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                x = 0.9 * x + 0.01 * u;
                1.0 + x
            })
            .collect();
        let model = |p: &[f64]| -> Option<Vec<f64>> { Some(y.iter().map(|y| p[0] - y).collect()) };
        let opts = FitOptions::new(vec![-10.0], vec![1e-6]);
        let plain = least_squares(&model, &[0.0], &opts).unwrap();
        assert_eq!(plain.ci95, plain.ci95_ols);
        assert_eq!(plain.hac_window, None);
        let in_series = InSeries {
            model: &model,
            lengths: vec![2000; 4],
        };
        let fit = least_squares(&in_series, &[0.0], &opts).unwrap();
        let half = |c: [f64; 2]| 0.5 * (c[1] - c[0]);
        let ratio = half(fit.ci95[0]) / half(fit.ci95_ols[0]);
        assert!(ratio > 3.0, "widened only {ratio}x");
        assert_eq!(fit.ci95_ols, plain.ci95_ols);
        assert!(fit.hac_window.is_some_and(|w| w > 1));
    }

    #[test]
    fn t_quantiles() {
        assert!((t975(10) - 2.228).abs() < 2e-3);
        assert!((t975(1000) - 1.962).abs() < 1e-3);
    }
}
