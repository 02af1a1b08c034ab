//! The float type the chain equations are generic over.
//!
//! `f32` on board, `f64` on the host. Every transcendental function goes
//! through [`libm`] or the core's own [`crate::physics::trig`] on both targets, never
//! through `std`: the host's glibc `sinf` and the MCU's would differ in the
//! last bit, and the firmware replay must be bit-identical with the host run
//! of the same core code. The `f32` sine and cosine are [`crate::physics::trig`]'s
//! (all `f32`, a few tens of instructions on a Cortex-M4F, where libm's
//! `sinf`/`cosf` fall into software `f64`); the `f64` ones stay libm's, so
//! the host simulator's accuracy is untouched.

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// A real number type: `f32` or `f64`.
pub trait Real:
    Copy
    + Debug
    + Default
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + 'static
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// π.
    const PI: Self;
    /// Machine epsilon.
    const EPSILON: Self;
    /// The largest finite value.
    const MAX: Self;

    /// Converts from `f64`, rounding to nearest.
    fn of(x: f64) -> Self;
    /// Converts to `f64` (exact).
    fn to_f64(self) -> f64;
    /// Sine (`f32`: [`crate::physics::trig`]; `f64`: libm).
    fn sin(self) -> Self;
    /// Cosine (`f32`: [`crate::physics::trig`]; `f64`: libm).
    fn cos(self) -> Self;
    /// `(sin x, cos x)`, from one argument reduction where the type has one.
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        (self.sin(), self.cos())
    }
    /// Square root (`f32`: [`sqrtf`]; `f64`: libm, correctly rounded).
    fn sqrt(self) -> Self;
    /// e^x (libm).
    fn exp(self) -> Self;
    /// Hyperbolic tangent (libm).
    fn tanh(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// True unless NaN or ±∞.
    fn is_finite(self) -> bool;
    /// True for NaN.
    fn is_nan(self) -> bool;

    /// `-1`, `0` or `1` (0 for 0 and NaN).
    #[inline]
    fn signum0(self) -> Self {
        if self > Self::ZERO {
            Self::ONE
        } else if self < Self::ZERO {
            -Self::ONE
        } else {
            Self::ZERO
        }
    }
    /// The larger of two values (NaN-ignoring on the left).
    #[inline]
    fn max(self, other: Self) -> Self {
        if self > other || other.is_nan() {
            self
        } else {
            other
        }
    }
    /// The smaller of two values (NaN-ignoring on the left).
    #[inline]
    fn min(self, other: Self) -> Self {
        if self < other || other.is_nan() {
            self
        } else {
            other
        }
    }
    /// Degrees to radians.
    #[inline]
    fn to_radians(self) -> Self {
        self * (Self::PI / Self::of(180.0))
    }
    /// Radians to degrees.
    #[inline]
    fn to_degrees(self) -> Self {
        self * (Self::of(180.0) / Self::PI)
    }
}

impl Real for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const PI: Self = core::f32::consts::PI;
    const EPSILON: Self = f32::EPSILON;
    const MAX: Self = f32::MAX;
    #[inline]
    fn of(x: f64) -> Self {
        x as f32
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline]
    fn sin(self) -> Self {
        crate::physics::trig::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        crate::physics::trig::cos(self)
    }
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        crate::physics::trig::sin_cos(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        sqrtf(self)
    }
    #[inline]
    fn exp(self) -> Self {
        libm::expf(self)
    }
    #[inline]
    fn tanh(self) -> Self {
        libm::tanhf(self)
    }
    #[inline]
    fn abs(self) -> Self {
        libm::fabsf(self)
    }
    #[inline]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline]
    fn is_nan(self) -> bool {
        f32::is_nan(self)
    }
}

impl Real for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const PI: Self = core::f64::consts::PI;
    const EPSILON: Self = f64::EPSILON;
    const MAX: Self = f64::MAX;
    #[inline]
    fn of(x: f64) -> Self {
        x
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline]
    fn sin(self) -> Self {
        libm::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        libm::cos(self)
    }
    /// libm's `sincos`: the same kernels on one argument reduction, so the
    /// same bits as `sin` and `cos` apart (test `sincos_is_sin_and_cos`).
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        libm::sincos(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        libm::sqrt(self)
    }
    #[inline]
    fn exp(self) -> Self {
        libm::exp(self)
    }
    #[inline]
    fn tanh(self) -> Self {
        libm::tanh(self)
    }
    #[inline]
    fn abs(self) -> Self {
        libm::fabs(self)
    }
    #[inline]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
    #[inline]
    fn is_nan(self) -> bool {
        f64::is_nan(self)
    }
}

/// Smallest normal `f32` scaled up before the square root's first guess.
const SQRT_TINY: f32 = 1e-30;
/// `2⁴⁸`: the scaling of a tiny argument (its root is scaled by `2²⁴`).
const SQRT_SCALE: f32 = 281_474_976_710_656.0;
/// `2⁻²⁴`: the root of `2⁻⁴⁸`.
const SQRT_UNSCALE: f32 = 5.960_464_5e-8;

/// `√x` in `f32` arithmetic only: a first guess from the exponent bits
/// (`bits/2 + 0x1fbd_1df5`, within 3.5 %), then three Newton steps
/// `y ← ½ (y + x/y)` (each squares the relative error: 6·10⁻⁴, 2·10⁻⁷,
/// then rounding): a few floating-point operations on a Cortex-M4F, where
/// libm's correctly rounded `sqrtf` runs an integer Goldschmidt iteration
/// the M4F has no hardware for, several times longer. Within 2 ulp of the exact root
/// (test `sqrtf_within_2_ulp`), bit-identical on every target (IEEE
/// `f32` operations only). `√0 = 0`, `√∞ = ∞`, NaN for a negative or NaN
/// argument.
#[inline]
pub fn sqrtf(x: f32) -> f32 {
    if !(x > 0.0) {
        return if x == 0.0 { 0.0 } else { f32::NAN };
    }
    if x == f32::INFINITY {
        return x;
    }
    let (v, unscale) = if x < SQRT_TINY {
        (x * SQRT_SCALE, SQRT_UNSCALE)
    } else {
        (x, 1.0)
    };
    let mut y = f32::from_bits((v.to_bits() >> 1) + 0x1fbd_1df5);
    for _ in 0..3 {
        y = 0.5 * (y + v / y);
    }
    y * unscale
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sincos_is_sin_and_cos() {
        // 200,003 bit patterns evenly spread over the f64 angles up to
        // 2^20 rad in magnitude (every branch of the argument reduction),
        // and a sweep of the angles a chain has (±4π).
        let patterns = (0..0x4130_0000_0000_0000u64)
            .step_by((0x4130_0000_0000_0000u64 / 200_003) as usize)
            .map(f64::from_bits);
        let sweep = (-100_000..=100_000).map(|i| f64::from(i) * 4.0 * core::f64::consts::PI / 1e5);
        for x in patterns.chain(sweep).flat_map(|x| [x, -x]) {
            let (s, c) = Real::sin_cos(x);
            assert_eq!(s.to_bits(), libm::sin(x).to_bits(), "sin({x:e})");
            assert_eq!(c.to_bits(), libm::cos(x).to_bits(), "cos({x:e})");
        }
    }

    #[test]
    fn sqrtf_within_2_ulp() {
        // Every 9973rd positive finite f32, denormals included.
        for bits in (1..0x7f80_0000u32).step_by(9973) {
            let x = f32::from_bits(bits);
            let want = (f64::from(x)).sqrt();
            let got = f64::from(sqrtf(x));
            let ulp = f64::from(f32::EPSILON) * want;
            assert!(
                (got - want).abs() <= 2.0 * ulp,
                "sqrtf({x}) = {got}, want {want}"
            );
        }
        assert_eq!(sqrtf(0.0), 0.0);
        assert_eq!(sqrtf(4.0), 2.0);
        assert_eq!(sqrtf(f32::INFINITY), f32::INFINITY);
        assert!(sqrtf(-1.0).is_nan() && sqrtf(f32::NAN).is_nan());
    }
}
