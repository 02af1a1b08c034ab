//! The stowed side of a joint: the format's `stowed_deg` is where a
//! joint's stroke starts and names no stop there (`docs/spec/physics.md`
//! §5: "there is no contact with the bus or between panels"), so a joint
//! pushed back by its neighbours swings past its stowed angle — a panel
//! through a panel, or a root panel into the body. The run is not refused
//! (the contract's own seed 001 T02 does it, joint 1 to about −100°); it is
//! never silent either: the integrators watch every accepted step with
//! [`StowedWatch`] and the run carries what it found
//! ([`crate::simulate::trajectory::Trajectory::past_stowed`]), which
//! `simulate` prints (`docs/simulator.md`, "The stowed side").

use crate::model::torque_table::HostChain;
use crate::simulate::ode::{Dense, State};
use std::fmt;

/// How far past its stowed angle a joint may go unreported \[deg\]: half a
/// count of the reference encoder (an AS5047P count is 0.022°), a passage
/// no sensor of the run could show.
pub const STOWED_TOLERANCE_DEG: f64 = 0.01;

/// Bisection steps that locate a turning point or the passage inside one
/// step (a step is at most 0.05 s: 2⁻⁴⁰ of it is far below a µs).
const LOCATE_ITERATIONS: usize = 40;

/// A joint that swung back past its stowed angle by more than
/// [`STOWED_TOLERANCE_DEG`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PastStowed {
    /// The joint, 1-based.
    pub joint: usize,
    /// Its stowed angle \[deg\].
    pub stowed_deg: f64,
    /// When it first went more than [`STOWED_TOLERANCE_DEG`] past it \[s\].
    pub first_s: f64,
    /// Its angle farthest past the stowed angle \[deg\].
    pub farthest_deg: f64,
    /// When it was there \[s\].
    pub farthest_s: f64,
}

impl PastStowed {
    /// How far past its stowed angle the joint went \[deg\] (positive).
    pub fn past_deg(&self) -> f64 {
        (self.farthest_deg - self.stowed_deg).abs()
    }
}

impl fmt::Display for PastStowed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "joint {} swung back past its stowed angle {:.2} deg at {:.6} s, farthest {:.2} deg \
             ({:.2} deg past) at {:.6} s; no stop is modelled on the stowed side \
             (docs/simulator.md, \"The stowed side\")",
            self.joint,
            self.stowed_deg,
            self.first_s,
            self.farthest_deg,
            self.past_deg(),
            self.farthest_s
        )
    }
}

/// Watches the joints of a chain for passages of their stowed angles over
/// the accepted steps of a run.
#[derive(Clone, Debug)]
pub struct StowedWatch<const N: usize> {
    /// Side of each stowed angle: `sign(φ_stowed)`.
    side: [f64; N],
    /// `|φ_stowed|` \[rad\].
    stroke: [f64; N],
    /// What was found so far, per joint.
    found: [Option<PastStowed>; N],
}

impl<const N: usize> StowedWatch<N> {
    /// A watch of `chain`'s joints at their stowed angles.
    pub fn new(chain: &HostChain<N>) -> Self {
        Self::stowed_at(chain.joints().map(|j| j.stowed_rad))
    }

    /// A watch of joints stowed at `stowed` \[rad\].
    pub fn stowed_at(stowed: [f64; N]) -> Self {
        StowedWatch {
            side: stowed.map(|s| if s >= 0.0 { 1.0 } else { -1.0 }),
            stroke: stowed.map(f64::abs),
            found: [None; N],
        }
    }

    /// How far joint `j` is past its stowed angle in state `s` \[rad\]
    /// (negative on the stroke).
    fn past(&self, j: usize, s: &State<N>) -> f64 {
        self.side[j] * s.q[j] - self.stroke[j]
    }

    /// Looks at one accepted step `[t0, t1]` of `dense`: for every joint not
    /// in `locked`, its farthest angle on the stowed side (the step's end,
    /// or a turning point inside the step, located on the dense output) and
    /// the instant it first went more than [`STOWED_TOLERANCE_DEG`] past.
    pub fn step(&mut self, dense: &Dense<N>, t0: f64, t1: f64, locked: &[bool; N]) {
        let (a, b) = (dense.at(t0), dense.at(t1));
        let tol = STOWED_TOLERANCE_DEG.to_radians();
        for j in (0..N).filter(|&j| !locked[j]) {
            let outward = |s: &State<N>| self.side[j] * s.v[j];
            // The farthest point of the step: a turning point (outward rate
            // from positive to not) or the end.
            let (tm, um) = if outward(&a) > 0.0 && outward(&b) <= 0.0 {
                let tm = bisect(t0, t1, |t| outward(&dense.at(t)) > 0.0);
                (tm, self.past(j, &dense.at(tm)))
            } else {
                (t1, self.past(j, &b))
            };
            if um <= tol {
                continue;
            }
            let first = match self.found[j] {
                Some(p) => p.first_s,
                None if self.past(j, &a) > tol => t0,
                None => bisect(t0, tm, |t| self.past(j, &dense.at(t)) <= tol),
            };
            self.record(j, um, first, tm);
        }
    }

    /// Looks at the angles `q` \[rad\] at `t` \[s\] alone (an integrator
    /// without a dense output, the rig's: its step ends), joints in
    /// `locked` left out.
    pub fn point(&mut self, t: f64, q: &[f64; N], locked: &[bool; N]) {
        let tol = STOWED_TOLERANCE_DEG.to_radians();
        for j in (0..N).filter(|&j| !locked[j]) {
            let u = self.side[j] * q[j] - self.stroke[j];
            if u <= tol {
                continue;
            }
            self.record(j, u, t, t);
        }
    }

    /// Records joint `j` `u` \[rad\] past its stowed angle at `at` \[s\],
    /// first past at `first` \[s\] unless it was before.
    fn record(&mut self, j: usize, u: f64, first: f64, at: f64) {
        let stowed_deg = (self.side[j] * self.stroke[j]).to_degrees();
        let farthest = (self.side[j] * (self.stroke[j] + u)).to_degrees();
        let found = self.found[j];
        if found.is_some_and(|p| farthest.abs() <= p.farthest_deg.abs()) {
            return;
        }
        self.found[j] = Some(PastStowed {
            joint: j + 1,
            stowed_deg,
            first_s: found.map_or(first, |p| p.first_s),
            farthest_deg: farthest,
            farthest_s: at,
        });
    }

    /// What was found: the joints that passed, in joint order.
    pub fn found(&self) -> Vec<PastStowed> {
        self.found.iter().flatten().copied().collect()
    }
}

/// The instant in `[lo, hi]` where `before` stops holding (it holds at
/// `lo`, not at `hi`), by bisection.
fn bisect(mut lo: f64, mut hi: f64, before: impl Fn(f64) -> bool) -> f64 {
    for _ in 0..LOCATE_ITERATIONS {
        let mid = 0.5 * (lo + hi);
        if before(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}
