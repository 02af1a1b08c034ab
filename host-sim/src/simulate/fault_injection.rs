//! Sensor faults injected into a measured run: what a failing encoder, latch
//! switch or clock does to the data the monitor sees (`docs/robustness.md`
//! has the model, the syntax and the monitor's contract per fault; the CLI
//! syntax is read and written by [`crate::simulate::fault_syntax`]).
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

/// Longest switch bounce the chatter fault models \[s\] (a switch bounces up
/// to 20 ms, `docs/robustness.md`).
pub const MAX_BOUNCE_S: f64 = 0.02;

/// Time slack when comparing a sample time with a window edge \[s\]: sample
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
        /// Start of the dropout \[s\].
        start_s: f64,
        /// Its length \[s\].
        duration_s: f64,
        /// Stale or missing readings.
        mode: DropoutMode,
    },
    /// `spike:joint=J:t=T:magnitude=M[:samples=K]` (default 1 sample): `K`
    /// readings from the first sample at or after `T` are off by `M`.
    Spike {
        /// Joint (1-based).
        joint: usize,
        /// Time of the spike \[s\].
        t_s: f64,
        /// Added to the reading \[deg\].
        magnitude_deg: f64,
        /// Consecutive samples affected (at least 1).
        samples: usize,
    },
    /// `stuck:joint=J:start=S[:value=V]`: the encoder reads `V` from `S` to
    /// the end of the run (its last reading before `S` when no `V`).
    StuckAt {
        /// Joint (1-based).
        joint: usize,
        /// When it sticks \[s\].
        start_s: f64,
        /// The value it sticks at \[deg\]; `None`: the last reading before.
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
        /// Bounce time \[s\].
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
        /// Standard deviation \[s\].
        sigma_s: f64,
    },
    /// `gap:start=S:duration=D`: no sample in `[S, S + D)`.
    TimeGap {
        /// Start of the gap \[s\].
        start_s: f64,
        /// Its length \[s\].
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
        /// Its start \[s\].
        start_s: f64,
        /// The run's last sample \[s\].
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

/// The time a fault starts \[s\], `None` for faults that act on the whole run.
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
mod tests;
