//! Failure criteria, their failure modes (one per criterion and joint) and
//! the margin of each mode (failure iff margin ≤ 0), from the [`Outcome`]
//! of one deployment.
//!
//! A wing is a series system: it fails when any joint fails any criterion.
//! Each (criterion, joint) pair is a [`Mode`] with its own margin, which
//! falls as *that joint's* deployment gets worse; the estimators search the
//! failure domain of every mode (the levels of subset simulation follow one
//! mode at a time, FORM finds one design point per mode). A single
//! `min` over the joints is not used to steer the search: on seed 001 T01
//! more friction at joint 2 makes joint 1 latch *earlier*, so a minimum of
//! time slacks rises first and the levels went the wrong way
//! (docs/reliability.md §8).
//!
//! Margins, `T` the mechanism's `duration_s`, `t_e` where the run stopped:
//!
//! - `not_latched`, joint j: latched at `t_j`: `m = T − t_j` \[s\], the time
//!   still left (→ 0 when it latches just at `T`); not latched:
//!   `m = −T |φ_j(t_e)| / |φ_j(0)|`, minus the fraction of its stroke still
//!   to go, in seconds of the run (→ 0 when it stops just at the latch). It
//!   falls monotonically with the joint's friction, or with a weaker
//!   spring: the joint latches later, then stops further from its latch.
//! - `not_held`, joint j: as `not_latched` with `t_j` the instant its
//!   latch last came to hold it, `None` when it does not hold it at the
//!   end: a ball plunger past its crest (since its last inward pass), a
//!   pawl in its notch (since its drop), whatever the switch reads; an
//!   ideal latch: its latch instant.
//! - `time>X`, joint j: latched at `t_j`: `m = X − t_j`; not latched by
//!   `t_e`: `m = X − t_e − t_e |φ_j(t_e)| / |φ_j(0)|` (continuous at a latch
//!   just at `t_e`).
//! - `latch_rate>X`, joint j: latched: `m = X − |ω_j|` [deg/s], `ω_j` the
//!   rate just before its latch; not latched: `X` (no impact).
//!
//! The system's margin is the smallest of its modes'.

use std::fmt;
use std::str::FromStr;

/// One failure criterion (`--fail`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Criterion {
    /// `not_latched`: some joint not latched within `duration_s` (a
    /// physical latch: its switch open at the end).
    NotLatched,
    /// `not_held`: some joint not held by its latch at the end (a ball
    /// plunger short of its crest, a pawl out of its notch or broken),
    /// whatever its switch reads; with an ideal latch, `not_latched`.
    NotHeld,
    /// `latch_rate>X`: some joint's rate at its latch above `X` [deg/s].
    LatchRateAbove(f64),
    /// `time>X`: the deployment (last latch) later than `X` \[s\].
    TimeAbove(f64),
}

/// Why a failure criterion was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "{0}: expected not_latched, latch_rate>X (deg/s), time>X (s) (X a positive number) or not_held"
)]
pub struct CriterionError(pub String);

impl FromStr for Criterion {
    type Err = CriterionError;
    fn from_str(s: &str) -> Result<Self, CriterionError> {
        let bad = || CriterionError(s.to_string());
        let t = s.trim();
        if t == "not_latched" {
            return Ok(Criterion::NotLatched);
        }
        if t == "not_held" {
            return Ok(Criterion::NotHeld);
        }
        let (name, x) = t.split_once('>').ok_or_else(bad)?;
        let x: f64 = x.trim().parse().map_err(|_| bad())?;
        if !(x > 0.0 && x.is_finite()) {
            return Err(bad());
        }
        match name.trim() {
            "latch_rate" => Ok(Criterion::LatchRateAbove(x)),
            "time" => Ok(Criterion::TimeAbove(x)),
            _ => Err(bad()),
        }
    }
}

impl Criterion {
    /// The unit of its modes' margins: `s` (`not_latched`, `not_held`,
    /// `time>X`) or `deg/s` (`latch_rate>X`).
    pub fn margin_unit(self) -> &'static str {
        match self {
            Criterion::NotLatched | Criterion::NotHeld | Criterion::TimeAbove(_) => "s",
            Criterion::LatchRateAbove(_) => "deg/s",
        }
    }
}

impl fmt::Display for Criterion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Criterion::NotLatched => f.write_str("not_latched"),
            Criterion::NotHeld => f.write_str("not_held"),
            Criterion::LatchRateAbove(x) => write!(f, "latch_rate>{x}"),
            Criterion::TimeAbove(x) => write!(f, "time>{x}"),
        }
    }
}

/// One failure mode: a criterion at one joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mode {
    /// The criterion.
    pub criterion: Criterion,
    /// The joint, 0-based.
    pub joint: usize,
}

impl fmt::Display for Mode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} at joint {}", self.criterion, self.joint + 1)
    }
}

/// The modes of some criteria on a mechanism of `joints` joints, criterion
/// by criterion, joint by joint.
pub fn modes(criteria: &[Criterion], joints: usize) -> Vec<Mode> {
    criteria
        .iter()
        .flat_map(|&criterion| (0..joints).map(move |joint| Mode { criterion, joint }))
        .collect()
}

/// What one deployment did, per joint.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Latch instant \[s\], `None` if not latched when the run stopped.
    pub latch_s: Vec<Option<f64>>,
    /// The instant the joint's latch last came to hold it \[s\], `None`
    /// if it does not hold it when the run stopped (`not_held`; an ideal
    /// latch's is its latch instant).
    pub held_s: Vec<Option<f64>>,
    /// Angular rate just before the latch [deg/s] (extrapolated from the
    /// last two samples before it to the latch instant), `None` if not
    /// latched or not sampled (no `latch_rate>X` criterion).
    pub latch_rate_deg_s: Vec<Option<f64>>,
    /// Angle where the run stopped \[deg\] (0 when latched).
    pub end_deg: Vec<f64>,
    /// Stowed angle \[deg\].
    pub stowed_deg: Vec<f64>,
    /// Where the run stopped \[s\] (`t_e`).
    pub end_s: f64,
    /// The mechanism's `duration_s` \[s\] (`T`).
    pub duration_s: f64,
}

impl Outcome {
    /// The fraction of joint `j`'s stroke still to go.
    fn to_go(&self, j: usize) -> f64 {
        self.end_deg[j].abs() / self.stowed_deg[j].abs().max(f64::MIN_POSITIVE)
    }

    /// `not_latched`'s margin of joint `j` with `at` its latch instant:
    /// the time still left, or minus the stroke still to go in seconds.
    fn time_left(&self, j: usize, at: Option<f64>) -> f64 {
        match at {
            Some(t) => (self.duration_s - t).max(0.0),
            None => -self.duration_s * self.to_go(j),
        }
    }

    /// The margin of one mode (failed iff ≤ 0), module doc.
    pub fn margin(&self, m: Mode) -> f64 {
        let j = m.joint;
        let latched = self.latch_s[j];
        match m.criterion {
            Criterion::NotLatched => self.time_left(j, latched),
            Criterion::NotHeld => self.time_left(j, self.held_s[j]),
            Criterion::TimeAbove(x) => match latched {
                Some(t) => x - t,
                None => x - self.end_s - self.end_s * self.to_go(j),
            },
            Criterion::LatchRateAbove(x) => match (latched, self.latch_rate_deg_s[j]) {
                (Some(_), Some(w)) => x - w.abs(),
                _ => x,
            },
        }
    }

    /// The margins of the modes, in order.
    pub fn margins(&self, modes: &[Mode]) -> Vec<f64> {
        modes.iter().map(|&m| self.margin(m)).collect()
    }

    /// The system's margin: the smallest over the modes of the criteria
    /// (any one fails).
    pub fn g(&self, criteria: &[Criterion]) -> f64 {
        modes(criteria, self.latch_s.len())
            .into_iter()
            .map(|m| self.margin(m))
            .fold(f64::INFINITY, f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_scores() {
        assert_eq!("not_latched".parse(), Ok(Criterion::NotLatched));
        assert_eq!(" not_held ".parse(), Ok(Criterion::NotHeld));
        assert_eq!(Criterion::NotHeld.to_string(), "not_held");
        assert_eq!("latch_rate>40".parse(), Ok(Criterion::LatchRateAbove(40.0)));
        assert_eq!("time > 2.5".parse(), Ok(Criterion::TimeAbove(2.5)));
        assert!("time>-1".parse::<Criterion>().is_err());
        assert!("latched".parse::<Criterion>().is_err());
        let o = Outcome {
            latch_s: vec![Some(1.0), None],
            held_s: vec![Some(1.0), None],
            latch_rate_deg_s: vec![Some(30.0), None],
            end_deg: vec![0.0, -4.0],
            stowed_deg: vec![90.0, -180.0],
            end_s: 10.0,
            duration_s: 10.0,
        };
        let ms = modes(&[Criterion::NotLatched], 2);
        assert_eq!(o.margins(&ms), vec![9.0, -10.0 * (4.0 / 180.0)]);
        assert_eq!(o.g(&[Criterion::NotLatched]), -10.0 * (4.0 / 180.0));
        assert_eq!(o.g(&[Criterion::LatchRateAbove(40.0)]), 10.0);
        assert_eq!(
            o.g(&[Criterion::TimeAbove(5.0)]),
            5.0 - 10.0 - 10.0 * (4.0 / 180.0)
        );
        let ok = Outcome {
            latch_s: vec![Some(1.0), Some(2.0)],
            held_s: vec![Some(1.0), Some(2.0)],
            latch_rate_deg_s: vec![Some(30.0), Some(-50.0)],
            end_deg: vec![0.0, 0.0],
            stowed_deg: vec![90.0, -180.0],
            end_s: 2.0,
            duration_s: 10.0,
        };
        assert_eq!(ok.g(&[Criterion::NotLatched]), 8.0);
        assert_eq!(
            ok.g(&[Criterion::NotLatched, Criterion::LatchRateAbove(40.0)]),
            -10.0
        );
        assert_eq!(ok.g(&[Criterion::TimeAbove(5.0)]), 3.0);
        // A switch open at the end over a latch that holds: not_latched
        // fails, not_held does not (joint 2 held since 3 s).
        let rattling = Outcome {
            held_s: vec![Some(1.0), Some(3.0)],
            ..o.clone()
        };
        assert!(rattling.g(&[Criterion::NotLatched]) < 0.0);
        assert_eq!(rattling.g(&[Criterion::NotHeld]), 7.0);
        // Held but the switch closed: the same margins as not_latched's.
        assert_eq!(o.g(&[Criterion::NotHeld]), o.g(&[Criterion::NotLatched]));
        let m = modes(&[Criterion::NotLatched, Criterion::TimeAbove(5.0)], 2);
        assert_eq!(m.len(), 4);
        assert_eq!(m[3].to_string(), "time>5 at joint 2");
    }

    #[test]
    fn a_latch_just_before_the_end_and_a_stop_just_short_meet_at_zero() {
        let at = |latch: Option<f64>, end: f64| Outcome {
            latch_s: vec![latch],
            held_s: vec![latch],
            latch_rate_deg_s: vec![None],
            end_deg: vec![end],
            stowed_deg: vec![90.0],
            end_s: 4.0,
            duration_s: 4.0,
        };
        let nl = Mode {
            criterion: Criterion::NotLatched,
            joint: 0,
        };
        let tm = Mode {
            criterion: Criterion::TimeAbove(3.0),
            joint: 0,
        };
        let (a, b) = (at(Some(4.0 - 1e-9), 0.0), at(None, 1e-7));
        assert!(a.margin(nl) > 0.0 && b.margin(nl) < 0.0);
        assert!((a.margin(nl) - b.margin(nl)).abs() < 1e-8);
        assert!((a.margin(tm) - b.margin(tm)).abs() < 1e-8);
    }
}
