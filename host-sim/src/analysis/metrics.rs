//! Comparing a model run with a measured run: `docs/spec/physics.md` section 8.
//!
//! Everything here works on plain slices so that any two runs sampled at the
//! same instants can be compared, whatever produced them:
//!
//! - `t_s: &[f64]`: the common sample times \[s\], strictly increasing;
//! - angles `&[f64]` (one joint) or `&[Vec<f64>]` (`[joint][sample]`), in
//!   **degrees**, the unit of the run CSV (`phi<j>_deg`);
//! - latch switches `&[bool]` / `&[Vec<bool>]` of the **measured** run.
//!
//! Three figures:
//!
//! | figure | source | formula | unit |
//! |---|---|---|---|
//! | trajectory error `TE_j` | seed 000 Eq. 14 (with the absolute value its text lost) | `100/n · Σ_i |φe(t_i) − φa(t_i)| / |φe(t_i)|` | % |
//! | sum of squares `SSE` | seed 001 Eq. 6 | `Σ_j Σ_i (φa_j(t_i) − φe_j(t_i))²` | deg² |
//! | RMS error | `physics.md` 8 | `sqrt(SSE / (n · joints))` | deg |
//!
//! `φe` is the experiment (measured run), `φa` the analysis (model). `TE_j`
//! counts only the samples before joint j latches in the measured run and where
//! `|φe| ≥ 1°` ([`TE_MIN_ANGLE_DEG`]): near the latch angle the relative error
//! divides by almost zero. `SSE` and RMS count every sample in a time window
//! (seed 001 uses the first 2 s at Δt = 0.01 s, i.e. 201 samples).

use std::fmt;

/// Samples with `|φe|` below this are left out of a trajectory error \[deg\].
pub const TE_MIN_ANGLE_DEG: f64 = 1.0;

/// Slack on the window bounds, so that a sample printed as `2.000` s is in a
/// window ending at 2 s whatever its floating-point rounding \[s\].
pub const WINDOW_SLACK_S: f64 = 1e-9;

/// Why two runs could not be compared.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum MetricError {
    /// Two series that must be sampled at the same instants have different lengths.
    LengthMismatch {
        /// What was being compared, e.g. `"joint 2 angles"`.
        what: String,
        /// Expected number of samples (the length of `t_s`).
        expected: usize,
        /// Number found.
        found: usize,
    },
    /// The model and the measured run have different numbers of joints.
    JointCountMismatch {
        /// Joints in the model run.
        model: usize,
        /// Joints in the measured run.
        measured: usize,
    },
    /// No sample satisfies the conditions, so the figure is undefined.
    NoSamples,
}

impl fmt::Display for MetricError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MetricError::LengthMismatch {
                what,
                expected,
                found,
            } => write!(f, "{what}: {found} samples, expected {expected}"),
            MetricError::JointCountMismatch { model, measured } => write!(
                f,
                "the model has {model} joints but the measured run has {measured}"
            ),
            MetricError::NoSamples => f.write_str("no sample to compare"),
        }
    }
}

impl std::error::Error for MetricError {}

/// A closed time window `[start_s, end_s]` \[s\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeWindow {
    /// First instant included \[s\].
    pub start_s: f64,
    /// Last instant included \[s\].
    pub end_s: f64,
}

impl TimeWindow {
    /// Every sample.
    pub const ALL: TimeWindow = TimeWindow {
        start_s: f64::NEG_INFINITY,
        end_s: f64::INFINITY,
    };

    /// `[0, seconds]`: e.g. `first(2.0)` is seed 001's window (Eq. 6, i = 0..200
    /// at Δt = 0.01 s), `first(4.0)` seed 000's (Eq. 14, "four seconds").
    #[cfg(test)]
    pub fn first(seconds: f64) -> Self {
        TimeWindow {
            start_s: 0.0,
            end_s: seconds,
        }
    }

    /// True when `t_s` lies in the window (bounds included, with
    /// [`WINDOW_SLACK_S`]).
    pub fn contains(&self, t_s: f64) -> bool {
        t_s >= self.start_s - WINDOW_SLACK_S && t_s <= self.end_s + WINDOW_SLACK_S
    }
}

fn check_len(
    what: impl FnOnce() -> String,
    expected: usize,
    found: usize,
) -> Result<(), MetricError> {
    if expected == found {
        Ok(())
    } else {
        Err(MetricError::LengthMismatch {
            what: what(),
            expected,
            found,
        })
    }
}

/// The index of the first sample at which the measured latch switch reads 1,
/// or `latch.len()` if the joint never latches: the samples `0..index` are
/// "before the joint latches".
pub fn latch_index(latch: &[bool]) -> usize {
    latch.iter().position(|&l| l).unwrap_or(latch.len())
}

/// Trajectory error of one joint, seed 000 Eq. 14 with the absolute value
/// (`physics.md` 8):
///
/// ```text
/// TE = 100/n · Σ_i |φe(t_i) − φa(t_i)| / |φe(t_i)|      [%]
/// ```
///
/// over the samples `i` in `window`, before the joint latches in the measured
/// run (`measured_latch`, see [`latch_index`]) and with `|φe(t_i)| ≥ 1°`;
/// `n` is the number of such samples.
///
/// - `t_s`: sample times \[s\];
/// - `model_deg`: `φa`, the model's angle of the joint \[deg\];
/// - `measured_deg`: `φe`, the measured angle \[deg\];
/// - `measured_latch`: the measured latch switch of the joint.
///
/// Returns [`MetricError::NoSamples`] when no sample qualifies. NaN samples
/// (missing measurements) are skipped.
pub fn trajectory_error_pct(
    t_s: &[f64],
    model_deg: &[f64],
    measured_deg: &[f64],
    measured_latch: &[bool],
    window: TimeWindow,
) -> Result<f64, MetricError> {
    let n = t_s.len();
    check_len(|| "model angles".into(), n, model_deg.len())?;
    check_len(|| "measured angles".into(), n, measured_deg.len())?;
    check_len(|| "measured latch switches".into(), n, measured_latch.len())?;
    let end = latch_index(measured_latch);
    let mut sum = 0.0;
    let mut count = 0usize;
    for i in 0..end {
        let (e, a) = (measured_deg[i], model_deg[i]);
        if !window.contains(t_s[i]) || !e.is_finite() || !a.is_finite() {
            continue;
        }
        if e.abs() < TE_MIN_ANGLE_DEG {
            continue;
        }
        sum += (e - a).abs() / e.abs();
        count += 1;
    }
    if count == 0 {
        return Err(MetricError::NoSamples);
    }
    Ok(100.0 * sum / count as f64)
}

/// [`trajectory_error_pct`] of every joint: `model_deg[j]`, `measured_deg[j]`,
/// `measured_latch[j]` are joint j+1's series. A joint with no qualifying
/// sample gets `None`.
pub fn trajectory_errors_pct(
    t_s: &[f64],
    model_deg: &[Vec<f64>],
    measured_deg: &[Vec<f64>],
    measured_latch: &[Vec<bool>],
    window: TimeWindow,
) -> Result<Vec<Option<f64>>, MetricError> {
    if model_deg.len() != measured_deg.len() || measured_latch.len() != measured_deg.len() {
        return Err(MetricError::JointCountMismatch {
            model: model_deg.len(),
            measured: measured_deg.len().min(measured_latch.len()),
        });
    }
    let mut out = Vec::with_capacity(model_deg.len());
    for j in 0..model_deg.len() {
        match trajectory_error_pct(
            t_s,
            &model_deg[j],
            &measured_deg[j],
            &measured_latch[j],
            window,
        ) {
            Ok(te) => out.push(Some(te)),
            Err(MetricError::NoSamples) => out.push(None),
            Err(MetricError::LengthMismatch {
                what,
                expected,
                found,
            }) => {
                return Err(MetricError::LengthMismatch {
                    what: format!("joint {}: {what}", j + 1),
                    expected,
                    found,
                })
            }
            Err(e) => return Err(e),
        }
    }
    Ok(out)
}

/// A sum of squared angle differences and how many samples it is over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sse {
    /// `Σ_j Σ_i (φa_j(t_i) − φe_j(t_i))²` \[deg²\] (seed 001 Eq. 6).
    pub sse_deg2: f64,
    /// Number of sample instants `n` in the window (each counts every joint).
    pub samples: usize,
    /// Number of joints summed over.
    pub joints: usize,
}

impl Sse {
    /// `sqrt(SSE / (n · joints))` \[deg\] (`physics.md` 8); NaN when empty.
    pub fn rms_deg(&self) -> f64 {
        rms_deg(self.sse_deg2, self.samples, self.joints)
    }
}

/// Seed 001 Eq. 6: the sum over joints and over the samples in `window` of
/// `(φa_j(t_i) − φe_j(t_i))²` \[deg²\]; `model_deg[j]` and `measured_deg[j]` are
/// joint j+1's angles \[deg\] at the instants `t_s` \[s\].
///
/// All samples in the window count, latched or not (a model that latches late
/// or never is penalised after the measured latch too). An instant at which
/// any joint's angle is NaN is left out for every joint, so that `n` is the
/// same for all joints.
pub fn sse_deg2(
    t_s: &[f64],
    model_deg: &[Vec<f64>],
    measured_deg: &[Vec<f64>],
    window: TimeWindow,
) -> Result<Sse, MetricError> {
    if model_deg.len() != measured_deg.len() {
        return Err(MetricError::JointCountMismatch {
            model: model_deg.len(),
            measured: measured_deg.len(),
        });
    }
    let n = t_s.len();
    for j in 0..model_deg.len() {
        check_len(
            || format!("joint {} model angles", j + 1),
            n,
            model_deg[j].len(),
        )?;
        check_len(
            || format!("joint {} measured angles", j + 1),
            n,
            measured_deg[j].len(),
        )?;
    }
    let mut sse = 0.0;
    let mut samples = 0usize;
    for i in 0..n {
        if !window.contains(t_s[i]) {
            continue;
        }
        let finite = (0..model_deg.len())
            .all(|j| model_deg[j][i].is_finite() && measured_deg[j][i].is_finite());
        if !finite {
            continue;
        }
        for j in 0..model_deg.len() {
            let d = model_deg[j][i] - measured_deg[j][i];
            sse += d * d;
        }
        samples += 1;
    }
    Ok(Sse {
        sse_deg2: sse,
        samples,
        joints: model_deg.len(),
    })
}

/// RMS angle error `sqrt(SSE / (n · joints))` \[deg\] from a sum of squares
/// \[deg²\] over `n` instants and `joints` joints; NaN if `n · joints = 0`.
pub fn rms_deg(sse_deg2: f64, samples: usize, joints: usize) -> f64 {
    let m = samples * joints;
    if m == 0 {
        f64::NAN
    } else {
        (sse_deg2 / m as f64).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn times(n: usize, dt: f64) -> Vec<f64> {
        (0..n).map(|i| i as f64 * dt).collect()
    }

    #[test]
    fn trajectory_error_is_mean_relative_error_before_latch() {
        let t = times(5, 0.1);
        let meas = [-90.0, -60.0, -30.0, -0.5, 0.0];
        let model = [-81.0, -66.0, -30.0, 10.0, 0.0];
        // Latches at sample 4: sample 3 counts only by time, but |φe| < 1°.
        let latch = [false, false, false, false, true];
        let te = trajectory_error_pct(&t, &model, &meas, &latch, TimeWindow::ALL).unwrap();
        // (9/90 + 6/60 + 0) / 3 · 100
        assert!((te - 100.0 * (0.1 + 0.1) / 3.0).abs() < 1e-12, "{te}");
        // The sign of the error does not cancel (absolute value).
        let model2 = [-99.0, -54.0, -30.0, 0.0, 0.0];
        let te2 = trajectory_error_pct(&t, &model2, &meas, &latch, TimeWindow::ALL).unwrap();
        assert!((te2 - te).abs() < 1e-12);
    }

    #[test]
    fn trajectory_error_stops_at_the_measured_latch_and_honours_the_window() {
        let t = times(4, 1.0);
        let meas = [100.0, 50.0, 20.0, 10.0];
        let model = [110.0, 50.0, 0.0, 0.0];
        let latch = [false, false, true, true];
        let te = trajectory_error_pct(&t, &model, &meas, &latch, TimeWindow::ALL).unwrap();
        assert!((te - 5.0).abs() < 1e-12);
        let te = trajectory_error_pct(&t, &model, &meas, &latch, TimeWindow::first(0.5)).unwrap();
        assert!((te - 10.0).abs() < 1e-12);
        assert_eq!(
            trajectory_error_pct(&t, &model, &meas, &[true; 4], TimeWindow::ALL),
            Err(MetricError::NoSamples)
        );
        assert!(matches!(
            trajectory_error_pct(&t, &model[..3], &meas, &latch, TimeWindow::ALL),
            Err(MetricError::LengthMismatch { .. })
        ));
    }

    #[test]
    fn sse_and_rms_over_a_window() {
        // Seed 001: i = 0..200 at 0.01 s is 201 samples in the first 2 s.
        let t = times(601, 0.01);
        let meas = vec![vec![0.0; 601], vec![1.0; 601]];
        let model = vec![vec![2.0; 601], vec![1.0; 601]];
        let s = sse_deg2(&t, &model, &meas, TimeWindow::first(2.0)).unwrap();
        assert_eq!(s.samples, 201);
        assert!((s.sse_deg2 - 4.0 * 201.0).abs() < 1e-9);
        // RMS over 2 joints: sqrt(4·201 / (201·2)) = sqrt(2).
        assert!((s.rms_deg() - 2f64.sqrt()).abs() < 1e-12);
        let all = sse_deg2(&t, &model, &meas, TimeWindow::ALL).unwrap();
        assert_eq!(all.samples, 601);
        assert!(rms_deg(0.0, 0, 3).is_nan());
    }

    #[test]
    fn identical_runs_have_zero_error_and_mismatches_are_errors() {
        let t = times(10, 0.1);
        let a: Vec<f64> = (0..10).map(|i| -90.0 + 9.0 * i as f64).collect();
        let latch = vec![false; 10];
        let runs = vec![a.clone(), a.clone()];
        let te = trajectory_errors_pct(&t, &runs, &runs, &[latch.clone(), latch], TimeWindow::ALL)
            .unwrap();
        assert_eq!(te, vec![Some(0.0), Some(0.0)]);
        let s = sse_deg2(&t, &runs, &runs, TimeWindow::ALL).unwrap();
        assert_eq!(s.sse_deg2, 0.0);
        assert!(matches!(
            sse_deg2(&t, &runs, &runs[..1], TimeWindow::ALL),
            Err(MetricError::JointCountMismatch { .. })
        ));
    }

    #[test]
    fn latch_index_is_the_first_closed_switch() {
        assert_eq!(latch_index(&[false, false, true, false]), 2);
        assert_eq!(latch_index(&[false, false]), 2);
        assert_eq!(latch_index(&[]), 0);
    }
}
