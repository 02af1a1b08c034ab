//! The knots of a tabulated hinge spring as step boundaries of the
//! ideal-latch chain (`deployment.rs`): a spring curve (`physics.md` 3.2:
//! the tape spring's Akima unfolding branch, its piecewise-linear folding
//! knee) is a cubic between its knots with a jump of its second derivative
//! (the knee: of its first) at each, so a DOPRI5 step over a knot makes an
//! error of lower order than the method's, and its energy ledger on
//! Gauss–Legendre nodes likewise. Stopping the step at the knot, located
//! on the dense output like any event, keeps every step on one piece of
//! the curve. The torque is continuous there: no restart, no impulse.

use deploywatch_core::physics::MAX_KNOTS;
use deploywatch_core::{Branch, Curve, Fold, Spring};

/// Most interior knots of one branch: the unfolding curve's and the knee's.
const MAX_INTERIOR: usize = 2 * MAX_KNOTS;

/// The interior knots of one joint's spring on one branch, `|φ|` \[rad\],
/// increasing (the first and last knot of a curve are left out: the
/// latch angle, and the clamp beyond the stowed angle).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Knots {
    at: [f64; MAX_INTERIOR],
    len: usize,
}

impl Knots {
    /// No knots (a linear spring, no spring).
    pub const NONE: Knots = Knots {
        at: [0.0; MAX_INTERIOR],
        len: 0,
    };

    /// The knots of `spring` on `branch`: the curve the branch follows
    /// (the folding knee below its end, the unfolding curve above it).
    pub fn of(spring: &Spring<f64>, branch: Branch) -> Knots {
        let mut k = Knots::NONE;
        let Spring::Curve { unfold, fold, .. } = spring else {
            return k;
        };
        match (branch, fold) {
            (Branch::Unfold, _) | (Branch::Fold, Fold::SameAsUnfold) => {
                k.push_interior(unfold, f64::NEG_INFINITY, f64::INFINITY)
            }
            (Branch::Fold, Fold::Curve(c)) => k.push_interior(c, f64::NEG_INFINITY, f64::INFINITY),
            (Branch::Fold, Fold::Knee { knee, above_deg }) => {
                k.push_interior(knee, f64::NEG_INFINITY, *above_deg);
                k.push(*above_deg);
                k.push_interior(unfold, *above_deg, f64::INFINITY);
            }
        }
        k
    }

    /// Appends the interior knots of `c` strictly between `lo` and `hi`
    /// \[deg\].
    fn push_interior(&mut self, c: &Curve<f64>, lo: f64, hi: f64) {
        for i in 1..c.len().saturating_sub(1) {
            if let Some((x, _)) = c.knot(i) {
                if x > lo && x < hi {
                    self.push(x);
                }
            }
        }
    }

    /// Appends the knot `deg` \[deg\] when above the last and positive.
    fn push(&mut self, deg: f64) {
        let rad = deg.to_radians();
        let above = self.len == 0 || self.at[self.len - 1] < rad;
        if rad > 0.0 && above && self.len < MAX_INTERIOR {
            self.at[self.len] = rad;
            self.len += 1;
        }
    }

    /// The piece of the curve holding `|φ| = abs_rad`: its knots below and
    /// above (±∞ beyond the first and last).
    pub fn around(&self, abs_rad: f64) -> (f64, f64) {
        let knots = &self.at[..self.len];
        let i = knots.partition_point(|&k| k <= abs_rad);
        let lo = if i == 0 {
            f64::NEG_INFINITY
        } else {
            knots[i - 1]
        };
        let hi = knots.get(i).copied().unwrap_or(f64::INFINITY);
        (lo, hi)
    }
}

/// The event function of leaving the piece `(lo, hi)` at `|φ| = abs_rad`:
/// positive inside, zero on a knot \[rad\].
pub fn inside(abs_rad: f64, (lo, hi): (f64, f64)) -> f64 {
    (abs_rad - lo).min(hi - abs_rad)
}

#[cfg(test)]
mod tests {
    use super::*;
    use deploywatch_core::TapePoints;

    /// Seed 001's TS-1 (`physics.md` 3.2): the unfolding branch stops at D
    /// and B and 90°; the folding branch at A and θ_B' on its knee, then
    /// at 90° on the unfolding curve; a linear spring nowhere.
    #[test]
    fn a_tape_springs_knots_are_its_branchs_interior_points() {
        let ts1 = TapePoints {
            a: (1.10, 69.39),
            b: (1.10, 1.50),
            d: (0.52, 37.0),
            m_90: 1.20,
            c_180: 2.32,
        };
        let s = Spring::tape(&ts1, 2.0).expect("TS-1");
        let deg = |k: Knots| -> Vec<f64> {
            k.at[..k.len]
                .iter()
                .map(|r| (r.to_degrees() * 1e9).round() / 1e9)
                .collect()
        };
        assert_eq!(deg(Knots::of(&s, Branch::Unfold)), [0.52, 1.10, 90.0]);
        assert_eq!(deg(Knots::of(&s, Branch::Fold)), [1.10, 1.12, 90.0]);
        let linear = Spring::Linear {
            preload_nm: 1.0,
            stiffness_nm_per_rad: 0.5,
            count: 2.0,
        };
        assert_eq!(Knots::of(&linear, Branch::Unfold), Knots::NONE);
        let u = Knots::of(&s, Branch::Unfold);
        let (d, b) = (0.52f64.to_radians(), 1.10f64.to_radians());
        assert_eq!(u.around(0.0), (f64::NEG_INFINITY, d));
        assert_eq!(u.around(0.01), (d, b));
        assert_eq!(u.around(d), (d, b), "on a knot: the piece above it");
        assert_eq!(u.around(3.2).1, f64::INFINITY);
        assert!(inside(0.011, (d, b)) > 0.0 && inside(0.02, (d, b)) < 0.0);
    }
}
