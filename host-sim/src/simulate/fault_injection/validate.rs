//! The checks of a fault's joint and parameters, each failure saying what
//! was expected.

use super::error::FaultError;
use super::fault::{SensorFault, MAX_BOUNCE_S, TIME_EPS_S};
use crate::data::run::MAX_ANGLE_DEG;

impl SensorFault {
    /// Checks the parameters, and the joint against a run or mechanism of
    /// `joints` joints. The message says what was expected.
    pub fn validate(&self, joints: usize) -> Result<(), FaultError> {
        let kind = self.kind();
        if let Some(joint) = self.joint().filter(|&j| j == 0 || j > joints) {
            return Err(FaultError::NoSuchJoint {
                kind,
                joint,
                joints,
            });
        }
        let p = Params { kind };
        let seconds = "a time in seconds, 0 or more";
        let positive_s = "a positive duration in seconds";
        match *self {
            SensorFault::Dropout {
                start_s,
                duration_s,
                ..
            }
            | SensorFault::TimeGap {
                start_s,
                duration_s,
            } => {
                p.check("start", start_s, start_s >= 0.0, seconds)?;
                p.check("duration", duration_s, duration_s > 0.0, positive_s)
            }
            SensorFault::Spike {
                t_s,
                magnitude_deg,
                samples,
                ..
            } => {
                p.check("t", t_s, t_s >= 0.0, seconds)?;
                let max = 2.0 * MAX_ANGLE_DEG;
                let within = format!("a finite angle in degrees within ±{max}");
                p.check(
                    "magnitude",
                    magnitude_deg,
                    magnitude_deg.abs() <= max,
                    &within,
                )?;
                p.check("samples", samples as f64, samples > 0, "1 or more samples")
            }
            SensorFault::StuckAt {
                start_s, value_deg, ..
            } => {
                p.check("start", start_s, start_s >= 0.0, seconds)?;
                let v = value_deg.unwrap_or(0.0);
                let within =
                    format!("an angle in degrees within ±{MAX_ANGLE_DEG} (what a run file holds)");
                p.check("value", v, v.abs() <= MAX_ANGLE_DEG, &within)
            }
            SensorFault::ParityError { rate, bits, .. } => {
                let fraction = "a fraction of the samples from 0 to 1";
                p.check("rate", rate, (0.0..=1.0).contains(&rate), fraction)?;
                let flips = "1 to 4 flipped bits per corrupted word";
                p.check("bits", f64::from(bits), (1..=4).contains(&bits), flips)
            }
            SensorFault::SwitchChatter { bounce_s, .. } => {
                let ok = bounce_s > 0.0 && bounce_s <= MAX_BOUNCE_S + TIME_EPS_S;
                let expected =
                    format!("a bounce time in seconds, more than 0 and at most {MAX_BOUNCE_S}");
                p.check("bounce", bounce_s, ok, &expected)
            }
            SensorFault::SwitchStuck { .. } => Ok(()),
            SensorFault::TimeJitter { sigma_s } => {
                let expected = "a positive standard deviation in seconds";
                p.check("sigma", sigma_s, sigma_s > 0.0, expected)
            }
        }
    }
}

/// The parameter checks of one fault kind.
struct Params {
    kind: &'static str,
}

impl Params {
    /// `key = value` must be finite and `ok`; the error says `expected`.
    fn check(
        &self,
        key: &'static str,
        value: f64,
        ok: bool,
        expected: &str,
    ) -> Result<(), FaultError> {
        if value.is_finite() && ok {
            Ok(())
        } else {
            Err(FaultError::BadParameter {
                kind: self.kind,
                key,
                value: value.to_string(),
                expected: expected.to_string(),
            })
        }
    }
}
