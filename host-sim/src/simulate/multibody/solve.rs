//! The constrained solves, all in the mass-matrix metric and all
//! rank-revealing (SVD), so that redundant constraints (a node joining four
//! links, the hinge latches over a truss already locked) never make them
//! singular.
//!
//! With `M = L Lᵀ` (Cholesky) and `W = C L⁻ᵀ`:
//! - acceleration: `q̈ = L⁻ᵀ (z + W⁺ (γ − W z))`, `z = L⁻¹ Q` — the
//!   minimum of `½ (q̈ − M⁻¹Q)ᵀ M (q̈ − M⁻¹Q)` subject to `C q̈ = γ`
//!   (Gauss's principle of least constraint; Udwadia & Kalaba 1992);
//! - velocity projection and plastic impact: `q̇⁺ = L⁻ᵀ (I − W⁺W) Lᵀ q̇⁻`,
//!   the `M`-orthogonal projection onto `C q̇ = 0` (`physics.md` 5 with the
//!   loop rows added);
//! - position projection: Gauss–Newton `Δq = −L⁻ᵀ W⁺ g(q)` until `g` stops
//!   decreasing (Hairer & Wanner II §VII.2, projection methods).

use nalgebra::{DMatrix, DVector};

use super::kin::{Kin, Model, RowsOut};

/// Singular values below this fraction of the largest count as zero in the
/// solves: rows that are exactly dependent (round-off).
pub const RANK_TOL: f64 = 1e-10;

/// A new lock whose row has a singular value below this fraction (in the
/// `M` metric) is implied by the rows already active: the seed 000 truss
/// closes only to 0.01 mm (`truss-link.md`), so the hinge latch over a
/// locked truss is dependent to about 1e-5, not to round-off.
pub const IMPLIED_TOL: f64 = 1e-3;

/// `W⁺ r`: by Cholesky of `W Wᵀ` (`W⁺ = Wᵀ (W Wᵀ)⁻¹`) when the rows are
/// clearly independent (every pivot above `RANK_TOL²` of the largest), else
/// by SVD with the relative threshold [`RANK_TOL`].
fn pinv_solve(w: &DMatrix<f64>, r: &DVector<f64>) -> Option<DVector<f64>> {
    if w.nrows() == 0 {
        return Some(DVector::zeros(w.ncols()));
    }
    let g = w * w.transpose();
    if let Some(ch) = g.clone().cholesky() {
        let d = ch.l_dirty().diagonal();
        let (lo, hi) = (d.min(), d.max());
        if lo * lo > hi * hi * RANK_TOL * RANK_TOL {
            return Some(w.transpose() * ch.solve(r));
        }
    }
    let svd = w.clone().svd(true, true);
    let smax = svd.singular_values.max();
    svd.solve(r, smax * RANK_TOL).ok()
}

/// Numerical rank of a matrix (singular values above `tol` times the largest).
pub fn rank(a: &DMatrix<f64>, tol: f64) -> usize {
    if a.nrows() == 0 || a.ncols() == 0 {
        return 0;
    }
    let s = a.clone().svd(false, false).singular_values;
    let smax = s.max();
    s.iter().filter(|&&x| x > smax * tol).count()
}

/// Cholesky factor and `W = C L⁻ᵀ`.
fn factor(m: DMatrix<f64>, c: &DMatrix<f64>) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    let l = m.cholesky()?.l();
    let wt = l.solve_lower_triangular(&c.transpose())?;
    Some((l, wt.transpose()))
}

/// In-place Cholesky `A = L Lᵀ` of a symmetric `n × n` row-major matrix
/// (lower triangle read and overwritten by `L`); `false` when not positive
/// definite.
fn cholesky_in_place(a: &mut [f64], n: usize) -> bool {
    // Row by row (Cholesky–Banachiewicz) on contiguous slices.
    for i in 0..n {
        let (done, rest) = a.split_at_mut(i * n);
        let row_i = &mut rest[..n];
        for j in 0..i {
            let row_j = &done[j * n..j * n + j + 1];
            let s = row_i[j] - dot_n(&row_i[..j], &row_j[..j]);
            row_i[j] = s / row_j[j];
        }
        let d = row_i[i] - dot_n(&row_i[..i], &row_i[..i]);
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        row_i[i] = d.sqrt();
    }
    true
}

/// `Σ aᵢ bᵢ` over the shorter of the two.
#[inline]
fn dot_n(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `x ← L⁻¹ x` (`L` lower, row-major `n × n`).
#[inline]
fn solve_l(l: &[f64], n: usize, x: &mut [f64]) {
    for i in 0..n {
        let row = &l[i * n..i * n + i];
        let mut s = x[i];
        for (lik, xk) in row.iter().zip(&x[..i]) {
            s -= lik * xk;
        }
        x[i] = s / l[i * n + i];
    }
}

/// `x ← L⁻ᵀ x` (`L` lower, row-major `n × n`).
#[inline]
fn solve_lt(l: &[f64], n: usize, x: &mut [f64]) {
    for i in (0..n).rev() {
        let mut s = x[i];
        for k in i + 1..n {
            s -= l[k * n + i] * x[k];
        }
        x[i] = s / l[i * n + i];
    }
}

/// Work space of the constrained solves for one model, allocated once: the
/// integrator evaluates and projects without touching the heap. It keeps the
/// last factorisation (`M = L Lᵀ`, `W = C L⁻ᵀ`, `W Wᵀ`), so that the
/// projections after a step reuse the one its last stage computed
/// (simplified Gauss–Newton: the metric and Jacobian frozen over the step,
/// Hairer & Wanner II §VII.2).
#[derive(Clone, Debug)]
pub(crate) struct Work {
    n: usize,
    /// Rows of the current factorisation.
    rows: usize,
    /// Kinematics scratch.
    pub kin: Kin,
    /// Cholesky factor `L` of `M`, row-major `n × n`.
    l: Vec<f64>,
    /// Right-hand side `Q`.
    f: Vec<f64>,
    /// `C`, row-major `rows × n`.
    c: Vec<f64>,
    gamma: Vec<f64>,
    /// `g(q)` at the factorisation.
    g: Vec<f64>,
    /// `W = C L⁻ᵀ`, row-major `rows × n` (row `i` is `L⁻¹ cᵢ`).
    w: Vec<f64>,
    /// Cholesky factor of `W Wᵀ`, row-major `rows × rows`, valid when `fast`.
    gl: Vec<f64>,
    /// `W Wᵀ` factored with every pivot above [`RANK_TOL`] of the largest;
    /// otherwise the pseudo-inverse goes through the SVD.
    fast: bool,
    /// Scratch: `n`, `n`, `rows`, `rows`, `n × n`.
    a: Vec<f64>,
    b: Vec<f64>,
    mu: Vec<f64>,
    res: Vec<f64>,
    mass: Vec<f64>,
    /// Pseudo-inverse solves that needed the SVD.
    pub svd_solves: usize,
}

impl Work {
    /// Work space for `model` with up to all its pins locked.
    pub fn new(model: &Model) -> Work {
        let n = model.n();
        let rmax = 2 * model.cut_pins().count() + model.sys.pins.len();
        Work {
            n,
            rows: 0,
            kin: Kin::default(),
            l: vec![0.0; n * n],
            f: vec![0.0; n],
            c: vec![0.0; rmax * n],
            gamma: vec![0.0; rmax],
            g: vec![0.0; rmax],
            w: vec![0.0; rmax * n],
            gl: vec![0.0; rmax * rmax],
            fast: false,
            a: vec![0.0; n],
            b: vec![0.0; n],
            mu: vec![0.0; rmax],
            res: vec![0.0; rmax],
            mass: vec![0.0; n * n],
            svd_solves: 0,
        }
    }

    /// Kinematics at `(q, q̇)` into [`Work::kin`].
    pub fn set_kin(&mut self, model: &Model, q: &[f64], v: &[f64]) {
        model.kin_into(q, v, &mut self.kin);
    }

    /// Factors at the current kinematics: `M = L Lᵀ` (and `Q` with
    /// `forces`), the rows `C`, `g` (and `γ`), `W = C L⁻ᵀ` and `W Wᵀ`.
    fn factor(&mut self, model: &Model, locked: &[bool], forces: bool) -> Option<()> {
        let n = self.n;
        model.mass_into(&self.kin, &mut self.l, forces.then_some(&mut self.f[..]));
        if !cholesky_in_place(&mut self.l, n) {
            return None;
        }
        let m = model.row_count(locked);
        let gamma: &mut [f64] = if forces {
            &mut self.gamma[..m]
        } else {
            &mut []
        };
        self.rows = model.rows_into(
            &self.kin,
            locked,
            RowsOut {
                c: &mut self.c[..m * n],
                gamma,
                g: &mut self.g[..m],
            },
        );
        self.factor_rows();
        Some(())
    }

    /// `W = C L⁻ᵀ` and the Cholesky of `W Wᵀ` from the rows in `self.c`
    /// and the factor in `self.l`.
    fn factor_rows(&mut self) {
        let (n, m) = (self.n, self.rows);
        if m == 0 {
            self.fast = true;
            return;
        }
        self.w[..m * n].copy_from_slice(&self.c[..m * n]);
        for wi in self.w[..m * n].chunks_exact_mut(n) {
            solve_l(&self.l, n, wi);
        }
        let w = &self.w[..m * n];
        for (i, (wi, gi)) in w
            .chunks_exact(n)
            .zip(self.gl.chunks_exact_mut(m))
            .enumerate()
        {
            for (wj, gij) in w.chunks_exact(n).zip(gi.iter_mut()).take(i + 1) {
                *gij = dot_n(wi, wj);
            }
        }
        self.fast = cholesky_in_place(&mut self.gl[..m * m], m) && {
            let d = (0..m).map(|i| self.gl[i * m + i]);
            let (lo, hi) = d.fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            });
            lo * lo > hi * hi * RANK_TOL * RANK_TOL
        };
    }

    /// Rebuilds `C` (and `W`, `W Wᵀ`) at `q` keeping the metric `L` of the
    /// last factorisation: the rows of a velocity projection at a state
    /// near the one `M` was factored at (any fixed positive-definite metric
    /// projects onto `C q̇ = 0`; a nearby `M` keeps it `M`-orthogonal to
    /// first order in the move).
    pub fn refresh_rows(&mut self, model: &Model, q: &[f64], locked: &[bool]) {
        let n = self.n;
        model.kin_positions_into(q, &mut self.kin);
        let m = model.row_count(locked);
        self.rows = model.rows_into(
            &self.kin,
            locked,
            RowsOut {
                c: &mut self.c[..m * n],
                gamma: &mut [],
                g: &mut self.g[..m],
            },
        );
        self.factor_rows();
    }

    /// `a ← W⁺ μ` with `μ` in `self.mu[..rows]` (the Cholesky of `W Wᵀ`,
    /// or the SVD when the rows are dependent).
    fn pinv(&mut self) -> Option<()> {
        let (n, m) = (self.n, self.rows);
        if self.fast {
            let mu = &mut self.mu[..m];
            solve_l(&self.gl, m, mu);
            solve_lt(&self.gl, m, mu);
            self.a.iter_mut().for_each(|x| *x = 0.0);
            for (i, &mi) in mu.iter().enumerate() {
                for (aj, wij) in self.a.iter_mut().zip(&self.w[i * n..(i + 1) * n]) {
                    *aj += wij * mi;
                }
            }
            return Some(());
        }
        self.svd_solves += 1;
        let w = DMatrix::from_row_slice(m, n, &self.w[..m * n]);
        let r = DVector::from_column_slice(&self.mu[..m]);
        let out = pinv_solve(&w, &r)?;
        self.a.copy_from_slice(out.as_slice());
        Some(())
    }

    /// Constrained acceleration `q̈` at `(q, q̇)` with the pins `locked`
    /// into `out`; leaves the factorisation at `q` for the projections.
    pub fn acceleration(
        &mut self,
        model: &Model,
        q: &[f64],
        v: &[f64],
        locked: &[bool],
        out: &mut [f64],
    ) -> Option<()> {
        let n = self.n;
        model.kin_into(q, v, &mut self.kin);
        self.factor(model, locked, true)?;
        // z = L⁻¹ Q; y = z + W⁺ (γ − W z); q̈ = L⁻ᵀ y.
        self.b.copy_from_slice(&self.f);
        solve_l(&self.l, n, &mut self.b);
        for i in 0..self.rows {
            let wi = &self.w[i * n..(i + 1) * n];
            self.mu[i] = self.gamma[i] - wi.iter().zip(&self.b).map(|(x, y)| x * y).sum::<f64>();
        }
        self.pinv()?;
        for (o, (z, a)) in out.iter_mut().zip(self.b.iter().zip(&self.a)) {
            *o = z + a;
        }
        solve_lt(&self.l, n, out);
        out.iter().all(|x| x.is_finite()).then_some(())
    }

    /// `M`-orthogonal projection of `q̇` onto `C q̇ = 0` with the current
    /// factorisation: `q̇ ← L⁻ᵀ (I − W⁺W) Lᵀ q̇`.
    pub fn project_velocity_factored(&mut self, v: &mut [f64]) -> Option<()> {
        let n = self.n;
        // p = Lᵀ v.
        for i in 0..n {
            let mut s = 0.0;
            for k in i..n {
                s += self.l[k * n + i] * v[k];
            }
            self.b[i] = s;
        }
        for i in 0..self.rows {
            let wi = &self.w[i * n..(i + 1) * n];
            self.mu[i] = wi.iter().zip(&self.b).map(|(x, y)| x * y).sum();
        }
        self.pinv()?;
        for (vi, (p, a)) in v.iter_mut().zip(self.b.iter().zip(&self.a)) {
            *vi = p - a;
        }
        solve_lt(&self.l, n, v);
        v.iter().all(|x| x.is_finite()).then_some(())
    }

    /// `max |g|` at `q` with the pins `locked` (positions left in
    /// [`Work::kin`]).
    pub fn residual(&mut self, model: &Model, q: &[f64], locked: &[bool]) -> f64 {
        model.kin_positions_into(q, &mut self.kin);
        self.residual_at_kin(model, locked)
    }

    /// `max |g|` at the current kinematics, into `self.res`.
    pub fn residual_at_kin(&mut self, model: &Model, locked: &[bool]) -> f64 {
        let m = model.rows_into(
            &self.kin,
            locked,
            RowsOut {
                c: &mut [],
                gamma: &mut [],
                g: &mut self.res,
            },
        );
        self.res[..m].iter().fold(0.0, |e, x| e.max(x.abs()))
    }

    /// Gauss–Newton `Δq = −L⁻ᵀ W⁺ g(q)` until `g` stops decreasing, with
    /// the factorisation refreshed at every iterate (`refactor`) or frozen
    /// (the simplified method after a step). Returns `max |g|`.
    fn gauss_newton(
        &mut self,
        model: &Model,
        q: &mut [f64],
        locked: &[bool],
        refactor: bool,
    ) -> Option<f64> {
        let n = self.n;
        let mut last = f64::INFINITY;
        for _ in 0..20 {
            let err = self.residual(model, q, locked);
            if err <= 1e-15 || err >= 0.5 * last {
                return Some(err.min(last));
            }
            last = err;
            if refactor {
                self.factor(model, locked, false)?;
            }
            let m = self.rows;
            self.mu[..m].copy_from_slice(&self.res[..m]);
            self.pinv()?;
            solve_lt(&self.l, n, &mut self.a);
            for (qi, d) in q.iter_mut().zip(&self.a) {
                *qi -= d;
            }
        }
        Some(last)
    }

    /// Projects `q` onto `g(q) = 0` with the current factorisation (frozen
    /// metric and Jacobian) and returns `max |g|`.
    pub fn project_position_factored(
        &mut self,
        model: &Model,
        q: &mut [f64],
        locked: &[bool],
    ) -> Option<f64> {
        self.gauss_newton(model, q, locked, false)
    }

    /// Projects `q` onto `g(q) = 0`, refactoring at every iterate; leaves
    /// the factorisation at the result for [`Work::project_velocity_factored`].
    pub fn project_position(
        &mut self,
        model: &Model,
        q: &mut [f64],
        locked: &[bool],
    ) -> Option<f64> {
        let err = self.gauss_newton(model, q, locked, true)?;
        self.factor(model, locked, false)?;
        Some(err)
    }

    /// Mechanical energy at `(q, q̇)` ([`Model::energy`]).
    pub fn energy(&mut self, model: &Model, q: &[f64], v: &[f64]) -> f64 {
        model.kin_into(q, v, &mut self.kin);
        model.energy_at(&self.kin, v, &mut self.mass)
    }
}

impl Model {
    /// Constrained acceleration `q̈` at `(q, q̇)` with the pins `locked`.
    pub fn acceleration(&self, q: &[f64], v: &[f64], locked: &[bool]) -> Option<Vec<f64>> {
        let mut out = vec![0.0; self.n()];
        Work::new(self).acceleration(self, q, v, locked, &mut out)?;
        Some(out)
    }

    /// `M`-orthogonal projection of `q̇` onto `C q̇ = 0`: after each step,
    /// and the plastic impact of a lock.
    pub fn project_velocity(&self, q: &[f64], v: &mut [f64], locked: &[bool]) -> Option<()> {
        let mut w = Work::new(self);
        w.set_kin(self, q, v);
        w.factor(self, locked, false)?;
        w.project_velocity_factored(v)
    }

    /// Projects `q` onto `g(q) = 0` (Gauss–Newton in the `M` metric) and
    /// returns the remaining constraint error `max |g|` [m or rad].
    pub fn project_position(&self, q: &mut [f64], locked: &[bool]) -> Option<f64> {
        Work::new(self).gauss_newton(self, q, locked, true)
    }

    /// Constraint error `max |g|` at `q` [m or rad].
    pub fn constraint_error(&self, q: &[f64], locked: &[bool]) -> f64 {
        Work::new(self).residual(self, q, locked)
    }

    /// Mobility from the Jacobian: `n − rank C` with the pins `locked`.
    pub fn mobility(&self, q: &[f64], locked: &[bool]) -> usize {
        let k: Kin = self.kin(q, &vec![0.0; q.len()]);
        let rows = self.rows(&k, locked);
        self.n() - rank(&rows.c, IMPLIED_TOL)
    }

    /// Whether locking pin `p` on top of `locked` adds an independent row
    /// (in the `M` metric, threshold [`IMPLIED_TOL`]).
    pub fn lock_is_independent(&self, q: &[f64], locked: &[bool], p: usize) -> bool {
        let k: Kin = self.kin(q, &vec![0.0; q.len()]);
        let (m, _) = self.mass_and_forces(&k);
        let before = self.rows(&k, locked);
        let mut with = locked.to_vec();
        with[p] = true;
        let after = self.rows(&k, &with);
        match (factor(m.clone(), &before.c), factor(m, &after.c)) {
            (Some((_, w0)), Some((_, w1))) => rank(&w1, IMPLIED_TOL) > rank(&w0, IMPLIED_TOL),
            _ => false,
        }
    }
}
