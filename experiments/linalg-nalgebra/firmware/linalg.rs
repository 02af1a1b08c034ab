//! `core/src/physics/linalg.rs` with nalgebra in place of the L D Lᵀ code: NOT the
//! core's file. `scripts/linalg-eval.sh firmware` copies core/ and
//! firmware-example/ to a scratch folder, puts this file in the copy's
//! `src/linalg.rs`, adds nalgebra (no default features, libm) to the copy's
//! dependencies and builds the firmware, to measure what adopting nalgebra's
//! Cholesky costs the firmware as a whole (flash, and the instruction counts
//! of `Monitor::update` / `predict` on a replay). Same public API as the
//! core's file; `mat_vec` stays the core's (nalgebra's, on the core's
//! arrays, costs more instructions: experiments/linalg-nalgebra).
//!
//! The core is generic over `Real` (f32 on the MCU, f64 on the host), which
//! nalgebra's `RealField` is not a supertrait of; to leave every other file
//! as it is, the functions pick the f32 or f64 nalgebra path by the type
//! (`dyn Any`, folded at compile time). The mask: the locked rows and
//! columns replaced by the identity, the locked right-hand side by zero.

use core::any::Any;

use crate::real::Real;
use nalgebra::{Cholesky, RealField, SMatrix, SVector};

/// Why a solve failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SolveError {
    /// The matrix is not symmetric positive definite.
    NotPositiveDefinite,
}

impl core::fmt::Display for SolveError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("mass matrix is not positive definite")
    }
}

impl core::error::Error for SolveError {}

fn masked<F: RealField + Copy, const N: usize>(
    m: &[[F; N]; N],
    locked: &[bool; N],
) -> SMatrix<F, N, N> {
    let mut a = SMatrix::<F, N, N>::identity();
    for (i, (row, li)) in m.iter().zip(locked).enumerate() {
        for (j, (mij, lj)) in row.iter().zip(locked).enumerate() {
            if !li && !lj {
                a[(i, j)] = *mij;
            }
        }
    }
    a
}

fn na_solve<F: RealField + Copy, const N: usize>(
    m: &[[F; N]; N],
    b: &[F; N],
    locked: &[bool; N],
) -> Option<[F; N]> {
    let chol = Cholesky::new(masked(m, locked))?;
    let mut r = SVector::<F, N>::from(*b);
    for (ri, li) in r.iter_mut().zip(locked) {
        if *li {
            *ri = F::zero();
        }
    }
    Some(chol.solve(&r).into())
}

/// `(M⁻¹)_jj` of the free block for every free `j` (0 for a locked one).
fn na_inv_diag<F: RealField + Copy, const N: usize>(
    m: &[[F; N]; N],
    locked: &[bool; N],
) -> Option<[F; N]> {
    let inv = Cholesky::new(masked(m, locked))?.inverse();
    Some(core::array::from_fn(|j| inv[(j, j)]))
}

/// `(M⁻¹)_jj` of one joint.
fn na_inv_jj<F: RealField + Copy, const N: usize>(
    m: &[[F; N]; N],
    locked: &[bool; N],
    j: usize,
) -> Option<F> {
    let chol = Cholesky::new(masked(m, locked))?;
    let mut e = SVector::<F, N>::zeros();
    *e.get_mut(j)? = F::one();
    chol.solve(&e).get(j).copied()
}

/// Runs `f32` or `f64` nalgebra code on a `T` that is one of them.
macro_rules! by_type {
    ($t:ty, $m:expr, |$mm:ident| $body:expr) => {{
        if let Some($mm) = ($m as &dyn Any).downcast_ref::<[[f32; N]; N]>() {
            ($body).map(|x| lift::<$t, _>(x))
        } else if let Some($mm) = ($m as &dyn Any).downcast_ref::<[[f64; N]; N]>() {
            ($body).map(|x| lift::<$t, _>(x))
        } else {
            None
        }
    }};
}

/// f32/f64 back to `T` (the same type: `of` is exact).
trait Lift<T> {
    fn lift(self) -> T;
}

impl<T: Real, const N: usize> Lift<[T; N]> for [f32; N] {
    fn lift(self) -> [T; N] {
        self.map(|v| T::of(v as f64))
    }
}
impl<T: Real, const N: usize> Lift<[T; N]> for [f64; N] {
    fn lift(self) -> [T; N] {
        self.map(T::of)
    }
}
impl<T: Real> Lift<T> for f32 {
    fn lift(self) -> T {
        T::of(self as f64)
    }
}
impl<T: Real> Lift<T> for f64 {
    fn lift(self) -> T {
        T::of(self)
    }
}

fn lift<T, X: Lift<T>>(x: X) -> T {
    x.lift()
}

fn any_vec<T: Real, F: 'static + Copy, const N: usize>(b: &[T; N]) -> Option<[F; N]> {
    (b as &dyn Any).downcast_ref::<[F; N]>().copied()
}

/// Solves `M x = b` on the free coordinates; locked entries of `x` are zero.
pub fn solve_spd_masked<T: Real, const N: usize>(
    m: &[[T; N]; N],
    b: &[T; N],
    locked: &[bool; N],
) -> Result<[T; N], SolveError> {
    let x: Option<[T; N]> = by_type!([T; N], m, |mm| any_vec(b)
        .and_then(|bb| na_solve(mm, &bb, locked)));
    x.ok_or(SolveError::NotPositiveDefinite)
}

fn inertia_of<T: Real>(d: T) -> Option<T> {
    let i = T::ONE / d;
    (d > T::ZERO && i.is_finite()).then_some(i)
}

/// Articulated inertia of each joint, `1/(M⁻¹)_jj` over the free
/// coordinates [kg·m²]; `None` for a locked joint, and for every joint when
/// the free block is not positive definite.
pub fn articulated_inertias<T: Real, const N: usize>(
    m: &[[T; N]; N],
    locked: &[bool; N],
) -> [Option<T>; N] {
    let d: Option<[T; N]> = by_type!([T; N], m, |mm| na_inv_diag(mm, locked));
    let Some(d) = d else {
        return [None; N];
    };
    core::array::from_fn(|j| if locked[j] { None } else { inertia_of(d[j]) })
}

/// Articulated inertia `1/(M⁻¹)_jj` of joint `j` alone [kg·m²].
pub fn articulated_inertia<T: Real, const N: usize>(
    m: &[[T; N]; N],
    locked: &[bool; N],
    j: usize,
) -> Option<T> {
    if locked.get(j).copied().unwrap_or(true) {
        return None;
    }
    let d: Option<T> = by_type!(T, m, |mm| na_inv_jj(mm, locked, j));
    inertia_of(d?)
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
