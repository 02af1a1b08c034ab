//! Hinge springs: linear torsion springs and moment–rotation curves with
//! hysteresis (tape springs).
//!
//! Reference: `docs/spec/physics.md` section 3. A hinge spring always drives
//! its joint towards `φ = 0`:
//!
//! ```text
//! τ_spring = −sign(φ) · count · T(|φ|, branch)      [N·m]
//! ```
//!
//! Curves are tabulated in degrees and N·m per hinge, as in seed 001 Table 1;
//! they are interpolated either piecewise linearly or with the Akima (1970)
//! spline, computed exactly as `scipy.interpolate.Akima1DInterpolator(x, y,
//! method="akima")` does (the reference implementation's choice), and clamped
//! to their end values outside the knots.

use crate::physics::real::Real;

/// Most knots a tabulated branch may have.
pub const MAX_KNOTS: usize = 16;

/// Which moment–rotation branch a hysteretic hinge is on (seed 001 Eq. 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Branch {
    /// `φ·φ̇ < 0`: the hinge is opening towards `φ = 0` (path C→B→D→O).
    Unfold,
    /// `φ·φ̇ ≥ 0`, rest included: folding path O→A→B→C.
    #[default]
    Fold,
}

impl Branch {
    /// The branch the rule of seed 001 Eq. 1 selects for angle `φ` and rate `φ̇`.
    #[inline]
    pub fn select<T: Real>(phi: T, phi_dot: T) -> Self {
        if phi * phi_dot < T::ZERO {
            Branch::Unfold
        } else {
            Branch::Fold
        }
    }
}

/// How a tabulated branch is interpolated between its knots.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interp {
    /// Straight lines between knots.
    Linear,
    /// Akima (1970) spline, as scipy's `Akima1DInterpolator(method="akima")`.
    Akima,
}

/// Why a tabulated curve was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum CurveError {
    /// Fewer than two knots.
    TooFewKnots,
    /// More than [`MAX_KNOTS`] knots.
    TooManyKnots,
    /// Knot abscissae are not strictly increasing.
    NotIncreasing,
    /// A knot is NaN or infinite.
    NotFinite,
}

impl core::fmt::Display for CurveError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            CurveError::TooFewKnots => "a curve needs at least 2 points",
            CurveError::TooManyKnots => "a curve has at most 16 points",
            CurveError::NotIncreasing => "curve angles must be strictly increasing",
            CurveError::NotFinite => "curve points must be finite numbers",
        })
    }
}

impl core::error::Error for CurveError {}

/// A tabulated function `T(θ)`, θ in degrees, as a piecewise cubic Hermite
/// curve (linear interpolation is the special case of chord slopes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curve<T> {
    /// Number of knots (at most [`MAX_KNOTS`]; a `u32`, the width of
    /// `usize` on the MCU, so that the host's monitor has its size).
    len: u32,
    linear: bool,
    x: [T; MAX_KNOTS],
    y: [T; MAX_KNOTS],
    slope: [T; MAX_KNOTS],
}

impl<T: Real> Curve<T> {
    /// Builds a curve through `points = [(deg, N·m), ...]`.
    pub fn new(points: &[(T, T)], interp: Interp) -> Result<Self, CurveError> {
        let n = points.len();
        if n < 2 {
            return Err(CurveError::TooFewKnots);
        }
        if n > MAX_KNOTS {
            return Err(CurveError::TooManyKnots);
        }
        let mut c = Curve {
            len: n as u32,
            linear: interp == Interp::Linear,
            x: [T::ZERO; MAX_KNOTS],
            y: [T::ZERO; MAX_KNOTS],
            slope: [T::ZERO; MAX_KNOTS],
        };
        let mut prev = None;
        for ((&(x, y), cx), cy) in points.iter().zip(c.x.iter_mut()).zip(c.y.iter_mut()) {
            if !x.is_finite() || !y.is_finite() {
                return Err(CurveError::NotFinite);
            }
            if prev.is_some_and(|p| x <= p) {
                return Err(CurveError::NotIncreasing);
            }
            prev = Some(x);
            *cx = x;
            *cy = y;
        }
        if !c.linear && n > 2 {
            c.akima_slopes();
        }
        Ok(c)
    }

    /// Knot slopes of the Akima spline, transcribed from scipy 1.17
    /// `Akima1DInterpolator.__init__` (method "akima", break_mult 1e-9).
    fn akima_slopes(&mut self) {
        // Clamped so that every index below is provably in bounds (no
        // panic path); `new` guarantees it anyway.
        let n = (self.len as usize).clamp(2, MAX_KNOTS);
        // m[2..n+1] are the chord slopes, two extrapolated on each side.
        let mut m = [T::ZERO; MAX_KNOTS + 3];
        for i in 0..n - 1 {
            m[i + 2] = (self.y[i + 1] - self.y[i]) / (self.x[i + 1] - self.x[i]);
        }
        let two = T::of(2.0);
        m[1] = two * m[2] - m[3];
        m[0] = two * m[1] - m[2];
        m[n + 1] = two * m[n] - m[n - 1];
        m[n + 2] = two * m[n + 1] - m[n];
        let mut f12max = -T::MAX;
        let mut f1 = [T::ZERO; MAX_KNOTS];
        let mut f2 = [T::ZERO; MAX_KNOTS];
        for i in 0..n {
            f1[i] = (m[i + 3] - m[i + 2]).abs();
            f2[i] = (m[i + 1] - m[i]).abs();
            f12max = f12max.max(f1[i] + f2[i]);
        }
        let cut = T::of(1e-9) * f12max;
        for i in 0..n {
            let f12 = f1[i] + f2[i];
            self.slope[i] = if f12 > cut {
                m[i + 1] + (f2[i] / f12) * (m[i + 2] - m[i + 1])
            } else {
                T::of(0.5) * (m[i + 3] + m[i])
            };
        }
    }

    /// Number of knots.
    pub fn len(&self) -> usize {
        self.len as usize
    }

    /// Always false: a curve has at least two knots.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The knots `(deg, N·m)`.
    pub fn knot(&self, i: usize) -> Option<(T, T)> {
        if i < self.len as usize {
            Some((self.x[i], self.y[i]))
        } else {
            None
        }
    }

    /// Index of the interval holding `x` (clamped to the first and last),
    /// below `n − 1` with `n` the knots used.
    #[inline]
    fn interval(&self, x: T, n: usize) -> usize {
        let mut i = 0;
        while i + 2 < n && self.x.get(i + 1).is_some_and(|&xi| x >= xi) {
            i += 1;
        }
        i.min(n.saturating_sub(2))
    }

    /// The value at `x` degrees, clamped to the end values outside the knots.
    #[inline]
    pub fn eval(&self, x: T) -> T {
        // Clamped so that every index below is provably in bounds (no
        // panic path on the monitor's sample path); `new` guarantees it.
        let n = (self.len as usize).clamp(2, MAX_KNOTS);
        if !(x > self.x[0]) {
            return self.y[0];
        }
        if x >= self.x[n - 1] {
            return self.y[n - 1];
        }
        let i = self.interval(x, n);
        let h = self.x[i + 1] - self.x[i];
        let s = (x - self.x[i]) / h;
        if self.linear {
            return self.y[i] + s * (self.y[i + 1] - self.y[i]);
        }
        let s2 = s * s;
        let s3 = s2 * s;
        let two = T::of(2.0);
        let three = T::of(3.0);
        let h00 = two * s3 - three * s2 + T::ONE;
        let h10 = s3 - two * s2 + s;
        let h01 = three * s2 - two * s3;
        let h11 = s3 - s2;
        h00 * self.y[i]
            + h10 * h * self.slope[i]
            + h01 * self.y[i + 1]
            + h11 * h * self.slope[i + 1]
    }

    /// `∫ T(θ) dθ` from `a` to `b` degrees (a ≤ b), in N·m·deg, with the
    /// curve clamped outside its knots. Exact for both interpolations.
    pub(crate) fn integral(&self, a: T, b: T) -> T {
        if !(b > a) {
            return T::ZERO;
        }
        self.antiderivative(b) - self.antiderivative(a)
    }

    /// `∫_{x0}^{x} T dθ` with `x0` the first knot and clamping outside.
    fn antiderivative(&self, x: T) -> T {
        let n = (self.len as usize).clamp(2, MAX_KNOTS);
        if !(x > self.x[0]) {
            return (x - self.x[0]) * self.y[0];
        }
        let mut acc = T::ZERO;
        for i in 0..n - 1 {
            let (x0, x1) = (self.x[i], self.x[i + 1]);
            if x <= x0 {
                break;
            }
            let h = x1 - x0;
            let s = if x >= x1 { T::ONE } else { (x - x0) / h };
            acc += h * self.segment_integral(i, s);
        }
        if x > self.x[n - 1] {
            acc += (x - self.x[n - 1]) * self.y[n - 1];
        }
        acc
    }

    /// `∫_0^s p_i(σ) dσ` for the Hermite cubic of interval `i` in its unit
    /// coordinate σ (multiply by the interval length for degrees).
    fn segment_integral(&self, i: usize, s: T) -> T {
        let knot = |v: &[T; MAX_KNOTS], k: usize| v.get(k).copied().unwrap_or(T::ZERO);
        let (y0, y1) = (knot(&self.y, i), knot(&self.y, i + 1));
        let half = T::of(0.5);
        if self.linear {
            return y0 * s + half * (y1 - y0) * s * s;
        }
        let h = knot(&self.x, i + 1) - knot(&self.x, i);
        let s2 = s * s;
        let s3 = s2 * s;
        let s4 = s3 * s;
        let third = T::ONE / T::of(3.0);
        let quarter = T::of(0.25);
        let i00 = half * s4 - s3 + s;
        let i10 = quarter * s4 - T::of(2.0) * third * s3 + half * s2;
        let i01 = -half * s4 + s3;
        let i11 = quarter * s4 - third * s3;
        i00 * y0 + i10 * h * knot(&self.slope, i) + i01 * y1 + i11 * h * knot(&self.slope, i + 1)
    }
}

/// The folding branch of a hysteretic curve spring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fold<T> {
    /// No hysteresis: folding follows the unfolding curve.
    SameAsUnfold,
    /// A curve of its own.
    Curve(Curve<T>),
    /// Seed 001 tape spring: piecewise linear `knee` below `above_deg`, the
    /// unfolding curve from there on (`docs/spec/physics.md` 3.2).
    Knee {
        /// (0, 0), (θ_A, A), (θ_B', U(θ_B')), linear.
        knee: Curve<T>,
        /// θ_B' \[deg\].
        above_deg: T,
    },
}

/// The points of one tape-spring type, seed 001 Table 1 (deg, N·m per hinge).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TapePoints<T> {
    /// Snap-through peak A on folding.
    pub a: (T, T),
    /// Point B where folding and unfolding meet.
    pub b: (T, T),
    /// Peak D on unfolding.
    pub d: (T, T),
    /// Moment at 90°.
    pub m_90: T,
    /// Moment at 180°.
    pub c_180: T,
}

/// A hinge spring of one joint (all its hinges together).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Spring<T> {
    /// No spring.
    None,
    /// `T(|φ|) = count · (T0 + k |φ|)` (seed 000, `physics.md` 3.1).
    Linear {
        /// Preload at the deployed angle, per hinge [N·m].
        preload_nm: T,
        /// Stiffness per hinge [N·m/rad].
        stiffness_nm_per_rad: T,
        /// Number of identical hinges.
        count: T,
    },
    /// A tabulated moment–rotation curve with optional hysteresis.
    Curve {
        /// Unfolding branch `U` (deg → N·m per hinge).
        unfold: Curve<T>,
        /// Folding branch `F`.
        fold: Fold<T>,
        /// Number of identical hinges.
        count: T,
    },
}

impl<T: Real> Spring<T> {
    /// The seed 001 tape-spring hinge of `physics.md` 3.2: `U` is the Akima
    /// spline through (0,0), D, B, (90, M), (180, C); `F` is linear through
    /// (0,0), A, (θ_B', U(θ_B')) with θ_B' = max(θ_B, θ_A + 0.02°), then `U`.
    pub fn tape(p: &TapePoints<T>, count: T) -> Result<Self, CurveError> {
        let unfold = Curve::new(
            &[
                (T::ZERO, T::ZERO),
                p.d,
                p.b,
                (T::of(90.0), p.m_90),
                (T::of(180.0), p.c_180),
            ],
            Interp::Akima,
        )?;
        let above = p.b.0.max(p.a.0 + T::of(0.02));
        let knee = Curve::new(
            &[(T::ZERO, T::ZERO), p.a, (above, unfold.eval(above))],
            Interp::Linear,
        )?;
        Ok(Spring::Curve {
            unfold,
            fold: Fold::Knee {
                knee,
                above_deg: above,
            },
            count,
        })
    }

    /// True when folding and unfolding differ (the branch matters).
    pub(crate) fn has_hysteresis(&self) -> bool {
        matches!(
            self,
            Spring::Curve {
                fold: Fold::Curve(_) | Fold::Knee { .. },
                ..
            }
        )
    }

    /// The angle \[rad\] below which folding and unfolding differ: `None`
    /// without hysteresis, θ_B' for a tape spring, `T::MAX` for a curve with
    /// a fold branch of its own. Above it a branch switch is smooth.
    pub fn hysteresis_below_rad(&self) -> Option<T> {
        match self {
            Spring::Curve {
                fold: Fold::Knee { above_deg, .. },
                ..
            } => Some(above_deg.to_radians()),
            Spring::Curve {
                fold: Fold::Curve(_),
                ..
            } => Some(T::MAX),
            _ => None,
        }
    }

    /// The magnitude `count · T(|φ|)` [N·m] at `|φ| = abs_rad` on `branch`.
    #[inline]
    pub fn magnitude(&self, abs_rad: T, branch: Branch) -> T {
        match self {
            Spring::None => T::ZERO,
            Spring::Linear {
                preload_nm,
                stiffness_nm_per_rad,
                count,
            } => *count * (*preload_nm + *stiffness_nm_per_rad * abs_rad),
            Spring::Curve {
                unfold,
                fold,
                count,
            } => {
                let deg = abs_rad.to_degrees();
                let m = match (branch, fold) {
                    (Branch::Unfold, _) | (Branch::Fold, Fold::SameAsUnfold) => unfold.eval(deg),
                    (Branch::Fold, Fold::Curve(c)) => c.eval(deg),
                    (Branch::Fold, Fold::Knee { knee, above_deg }) => {
                        if deg >= *above_deg {
                            unfold.eval(deg)
                        } else {
                            knee.eval(deg)
                        }
                    }
                };
                *count * m
            }
        }
    }

    /// The spring torque `−sign(φ) · count · T(|φ|, branch)` [N·m].
    #[inline]
    pub fn torque(&self, phi_rad: T, branch: Branch) -> T {
        -phi_rad.signum0() * self.magnitude(phi_rad.abs(), branch)
    }

    /// Energy the spring releases on the unfolding branch between `|φ| = a`
    /// and `|φ| = b` radians (0 ≤ a ≤ b): `∫_a^b count·T(θ) dθ` \[J\].
    /// `E_D` of seed 000 Eq. 17 is `release(0, stroke)`.
    pub fn release(&self, a_rad: T, b_rad: T) -> T {
        if !(b_rad > a_rad) {
            return T::ZERO;
        }
        match self {
            Spring::None => T::ZERO,
            Spring::Linear {
                preload_nm: t0,
                stiffness_nm_per_rad: k,
                count: n,
            } => *n * (*t0 * (b_rad - a_rad) + T::of(0.5) * *k * (b_rad * b_rad - a_rad * a_rad)),
            Spring::Curve { unfold, count, .. } => {
                let deg_to_rad = T::PI / T::of(180.0);
                *count * unfold.integral(a_rad.to_degrees(), b_rad.to_degrees()) * deg_to_rad
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ts1() -> Spring<f64> {
        Spring::tape(
            &TapePoints {
                a: (1.10, 69.39),
                b: (1.10, 1.50),
                d: (0.52, 37.0),
                m_90: 1.20,
                c_180: 2.32,
            },
            1.0,
        )
        .unwrap()
    }

    #[test]
    fn tape_passes_through_its_points_and_clamps() {
        let s = ts1();
        let r = |d: f64| d.to_radians();
        assert!((s.magnitude(r(0.52), Branch::Unfold) - 37.0).abs() < 1e-9);
        assert!((s.magnitude(r(1.10), Branch::Unfold) - 1.50).abs() < 1e-9);
        assert!((s.magnitude(r(90.0), Branch::Unfold) - 1.20).abs() < 1e-9);
        assert!((s.magnitude(r(180.0), Branch::Unfold) - 2.32).abs() < 1e-9);
        assert!((s.magnitude(r(250.0), Branch::Unfold) - 2.32).abs() < 1e-12);
        // Folding: linear knee up to θ_B' = 1.12°, through A.
        assert!((s.magnitude(r(1.10), Branch::Fold) - 69.39).abs() < 1e-9);
        assert!((s.magnitude(r(0.55), Branch::Fold) - 69.39 / 2.0).abs() < 1e-9);
        // Above the knee both branches agree.
        assert_eq!(
            s.magnitude(r(45.0), Branch::Fold),
            s.magnitude(r(45.0), Branch::Unfold)
        );
        // Restoring: the torque points towards φ = 0.
        assert!(s.torque(r(-30.0), Branch::Unfold) > 0.0);
        assert!(s.torque(r(30.0), Branch::Unfold) < 0.0);
        assert_eq!(s.torque(0.0, Branch::Unfold), 0.0);
    }

    #[test]
    fn akima_matches_scipy() {
        // scipy 1.17.1: Akima1DInterpolator([0, .52, 1.1, 90, 180],
        // [0, 37, 1.5, 1.2, 2.32], method="akima") at these abscissae.
        let s = ts1();
        let cases = [
            (0.3, 31.527452452425372),
            (0.8, 18.71855388396614),
            (10.0, 1.4045735927600937),
            (45.0, 1.0960456704612322),
            (135.0, 1.6709720120116682),
        ];
        for (deg, want) in cases {
            let got = s.magnitude(deg.to_radians(), Branch::Unfold);
            assert!((got - want).abs() < 1e-9, "{deg}: {got} vs {want}");
        }
    }

    #[test]
    fn release_integrates_the_curve() {
        let s = ts1();
        // Trapezoid check with a fine grid.
        let (a, b) = (0.2f64.to_radians(), 120f64.to_radians());
        let n = 200_000;
        let h = (b - a) / n as f64;
        let mut acc = 0.0;
        for i in 0..n {
            let x0 = a + i as f64 * h;
            acc +=
                0.5 * h * (s.magnitude(x0, Branch::Unfold) + s.magnitude(x0 + h, Branch::Unfold));
        }
        assert!((s.release(a, b) - acc).abs() < 1e-6 * acc.abs());
        let lin = Spring::Linear {
            preload_nm: 1.41799,
            stiffness_nm_per_rad: 0.478740,
            count: 1.0,
        };
        // Seed 000 Table 10: E_D = 2.818 J over 90°.
        assert!((lin.release(0.0, core::f64::consts::FRAC_PI_2) - 2.818).abs() < 1e-3);
    }

    #[test]
    fn bad_curves_are_errors() {
        assert_eq!(
            Curve::<f64>::new(&[(0.0, 1.0)], Interp::Akima),
            Err(CurveError::TooFewKnots)
        );
        assert_eq!(
            Curve::<f64>::new(&[(0.0, 1.0), (0.0, 2.0)], Interp::Akima),
            Err(CurveError::NotIncreasing)
        );
        assert_eq!(
            Curve::<f64>::new(&[(0.0, f64::NAN), (1.0, 2.0)], Interp::Linear),
            Err(CurveError::NotFinite)
        );
    }
}
