//! `f32` sine and cosine in `f32` arithmetic only: a few tens of
//! instructions on a Cortex-M4F, and the same bits on the host and the MCU.
//!
//! libm's `sinf`/`cosf` reduce their argument and evaluate their kernels in
//! `f64`, which a Cortex-M4F has no hardware for: each call becomes
//! software double arithmetic (`__aeabi_d*`, several hundred instructions).
//! Here everything stays in `f32`:
//!
//! ```text
//! k = round(x · 2/π),   r = ((x − k·P₁) − k·P₂) − k·P₃      (Cody & Waite)
//! sin r ≈ r + r³ (S₁ + r² (S₂ + r² S₃)),
//! cos r ≈ 1 − r²/2 + r⁴ (C₁ + r² (C₂ + r² C₃)),   |r| ≤ π/4
//! ```
//! and the quadrant `k mod 4` picks `±sin r` or `±cos r`. `P₁ + P₂ + P₃ = π/2`
//! with `P₁` (8 bits) and `P₂` (11 bits) short enough that `k·P₁` and
//! `k·P₂` are exact for `|k| < 2¹³` (`|x|` up to about 1.2·10⁴ rad); the minimax coefficients are
//! Cephes' `sinf`/`cosf` (S. L. Moshier, *Methods and Programs for
//! Mathematical Functions*, 1989). Error: within 2·10⁻⁷ absolute of the
//! exact value for `|x| ≤` [`MAX_ARG`] (test `matches_f64_libm`). Beyond [`MAX_ARG`] the
//! reduction is no longer exact and the result is NaN, as for a NaN or
//! infinite argument (no angle of a deployment comes near: the monitor's
//! encoders read within ±720°).
//!
//! IEEE `f32` addition and multiplication round the same way everywhere and
//! rustc never fuses or reorders them, so the result is bit-identical on every
//! target.

use core::f32::consts::FRAC_2_PI;

/// First part of π/2 (8 significant bits) \[rad\].
const PIO2_1: f32 = 1.570_312_5;
/// Second part of π/2 (11 significant bits) \[rad\].
const PIO2_2: f32 = 4.837_513e-4;
/// Third part of π/2, the rest rounded to `f32` \[rad\].
const PIO2_3: f32 = 7.549_79e-8;
/// Largest `|x|` reduced exactly: `2¹³ · π/2` \[rad\].
pub const MAX_ARG: f32 = 8192.0 * PIO2_1;
/// Sine kernel coefficients (Cephes `sinf`).
const S1: f32 = -0.166_666_55;
const S2: f32 = 8.332_161e-3;
const S3: f32 = -1.951_529_6e-4;
/// Cosine kernel coefficients (Cephes `cosf`).
const C1: f32 = 4.166_664_6e-2;
const C2: f32 = -1.388_731_6e-3;
const C3: f32 = 2.443_315_7e-5;

/// `sin r` for `|r| ≤ π/4`.
#[inline]
fn sin_kernel(r: f32) -> f32 {
    let z = r * r;
    ((S3 * z + S2) * z + S1) * z * r + r
}

/// `cos r` for `|r| ≤ π/4`.
#[inline]
fn cos_kernel(r: f32) -> f32 {
    let z = r * r;
    ((C3 * z + C2) * z + C1) * z * z - 0.5 * z + 1.0
}

/// `(k mod 4, r)` with `x = k·π/2 + r`, `|r| ≤ π/4`; `r` NaN beyond
/// [`MAX_ARG`].
#[inline]
fn reduce(x: f32) -> (u32, f32) {
    if !(libm::fabsf(x) <= MAX_ARG) {
        return (0, f32::NAN);
    }
    let y = x * FRAC_2_PI;
    // Round half away from zero (|y| < 2¹³: no overflow).
    let k = if y >= 0.0 { y + 0.5 } else { y - 0.5 } as i32;
    let kf = k as f32;
    let r = ((x - kf * PIO2_1) - kf * PIO2_2) - kf * PIO2_3;
    (k as u32 & 3, r)
}

/// `(sin x, cos x)` from one argument reduction.
#[inline]
pub fn sin_cos(x: f32) -> (f32, f32) {
    let (q, r) = reduce(x);
    let (s, c) = (sin_kernel(r), cos_kernel(r));
    match q {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// `sin x`.
#[inline]
pub fn sin(x: f32) -> f32 {
    let (q, r) = reduce(x);
    match q {
        0 => sin_kernel(r),
        1 => cos_kernel(r),
        2 => -sin_kernel(r),
        _ => -cos_kernel(r),
    }
}

/// `cos x`.
#[inline]
pub fn cos(x: f32) -> f32 {
    let (q, r) = reduce(x);
    match q {
        0 => cos_kernel(r),
        1 => -sin_kernel(r),
        2 => -cos_kernel(r),
        _ => sin_kernel(r),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_f64_libm() {
        let mut worst = 0.0f64;
        let n = 2_000_000;
        for i in 0..=n {
            let x = MAX_ARG * (2.0 * (i as f32 / n as f32) - 1.0);
            let (s, c) = sin_cos(x);
            let xs = f64::from(x);
            let es = (f64::from(s) - libm::sin(xs)).abs();
            let ec = (f64::from(c) - libm::cos(xs)).abs();
            worst = worst.max(es).max(ec);
            assert_eq!(s, sin(x));
            assert_eq!(c, cos(x));
        }
        assert!(worst < 2e-7, "worst absolute error {worst:e}");
        // Small angles, where the relative error matters.
        for i in 1..10_000 {
            let x = i as f32 * 1e-4;
            let rel = (f64::from(sin(x)) - libm::sin(f64::from(x))).abs() / f64::from(x);
            assert!(rel < 2e-7, "sin({x}) relative error {rel:e}");
            assert_eq!(sin(-x), -sin(x));
            assert_eq!(cos(-x), cos(x));
        }
    }

    #[test]
    fn special_values() {
        assert_eq!(sin(0.0), 0.0);
        assert_eq!(cos(0.0), 1.0);
        assert!(sin(f32::NAN).is_nan() && cos(f32::INFINITY).is_nan());
        assert!(sin(1e30).is_nan() && cos(-1e30).is_nan() && sin(MAX_ARG * 1.001).is_nan());
        assert!(sin(MAX_ARG).abs() <= 1.0);
    }
}
