//! Response-surface method (RSM) with central composite designs (CCD), as
//! seed 000 uses it to identify the equivalent friction torques (section 4.3,
//! Eqs. 15–16, Table 9).
//!
//! Three parts:
//!
//! 1. **Designs** ([`Ccd`]): `2^k` factorial runs, `2k` axial runs and `n0`
//!    centre runs of `k` factors, in coded units, mapped to natural units by a
//!    [`Coding`] (`x = centre + half_range · x_coded`). Three kinds:
//!    circumscribed (rotatable, axial distance `α = (2^k)^(1/4)`, 1.682 for
//!    k = 3, the design of seed 000 Table 9), face-centred (`α = 1`) and
//!    inscribed (the circumscribed design shrunk by `1/α` so that the axial
//!    runs lie on the box faces and the factorial runs at `±1/α`).
//! 2. **The full quadratic model** ([`Quadratic`], seed 000 Eq. 15):
//!
//!    ```text
//!    y = β0 + Σ_i βi xi + Σ_{i<j} βij xi xj + Σ_i βii xi²
//!    ```
//!
//!    with `1 + k + k(k−1)/2 + k` coefficients stored in exactly that order
//!    (for k = 3: β0, β1, β2, β3, β12, β13, β23, β11, β22, β33, the order of
//!    seed 000 Eq. 16), fitted by least squares ([`fit_quadratic`], an SVD of
//!    the regression matrix) with R² and adjusted R².
//!    The model is in whatever units its inputs were in; [`Quadratic::to_natural`]
//!    and [`Quadratic::to_coded`] convert exactly between coded and natural
//!    units (the same surface, so R² does not depend on the coding).
//! 3. **The constrained minimum** of a surface, or of a weighted sum of
//!    surfaces ([`Quadratic::weighted_sum`]), inside a box ([`minimize_in_box`](super::rsm_box::minimize_in_box)).
//!    A quadratic's minimum over a box lies in the relative interior of one of
//!    the box's `3^k` faces (vertices, edges, …, the interior), where the
//!    gradient restricted to the face vanishes: a linear system. Solving it on
//!    every face and keeping the lowest feasible point is exact, whether the
//!    surface is convex or not (see [`minimize_in_box`](super::rsm_box::minimize_in_box) for why singular faces
//!    can be skipped). For many factors (k > [`EXACT_MAX_FACTORS`]) a
//!    multi-start projected-gradient method with an active-set polish is used
//!    instead ([`minimize_in_box_projected`](super::rsm_box::minimize_in_box_projected)).

use nalgebra::{DMatrix, DVector};
use std::fmt;

/// Up to this many factors [`minimize_in_box`](super::rsm_box::minimize_in_box) enumerates all `3^k` faces
/// (59 049 for k = 10); above, it uses [`minimize_in_box_projected`](super::rsm_box::minimize_in_box_projected).
pub const EXACT_MAX_FACTORS: usize = 10;

/// Singular values below this fraction of the largest make the regression
/// matrix rank-deficient.
pub const RANK_TOLERANCE: f64 = 1e-10;

/// What went wrong in a design, a fit or a minimisation.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum RsmError {
    /// A design needs at least one factor.
    NoFactors,
    /// A vector has the wrong length.
    DimensionMismatch {
        /// What was being checked.
        what: &'static str,
        /// The length expected.
        expected: usize,
        /// The length found.
        found: usize,
    },
    /// Fewer runs than model terms: the coefficients are not determined.
    TooFewRuns {
        /// Runs given.
        runs: usize,
        /// Terms of the model.
        terms: usize,
    },
    /// The runs do not determine every coefficient (e.g. a factor that never varies).
    RankDeficient,
    /// A half-range is not positive, or a box bound is not below its upper bound.
    BadBox,
    /// An input is NaN or infinite.
    NotFinite,
}

impl fmt::Display for RsmError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RsmError::NoFactors => f.write_str("a design needs at least one factor"),
            RsmError::DimensionMismatch {
                what,
                expected,
                found,
            } => write!(f, "{what}: length {found}, expected {expected}"),
            RsmError::TooFewRuns { runs, terms } => {
                write!(f, "{runs} runs cannot determine a model of {terms} terms")
            }
            RsmError::RankDeficient => {
                f.write_str("the runs do not determine every coefficient of the model")
            }
            RsmError::BadBox => f.write_str(
                "every half-range must be positive and every lower bound below its upper bound",
            ),
            RsmError::NotFinite => f.write_str("inputs must be finite numbers"),
        }
    }
}

impl std::error::Error for RsmError {}

pub(crate) fn check_dim(what: &'static str, expected: usize, found: usize) -> Result<(), RsmError> {
    if expected == found {
        Ok(())
    } else {
        Err(RsmError::DimensionMismatch {
            what,
            expected,
            found,
        })
    }
}

// ---------------------------------------------------------------- designs

/// The kind of central composite design.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CcdKind {
    /// Circumscribed (CCC), rotatable: factorial runs at ±1, axial runs at
    /// ±α with `α = (2^k)^(1/4)`, outside the factorial box.
    Circumscribed,
    /// Face-centred (CCF): axial runs on the faces, `α = 1`.
    FaceCentred,
    /// Inscribed (CCI): the rotatable design scaled by `1/α`, so that every
    /// run lies in the box `[−1, 1]^k` (axial at ±1, factorial at ±1/α).
    Inscribed,
}

impl std::fmt::Display for CcdKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            CcdKind::Circumscribed => "circumscribed",
            CcdKind::FaceCentred => "face-centred",
            CcdKind::Inscribed => "inscribed",
        })
    }
}

/// A central composite design of `k` factors with `n0` centre runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ccd {
    factors: usize,
    kind: CcdKind,
    centre_runs: usize,
}

/// The rotatable axial distance `α = (2^k)^(1/4)` of a full `2^k` factorial
/// core (1.6818 for k = 3).
pub fn rotatable_alpha(factors: usize) -> f64 {
    2f64.powf(factors as f64 / 4.0)
}

impl Ccd {
    /// A design of `factors ≥ 1` factors with `centre_runs` centre runs.
    pub fn new(factors: usize, kind: CcdKind, centre_runs: usize) -> Result<Self, RsmError> {
        if factors == 0 {
            return Err(RsmError::NoFactors);
        }
        Ok(Ccd {
            factors,
            kind,
            centre_runs,
        })
    }

    /// Number of factors `k`.
    pub fn factors(&self) -> usize {
        self.factors
    }

    /// The kind of design.
    pub fn kind(&self) -> CcdKind {
        self.kind
    }

    /// Number of runs `2^k + 2k + n0`.
    pub fn runs(&self) -> usize {
        (1usize << self.factors) + 2 * self.factors + self.centre_runs
    }

    /// The axial distance in coded units: `(2^k)^(1/4)` (circumscribed),
    /// 1 (face-centred, inscribed).
    pub fn alpha(&self) -> f64 {
        match self.kind {
            CcdKind::Circumscribed => rotatable_alpha(self.factors),
            CcdKind::FaceCentred | CcdKind::Inscribed => 1.0,
        }
    }

    /// The level of the factorial runs in coded units: 1, or `1/α` inscribed.
    pub fn factorial_level(&self) -> f64 {
        match self.kind {
            CcdKind::Inscribed => 1.0 / rotatable_alpha(self.factors),
            CcdKind::Circumscribed | CcdKind::FaceCentred => 1.0,
        }
    }

    /// The runs in coded units, in this order: the `2^k` factorial runs in
    /// standard (Yates) order (factor 1 alternating fastest, `−` first), then
    /// the axial runs `−α e_1, +α e_1, −α e_2, …`, then the centre runs.
    pub fn coded_points(&self) -> Vec<Vec<f64>> {
        let k = self.factors;
        let f = self.factorial_level();
        let a = self.alpha();
        let mut pts = Vec::with_capacity(self.runs());
        for r in 0..(1usize << k) {
            pts.push(
                (0..k)
                    .map(|i| if (r >> i) & 1 == 1 { f } else { -f })
                    .collect(),
            );
        }
        for i in 0..k {
            for s in [-a, a] {
                let mut p = vec![0.0; k];
                p[i] = s;
                pts.push(p);
            }
        }
        for _ in 0..self.centre_runs {
            pts.push(vec![0.0; k]);
        }
        pts
    }

    /// The runs in natural units, `centre + half_range · coded`.
    pub fn natural_points(&self, coding: &Coding) -> Result<Vec<Vec<f64>>, RsmError> {
        check_dim("coding", self.factors, coding.factors())?;
        Ok(self
            .coded_points()
            .iter()
            .map(|p| coding.to_natural(p))
            .collect())
    }
}

/// Coded ↔ natural units: `x = centre + half_range · x_coded`, so that the
/// coded box `[−1, 1]^k` is `[centre − half_range, centre + half_range]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Coding {
    centre: Vec<f64>,
    half_range: Vec<f64>,
}

impl Coding {
    /// A coding from the centre and the (positive) half-ranges, natural units.
    pub fn new(centre: Vec<f64>, half_range: Vec<f64>) -> Result<Self, RsmError> {
        check_dim("half_range", centre.len(), half_range.len())?;
        if centre.is_empty() {
            return Err(RsmError::NoFactors);
        }
        if centre.iter().chain(&half_range).any(|v| !v.is_finite()) {
            return Err(RsmError::NotFinite);
        }
        if half_range.iter().any(|&h| h <= 0.0) {
            return Err(RsmError::BadBox);
        }
        Ok(Coding { centre, half_range })
    }

    /// Number of factors.
    pub fn factors(&self) -> usize {
        self.centre.len()
    }

    /// The centre (natural units).
    pub fn centre(&self) -> &[f64] {
        &self.centre
    }

    /// The half-ranges (natural units).
    pub fn half_range(&self) -> &[f64] {
        &self.half_range
    }

    /// `(x − centre) / half_range`.
    pub fn to_coded(&self, natural: &[f64]) -> Vec<f64> {
        natural
            .iter()
            .zip(self.centre.iter().zip(&self.half_range))
            .map(|(x, (c, h))| (x - c) / h)
            .collect()
    }

    /// `centre + half_range · coded`.
    pub fn to_natural(&self, coded: &[f64]) -> Vec<f64> {
        coded
            .iter()
            .zip(self.centre.iter().zip(&self.half_range))
            .map(|(u, (c, h))| c + h * u)
            .collect()
    }

    /// The natural-unit box of the coded box `[−s, s]^k`: `(lower, upper)`.
    /// `s = 1` is the factorial box; `s = α` reaches the axial runs.
    pub fn natural_box(&self, s: f64) -> (Vec<f64>, Vec<f64>) {
        let lo = self.to_natural(&vec![-s; self.factors()]);
        let hi = self.to_natural(&vec![s; self.factors()]);
        (lo, hi)
    }
}

// ---------------------------------------------------------------- the model

/// A full quadratic in `k` variables (seed 000 Eq. 15), coefficients in the
/// order `β0; β1..βk; β12, β13, .., β1k, β23, .., β(k−1)k; β11..βkk`.
#[derive(Clone, Debug, PartialEq)]
pub struct Quadratic {
    factors: usize,
    coefficients: Vec<f64>,
}

/// Index of `βij` (i < j, 0-based) among the interaction terms.
fn pair_index(k: usize, i: usize, j: usize) -> usize {
    // Pairs (0,1), (0,2), .., (0,k−1), (1,2), ..: rows before i hold
    // Σ_{r<i} (k−1−r) pairs.
    i * (2 * k - i - 1) / 2 + (j - i - 1)
}

impl Quadratic {
    /// Number of terms `1 + k + k(k−1)/2 + k` of a full quadratic in `k` variables.
    pub fn term_count(factors: usize) -> usize {
        1 + 2 * factors + factors * factors.saturating_sub(1) / 2
    }

    /// A model from its coefficients in the documented order.
    pub fn new(factors: usize, coefficients: Vec<f64>) -> Result<Self, RsmError> {
        if factors == 0 {
            return Err(RsmError::NoFactors);
        }
        check_dim(
            "coefficients",
            Self::term_count(factors),
            coefficients.len(),
        )?;
        Ok(Quadratic {
            factors,
            coefficients,
        })
    }

    /// Number of variables `k`.
    pub fn factors(&self) -> usize {
        self.factors
    }

    /// The coefficients in the documented order.
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// Names of the terms for `k` variables, `x1..xk` (1-based): `"1"`, `"x1"`,
    /// …, `"x1*x2"`, …, `"x1^2"`, … (the coefficient names `β0, β1, .., β12,
    /// .., β11, ..` follow the same order).
    pub fn term_names(factors: usize) -> Vec<String> {
        let mut v = vec!["1".to_string()];
        v.extend((1..=factors).map(|i| format!("x{i}")));
        for i in 1..=factors {
            for j in i + 1..=factors {
                v.push(format!("x{i}*x{j}"));
            }
        }
        v.extend((1..=factors).map(|i| format!("x{i}^2")));
        v
    }

    /// Names of the coefficients: `"b0"`, `"b1"`, …, `"b12"`, …, `"b11"`, …
    /// (indices separated by `_` when k ≥ 10, e.g. `"b3_12"`).
    pub fn coefficient_names(factors: usize) -> Vec<String> {
        let sep = if factors >= 10 { "_" } else { "" };
        let mut v = vec!["b0".to_string()];
        v.extend((1..=factors).map(|i| format!("b{i}")));
        for i in 1..=factors {
            for j in i + 1..=factors {
                v.push(format!("b{i}{sep}{j}"));
            }
        }
        v.extend((1..=factors).map(|i| format!("b{i}{sep}{i}")));
        v
    }

    /// The regressors `[1, x1, .., xk, x1x2, .., x1², ..]` of a point.
    pub fn terms(x: &[f64]) -> Vec<f64> {
        let k = x.len();
        let mut t = Vec::with_capacity(Self::term_count(k));
        t.push(1.0);
        t.extend_from_slice(x);
        for i in 0..k {
            for j in i + 1..k {
                t.push(x[i] * x[j]);
            }
        }
        t.extend(x.iter().map(|v| v * v));
        t
    }

    /// `β0`.
    pub fn intercept(&self) -> f64 {
        self.coefficients[0]
    }

    /// `βi` of variable `i` (0-based).
    pub fn linear(&self, i: usize) -> f64 {
        self.coefficients[1 + i]
    }

    /// `βij` (0-based, order irrelevant; `i == j` gives `βii`).
    pub fn interaction(&self, i: usize, j: usize) -> f64 {
        let k = self.factors;
        if i == j {
            return self.pure(i);
        }
        let (a, b) = if i < j { (i, j) } else { (j, i) };
        self.coefficients[1 + k + pair_index(k, a, b)]
    }

    /// `βii` of variable `i` (0-based).
    pub fn pure(&self, i: usize) -> f64 {
        let k = self.factors;
        self.coefficients[1 + k + k * (k - 1) / 2 + i]
    }

    /// The value at `x` (length `k`, the model's units).
    pub fn eval(&self, x: &[f64]) -> f64 {
        Self::terms(x)
            .iter()
            .zip(&self.coefficients)
            .map(|(t, b)| t * b)
            .sum()
    }

    /// The gradient `b + H x` at `x`.
    pub fn gradient(&self, x: &[f64]) -> Vec<f64> {
        let (_, b, h) = self.parts();
        let g = b + &h * DVector::from_column_slice(x);
        g.iter().copied().collect()
    }

    /// The model as `c + bᵀx + ½ xᵀ H x`: `(c, b, H)`, with `H` symmetric,
    /// `H_ii = 2 βii`, `H_ij = βij`.
    pub fn parts(&self) -> (f64, DVector<f64>, DMatrix<f64>) {
        let k = self.factors;
        let b = DVector::from_fn(k, |i, _| self.linear(i));
        let h = DMatrix::from_fn(k, k, |i, j| {
            if i == j {
                2.0 * self.pure(i)
            } else {
                self.interaction(i, j)
            }
        });
        (self.intercept(), b, h)
    }

    /// The model `c + bᵀx + ½ xᵀ H x` (`H` symmetrised).
    pub fn from_parts(c: f64, b: &DVector<f64>, h: &DMatrix<f64>) -> Result<Self, RsmError> {
        let k = b.len();
        if k == 0 {
            return Err(RsmError::NoFactors);
        }
        check_dim("Hessian rows", k, h.nrows())?;
        check_dim("Hessian columns", k, h.ncols())?;
        let mut coef = Vec::with_capacity(Self::term_count(k));
        coef.push(c);
        coef.extend(b.iter());
        for i in 0..k {
            for j in i + 1..k {
                coef.push(0.5 * (h[(i, j)] + h[(j, i)]));
            }
        }
        coef.extend((0..k).map(|i| 0.5 * h[(i, i)]));
        Self::new(k, coef)
    }

    /// This model, fitted in coded units, expressed in natural units: the same
    /// surface, `f_nat(x) = f_coded(coding.to_coded(x))`.
    pub fn to_natural(&self, coding: &Coding) -> Result<Self, RsmError> {
        check_dim("coding", self.factors, coding.factors())?;
        // x_c = D (x − m), D = diag(1/h): H' = D H D, b' = D b − H' m,
        // c' = c − bᵀ D m + ½ mᵀ H' m.
        let (c, b, h) = self.parts();
        let d = DVector::from_iterator(self.factors, coding.half_range.iter().map(|h| 1.0 / h));
        let m = DVector::from_column_slice(&coding.centre);
        let hn = DMatrix::from_fn(self.factors, self.factors, |i, j| d[i] * h[(i, j)] * d[j]);
        let db = b.component_mul(&d);
        let bn = &db - &hn * &m;
        let cn = c - db.dot(&m) + 0.5 * m.dot(&(&hn * &m));
        Self::from_parts(cn, &bn, &hn)
    }

    /// This model, in natural units, expressed in coded units:
    /// `f_coded(u) = f_nat(coding.to_natural(u))`.
    pub fn to_coded(&self, coding: &Coding) -> Result<Self, RsmError> {
        check_dim("coding", self.factors, coding.factors())?;
        // x = m + S u, S = diag(h): H' = S H S, b' = S (b + H m), c' = f(m).
        let (_, b, h) = self.parts();
        let s = DVector::from_column_slice(&coding.half_range);
        let m = DVector::from_column_slice(&coding.centre);
        let hc = DMatrix::from_fn(self.factors, self.factors, |i, j| s[i] * h[(i, j)] * s[j]);
        let bc = (b + &h * &m).component_mul(&s);
        let cc = self.eval(&coding.centre);
        Self::from_parts(cc, &bc, &hc)
    }

    /// `Σ w_i · f_i`: the combined objective of several responses fitted in the
    /// same units (e.g. TE1 + TE2 of seed 000 with weights 1, 1).
    pub fn weighted_sum(parts: &[(f64, &Quadratic)]) -> Result<Self, RsmError> {
        let first = parts.first().ok_or(RsmError::NoFactors)?;
        let k = first.1.factors;
        let mut coef = vec![0.0; Self::term_count(k)];
        for (w, q) in parts {
            check_dim("surfaces of a weighted sum", k, q.factors)?;
            if !w.is_finite() {
                return Err(RsmError::NotFinite);
            }
            for (c, b) in coef.iter_mut().zip(&q.coefficients) {
                *c += w * b;
            }
        }
        Self::new(k, coef)
    }
}

/// A least-squares fit of a full quadratic.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    /// The fitted model (in the units of the points given).
    pub model: Quadratic,
    /// Coefficient of determination `1 − SSE/SST` (NaN if the responses are all equal).
    pub r2: f64,
    /// Adjusted `R² = 1 − (1 − R²)(n − 1)/(n − p)` (NaN if `n = p`).
    pub adj_r2: f64,
    /// Residuals `y_i − f(x_i)`, in the order of the runs.
    pub residuals: Vec<f64>,
    /// Residual sum of squares `SSE = Σ r_i²`.
    pub sse: f64,
    /// Total sum of squares `SST = Σ (y_i − ȳ)²`.
    pub sst: f64,
    /// Number of runs `n`.
    pub runs: usize,
}

impl Fit {
    /// Root-mean-square residual `sqrt(SSE / n)`, in the response's unit.
    pub fn rms_residual(&self) -> f64 {
        (self.sse / self.runs as f64).sqrt()
    }
}

/// Fits the full quadratic of seed 000 Eq. 15 to the runs `points` (each of
/// length `k`) and responses `y` by least squares (an SVD of the `n × p`
/// regression matrix).
///
/// Errors: fewer runs than terms, a rank-deficient design (singular values
/// below [`RANK_TOLERANCE`] of the largest), mismatched lengths, NaN inputs.
pub fn fit_quadratic(points: &[Vec<f64>], y: &[f64]) -> Result<Fit, RsmError> {
    let n = points.len();
    check_dim("responses", n, y.len())?;
    let k = points
        .first()
        .map(|p| p.len())
        .ok_or(RsmError::TooFewRuns { runs: 0, terms: 1 })?;
    if k == 0 {
        return Err(RsmError::NoFactors);
    }
    let p = Quadratic::term_count(k);
    if n < p {
        return Err(RsmError::TooFewRuns { runs: n, terms: p });
    }
    let mut x = DMatrix::zeros(n, p);
    for (r, pt) in points.iter().enumerate() {
        check_dim("a run", k, pt.len())?;
        if pt.iter().any(|v| !v.is_finite()) || !y[r].is_finite() {
            return Err(RsmError::NotFinite);
        }
        for (c, t) in Quadratic::terms(pt).into_iter().enumerate() {
            x[(r, c)] = t;
        }
    }
    let yv = DVector::from_column_slice(y);
    let svd = x.clone().svd(true, true);
    let smax = svd.singular_values.max();
    if smax.is_nan() || smax <= 0.0 || svd.singular_values.min() <= RANK_TOLERANCE * smax {
        return Err(RsmError::RankDeficient);
    }
    let beta = svd
        .solve(&yv, RANK_TOLERANCE * smax)
        .map_err(|_| RsmError::RankDeficient)?;
    let fitted = &x * &beta;
    let residuals: Vec<f64> = (0..n).map(|i| y[i] - fitted[i]).collect();
    let sse: f64 = residuals.iter().map(|r| r * r).sum();
    let mean = y.iter().sum::<f64>() / n as f64;
    let sst: f64 = y.iter().map(|v| (v - mean) * (v - mean)).sum();
    let r2 = if sst > 0.0 { 1.0 - sse / sst } else { f64::NAN };
    let adj_r2 = if n > p {
        1.0 - (1.0 - r2) * (n as f64 - 1.0) / (n - p) as f64
    } else {
        f64::NAN
    };
    Ok(Fit {
        model: Quadratic::new(k, beta.iter().copied().collect())?,
        r2,
        adj_r2,
        residuals,
        sse,
        sst,
        runs: n,
    })
}

#[cfg(test)]
mod tests;
