//! What each fault does to the readings: encoder and switch faults sample by
//! sample, then the clock's (jitter, gaps), and the AS5047P answer word
//! corrupted on the wire.

use super::error::FaultError;
use super::fault::{DropoutMode, SensorFault, TIME_EPS_S};
use crate::data::run::Run;
use crate::simulate::sensor::RESOLUTION_DEG;
use deploywatch_core::monitor::encoder;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// Largest jitter as a fraction of the shortest sample interval.
const MAX_JITTER_FRACTION: f64 = 0.45;

/// Applies one encoder or switch fault (the clock faults are applied
/// after: [`jitter`], [`drop_rows`]); returns the number of samples changed.
pub(super) fn apply_sensor_fault(
    run: &mut Run,
    t0: &[f64],
    f: &SensorFault,
    rng: &mut ChaCha8Rng,
) -> usize {
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
pub(super) fn jitter(
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
pub(super) fn drop_rows(run: &mut Run, keep: &[bool]) {
    fn retain<T>(v: &mut Vec<T>, keep: &[bool]) {
        let mut it = keep.iter();
        v.retain(|_| *it.next().unwrap_or(&true));
    }
    retain(&mut run.t_s, keep);
    run.phi_deg.iter_mut().for_each(|v| retain(v, keep));
    run.latch.iter_mut().for_each(|v| retain(v, keep));
}

/// True when `t` is in `[start, start + duration)`, to the time slack.
pub(super) fn in_window(t: f64, start_s: f64, duration_s: f64) -> bool {
    t >= start_s - TIME_EPS_S && t < start_s + duration_s - TIME_EPS_S
}

/// Equal readings, `NaN` equal to `NaN`.
pub(super) fn same(a: f64, b: f64) -> bool {
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
