//! The CLI syntax of a sensor fault (`KIND:key=value:...`,
//! `docs/robustness.md`): read by `FromStr`, written by `Display`, so that
//! a fault's text reads back as the same fault.

use crate::simulate::fault_injection::*;
use std::fmt;
use std::str::FromStr;

impl fmt::Display for SensorFault {
    /// The CLI syntax, which [`SensorFault::from_str`] reads back.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            SensorFault::Dropout {
                joint,
                start_s,
                duration_s,
                mode,
            } => write!(
                f,
                "dropout:joint={joint}:start={start_s}:duration={duration_s}:mode={}",
                mode.name()
            ),
            SensorFault::Spike {
                joint,
                t_s,
                magnitude_deg,
                samples,
            } => {
                write!(f, "spike:joint={joint}:t={t_s}:magnitude={magnitude_deg}")?;
                if samples != 1 {
                    write!(f, ":samples={samples}")?;
                }
                Ok(())
            }
            SensorFault::StuckAt {
                joint,
                start_s,
                value_deg,
            } => {
                write!(f, "stuck:joint={joint}:start={start_s}")?;
                if let Some(v) = value_deg {
                    write!(f, ":value={v}")?;
                }
                Ok(())
            }
            SensorFault::ParityError { joint, rate, bits } => {
                write!(f, "parity:joint={joint}:rate={rate}")?;
                if bits != 1 {
                    write!(f, ":bits={bits}")?;
                }
                Ok(())
            }
            SensorFault::SwitchChatter { joint, bounce_s } => {
                write!(f, "chatter:joint={joint}:bounce={bounce_s}")
            }
            SensorFault::SwitchStuck { joint, closed } => write!(
                f,
                "switch_stuck:joint={joint}:state={}",
                if closed { "closed" } else { "open" }
            ),
            SensorFault::TimeJitter { sigma_s } => write!(f, "jitter:sigma={sigma_s}"),
            SensorFault::TimeGap {
                start_s,
                duration_s,
            } => write!(f, "gap:start={start_s}:duration={duration_s}"),
        }
    }
}

/// The keys each kind takes: (required, optional).
fn keys_of(kind: &str) -> (&'static [&'static str], &'static [&'static str]) {
    match kind {
        "dropout" => (&["joint", "start", "duration"], &["mode"]),
        "spike" => (&["joint", "t", "magnitude"], &["samples"]),
        "stuck" => (&["joint", "start"], &["value"]),
        "parity" => (&["joint", "rate"], &["bits"]),
        "chatter" => (&["joint", "bounce"], &[]),
        "switch_stuck" => (&["joint", "state"], &[]),
        "jitter" => (&["sigma"], &[]),
        "gap" => (&["start", "duration"], &[]),
        _ => (&[], &[]),
    }
}

impl FromStr for SensorFault {
    type Err = FaultError;

    /// Parses `KIND:key=value:...` (the `--fault` syntax; see the variants).
    /// Checks the parameters but not the joint's existence (that needs the
    /// mechanism: [`SensorFault::validate`]).
    fn from_str(s: &str) -> Result<Self, FaultError> {
        let text = || s.to_string();
        let mut parts = s.split(':');
        let kind_given = parts.next().unwrap_or("").trim();
        let Some(&kind) = KINDS.iter().find(|k| **k == kind_given) else {
            return Err(FaultError::UnknownKind {
                kind: kind_given.to_string(),
                text: text(),
            });
        };
        let a = FaultArgs {
            given: fault_keys(kind, parts, s)?,
            text: s,
        };
        let joint = || a.int("joint", "a joint number from 1");
        let fault = match kind {
            "dropout" => SensorFault::Dropout {
                joint: joint()?,
                start_s: a.num("start")?,
                duration_s: a.num("duration")?,
                mode: match a.get("mode").unwrap_or("missing") {
                    "stale" => DropoutMode::Stale,
                    "missing" => DropoutMode::Missing,
                    _ => return Err(a.bad("mode", "stale or missing")),
                },
            },
            "spike" => SensorFault::Spike {
                joint: joint()?,
                t_s: a.num("t")?,
                magnitude_deg: a.num("magnitude")?,
                samples: match a.get("samples") {
                    Some(_) => a.int("samples", "a number of samples from 1")?,
                    None => 1,
                },
            },
            "stuck" => SensorFault::StuckAt {
                joint: joint()?,
                start_s: a.num("start")?,
                value_deg: a.get("value").map(|_| a.num("value")).transpose()?,
            },
            "parity" => SensorFault::ParityError {
                joint: joint()?,
                rate: a.num("rate")?,
                bits: match a.get("bits") {
                    Some(_) => a.int("bits", "1 to 4 flipped bits")? as u32,
                    None => 1,
                },
            },
            "chatter" => SensorFault::SwitchChatter {
                joint: joint()?,
                bounce_s: a.num("bounce")?,
            },
            "switch_stuck" => SensorFault::SwitchStuck {
                joint: joint()?,
                closed: match a.get("state").unwrap_or("") {
                    "closed" => true,
                    "open" => false,
                    _ => return Err(a.bad("state", "open or closed")),
                },
            },
            "jitter" => SensorFault::TimeJitter {
                sigma_s: a.num("sigma")?,
            },
            _ => SensorFault::TimeGap {
                start_s: a.num("start")?,
                duration_s: a.num("duration")?,
            },
        };
        // Parameters only: any joint from 1 passes here.
        fault.validate(usize::MAX).map_err(|e| FaultError::InText {
            text: text(),
            source: Box::new(e),
        })?;
        Ok(fault)
    }
}

/// The `key=value` parts of one `--fault` text, read as values.
struct FaultArgs<'s> {
    given: Vec<(&'s str, &'s str)>,
    text: &'s str,
}

impl FaultArgs<'_> {
    /// The value of `key`, if given.
    fn get(&self, key: &str) -> Option<&str> {
        self.given.iter().find(|(g, _)| *g == key).map(|(_, v)| *v)
    }

    /// `key`'s value is not `expected`.
    fn bad(&self, key: &'static str, expected: &'static str) -> FaultError {
        FaultError::BadValue {
            key,
            value: self.get(key).unwrap_or("").to_string(),
            expected,
            text: self.text.to_string(),
        }
    }

    /// `key` as a finite number.
    fn num(&self, key: &'static str) -> Result<f64, FaultError> {
        match self.get(key).unwrap_or("").parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(self.bad(key, "a finite number")),
        }
    }

    /// `key` as a non-negative integer (`what` says which).
    fn int(&self, key: &'static str, what: &'static str) -> Result<usize, FaultError> {
        let v = self.get(key).unwrap_or("");
        v.parse::<usize>().map_err(|_| self.bad(key, what))
    }
}

/// The `key=value` parts of a `--fault` text `s` of `kind`: each key known
/// to the kind, given once, every required one given.
fn fault_keys<'s>(
    kind: &'static str,
    parts: impl Iterator<Item = &'s str>,
    s: &str,
) -> Result<Vec<(&'s str, &'s str)>, FaultError> {
    let (required, optional) = keys_of(kind);
    let mut given: Vec<(&str, &str)> = Vec::new();
    for p in parts {
        let (k, v) = p.split_once('=').ok_or_else(|| FaultError::NotKeyValue {
            part: p.to_string(),
            text: s.to_string(),
        })?;
        let (k, v) = (k.trim(), v.trim());
        if !required.contains(&k) && !optional.contains(&k) {
            return Err(FaultError::UnknownKey {
                key: k.to_string(),
                kind,
                allowed: required.iter().chain(optional).copied().collect(),
                text: s.to_string(),
            });
        }
        if given.iter().any(|(g, _)| *g == k) {
            return Err(FaultError::RepeatedKey {
                key: k.to_string(),
                text: s.to_string(),
            });
        }
        given.push((k, v));
    }
    if let Some(&key) = required
        .iter()
        .find(|r| !given.iter().any(|(g, _)| g == *r))
    {
        return Err(FaultError::MissingKey {
            key,
            kind,
            required,
            text: s.to_string(),
        });
    }
    Ok(given)
}
