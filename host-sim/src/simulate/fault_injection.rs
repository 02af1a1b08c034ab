//! Sensor faults injected into a measured run: what a failing encoder, latch
//! switch or clock does to the data the monitor sees (issue 7;
//! `docs/robustness.md` has the model, the syntax and the monitor's
//! contract per fault).
//!
//! A fault is applied to a [`Run`] after [`crate::simulate::sensor::measure`], so the
//! motion is the healthy one and only the readings are wrong: the truth
//! stays available from the [`crate::simulate::deployment::Trajectory`] for scoring the
//! monitor. Every random choice comes from a ChaCha8 generator seeded with
//! the run's seed, one stream per fault (stream `1 + k` for the k-th fault
//! of the list; the sensor noise uses stream 0), so the same seed and the
//! same list give the same run byte for byte, and adding a fault does not
//! change what the others do.
//!
//! # The faults
//! | kind (CLI) | what the run shows |
//! |---|---|
//! | `dropout` | joint `j`'s angle in `[start, start + duration)` repeats the last reading before it (`mode=stale`) or is missing, `NaN` (`mode=missing`) |
//! | `spike` | `samples` readings of joint `j` from the first sample at or after `t` are off by `magnitude` degrees |
//! | `stuck` | joint `j`'s angle from `start` on is `value`, or the last reading before `start` when no value is given |
//! | `parity` | a fraction `rate` of joint `j`'s AS5047P answer words get `bits` bit flips: an odd number breaks the even parity and the driver rejects the reading (missing, `NaN`); an even number passes the parity and gives a wrong angle, unless the error-flag bit was set |
//! | `chatter` | joint `j`'s switch bounces on closing: the sample after the first closed one reads open, then each sample up to `bounce` seconds after the closing reads open or closed at random |
//! | `switch_stuck` | joint `j`'s switch reads `state` (open or closed) for the whole run |
//! | `jitter` | every time stamp but the first is off by a normal error of σ = `sigma` seconds, clipped to ±0.45 of the shortest sample interval so that the times stay increasing |
//! | `gap` | the samples in `[start, start + duration)` are lost: no row at all |
//!
//! Encoder and switch faults are applied in the order given, then the
//! jitter, then the gaps; every window refers to the original time stamps.
//!
//! # Missing samples
//! A missing encoder reading is `NaN` in [`Run::phi_deg`], as in the
//! monitor's `Sample`. A run that has one carries the metadata
//! [`MISSING_SAMPLES_KEY`]` = "NaN"`, which [`apply`] sets: only such a run
//! may be written with `NaN` fields, and only a reader that asks for it
//! ([`crate::data::run::ReadOptions::allow_missing`]) accepts them.

use crate::data::run::{Run, MAX_ANGLE_DEG, MISSING_SAMPLES_KEY, MISSING_SAMPLES_VALUE};
use crate::simulate::sensor::RESOLUTION_DEG;
use deploywatch_core::encoder;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::fmt;
use std::str::FromStr;

/// Longest switch bounce the chatter fault models [s] (issue 7: "bounce up
/// to 20 ms").
pub const MAX_BOUNCE_S: f64 = 0.02;

/// Time slack when comparing a sample time with a window edge [s]: sample
/// times are written to 1 µs.
const TIME_EPS_S: f64 = 1e-9;

/// Largest jitter as a fraction of the shortest sample interval.
const MAX_JITTER_FRACTION: f64 = 0.45;

/// What a dropped encoder reading becomes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DropoutMode {
    /// The driver repeats its last good reading (a frozen bus or FIFO).
    Stale,
    /// The reading is missing: `NaN`.
    Missing,
}

impl DropoutMode {
    /// The name used in the CLI syntax.
    pub fn name(self) -> &'static str {
        match self {
            DropoutMode::Stale => "stale",
            DropoutMode::Missing => "missing",
        }
    }
}

/// The sensor of a joint a fault acts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FaultTarget {
    /// The encoder of joint `j` (1-based).
    Encoder(usize),
    /// The latch switch of joint `j` (1-based).
    Switch(usize),
    /// The time stamps (every joint).
    Clock,
}

/// One sensor fault. Joints are 1-based, times in seconds from the release,
/// angles in degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SensorFault {
    /// `dropout:joint=J:start=S:duration=D[:mode=stale|missing]` (default
    /// `missing`): the encoder gives no fresh reading in `[S, S + D)`.
    Dropout {
        /// Joint (1-based).
        joint: usize,
        /// Start of the dropout [s].
        start_s: f64,
        /// Its length [s].
        duration_s: f64,
        /// Stale or missing readings.
        mode: DropoutMode,
    },
    /// `spike:joint=J:t=T:magnitude=M[:samples=K]` (default 1 sample): `K`
    /// readings from the first sample at or after `T` are off by `M`.
    Spike {
        /// Joint (1-based).
        joint: usize,
        /// Time of the spike [s].
        t_s: f64,
        /// Added to the reading [deg].
        magnitude_deg: f64,
        /// Consecutive samples affected (at least 1).
        samples: usize,
    },
    /// `stuck:joint=J:start=S[:value=V]`: the encoder reads `V` from `S` to
    /// the end of the run (its last reading before `S` when no `V`).
    StuckAt {
        /// Joint (1-based).
        joint: usize,
        /// When it sticks [s].
        start_s: f64,
        /// The value it sticks at [deg]; `None`: the last reading before.
        value_deg: Option<f64>,
    },
    /// `parity:joint=J:rate=R[:bits=B]` (default 1 bit): a fraction `R` of
    /// the encoder's answer words get `B` bit flips.
    ParityError {
        /// Joint (1-based).
        joint: usize,
        /// Probability that a sample's word is corrupted, in `[0, 1]`.
        rate: f64,
        /// Bits flipped in a corrupted word, 1 to 4: odd numbers fail the
        /// parity check, even numbers pass it.
        bits: u32,
    },
    /// `chatter:joint=J:bounce=B`: the switch bounces for `B` seconds
    /// (at most [`MAX_BOUNCE_S`]) after each closing.
    SwitchChatter {
        /// Joint (1-based).
        joint: usize,
        /// Bounce time [s].
        bounce_s: f64,
    },
    /// `switch_stuck:joint=J:state=open|closed`: the switch reads `state`
    /// for the whole run.
    SwitchStuck {
        /// Joint (1-based).
        joint: usize,
        /// True: stuck closed; false: stuck open.
        closed: bool,
    },
    /// `jitter:sigma=S`: time-stamp jitter of σ = `S` seconds.
    TimeJitter {
        /// Standard deviation [s].
        sigma_s: f64,
    },
    /// `gap:start=S:duration=D`: no sample in `[S, S + D)`.
    TimeGap {
        /// Start of the gap [s].
        start_s: f64,
        /// Its length [s].
        duration_s: f64,
    },
}

/// The kinds of fault, as named in the CLI syntax.
pub const KINDS: [&str; 8] = [
    "dropout",
    "spike",
    "stuck",
    "parity",
    "chatter",
    "switch_stuck",
    "jitter",
    "gap",
];

impl SensorFault {
    /// The kind's name in the CLI syntax (one of [`KINDS`]).
    pub fn kind(&self) -> &'static str {
        match self {
            SensorFault::Dropout { .. } => "dropout",
            SensorFault::Spike { .. } => "spike",
            SensorFault::StuckAt { .. } => "stuck",
            SensorFault::ParityError { .. } => "parity",
            SensorFault::SwitchChatter { .. } => "chatter",
            SensorFault::SwitchStuck { .. } => "switch_stuck",
            SensorFault::TimeJitter { .. } => "jitter",
            SensorFault::TimeGap { .. } => "gap",
        }
    }

    /// The sensor the fault acts on.
    pub fn target(&self) -> FaultTarget {
        match *self {
            SensorFault::Dropout { joint, .. }
            | SensorFault::Spike { joint, .. }
            | SensorFault::StuckAt { joint, .. }
            | SensorFault::ParityError { joint, .. } => FaultTarget::Encoder(joint),
            SensorFault::SwitchChatter { joint, .. } | SensorFault::SwitchStuck { joint, .. } => {
                FaultTarget::Switch(joint)
            }
            SensorFault::TimeJitter { .. } | SensorFault::TimeGap { .. } => FaultTarget::Clock,
        }
    }

    /// The joint the fault acts on (1-based), `None` for clock faults.
    pub fn joint(&self) -> Option<usize> {
        match self.target() {
            FaultTarget::Encoder(j) | FaultTarget::Switch(j) => Some(j),
            FaultTarget::Clock => None,
        }
    }

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

/// Why a `--fault` was refused, or a fault could not be applied to a run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FaultError {
    /// Not one of the fault kinds.
    #[error("unknown fault `{kind}` in `{text}`: expected one of {}", KINDS.join(", "))]
    UnknownKind {
        /// The kind given.
        kind: String,
        /// The whole `--fault` text.
        text: String,
    },
    /// A part that is not `key=value`.
    #[error("`{part}` in `{text}`: expected key=value")]
    NotKeyValue {
        /// The part.
        part: String,
        /// The whole `--fault` text.
        text: String,
    },
    /// A key the kind does not take.
    #[error("unknown key `{key}` in `{text}`: {kind} takes {}", allowed.join(", "))]
    UnknownKey {
        /// The key.
        key: String,
        /// The fault kind.
        kind: &'static str,
        /// The keys it takes.
        allowed: Vec<&'static str>,
        /// The whole `--fault` text.
        text: String,
    },
    /// A key given twice.
    #[error("key `{key}` given twice in `{text}`")]
    RepeatedKey {
        /// The key.
        key: String,
        /// The whole `--fault` text.
        text: String,
    },
    /// A required key is absent.
    #[error("`{text}`: missing {key}=...; {kind} needs {}", required.join(", "))]
    MissingKey {
        /// The key.
        key: &'static str,
        /// The fault kind.
        kind: &'static str,
        /// The keys it needs.
        required: &'static [&'static str],
        /// The whole `--fault` text.
        text: String,
    },
    /// A value that does not parse.
    #[error("`{key}={value}` in `{text}`: expected {expected}")]
    BadValue {
        /// The key.
        key: &'static str,
        /// The value as written.
        value: String,
        /// What was expected.
        expected: &'static str,
        /// The whole `--fault` text.
        text: String,
    },
    /// A parameter out of its range.
    #[error("{kind}: {key}={value}: expected {expected}")]
    BadParameter {
        /// The fault kind.
        kind: &'static str,
        /// The key.
        key: &'static str,
        /// The value.
        value: String,
        /// What was expected.
        expected: String,
    },
    /// [`FaultError::BadParameter`] found while parsing `text`.
    #[error("`{text}`: {source}")]
    InText {
        /// The whole `--fault` text.
        text: String,
        /// What was wrong.
        #[source]
        source: Box<FaultError>,
    },
    /// A joint the run or mechanism does not have.
    #[error("{kind}: joint {joint} does not exist (expected a joint from 1 to {joints})")]
    NoSuchJoint {
        /// The fault kind.
        kind: &'static str,
        /// The joint given.
        joint: usize,
        /// The joint count.
        joints: usize,
    },
    /// A fault that starts after the run's last sample (it would do nothing).
    #[error("{fault}: starts at {start_s} s, after the run ends ({end_s} s): expected a start from 0 to {end_s} s")]
    AfterEnd {
        /// The fault, in the `--fault` syntax.
        fault: String,
        /// Its start [s].
        start_s: f64,
        /// The run's last sample [s].
        end_s: f64,
    },
    /// The run has no samples.
    #[error("the run has no samples: expected at least one")]
    EmptyRun,
    /// The run's series differ in length.
    #[error("the run's series do not all have one value per time stamp")]
    RaggedRun,
    /// The gaps would remove every sample.
    #[error("the gaps remove every sample of the run: expected at least one left")]
    GapsRemoveAll,
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

/// What one fault did to a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaultReport {
    /// The fault.
    pub fault: SensorFault,
    /// Samples it changed: readings altered or made missing, switch readings
    /// flipped, time stamps moved, rows removed.
    pub samples: usize,
}

impl fmt::Display for FaultReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {} sample(s) affected", self.fault, self.samples)
    }
}

/// The faults of a list as one metadata value: their CLI syntax joined by
/// `"; "` (`"none"` for none).
pub fn describe(faults: &[SensorFault]) -> String {
    if faults.is_empty() {
        return "none".to_string();
    }
    faults
        .iter()
        .map(|f| f.to_string())
        .collect::<Vec<_>>()
        .join("; ")
}

/// Applies `faults` to `run` (a run measured by [`crate::simulate::sensor::measure`]),
/// deterministically from `seed`; returns what each fault did, in the order
/// given.
///
/// Fails, leaving the run unchanged, when a fault does not fit the run (a
/// joint it does not have, a bad parameter) or when the gaps would remove
/// every sample. Sets the metadata `faults` ([`describe`]) and, when a
/// reading went missing, [`MISSING_SAMPLES_KEY`].
pub fn apply(
    run: &mut Run,
    faults: &[SensorFault],
    seed: u64,
) -> Result<Vec<FaultReport>, FaultError> {
    check_fits(run, faults)?;
    let t0: Vec<f64> = run.t_s.clone();
    let keep: Vec<bool> = t0
        .iter()
        .map(|&t| {
            !faults.iter().any(|f| match *f {
                SensorFault::TimeGap {
                    start_s,
                    duration_s,
                } => in_window(t, start_s, duration_s),
                _ => false,
            })
        })
        .collect();
    if !keep.iter().any(|k| *k) {
        return Err(FaultError::GapsRemoveAll);
    }
    let rng_for = |k: usize| {
        let mut r = ChaCha8Rng::seed_from_u64(seed);
        r.set_stream(1 + k as u64);
        r
    };
    // Encoder and switch faults in the order given, then the jitter, then
    // the gaps.
    let mut counts = vec![0usize; faults.len()];
    for (k, f) in faults.iter().enumerate() {
        counts[k] = apply_sensor_fault(run, &t0, f, &mut rng_for(k));
    }
    for (k, f) in faults.iter().enumerate() {
        if let SensorFault::TimeJitter { sigma_s } = *f {
            counts[k] = jitter(&mut run.t_s, &t0, sigma_s, &mut rng_for(k))?;
        }
    }
    for (k, f) in faults.iter().enumerate() {
        if let SensorFault::TimeGap {
            start_s,
            duration_s,
        } = *f
        {
            counts[k] = t0
                .iter()
                .filter(|&&t| in_window(t, start_s, duration_s))
                .count();
        }
    }
    drop_rows(run, &keep);

    if !faults.is_empty() {
        run.set_meta("faults", &describe(faults));
    }
    if run.phi_deg.iter().flatten().any(|x| x.is_nan()) {
        run.set_meta(MISSING_SAMPLES_KEY, MISSING_SAMPLES_VALUE);
    }
    Ok(faults
        .iter()
        .zip(counts)
        .map(|(&fault, samples)| FaultReport { fault, samples })
        .collect())
}

/// The time a fault starts [s], `None` for faults that act on the whole run.
fn start_of(f: &SensorFault) -> Option<f64> {
    match *f {
        SensorFault::Dropout { start_s, .. }
        | SensorFault::StuckAt { start_s, .. }
        | SensorFault::TimeGap { start_s, .. } => Some(start_s),
        SensorFault::Spike { t_s, .. } => Some(t_s),
        _ => None,
    }
}

/// Checks that the run is well formed and that every fault fits it: its
/// joint exists, its parameters are valid, and it starts before the run
/// ends (a fault that starts later would silently do nothing).
fn check_fits(run: &Run, faults: &[SensorFault]) -> Result<(), FaultError> {
    let n = run.joints();
    let Some(&end_s) = run.t_s.last() else {
        return Err(FaultError::EmptyRun);
    };
    if run.latch.len() != n
        || run.phi_deg.iter().any(|s| s.len() != run.len())
        || run.latch.iter().any(|s| s.len() != run.len())
    {
        return Err(FaultError::RaggedRun);
    }
    for f in faults {
        f.validate(n)?;
        if let Some(start) = start_of(f).filter(|&s| s > end_s + TIME_EPS_S) {
            return Err(FaultError::AfterEnd {
                fault: f.to_string(),
                start_s: start,
                end_s,
            });
        }
    }
    Ok(())
}

/// Applies one encoder or switch fault (the clock faults are applied
/// after: [`jitter`], [`drop_rows`]); returns the number of samples changed.
fn apply_sensor_fault(run: &mut Run, t0: &[f64], f: &SensorFault, rng: &mut ChaCha8Rng) -> usize {
    match *f {
        SensorFault::Dropout {
            joint,
            start_s,
            duration_s,
            mode,
        } => dropout(&mut run.phi_deg[joint - 1], t0, start_s, duration_s, mode),
        SensorFault::Spike {
            joint,
            t_s,
            magnitude_deg,
            samples,
        } => spike(&mut run.phi_deg[joint - 1], t0, t_s, magnitude_deg, samples),
        SensorFault::StuckAt {
            joint,
            start_s,
            value_deg,
        } => stuck(&mut run.phi_deg[joint - 1], t0, start_s, value_deg),
        SensorFault::ParityError { joint, rate, bits } => {
            parity(&mut run.phi_deg[joint - 1], rate, bits, rng)
        }
        SensorFault::SwitchChatter { joint, bounce_s } => {
            chatter(&mut run.latch[joint - 1], t0, bounce_s, rng)
        }
        SensorFault::SwitchStuck { joint, closed } => {
            let latch = &mut run.latch[joint - 1];
            let c = latch.iter().filter(|&&l| l != closed).count();
            latch.iter_mut().for_each(|l| *l = closed);
            c
        }
        SensorFault::TimeJitter { .. } | SensorFault::TimeGap { .. } => 0,
    }
}

/// `dropout`: the readings in the window repeat the last one before it, or
/// are missing.
fn dropout(phi: &mut [f64], t0: &[f64], start_s: f64, duration_s: f64, mode: DropoutMode) -> usize {
    let mut c = 0;
    let mut held: Option<f64> = None;
    for i in 0..t0.len() {
        if !in_window(t0[i], start_s, duration_s) {
            continue;
        }
        let value = match mode {
            DropoutMode::Missing => f64::NAN,
            // The last reading before the window, or the window's first
            // reading when it opens the run.
            DropoutMode::Stale => *held.get_or_insert(if i > 0 { phi[i - 1] } else { phi[i] }),
        };
        if !same(phi[i], value) {
            c += 1;
        }
        phi[i] = value;
    }
    c
}

/// `spike`: `samples` readings from the first at or after `t_s` are off by
/// `magnitude_deg`.
fn spike(phi: &mut [f64], t0: &[f64], t_s: f64, magnitude_deg: f64, samples: usize) -> usize {
    let first = t0
        .iter()
        .position(|&t| t >= t_s - TIME_EPS_S)
        .unwrap_or(t0.len());
    let last = (first + samples).min(t0.len());
    for x in &mut phi[first..last] {
        *x += magnitude_deg;
    }
    last - first
}

/// `stuck`: from `start_s` on, `value_deg` or the last reading before.
fn stuck(phi: &mut [f64], t0: &[f64], start_s: f64, value_deg: Option<f64>) -> usize {
    let first = t0
        .iter()
        .position(|&t| t >= start_s - TIME_EPS_S)
        .unwrap_or(t0.len());
    let value = value_deg.unwrap_or_else(|| {
        let i = first.saturating_sub(1).min(phi.len() - 1);
        phi[i]
    });
    let mut c = 0;
    for x in &mut phi[first..] {
        if !same(*x, value) {
            c += 1;
        }
        *x = value;
    }
    c
}

/// `parity`: a fraction `rate` of the answer words get `bits` flipped bits.
fn parity(phi: &mut [f64], rate: f64, bits: u32, rng: &mut ChaCha8Rng) -> usize {
    let mut c = 0;
    for x in phi.iter_mut() {
        // One draw per sample whatever happens, so that the corrupted
        // samples do not depend on the readings.
        let hit = rng.gen::<f64>() < rate;
        let mut flips = 0u16;
        while flips.count_ones() < bits {
            flips |= 1 << rng.gen_range(0..16);
        }
        if hit && x.is_finite() {
            *x = corrupt_word(*x, flips);
            c += 1;
        }
    }
    c
}

/// `chatter`: after each closing, the next sample reads open, then each
/// sample up to `bounce_s` after the closing reads at random.
fn chatter(latch: &mut [bool], t0: &[f64], bounce_s: f64, rng: &mut ChaCha8Rng) -> usize {
    let closings: Vec<usize> = (0..latch.len())
        .filter(|&i| latch[i] && (i == 0 || !latch[i - 1]))
        .collect();
    let mut c = 0;
    for i in closings {
        let tc = t0[i];
        for k in i + 1..latch.len() {
            if t0[k] - tc > bounce_s + TIME_EPS_S {
                break;
            }
            let reads = if k == i + 1 { false } else { rng.gen::<bool>() };
            if reads != latch[k] {
                c += 1;
            }
            latch[k] = reads;
        }
    }
    c
}

/// `jitter`: every time stamp but the first off by N(0, σ), clipped to
/// ±[`MAX_JITTER_FRACTION`] of the shortest interval of the original times.
fn jitter(
    t_s: &mut [f64],
    t0: &[f64],
    sigma_s: f64,
    rng: &mut ChaCha8Rng,
) -> Result<usize, FaultError> {
    let dt_min = t0
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let limit = if dt_min.is_finite() {
        MAX_JITTER_FRACTION * dt_min
    } else {
        0.0
    };
    let normal = Normal::new(0.0, sigma_s).map_err(|_| FaultError::BadParameter {
        kind: "jitter",
        key: "sigma",
        value: sigma_s.to_string(),
        expected: "a positive standard deviation in seconds".to_string(),
    })?;
    let mut c = 0;
    for t in t_s.iter_mut().skip(1) {
        let e = normal.sample(rng).clamp(-limit, limit);
        if e != 0.0 {
            c += 1;
        }
        *t += e;
    }
    Ok(c)
}

/// `gap`: removes the rows whose `keep` is false.
fn drop_rows(run: &mut Run, keep: &[bool]) {
    fn retain<T>(v: &mut Vec<T>, keep: &[bool]) {
        let mut it = keep.iter();
        v.retain(|_| *it.next().unwrap_or(&true));
    }
    retain(&mut run.t_s, keep);
    run.phi_deg.iter_mut().for_each(|v| retain(v, keep));
    run.latch.iter_mut().for_each(|v| retain(v, keep));
}

/// True when `t` is in `[start, start + duration)`, to the time slack.
fn in_window(t: f64, start_s: f64, duration_s: f64) -> bool {
    t >= start_s - TIME_EPS_S && t < start_s + duration_s - TIME_EPS_S
}

/// Equal readings, `NaN` equal to `NaN`.
fn same(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

/// The reading `deg` after the AS5047P answer word that carried it had the
/// bits of `flips` inverted on the wire: `NaN` when the driver rejects the
/// word (parity or error flag: [`encoder::check_answer`], what the driver
/// does), otherwise the reading with the count changed by the corrupted
/// data bits (the driver has no way to notice).
pub fn corrupt_word(deg: f64, flips: u16) -> f64 {
    let turn = i64::from(encoder::COUNTS_PER_TURN);
    let count = ((deg / RESOLUTION_DEG).round() as i64).rem_euclid(turn) as u16;
    let data = count & encoder::DATA_MASK;
    match encoder::check_answer(encoder::with_even_parity(data) ^ flips) {
        Ok(bad) => deg + (i64::from(bad) - i64::from(data)) as f64 * RESOLUTION_DEG,
        Err(_) => f64::NAN,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use deploywatch_core::encoder::{ERROR_FLAG_BIT, PARITY_BIT};

    /// A 2-joint run at 100 Hz over 1 s: joint 1 moves from -90 to 0 and
    /// latches at 0.5 s; joint 2 stays at 45 and never latches.
    fn run() -> Run {
        let t: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
        let phi1: Vec<f64> = t.iter().map(|&t| (-90.0 + 180.0 * t).min(0.0)).collect();
        let latch1: Vec<bool> = t.iter().map(|&t| t >= 0.5 - 1e-12).collect();
        Run {
            metadata: vec![("mechanism".into(), "test".into())],
            phi_deg: vec![phi1, vec![45.0; t.len()]],
            latch: vec![latch1, vec![false; t.len()]],
            extra: Vec::new(),
            t_s: t,
        }
    }

    fn applied(spec: &str) -> (Run, usize) {
        let mut r = run();
        let f: SensorFault = spec.parse().unwrap();
        let rep = apply(&mut r, &[f], 7).unwrap();
        r.validate("test").unwrap();
        (r, rep[0].samples)
    }

    #[test]
    fn cli_syntax_round_trips_and_rejects_with_what_was_expected() {
        for s in [
            "dropout:joint=1:start=0.5:duration=0.1:mode=stale",
            "dropout:joint=2:start=0:duration=1:mode=missing",
            "spike:joint=1:t=0.3:magnitude=-25",
            "spike:joint=1:t=0.3:magnitude=5:samples=3",
            "stuck:joint=1:start=0.2",
            "stuck:joint=1:start=0.2:value=-10",
            "parity:joint=2:rate=0.05",
            "parity:joint=2:rate=0.05:bits=2",
            "chatter:joint=1:bounce=0.02",
            "switch_stuck:joint=1:state=open",
            "switch_stuck:joint=1:state=closed",
            "jitter:sigma=0.002",
            "gap:start=0.4:duration=0.15",
        ] {
            let f: SensorFault = s.parse().unwrap_or_else(|e| panic!("{s}: {e}"));
            assert_eq!(f.to_string(), s);
        }
        let d: SensorFault = "dropout:joint=1:start=0.5:duration=0.1".parse().unwrap();
        assert!(matches!(
            d,
            SensorFault::Dropout {
                mode: DropoutMode::Missing,
                ..
            }
        ));
        for (bad, says) in [
            ("stall:joint=1", "expected one of dropout, spike"),
            ("dropout:joint=1:start=0.5", "missing duration=..."),
            (
                "dropout:joint=1:start=0.5:duration=0.1:mode=frozen",
                "expected stale or missing",
            ),
            ("spike:joint=0:t=1:magnitude=3", "joint 0 does not exist"),
            ("spike:joint=x:t=1:magnitude=3", "expected a joint number"),
            (
                "spike:joint=1:t=1:magnitude=nan",
                "expected a finite number",
            ),
            ("chatter:joint=1:bounce=0.05", "at most 0.02"),
            ("parity:joint=1:rate=1.5", "from 0 to 1"),
            ("parity:joint=1:rate=0.1:bits=0", "1 to 4"),
            ("gap:start=0.1:duration=0", "positive duration"),
            ("gap:start=0.1:duration=0.1:joint=1", "unknown key `joint`"),
            ("jitter:sigma=0.001:sigma=0.002", "given twice"),
            ("switch_stuck:joint=1:state=half", "expected open or closed"),
            ("stuck:joint=1:start=0:value=1000", "within ±720"),
            ("jitter", "missing sigma"),
            ("gap:0.1", "expected key=value"),
        ] {
            let e = bad.parse::<SensorFault>().unwrap_err().to_string();
            assert!(e.contains(says), "{bad}: {e}");
        }
        let f: SensorFault = "spike:joint=3:t=1:magnitude=3".parse().unwrap();
        assert!(f
            .validate(2)
            .unwrap_err()
            .to_string()
            .contains("joint 3 does not exist (expected a joint from 1 to 2)"));
    }

    #[test]
    fn dropout_stale_repeats_the_last_reading_before_the_window() {
        // GIVEN joint 1 moving, WHEN its encoder freezes from 0.2 s for 0.1 s
        let (r, n) = applied("dropout:joint=1:start=0.2:duration=0.1:mode=stale");
        let before = run().phi_deg[0][19];
        // THEN samples 20..=29 read the value of sample 19, and only they
        assert_eq!(n, 10);
        for i in 20..30 {
            assert_eq!(r.phi_deg[0][i], before, "sample {i}");
        }
        assert_eq!(r.phi_deg[0][30], run().phi_deg[0][30]);
        assert_eq!(r.phi_deg[1], run().phi_deg[1]);
        assert!(r.meta(MISSING_SAMPLES_KEY).is_none());
        assert_eq!(
            r.meta("faults"),
            Some("dropout:joint=1:start=0.2:duration=0.1:mode=stale")
        );
    }

    #[test]
    fn dropout_missing_makes_nan_and_declares_it() {
        let (r, n) = applied("dropout:joint=2:start=0.5:duration=0.05:mode=missing");
        assert_eq!(n, 5);
        assert!((50..55).all(|i| r.phi_deg[1][i].is_nan()));
        assert_eq!(r.phi_deg[1].iter().filter(|x| x.is_nan()).count(), 5);
        assert_eq!(r.meta(MISSING_SAMPLES_KEY), Some(MISSING_SAMPLES_VALUE));
        // The switch and the time stamps are untouched.
        assert_eq!(r.latch, run().latch);
        assert_eq!(r.t_s, run().t_s);
    }

    #[test]
    fn spike_offsets_the_given_number_of_samples() {
        let (r, n) = applied("spike:joint=1:t=0.305:magnitude=30:samples=2");
        assert_eq!(n, 2);
        let base = run();
        for i in 0..r.len() {
            let d = r.phi_deg[0][i] - base.phi_deg[0][i];
            let want = if i == 31 || i == 32 { 30.0 } else { 0.0 };
            assert!((d - want).abs() < 1e-9, "sample {i}: {d}");
        }
        // A spike after the end of the run would do nothing: refused, the
        // run unchanged.
        let mut r = run();
        let late = "spike:joint=1:t=5:magnitude=30".parse().unwrap();
        let e = apply(&mut r, &[late], 0).unwrap_err();
        assert!(matches!(e, FaultError::AfterEnd { .. }), "{e}");
        assert!(e.to_string().contains("after the run ends (1 s)"), "{e}");
        assert_eq!(r, run());
    }

    #[test]
    fn stuck_holds_a_value_to_the_end() {
        let (r, n) = applied("stuck:joint=1:start=0.1");
        let held = run().phi_deg[0][9];
        assert!(r.phi_deg[0][10..].iter().all(|&x| x == held));
        assert_eq!(n, 91);
        let (r, _) = applied("stuck:joint=1:start=0.1:value=-12.5");
        assert!(r.phi_deg[0][10..].iter().all(|&x| x == -12.5));
        assert_eq!(r.phi_deg[0][9], run().phi_deg[0][9]);
    }

    #[test]
    fn one_flipped_bit_fails_the_parity_and_two_pass_it() {
        // GIVEN a reading on the 14-bit grid
        let deg = 1234.0 * RESOLUTION_DEG;
        // WHEN one bit (any, data, error flag or parity) flips
        for b in 0..16 {
            // THEN the driver rejects the word
            assert!(corrupt_word(deg, 1 << b).is_nan(), "bit {b}");
        }
        // WHEN two data bits flip, THEN the parity passes and the angle is wrong
        let x = corrupt_word(deg, 0b1_0000_0001);
        assert!(
            (x - f64::from(1234 ^ 0b1_0000_0001) * RESOLUTION_DEG).abs() < 1e-9,
            "{x}"
        );
        // WHEN a data bit and the parity bit flip, THEN a wrong angle passes too
        let x = corrupt_word(deg, PARITY_BIT | 2);
        assert!(
            (x - f64::from(1234 ^ 2) * RESOLUTION_DEG).abs() < 1e-9,
            "{x}"
        );
        // WHEN the error flag is one of two flips, THEN the driver rejects it
        assert!(corrupt_word(deg, ERROR_FLAG_BIT | 1).is_nan());
        // Negative and multi-turn readings keep their turn.
        let deg = -180.0 + 3.0 * RESOLUTION_DEG;
        let x = corrupt_word(deg, 0b11);
        assert!((x - deg).abs() < 4.0 * RESOLUTION_DEG && x < 0.0, "{x}");
    }

    #[test]
    fn parity_errors_hit_about_the_rate_and_depend_on_the_seed_only() {
        let f: SensorFault = "parity:joint=1:rate=0.2".parse().unwrap();
        let mut a = run();
        let ra = apply(&mut a, &[f], 1).unwrap();
        let nan = a.phi_deg[0].iter().filter(|x| x.is_nan()).count();
        // One flipped bit: every corrupted word is rejected.
        assert_eq!(nan, ra[0].samples);
        assert!((8..=35).contains(&nan), "{nan} of 101 at rate 0.2");
        assert_eq!(a.meta(MISSING_SAMPLES_KEY), Some(MISSING_SAMPLES_VALUE));
        let mut b = run();
        apply(&mut b, &[f], 1).unwrap();
        assert!(a.phi_deg[0]
            .iter()
            .zip(&b.phi_deg[0])
            .all(|(x, y)| same(*x, *y)));
        let mut c = run();
        apply(&mut c, &[f], 2).unwrap();
        assert!(!a.phi_deg[0]
            .iter()
            .zip(&c.phi_deg[0])
            .all(|(x, y)| same(*x, *y)));
        // Two bits: no missing sample, but wrong readings (or EF rejections).
        let mut d = run();
        let f2: SensorFault = "parity:joint=1:rate=0.2:bits=2".parse().unwrap();
        let rd = apply(&mut d, &[f2], 1).unwrap();
        let wrong = d.phi_deg[0]
            .iter()
            .zip(&run().phi_deg[0])
            .filter(|(x, y)| !same(**x, **y))
            .count();
        assert!(wrong > 0 && wrong <= rd[0].samples);
        assert!(d.phi_deg[0]
            .iter()
            .any(|x| x.is_finite() && !run().phi_deg[0].contains(x)));
    }

    #[test]
    fn chatter_bounces_after_the_closing_then_stays_closed() {
        let (r, n) = applied("chatter:joint=1:bounce=0.02");
        // Closing at sample 50: 50 closed, 51 open, 52 random, 53.. closed.
        assert!(!r.latch[0][49] && r.latch[0][50] && !r.latch[0][51]);
        assert!(r.latch[0][53..].iter().all(|&l| l));
        assert!((1..=2).contains(&n));
        // A switch that never closes has nothing to bounce.
        let (r, n) = applied("chatter:joint=2:bounce=0.02");
        assert_eq!((n, r.latch), (0, run().latch));
    }

    #[test]
    fn switch_stuck_reads_one_state_throughout() {
        let (r, n) = applied("switch_stuck:joint=1:state=open");
        assert!(r.latch[0].iter().all(|&l| !l));
        assert_eq!(n, 51);
        let (r, n) = applied("switch_stuck:joint=2:state=closed");
        assert!(r.latch[1].iter().all(|&l| l));
        assert_eq!(n, 101);
        assert_eq!(r.phi_deg, run().phi_deg);
    }

    #[test]
    fn jitter_keeps_times_increasing_and_the_first_at_zero() {
        // A jitter far larger than the sample interval is clipped.
        let (r, n) = applied("jitter:sigma=1");
        assert_eq!(r.t_s[0], 0.0);
        assert_eq!(n, 100);
        for w in r.t_s.windows(2) {
            assert!(w[1] - w[0] >= 0.1 * 0.01 - 1e-12, "{w:?}");
        }
        let (r, _) = applied("jitter:sigma=0.0005");
        let err: f64 = r
            .t_s
            .iter()
            .zip(&run().t_s)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(err > 0.0 && err <= 0.0045 + 1e-12);
        assert_eq!(r.phi_deg, run().phi_deg);
    }

    #[test]
    fn gap_removes_rows_and_never_all_of_them() {
        let (r, n) = applied("gap:start=0.45:duration=0.1");
        assert_eq!(n, 10);
        assert_eq!(r.len(), 91);
        assert!(r
            .t_s
            .iter()
            .all(|&t| !(0.45 - 1e-9..0.55 - 1e-9).contains(&t)));
        // The latch happened in the gap: the next row already reads latched.
        let i = r.t_s.iter().position(|&t| t > 0.5).unwrap();
        assert!(r.latch[0][i] && !r.latch[0][i - 1]);
        let mut r = run();
        let e = apply(&mut r, &["gap:start=0:duration=2".parse().unwrap()], 0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("remove every sample"), "{e}");
        assert_eq!(r, run());
    }

    #[test]
    fn faults_combine_deterministically_and_windows_use_the_original_times() {
        let faults: Vec<SensorFault> = [
            "jitter:sigma=0.002",
            "gap:start=0.2:duration=0.05",
            "dropout:joint=1:start=0.6:duration=0.03:mode=missing",
            "chatter:joint=1:bounce=0.02",
        ]
        .iter()
        .map(|s| s.parse().unwrap())
        .collect();
        let mut a = run();
        let rep = apply(&mut a, &faults, 11).unwrap();
        assert_eq!(
            rep.iter().map(|r| r.samples).collect::<Vec<_>>()[1..3],
            [5, 3]
        );
        assert_eq!(a.len(), 96);
        assert_eq!(a.phi_deg[0].iter().filter(|x| x.is_nan()).count(), 3);
        let mut b = run();
        apply(&mut b, &faults, 11).unwrap();
        assert_eq!(a.to_csv_string(), b.to_csv_string());
        // Adding a fault does not change what the others drew.
        let mut c = run();
        let mut more = faults.clone();
        more.push("spike:joint=2:t=0.9:magnitude=4".parse().unwrap());
        apply(&mut c, &more, 11).unwrap();
        assert_eq!(a.t_s, c.t_s);
        assert_eq!(a.latch, c.latch);
        // The faulted run is writable and declares what was done to it.
        a.validate("a").unwrap();
        assert!(a
            .meta("faults")
            .unwrap()
            .starts_with("jitter:sigma=0.002; gap:"));
    }

    #[test]
    fn a_fault_that_does_not_fit_the_run_leaves_it_unchanged() {
        let mut r = run();
        let e = apply(&mut r, &["stuck:joint=3:start=0".parse().unwrap()], 0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("joint 3 does not exist"), "{e}");
        assert_eq!(r, run());
    }
}
