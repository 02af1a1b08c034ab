//! Failure criteria and their continuous limit-state values `g` (failure
//! iff `g ≤ 0`), from the [`Outcome`] of one deployment.
//!
//! Subset simulation needs `g` to decrease continuously into the failure
//! domain, not a pass/fail flag:
//!
//! - `not_latched`: per joint, latched at `t_j`: `g_j = T − t_j` [s], the
//!   time left of `duration_s = T` (→ 0 when it latches just at `T`); not
//!   latched: `g_j = −T |φ_j(T)| / |φ_j(0)|` [s], minus the fraction of its
//!   stroke still to go, scaled by `T` (→ 0 when it stops just at the latch).
//!   `g = min_j g_j`. Time slack puts every joint on the same scale, so that
//!   the levels of subset simulation follow whichever joint comes closest to
//!   failing (a margin in angle or rate would let the fast joints hide the
//!   slow one).
//! - `latch_rate>X`: `g = X − max_j |ω_j|` [deg/s] over the latched joints
//!   (`X` when none latched).
//! - `time>X`: `g = X − t_last` [s], `t_last` the last latch, `T` when some
//!   joint did not latch (then `X − T < 0`: `X` must be below `T`).
//!
//! With several criteria `g` is the smallest (any one fails).

use std::fmt;
use std::str::FromStr;

/// One failure criterion (`--fail`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Criterion {
    /// `not_latched`: some joint not latched within `duration_s`.
    NotLatched,
    /// `latch_rate>X`: some joint's rate at its latch above `X` [deg/s].
    LatchRateAbove(f64),
    /// `time>X`: the deployment (last latch) later than `X` [s].
    TimeAbove(f64),
}

/// Why a `--fail` was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "--fail {0}: expected not_latched, latch_rate>X (deg/s) or time>X (s), X a positive number"
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

impl fmt::Display for Criterion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Criterion::NotLatched => f.write_str("not_latched"),
            Criterion::LatchRateAbove(x) => write!(f, "latch_rate>{x}"),
            Criterion::TimeAbove(x) => write!(f, "time>{x}"),
        }
    }
}

/// What one deployment did, per joint.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Latch instant [s], `None` if not latched by `duration_s`.
    pub latch_s: Vec<Option<f64>>,
    /// Angular rate just before the latch [deg/s] (extrapolated from the
    /// last two samples before it to the latch instant), `None` if not latched.
    pub latch_rate_deg_s: Vec<Option<f64>>,
    /// Angle at the end [deg] (0 when latched).
    pub end_deg: Vec<f64>,
    /// Angle at the start [deg] (the stowed angle).
    pub stowed_deg: Vec<f64>,
    /// `duration_s` of the run [s].
    pub duration_s: f64,
}

impl Outcome {
    /// The limit-state value of one criterion.
    pub fn g_of(&self, c: Criterion) -> f64 {
        let t_end = self.duration_s;
        match c {
            Criterion::NotLatched => self
                .latch_s
                .iter()
                .zip(&self.end_deg)
                .zip(&self.stowed_deg)
                .map(|((l, end), stowed)| match l {
                    Some(t) => (t_end - t).max(0.0),
                    None => -t_end * end.abs() / stowed.abs().max(f64::MIN_POSITIVE),
                })
                .fold(f64::INFINITY, f64::min),
            Criterion::LatchRateAbove(x) => {
                let w = self
                    .latch_rate_deg_s
                    .iter()
                    .flatten()
                    .map(|w| w.abs())
                    .fold(0.0, f64::max);
                x - w
            }
            Criterion::TimeAbove(x) => {
                let last = if self.latch_s.iter().all(Option::is_some) {
                    self.latch_s.iter().flatten().copied().fold(0.0, f64::max)
                } else {
                    t_end
                };
                x - last
            }
        }
    }

    /// `g = min` over the criteria: failed iff `g ≤ 0`.
    pub fn g(&self, criteria: &[Criterion]) -> f64 {
        criteria
            .iter()
            .map(|&c| self.g_of(c))
            .fold(f64::INFINITY, f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_scores() {
        assert_eq!("not_latched".parse(), Ok(Criterion::NotLatched));
        assert_eq!("latch_rate>40".parse(), Ok(Criterion::LatchRateAbove(40.0)));
        assert_eq!("time > 2.5".parse(), Ok(Criterion::TimeAbove(2.5)));
        assert!("time>-1".parse::<Criterion>().is_err());
        assert!("latched".parse::<Criterion>().is_err());
        let o = Outcome {
            latch_s: vec![Some(1.0), None],
            latch_rate_deg_s: vec![Some(30.0), None],
            end_deg: vec![0.0, -4.0],
            stowed_deg: vec![90.0, -180.0],
            duration_s: 10.0,
        };
        assert_eq!(o.g_of(Criterion::NotLatched), -10.0 * 4.0 / 180.0);
        assert_eq!(o.g_of(Criterion::LatchRateAbove(40.0)), 10.0);
        assert_eq!(o.g_of(Criterion::TimeAbove(5.0)), -5.0);
        let ok = Outcome {
            latch_s: vec![Some(1.0), Some(2.0)],
            latch_rate_deg_s: vec![Some(30.0), Some(-50.0)],
            end_deg: vec![0.0, 0.0],
            stowed_deg: vec![90.0, -180.0],
            duration_s: 10.0,
        };
        assert_eq!(ok.g_of(Criterion::NotLatched), 8.0);
        assert_eq!(
            ok.g(&[Criterion::NotLatched, Criterion::LatchRateAbove(40.0)]),
            -10.0
        );
        assert_eq!(ok.g_of(Criterion::TimeAbove(5.0)), 3.0);
    }
}
