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
    /// above (±∞ beyond the first and last). On a knot, the piece the joint
    /// moves into: below it when `|φ|` is `falling`, above it otherwise.
    /// (A piece whose bound the joint sits on is never left by the event
    /// search, which fires only when `inside` goes from positive to zero or
    /// below: the piece behind a falling `|φ|` would keep every knot below
    /// from stopping a step.)
    pub fn around(&self, abs_rad: f64, falling: bool) -> (f64, f64) {
        let knots = &self.at[..self.len];
        let i = match falling {
            true => knots.partition_point(|&k| k < abs_rad),
            false => knots.partition_point(|&k| k <= abs_rad),
        };
        self.piece_below(i)
    }

    /// The piece past the bound of `(lo, hi)` that `|φ| = abs_rad` reached
    /// at a knot event: the one below `lo` when `abs_rad` is nearer `lo`,
    /// the one above `hi` otherwise. It does not depend on which side of
    /// the knot the event's root fell by a rounding.
    pub fn past(&self, (lo, hi): (f64, f64), abs_rad: f64) -> (f64, f64) {
        let knots = &self.at[..self.len];
        match abs_rad - lo <= hi - abs_rad {
            true => self.piece_below(knots.partition_point(|&k| k < lo)),
            false => self.piece_below(knots.partition_point(|&k| k <= hi)),
        }
    }

    /// The piece between the knots `i − 1` and `i` (±∞ past the ends).
    fn piece_below(&self, i: usize) -> (f64, f64) {
        let knots = &self.at[..self.len];
        let lo = match i.checked_sub(1).and_then(|k| knots.get(k)) {
            Some(&k) => k,
            None => f64::NEG_INFINITY,
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

    /// Seed 001's TS-1 tape spring, two of them (`physics.md` 3.2).
    fn ts1() -> Spring<f64> {
        let ts1 = TapePoints {
            a: (1.10, 69.39),
            b: (1.10, 1.50),
            d: (0.52, 37.0),
            m_90: 1.20,
            c_180: 2.32,
        };
        Spring::tape(&ts1, 2.0).expect("TS-1")
    }

    /// TS-1's knots: the unfolding branch stops at D and B and 90°; the
    /// folding branch at A and θ_B' on its knee, then at 90° on the
    /// unfolding curve; a linear spring nowhere.
    #[test]
    fn a_tape_springs_knots_are_its_branchs_interior_points() {
        let s = ts1();
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
        assert_eq!(u.around(0.0, true), (f64::NEG_INFINITY, d));
        assert_eq!(u.around(0.01, false), (d, b));
        assert_eq!(u.around(0.01, true), (d, b));
        assert_eq!(u.around(d, false), (d, b), "on a knot rising: above it");
        assert_eq!(
            u.around(d, true),
            (f64::NEG_INFINITY, d),
            "falling: below it"
        );
        assert_eq!(u.around(3.2, true).1, f64::INFINITY);
        assert!(inside(0.011, (d, b)) > 0.0 && inside(0.02, (d, b)) < 0.0);
    }

    /// A knot event's root falls on either side of the knot by a rounding;
    /// the piece after it is the one past the knot either way, below it
    /// when `|φ|` came down to it (the panel unfolding), above it when it
    /// came up.
    #[test]
    fn the_piece_past_a_knot_does_not_depend_on_the_side_of_its_root() {
        let u = Knots::of(&ts1(), Branch::Unfold);
        let [d, b, n] = [0.52f64, 1.10, 90.0].map(f64::to_radians);
        let near = |k: f64| [k, k * (1.0 + 1e-15), k * (1.0 - 1e-15)];
        for abs in near(n) {
            assert_eq!(
                u.past((n, f64::INFINITY), abs),
                (b, n),
                "down through 90° at {abs}"
            );
        }
        for abs in near(b) {
            assert_eq!(u.past((b, n), abs), (d, b), "down through B at {abs}");
            assert_eq!(u.past((d, b), abs), (b, n), "up through B at {abs}");
        }
        for abs in near(d) {
            assert_eq!(
                u.past((d, b), abs),
                (f64::NEG_INFINITY, d),
                "down through D at {abs}"
            );
        }
        // Each piece past a knot is a piece of the curve, with the knot
        // reached as its bound.
        for (piece, abs) in [((b, n), b), ((d, b), b), ((b, n), n), ((d, b), d)] {
            let next = u.past(piece, abs);
            assert!(
                next.0 == abs || next.1 == abs,
                "{piece:?} at {abs}: {next:?}"
            );
            assert_eq!(
                u.around((next.0.max(0.0) + next.1.min(4.0)) / 2.0, true),
                next
            );
        }
    }

    /// Each knot a deploying joint passes ends a step: seed 001 T01, each
    /// tape-spring joint unfolding from its stowed angle to its latch,
    /// stops at least once on every knot of its unfolding curve below its
    /// stowed angle, at the reliability verdicts' tolerance and 24 draws
    /// of its friction. Which side of a knot an event's root falls on is a
    /// rounding, so it takes several draws to see a piece left behind:
    /// with the piece found as if `|φ|` rose, the third draw stops on 6 of
    /// the 8 knots.
    #[test]
    fn every_knot_a_deploying_joint_passes_ends_a_step() {
        use crate::model::effect::Effect;
        use crate::model::mechanism::Mechanism;
        use crate::simulate::deployment::simulate;
        use crate::simulate::trajectory::SimOptions;
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../data/mechanisms/seed001_T01.toml");
        let mech = Mechanism::load(&path).expect("seed 001 T01");
        let chain = mech
            .chain::<3>(&[Default::default(); 3], Default::default())
            .expect("three joints");
        let passed: usize = chain
            .joints()
            .iter()
            .map(|jt| {
                let k = Knots::of(&jt.spring, Branch::Unfold);
                let below = |&&x: &&f64| x < jt.stowed_rad.abs() * (1.0 - 1e-12);
                k.at[..k.len].iter().filter(below).count()
            })
            .sum();
        assert!(
            passed >= 3,
            "T01's springs have knots below their stowed angles"
        );
        // The identified friction of seed 001 T01 (the reliability case of
        // docs/measured.md), each joint's scaled by 0.9 to 1.1.
        for i in 0..24 {
            let scale = |j: usize| 0.9 + 0.2 * (((i * 7 + j * 5) % 24) as f64 / 23.0);
            let effects: Vec<Effect> = [2.63, 1.7, 0.001]
                .iter()
                .enumerate()
                .map(|(j, c)| {
                    let v = c * scale(j);
                    let text = format!("coulomb_friction:joint={}:value={v}", j + 1);
                    text.parse().expect("effect")
                })
                .collect();
            let opts = SimOptions {
                rtol: 1e-6,
                atol: 1e-6,
                ..SimOptions::default()
            };
            let run = simulate(&mech, &effects, &opts).expect("simulates");
            assert!(run.deployed(), "{effects:?}");
            assert!(
                run.stats.knots >= passed,
                "{effects:?}: {} steps ended on a knot, {passed} knots passed",
                run.stats.knots
            );
        }
    }
}
