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

use super::kin::{Kin, Model};

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

impl Model {
    /// Constrained acceleration `q̈` at `(q, q̇)` with the pins `locked`.
    pub fn acceleration(&self, q: &[f64], v: &[f64], locked: &[bool]) -> Option<Vec<f64>> {
        let k = self.kin(q, v);
        let (m, f) = self.mass_and_forces(&k);
        let rows = self.rows(&k, locked);
        let (l, w) = factor(m, &rows.c)?;
        let z = l.solve_lower_triangular(&f)?;
        let r = &rows.gamma - &w * &z;
        let y = z + pinv_solve(&w, &r)?;
        let a = l.tr_solve_lower_triangular(&y)?;
        a.iter()
            .all(|x| x.is_finite())
            .then(|| a.as_slice().to_vec())
    }

    /// `M`-orthogonal projection of `q̇` onto `C q̇ = 0`: after each step,
    /// and the plastic impact of a lock.
    pub fn project_velocity(&self, q: &[f64], v: &mut [f64], locked: &[bool]) -> Option<()> {
        let k = self.kin(q, v);
        let (m, _) = self.mass_and_forces(&k);
        let rows = self.rows(&k, locked);
        let (l, w) = factor(m, &rows.c)?;
        let mut p = l.transpose() * DVector::from_column_slice(v);
        let wp = &w * &p;
        p -= pinv_solve(&w, &wp)?;
        let out = l.tr_solve_lower_triangular(&p)?;
        v.copy_from_slice(out.as_slice());
        Some(())
    }

    /// Projects `q` onto `g(q) = 0` (Gauss–Newton in the `M` metric) and
    /// returns the remaining constraint error `max |g|` [m or rad].
    pub fn project_position(&self, q: &mut [f64], locked: &[bool]) -> Option<f64> {
        let zero = vec![0.0; q.len()];
        let mut last = f64::INFINITY;
        for _ in 0..20 {
            let k = self.kin(q, &zero);
            let rows = self.rows(&k, locked);
            let err = rows.g.amax();
            if err <= 1e-15 || err >= 0.5 * last {
                return Some(err.min(last));
            }
            last = err;
            let (m, _) = self.mass_and_forces(&k);
            let (l, w) = factor(m, &rows.c)?;
            let dy = pinv_solve(&w, &rows.g)?;
            let dq = l.tr_solve_lower_triangular(&dy)?;
            for (qi, d) in q.iter_mut().zip(dq.iter()) {
                *qi -= d;
            }
        }
        Some(last)
    }

    /// Constraint error `max |g|` at `q` [m or rad].
    pub fn constraint_error(&self, q: &[f64], locked: &[bool]) -> f64 {
        let k = self.kin(q, &vec![0.0; q.len()]);
        self.rows(&k, locked).g.amax()
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
