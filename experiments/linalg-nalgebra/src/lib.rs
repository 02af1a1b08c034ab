//! `deploywatch_core::linalg` against nalgebra's fixed-size `SMatrix` /
//! `SVector` (no std, no alloc, libm).
//!
//! Both implementations have the same signatures, on the core's row-major
//! arrays, so that the same inputs go through both and the functions the
//! firmware links can be swapped one for one:
//!
//! | function | `core_impl` | `nalgebra_impl` |
//! |---|---|---|
//! | `solve` | `solve_spd_masked` (L D Lᵀ, no square root) | `Cholesky::new` + `solve` on the masked matrix |
//! | `solve_lu` | — | `lu()` + `solve` on the masked matrix |
//! | `inertias` | `articulated_inertias` | `Cholesky::new` + `inverse`, `1/(M⁻¹)_jj` |
//! | `inertia` | `articulated_inertia` | `Cholesky::new` + `solve(e_j)` |
//! | `mat_vec` | `mat_vec` | `SMatrix * SVector` |
//! | `mat_vec_native` | — | `SMatrix * SVector` on `SMatrix` inputs |
//! | `mat_vec_rows` | one dot product per row (not in the core) | — |
//!
//! Every function is `#[inline(never)]` and monomorphised for `f32` and
//! N = 2, 3 (the firmware's monitors), so that its symbol can be sized with
//! `arm-none-eabi-nm -S` and its calls counted.
#![no_std]

/// A solve's answer: `None` when the free block is not positive definite
/// (or singular, for LU).
pub type Solved<const N: usize> = Option<[f32; N]>;

/// Implementation (a): today's `deploywatch_core::linalg`.
#[cfg(feature = "impl-core")]
pub mod core_impl {
    use super::Solved;
    use deploywatch_core::linalg;

    macro_rules! sized {
        ($n:literal, $solve:ident, $inertias:ident, $inertia:ident, $mat_vec:ident) => {
            /// `solve_spd_masked`.
            #[inline(never)]
            pub fn $solve(m: &[[f32; $n]; $n], b: &[f32; $n], locked: &[bool; $n]) -> Solved<$n> {
                linalg::solve_spd_masked(m, b, locked).ok()
            }
            /// `articulated_inertias`.
            #[inline(never)]
            pub fn $inertias(m: &[[f32; $n]; $n], locked: &[bool; $n]) -> [Option<f32>; $n] {
                linalg::articulated_inertias(m, locked)
            }
            /// `articulated_inertia`.
            #[inline(never)]
            pub fn $inertia(m: &[[f32; $n]; $n], locked: &[bool; $n], j: usize) -> Option<f32> {
                linalg::articulated_inertia(m, locked, j)
            }
            /// `mat_vec`.
            #[inline(never)]
            pub fn $mat_vec(m: &[[f32; $n]; $n], x: &[f32; $n]) -> [f32; $n] {
                linalg::mat_vec(m, x)
            }
        };
    }
    sized!(2, solve2, inertias2, inertia2, mat_vec2);
    sized!(3, solve3, inertias3, inertia3, mat_vec3);

    /// `M x` on the core's arrays as one dot product per row, summed in the
    /// core's order from 0 (so bit-identical with `linalg::mat_vec`): to
    /// tell whether a gain of nalgebra's product comes from nalgebra or from
    /// the shape of the loop. Not in the core.
    #[inline(always)]
    fn mat_vec_rows<const N: usize>(m: &[[f32; N]; N], x: &[f32; N]) -> [f32; N] {
        let mut y = [0.0; N];
        for (yi, row) in y.iter_mut().zip(m) {
            *yi = row.iter().zip(x).fold(0.0, |s, (a, b)| s + a * b);
        }
        y
    }

    /// [`mat_vec_rows`] for N = 2.
    #[inline(never)]
    pub fn mat_vec_rows2(m: &[[f32; 2]; 2], x: &[f32; 2]) -> [f32; 2] {
        mat_vec_rows(m, x)
    }

    /// [`mat_vec_rows`] for N = 3.
    #[inline(never)]
    pub fn mat_vec_rows3(m: &[[f32; 3]; 3], x: &[f32; 3]) -> [f32; 3] {
        mat_vec_rows(m, x)
    }
}

/// Implementation (b): nalgebra's `SMatrix` / `SVector`.
///
/// **The mask.** nalgebra's decompositions have no notion of locked
/// coordinates, and without a heap the free block cannot be cut out into a
/// smaller matrix of a size known only at run time. So the masked matrix is
/// built as `physics.md` section 5 (and `core::linalg`'s module doc) state
/// it: the locked rows and columns replaced by the identity, the locked
/// entries of the right-hand side by zero. The factorisation of that matrix
/// is the free block's with ones on the locked diagonal, so the free
/// entries of `x` are the free block's solution and the locked ones are
/// exactly zero (`0 / 1`), and `(M⁻¹)_jj` of a free joint is the free
/// block's. The cost: `N²` selects to build the matrix, and the locked
/// coordinates are factorised and substituted like free ones (the core
/// skips them).
#[cfg(feature = "impl-nalgebra")]
pub mod nalgebra_impl {
    use super::Solved;
    use nalgebra::{Cholesky, SMatrix, SVector};

    /// `M` with its locked rows and columns replaced by the identity, in
    /// nalgebra's column-major storage.
    #[inline(always)]
    fn masked<const N: usize>(m: &[[f32; N]; N], locked: &[bool; N]) -> SMatrix<f32, N, N> {
        let mut a = SMatrix::<f32, N, N>::identity();
        for (i, (row, li)) in m.iter().zip(locked).enumerate() {
            for (j, (mij, lj)) in row.iter().zip(locked).enumerate() {
                if !li && !lj {
                    a[(i, j)] = *mij;
                }
            }
        }
        a
    }

    /// `b` with its locked entries zero.
    #[inline(always)]
    fn masked_rhs<const N: usize>(b: &[f32; N], locked: &[bool; N]) -> SVector<f32, N> {
        let mut r = SVector::<f32, N>::from(*b);
        for (ri, li) in r.iter_mut().zip(locked) {
            if *li {
                *ri = 0.0;
            }
        }
        r
    }

    #[inline(always)]
    fn solve<const N: usize>(m: &[[f32; N]; N], b: &[f32; N], locked: &[bool; N]) -> Solved<N> {
        let chol = Cholesky::new(masked(m, locked))?;
        Some(chol.solve(&masked_rhs(b, locked)).into())
    }

    /// `1/d` when it is a positive finite inertia (the core's test).
    #[inline(always)]
    fn inertia_of(d: f32) -> Option<f32> {
        let i = 1.0 / d;
        (d > 0.0 && i.is_finite()).then_some(i)
    }

    #[inline(always)]
    fn inertias<const N: usize>(m: &[[f32; N]; N], locked: &[bool; N]) -> [Option<f32>; N] {
        let Some(chol) = Cholesky::new(masked(m, locked)) else {
            return [None; N];
        };
        let inv = chol.inverse();
        let mut out = [None; N];
        for (j, (o, l)) in out.iter_mut().zip(locked).enumerate() {
            if !l {
                *o = inertia_of(inv[(j, j)]);
            }
        }
        out
    }

    #[inline(always)]
    fn inertia<const N: usize>(m: &[[f32; N]; N], locked: &[bool; N], j: usize) -> Option<f32> {
        if locked.get(j).copied().unwrap_or(true) {
            return None;
        }
        let chol = Cholesky::new(masked(m, locked))?;
        let mut e = SVector::<f32, N>::zeros();
        *e.get_mut(j)? = 1.0;
        inertia_of(*chol.solve(&e).get(j)?)
    }

    #[inline(always)]
    fn mat_vec<const N: usize>(m: &[[f32; N]; N], x: &[f32; N]) -> [f32; N] {
        let a = SMatrix::<f32, N, N>::from_fn(|i, j| m[i][j]);
        (a * SVector::<f32, N>::from(*x)).into()
    }

    macro_rules! sized {
        ($n:literal, $solve:ident, $solve_lu:ident, $inertias:ident, $inertia:ident, $mat_vec:ident, $mat_vec_native:ident) => {
            /// `Cholesky::new` + `solve` on the masked matrix.
            #[inline(never)]
            pub fn $solve(m: &[[f32; $n]; $n], b: &[f32; $n], locked: &[bool; $n]) -> Solved<$n> {
                solve(m, b, locked)
            }
            /// `lu()` + `solve` on the masked matrix (per size: nalgebra's
            /// `LU` of a generic `Const<N>` needs typenum bounds,
            /// `Const<N>: DimMin<Const<N>, Output = Const<N>>`).
            #[inline(never)]
            pub fn $solve_lu(
                m: &[[f32; $n]; $n],
                b: &[f32; $n],
                locked: &[bool; $n],
            ) -> Solved<$n> {
                let x = masked(m, locked).lu().solve(&masked_rhs(b, locked))?;
                Some(x.into())
            }
            /// `Cholesky::new` + `inverse`.
            #[inline(never)]
            pub fn $inertias(m: &[[f32; $n]; $n], locked: &[bool; $n]) -> [Option<f32>; $n] {
                inertias(m, locked)
            }
            /// `Cholesky::new` + `solve(e_j)`.
            #[inline(never)]
            pub fn $inertia(m: &[[f32; $n]; $n], locked: &[bool; $n], j: usize) -> Option<f32> {
                inertia(m, locked, j)
            }
            /// `SMatrix * SVector`.
            #[inline(never)]
            pub fn $mat_vec(m: &[[f32; $n]; $n], x: &[f32; $n]) -> [f32; $n] {
                mat_vec(m, x)
            }
            /// `SMatrix * SVector` on nalgebra's own types (no conversion
            /// from the core's arrays): what `mat_vec` would cost if the
            /// chain kept its mass matrix as an `SMatrix`.
            #[inline(never)]
            pub fn $mat_vec_native(
                a: &SMatrix<f32, $n, $n>,
                x: &SVector<f32, $n>,
            ) -> SVector<f32, $n> {
                a * x
            }
        };
    }
    sized!(
        2,
        solve2,
        solve_lu2,
        inertias2,
        inertia2,
        mat_vec2,
        mat_vec_native2
    );
    sized!(
        3,
        solve3,
        solve_lu3,
        inertias3,
        inertia3,
        mat_vec3,
        mat_vec_native3
    );
}
