//! The chain's kinematics over the first `n ≤ M` joints: absolute angles
//! `θ = S φ`, their cosines and sines, `Sᵀ x`, and the congruence `Sᵀ D S`.

use crate::physics::real::Real;

/// Absolute panel angles `θ = S φ` \[rad\] of the first `n ≤ M` joints.
#[inline(always)]
pub(super) fn absolute<T: Real, const M: usize>(n: usize, phi: &[T; M]) -> [T; M] {
    let n = n.min(M);
    let mut th = [T::ZERO; M];
    let mut acc = T::ZERO;
    for i in 0..n {
        acc += phi[i];
        th[i] = acc;
    }
    th
}

/// `(cos θ_k, sin θ_k)` for the first `n ≤ M` panels.
#[inline(always)]
pub(super) fn trig<T: Real, const M: usize>(n: usize, theta: &[T; M]) -> ([T; M], [T; M]) {
    let n = n.min(M);
    let mut c = [T::ZERO; M];
    let mut s = [T::ZERO; M];
    for k in 0..n {
        (s[k], c[k]) = theta[k].sin_cos();
    }
    (c, s)
}

/// `Sᵀ x`: `(Sᵀ x)_j = Σ_{j ≤ k < n} x_k`.
#[inline(always)]
pub(super) fn st<T: Real, const M: usize>(n: usize, x: &[T; M]) -> [T; M] {
    let n = n.min(M);
    let mut y = [T::ZERO; M];
    let mut acc = T::ZERO;
    for j in (0..n).rev() {
        acc += x[j];
        y[j] = acc;
    }
    y
}

/// `Sᵀ D S` from `D`, over the first `n ≤ M` joints, in place: `d` holds
/// `D` on entry and `Sᵀ D S` on return (each entry is read once before
/// it is overwritten, so the sums are those of separate matrices; one
/// matrix fewer to clear and copy on the MCU).
#[inline(always)]
pub(super) fn congruence<T: Real, const M: usize>(n: usize, d: &mut [[T; M]; M]) {
    let n = n.min(M);
    // R = D S (suffix sums along columns), M = Sᵀ R (suffix sums along rows).
    for row in d.iter_mut().take(n) {
        let mut acc = T::ZERO;
        for k in (0..n).rev() {
            acc += row[k];
            row[k] = acc;
        }
    }
    for k in 0..n {
        let mut acc = T::ZERO;
        for j in (0..n).rev() {
            acc += d[j][k];
            d[j][k] = acc;
        }
    }
}
