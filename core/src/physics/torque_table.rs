//! The `torque_table` effect (`docs/spec/physics.md` section 6): an extra
//! joint torque of a form no named effect has, given as tables.
//!
//! ```text
//! τ_table(φ, φ̇) = f(φ_deg) + g(φ̇_deg_s)        [N·m]
//! ```
//!
//! `f` and `g` are piecewise linear through their points and held constant
//! beyond the end points; either may be absent (zero). The sign is that of
//! every joint torque: positive increases `φ`. A diagnosis that discovers a
//! torque the vocabulary lacks reports it in this form.
//!
//! Tables are fixed-size so that the chain stays heap-free: a table holds
//! at most `K` points, a const parameter. The on-board monitor's chain
//! uses the default, [`TABLE_MAX_KNOTS`]; the host simulator evaluates
//! larger tables with the same code (its own `K`), and a table for the
//! monitor is a compressed export of it.

use crate::physics::real::Real;

/// Most points of one table on the monitor (the default `K` of [`Table`],
/// [`TorqueTable`] and the chain): eight keep `JointEffects` small enough
/// for the monitor's RAM budget (`tests/monitor/footprint.rs`).
pub const TABLE_MAX_KNOTS: usize = 8;

/// Why a table was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum TableError {
    /// Fewer than two points.
    TooFewPoints,
    /// More points than the table holds (its `K`, [`TABLE_MAX_KNOTS`] on
    /// the monitor).
    TooManyPoints,
    /// Abscissae are not strictly increasing.
    NotIncreasing,
    /// A point is NaN or infinite.
    NotFinite,
}

impl core::fmt::Display for TableError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            TableError::TooFewPoints => "a torque table needs at least 2 points",
            TableError::TooManyPoints => "a torque table has more points than it holds",
            TableError::NotIncreasing => "torque table abscissae must be strictly increasing",
            TableError::NotFinite => "torque table points must be finite numbers",
        })
    }
}

impl core::error::Error for TableError {}

/// A piecewise-linear table `y(x)` of at most `K` points, clamped to its
/// end values outside its points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Table<T, const K: usize = TABLE_MAX_KNOTS> {
    len: usize,
    x: [T; K],
    y: [T; K],
}

impl<T: Real, const K: usize> Table<T, K> {
    /// A table through `xs` (strictly increasing) and `ys` (same length).
    pub fn new(xs: &[T], ys: &[T]) -> Result<Self, TableError> {
        let n = xs.len();
        if n < 2 || ys.len() != n {
            return Err(TableError::TooFewPoints);
        }
        if n > K {
            return Err(TableError::TooManyPoints);
        }
        let mut t = Table {
            len: n,
            x: [T::ZERO; K],
            y: [T::ZERO; K],
        };
        for i in 0..n {
            if !xs[i].is_finite() || !ys[i].is_finite() {
                return Err(TableError::NotFinite);
            }
            if i > 0 && !(xs[i] > xs[i - 1]) {
                return Err(TableError::NotIncreasing);
            }
            t.x[i] = xs[i];
            t.y[i] = ys[i];
        }
        Ok(t)
    }

    /// The abscissae.
    pub fn xs(&self) -> &[T] {
        self.x.get(..self.len).unwrap_or(&[])
    }

    /// The values.
    pub fn ys(&self) -> &[T] {
        self.y.get(..self.len).unwrap_or(&[])
    }

    /// `y(x)`: linear between points, the end value beyond them.
    #[inline]
    pub fn eval(&self, x: T) -> T {
        let (xs, ys) = (self.xs(), self.ys());
        let (Some(&x0), Some(&y0)) = (xs.first(), ys.first()) else {
            return T::ZERO;
        };
        if !(x > x0) {
            return y0;
        }
        // No indexing: every access is proven in bounds, so the sample path
        // links no panic (`scripts/firmware.sh panic-check`).
        for (xw, yw) in xs.windows(2).zip(ys.windows(2)) {
            let (&[xa, xb], &[ya, yb]) = (xw, yw) else {
                continue;
            };
            if x < xb {
                let s = (x - xa) / (xb - xa);
                return ya + s * (yb - ya);
            }
        }
        ys.last().copied().unwrap_or(T::ZERO)
    }
}

/// The `torque_table` of one joint: `f(φ)` over the angle [deg → N·m] and
/// `g(φ̇)` over the rate [deg/s → N·m], either or both, each of at most `K`
/// points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorqueTable<T, const K: usize = TABLE_MAX_KNOTS> {
    /// `f`: torque [N·m] against the joint angle \[deg\].
    pub angle: Option<Table<T, K>>,
    /// `g`: torque [N·m] against the joint rate [deg/s].
    pub rate: Option<Table<T, K>>,
}

impl<T, const K: usize> Default for TorqueTable<T, K> {
    /// No table: zero torque.
    fn default() -> Self {
        TorqueTable {
            angle: None,
            rate: None,
        }
    }
}

impl<T: Real, const K: usize> TorqueTable<T, K> {
    /// `f(φ) + g(φ̇)` [N·m] at angle `phi` \[rad\] and rate `phi_dot` [rad/s].
    #[inline]
    pub fn torque(&self, phi: T, phi_dot: T) -> T {
        let mut t = T::ZERO;
        if let Some(f) = &self.angle {
            t += f.eval(phi.to_degrees());
        }
        if let Some(g) = &self.rate {
            t += g.eval(phi_dot.to_degrees());
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn given_a_table_when_evaluated_then_linear_inside_and_held_outside() {
        let t = Table::<f64>::new(&[-90.0, -45.0, 0.0], &[0.0, 0.4, 0.1]).unwrap();
        assert_eq!(t.eval(-120.0), 0.0);
        assert!((t.eval(-67.5) - 0.2).abs() < 1e-12);
        assert!((t.eval(-22.5) - 0.25).abs() < 1e-12);
        assert_eq!(t.eval(10.0), 0.1);
        assert_eq!(t.eval(f64::NAN), 0.0);
    }

    #[test]
    fn given_bad_points_then_a_named_error() {
        assert_eq!(
            Table::<f64>::new(&[1.0], &[1.0]),
            Err(TableError::TooFewPoints)
        );
        assert_eq!(
            Table::<f64>::new(&[1.0, 1.0], &[1.0, 2.0]),
            Err(TableError::NotIncreasing)
        );
        assert_eq!(
            Table::<f64>::new(&[0.0, f64::NAN], &[1.0, 2.0]),
            Err(TableError::NotFinite)
        );
        assert_eq!(
            Table::<f64>::new(&[0.0; 9], &[0.0; 9]),
            Err(TableError::TooManyPoints)
        );
    }

    #[test]
    fn given_a_larger_capacity_then_more_points_and_the_same_evaluation() {
        let xs: [f64; 16] = core::array::from_fn(|i| i as f64 * 10.0);
        let ys: [f64; 16] = core::array::from_fn(|i| (i % 3) as f64);
        let big = Table::<f64, 16>::new(&xs, &ys).unwrap();
        assert_eq!(big.xs().len(), 16);
        assert!((big.eval(15.0) - 1.5).abs() < 1e-12);
        assert_eq!(big.eval(200.0), 0.0);
        assert_eq!(
            Table::<f64, 16>::new(&[0.0; 17], &[0.0; 17]),
            Err(TableError::TooManyPoints)
        );
        let small = Table::<f64>::new(&xs[..8], &ys[..8]).unwrap();
        for x in [-5.0, 12.5, 33.0, 70.0, 68.0] {
            assert_eq!(small.eval(x), big.eval(x));
        }
    }

    #[test]
    fn given_angle_and_rate_tables_then_the_torques_add() {
        let tt = TorqueTable {
            angle: Some(Table::<f64>::new(&[-90.0, 0.0], &[1.0, 1.0]).unwrap()),
            rate: Some(Table::<f64>::new(&[0.0, 100.0], &[0.0, -1.0]).unwrap()),
        };
        let t = tt.torque(-0.5, 50f64.to_radians());
        assert!((t - 0.5).abs() < 1e-12);
    }
}
