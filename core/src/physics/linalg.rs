//! Fixed-size dense linear algebra for the joint-space equations (N ≤ 4).
//!
//! Joints that are locked (latched) are removed from the coordinates by
//! replacing their rows and columns with the identity and their right-hand
//! side with zero: the free block is then solved exactly as if the locked
//! coordinates were not there (`physics.md` section 5).

use crate::physics::real::Real;

/// Why a solve failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SolveError {
    /// The matrix is not symmetric positive definite (a zero-mass panel, or
    /// NaN in the state).
    NotPositiveDefinite,
}

impl core::fmt::Display for SolveError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("mass matrix is not positive definite")
    }
}

impl core::error::Error for SolveError {}

/// Solves `M x = b` on the free coordinates (`locked[i] == false`) by an
/// `L D Lᵀ` factorisation; locked entries of `x` are zero.
pub fn solve_spd_masked<T: Real, const N: usize>(
    m: &[[T; N]; N],
    b: &[T; N],
    locked: &[bool; N],
) -> Result<[T; N], SolveError> {
    solve_spd_masked_n(N, m, b, locked)
}

/// [`solve_spd_masked`] on the first `n ≤ M` coordinates of arrays of
/// capacity `M` (the joint count known at run time; entries past `n` of
/// the result are zero). The same arithmetic in the same order as with
/// `M = n`.
#[inline(always)]
pub fn solve_spd_masked_n<T: Real, const M: usize>(
    n: usize,
    m: &[[T; M]; M],
    b: &[T; M],
    locked: &[bool; M],
) -> Result<[T; M], SolveError> {
    let mut l = [[T::ZERO; M]; M];
    ldl_masked(n, m, locked, &mut l)?;
    Ok(substitute(n, &l, b, locked))
}

/// The factors of `M = L D Lᵀ` (`L` unit lower triangular, `D` diagonal)
/// of the free block of the first `n` coordinates, `D` on the diagonal
/// of the result and `L` below it; locked rows and columns hold the
/// identity. The square-root-free form
/// of Cholesky's factorisation (Golub & Van Loan, *Matrix Computations*,
/// 4th ed., §4.1.2): the same arithmetic without the `N` square roots,
/// which a Cortex-M4F computes in software.
///
/// ```text
/// L_ij = (M_ij − Σ_{k<j} L_ik L_jk D_k) / D_j,   D_i = M_ii − Σ_{k<i} L_ik² D_k
/// ```
///
/// The factors are written into `l` (zero on entry), not returned: a
/// returned `Result` of the matrix is copied once more on the MCU (a
/// `memcpy` of 36 bytes at 3 joints, twice per solve).
fn ldl_masked<T: Real, const N: usize>(
    n: usize,
    m: &[[T; N]; N],
    locked: &[bool; N],
    l: &mut [[T; N]; N],
) -> Result<(), SolveError> {
    for i in 0..n.min(N) {
        if locked[i] {
            l[i][i] = T::ONE;
            continue;
        }
        for j in 0..i + 1 {
            if locked[j] {
                continue;
            }
            let mut s = m[i][j];
            for k in 0..j {
                if !locked[k] {
                    s -= l[i][k] * l[j][k] * l[k][k];
                }
            }
            if i == j {
                // `!(s > 0)` also catches NaN.
                if !(s > T::ZERO) {
                    return Err(SolveError::NotPositiveDefinite);
                }
                l[i][i] = s;
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    Ok(())
}

/// `L y = b`, `D z = y`, then `Lᵀ x = z`, on the free coordinates of
/// the first `n`.
fn substitute<T: Real, const N: usize>(
    n: usize,
    l: &[[T; N]; N],
    b: &[T; N],
    locked: &[bool; N],
) -> [T; N] {
    let n = n.min(N);
    let mut y = [T::ZERO; N];
    for i in 0..n {
        if locked[i] {
            continue;
        }
        let mut s = b[i];
        for k in 0..i {
            s -= l[i][k] * y[k];
        }
        y[i] = s;
    }
    let mut x = [T::ZERO; N];
    for i in (0..n).rev() {
        if locked[i] {
            continue;
        }
        let mut s = y[i] / l[i][i];
        for k in i + 1..n {
            s -= l[k][i] * x[k];
        }
        x[i] = s;
    }
    x
}

/// Articulated inertia of each joint, `1/(M⁻¹)_jj` over the free
/// coordinates [kg·m²]: the inertia a joint feels with every other free
/// joint free to move (Featherstone, *Rigid Body Dynamics Algorithms*,
/// 2008, §7.1). One factorisation, one substitution per joint. `None` for
/// a locked joint, and for every joint when the free block is not
/// positive definite. (The tests' form: the monitor uses
/// [`articulated_inertias_n`].)
#[cfg(test)]
pub fn articulated_inertias<T: Real, const N: usize>(
    m: &[[T; N]; N],
    locked: &[bool; N],
) -> [Option<T>; N] {
    articulated_inertias_n(N, m, locked)
}

/// `articulated_inertias` of the first `n ≤ M` coordinates of arrays of
/// capacity `M` (`None` past `n`); the same arithmetic as with `M = n`.
#[inline(always)]
pub fn articulated_inertias_n<T: Real, const M: usize>(
    n: usize,
    m: &[[T; M]; M],
    locked: &[bool; M],
) -> [Option<T>; M] {
    let mut l = [[T::ZERO; M]; M];
    if ldl_masked(n, m, locked, &mut l).is_err() {
        return [None; M];
    }
    core::array::from_fn(|j| {
        if j >= n || locked[j] {
            return None;
        }
        let mut e = [T::ZERO; M];
        e[j] = T::ONE;
        let d = substitute(n, &l, &e, locked)[j];
        let i = T::ONE / d;
        (d > T::ZERO && i.is_finite()).then_some(i)
    })
}

/// Articulated inertia `1/(M⁻¹)_jj` of joint `j` alone [kg·m²], among the
/// first `n ≤ M` coordinates of arrays of capacity `M`: the same
/// factorisation and substitution as [`articulated_inertias_n`], for one
/// joint (the monitor evaluates one joint's margin per sample). `None` for
/// `j ≥ n`, a locked joint, and when the free block is not positive
/// definite.
#[inline(always)]
pub fn articulated_inertia_n<T: Real, const M: usize>(
    n: usize,
    m: &[[T; M]; M],
    locked: &[bool; M],
    j: usize,
) -> Option<T> {
    if j >= n || locked.get(j).copied().unwrap_or(true) {
        return None;
    }
    let mut l = [[T::ZERO; M]; M];
    ldl_masked(n, m, locked, &mut l).ok()?;
    let mut e = [T::ZERO; M];
    if let Some(ej) = e.get_mut(j) {
        *ej = T::ONE;
    }
    let d = substitute(n, &l, &e, locked).get(j).copied()?;
    let i = T::ONE / d;
    (d > T::ZERO && i.is_finite()).then_some(i)
}

/// `y = M x`.
pub fn mat_vec<T: Real, const N: usize>(m: &[[T; N]; N], x: &[T; N]) -> [T; N] {
    let mut y = [T::ZERO; N];
    for i in 0..N {
        for j in 0..N {
            y[i] += m[i][j] * x[j];
        }
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_and_masks() {
        let m = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]];
        let b = [1.0, 2.0, 3.0];
        let x = solve_spd_masked(&m, &b, &[false; 3]).unwrap();
        let r = mat_vec(&m, &x);
        for i in 0..3 {
            assert!((r[i] - b[i]).abs() < 1e-12);
        }
        let x = solve_spd_masked(&m, &b, &[false, true, false]).unwrap();
        assert_eq!(x[1], 0.0);
        // Free block [[4, .5], [.5, 2]] x = [1, 3].
        assert!((4.0 * x[0] + 0.5 * x[2] - 1.0).abs() < 1e-12);
        assert!((0.5 * x[0] + 2.0 * x[2] - 3.0).abs() < 1e-12);
        // (M⁻¹)_00 of the free block is 2/(8 − 0.25).
        let inertia = articulated_inertias(&m, &[false, true, false]);
        assert!((inertia[0].unwrap() - 7.75 / 2.0).abs() < 1e-12);
        assert_eq!(inertia[1], None);
        assert!((inertia[2].unwrap() - 7.75 / 4.0).abs() < 1e-12);
        assert_eq!(
            articulated_inertias(&[[0.0, 0.0], [0.0, 1.0]], &[false; 2]),
            [None; 2]
        );
        let bad = [[0.0, 0.0], [0.0, 1.0]];
        assert_eq!(
            solve_spd_masked(&bad, &[1.0, 1.0], &[false; 2]),
            Err(SolveError::NotPositiveDefinite)
        );
    }
}
