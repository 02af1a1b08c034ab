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
//! ([`crate::data::run::ReadOptions::allow_missing`]) accepts them.//!
//! One module per responsibility: `fault` (the kinds and their parameters),
//! `validate` (their checks), `error`, `readings` (what each fault does to
//! the run); here, [`apply`] and its report.

mod error;
mod fault;
mod readings;
mod validate;

pub use error::FaultError;
pub use fault::{DropoutMode, SensorFault, KINDS};

use crate::data::run::{Run, MISSING_SAMPLES_KEY, MISSING_SAMPLES_VALUE};
use fault::TIME_EPS_S;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use readings::{apply_sensor_fault, drop_rows, in_window, jitter};
use std::fmt;

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

#[cfg(test)]
mod tests;
