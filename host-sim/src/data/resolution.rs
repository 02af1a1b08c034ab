//! How finely a run's samples resolve its motion: the most any joint turns
//! between two readings. The on-board monitor follows each joint from its
//! readings (its rate filters, the impact window and the whip's parabola
//! and cubic, `docs/monitor.md` §6.2); where a joint turns by tens of
//! degrees between two readings (a light wing recorded at 20 Hz) its
//! `encoder_outlier` and `estimator_reset` flags, rates and predictions
//! stop meaning what they say. `replay` warns of such a run
//! ([`note`]); it replays it all the same.

use crate::data::glitch::glitches;
use crate::data::run::Run;

/// The most a joint may turn between two readings for the monitor to
/// follow it \[deg\]: the clean runs of the light wings of
/// `tests/monitor/light_wings.rs` at 100 Hz turn a joint by up to 33° a
/// reading and raise no flag; the same wings at 20 Hz (35 to 100 degrees
/// a reading) raise `encoder_outlier` on clean runs.
pub const RESOLVED_STEP_DEG: f64 = 35.0;

/// The largest step of one joint's readings between two samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coarsest {
    /// The joint (0-based).
    pub joint: usize,
    /// The step \[deg\].
    pub step_deg: f64,
    /// The time of the sample it ends at \[s\].
    pub t_s: f64,
}

/// The largest change of any joint's reading between two consecutive
/// samples, the steps into and out of a glitch ([`glitches`]) and those
/// with a missing reading left out; `None` without two readings in a row.
pub fn coarsest_step(run: &Run) -> Option<Coarsest> {
    let mut best: Option<Coarsest> = None;
    for (j, phi) in run.phi_deg.iter().enumerate() {
        let glitch = glitches(run, j);
        for i in 1..phi.len() {
            if glitch.contains(&i) || glitch.contains(&(i - 1)) {
                continue;
            }
            let step = (phi[i] - phi[i - 1]).abs();
            if step.is_finite() && best.is_none_or(|b| step > b.step_deg) {
                best = Some(Coarsest {
                    joint: j,
                    step_deg: step,
                    t_s: run.t_s.get(i).copied().unwrap_or(f64::NAN),
                });
            }
        }
    }
    best
}

/// `replay`'s warning (without the `warning:` prefix) when a joint of
/// `run` (read from `file`) turns by more than [`RESOLVED_STEP_DEG`]
/// between two readings, with the sample rate that would keep it within.
pub fn note(run: &Run, file: &str) -> Option<String> {
    let c = coarsest_step(run)?;
    if c.step_deg <= RESOLVED_STEP_DEG {
        return None;
    }
    let n = run.t_s.len();
    let hz = if n >= 2 {
        (n - 1) as f64 / (run.t_s[n - 1] - run.t_s[0])
    } else {
        f64::NAN
    };
    let needed = (hz * c.step_deg / RESOLVED_STEP_DEG / 10.0).ceil() * 10.0;
    Some(format!(
        "{file}: joint {joint} turns by {step:.1} deg between two readings (the sample at \
         t = {t:.3} s; {hz:.0} Hz): the monitor follows a joint from its readings up to about \
         {RESOLVED_STEP_DEG:.0} deg a reading, and on this run its encoder_outlier and \
         estimator_reset flags, rates and predictions are not to be trusted where the joints \
         move fastest; a recording at {needed:.0} Hz or more would resolve the motion",
        joint = c.joint + 1,
        step = c.step_deg,
        t = c.t_s,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::glitch::tests::run;

    #[test]
    fn a_joint_turning_more_than_the_resolved_step_a_reading_is_warned_of() {
        // 2,000 deg/s at 20 Hz: 100 deg a reading.
        let w = note(&run(2000.0, 20.0, 0.0), "r.csv").expect("a warning");
        assert!(w.starts_with("r.csv: joint 1 turns by 100.0 deg"), "{w}");
        assert!(w.contains("20 Hz"), "{w}");
        assert!(w.contains("at 60 Hz or more"), "{w}");
        // The same motion at 100 Hz: 20 deg a reading.
        assert_eq!(note(&run(2000.0, 100.0, 0.0), "r.csv"), None);
    }

    #[test]
    fn a_glitch_is_not_a_step_of_the_motion() {
        let r = run(100.0, 100.0, 60.0);
        let c = coarsest_step(&r).expect("steps");
        assert!((c.step_deg - 1.0).abs() < 1e-9, "{c:?}");
        assert_eq!(note(&r, "r.csv"), None);
    }
}
