//! Glitches of a run's angle readings: one reading that leaves both its
//! neighbours faster than any panel turns and comes straight back (an
//! encoder's or a logger's corrupted sample). [`crate::data::consistency::check`]
//! names each as a warning; a campaign (`identify`, `diagnose`) leaves its
//! row out ([`without_glitches`]), where one such reading would otherwise
//! weigh in the fit as a residual of tens of degrees; `replay` gives the
//! monitor the run as it was read (the monitor rejects a spike itself,
//! `encoder_outlier`, docs/monitor.md).

use crate::data::run::Run;

/// The smallest height of a glitch at any sample rate \[deg\]: far beyond
/// encoder noise (0.02 deg) and the rebound of a panel off its stop between
/// two samples at 1 kHz.
pub const GLITCH_MIN_DEG: f64 = 10.0;

/// The rate a reading must leave and rejoin its neighbours at to be a
/// glitch \[deg/s\]: 720 deg/s (12.6 rad/s), more than any panel of a
/// deployment turns; at 20 Hz a glitch is 36 deg high or more.
pub const GLITCH_RATE_DEG_S: f64 = 720.0;

/// The readings either side of a glitch agree within this fraction of its
/// height: the reading comes back to where it left (a rebound off a stop
/// does not).
pub const GLITCH_RETURN: f64 = 0.25;

/// The samples of joint `j` (0-based) of `run` that are glitches: readings
/// `b` between finite neighbours `a`, `c` with `b − a` and `c − b` of
/// opposite signs, each larger than [`GLITCH_MIN_DEG`] and than
/// [`GLITCH_RATE_DEG_S`] times the longer of the two intervals, and
/// `|c − a|` at most [`GLITCH_RETURN`] of the smaller.
pub fn glitches(run: &Run, j: usize) -> Vec<usize> {
    let Some(phi) = run.phi_deg.get(j) else {
        return Vec::new();
    };
    let t = &run.t_s;
    (1..phi.len().saturating_sub(1))
        .filter(|&i| {
            let (a, b, c) = (phi[i - 1], phi[i], phi[i + 1]);
            if !(a.is_finite() && b.is_finite() && c.is_finite()) {
                return false;
            }
            let (d1, d2) = (b - a, c - b);
            let height = d1.abs().min(d2.abs());
            let dt = (t[i] - t[i - 1]).max(t[i + 1] - t[i]);
            d1 * d2 < 0.0
                && height > GLITCH_MIN_DEG.max(GLITCH_RATE_DEG_S * dt)
                && (c - a).abs() <= GLITCH_RETURN * height
        })
        .collect()
}

/// One warning per joint with glitches (`file:line: ...`, the first one's
/// line, without the `warning:` prefix); `line_of` gives a sample's line.
pub fn warnings(run: &Run, file: &str, line_of: impl Fn(usize) -> usize) -> Vec<String> {
    (0..run.joints())
        .filter_map(|j| {
            let found = glitches(run, j);
            let &i = found.first()?;
            let phi = &run.phi_deg[j];
            let more = match found.len() {
                1 => String::new(),
                n => format!(" ({n} such readings in the column, the first here)"),
            };
            Some(format!(
                "{file}:{line}: column `phi{joint}_deg` (column {column}): joint {joint}'s reading \
                 jumps from {a} deg to {b} deg at t = {t} s and back to {c} deg at the next \
                 sample, faster than a panel turns: a glitch of the encoder or the logger{more}? \
                 identify and diagnose leave its row out; replay gives the monitor the run as \
                 read",
                line = line_of(i),
                joint = j + 1,
                column = 2 + j,
                a = phi[i - 1],
                b = phi[i],
                c = phi[i + 1],
                t = run.t_s[i],
            ))
        })
        .collect()
}

/// `run` without the rows of its glitches (of any joint), and how many rows
/// were left out.
pub fn without_glitches(mut run: Run) -> (Run, usize) {
    let mut rows: Vec<usize> = (0..run.joints()).flat_map(|j| glitches(&run, j)).collect();
    rows.sort_unstable();
    rows.dedup();
    if rows.is_empty() {
        return (run, 0);
    }
    let keep: Vec<bool> = (0..run.len())
        .map(|i| rows.binary_search(&i).is_err())
        .collect();
    let kept = |v: &mut Vec<f64>| {
        let mut k = keep.iter();
        v.retain(|_| k.next().copied().unwrap_or(true));
    };
    kept(&mut run.t_s);
    for column in &mut run.phi_deg {
        kept(column);
    }
    for column in &mut run.latch {
        let mut k = keep.iter();
        column.retain(|_| k.next().copied().unwrap_or(true));
    }
    for column in &mut run.extra {
        kept(&mut column.values);
    }
    (run, rows.len())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A joint turning at `rate` deg/s from −90° sampled at `hz` for 40
    /// samples, with `glitch` added to the reading of sample 10.
    pub(crate) fn run(rate: f64, hz: f64, glitch: f64) -> Run {
        let t: Vec<f64> = (0..40).map(|i| i as f64 / hz).collect();
        let mut phi: Vec<f64> = t.iter().map(|t| -90.0 + rate * t).collect();
        phi[10] += glitch;
        Run {
            t_s: t,
            phi_deg: vec![phi],
            latch: vec![vec![false; 40]],
            ..Run::default()
        }
    }

    #[test]
    fn a_reading_out_and_back_faster_than_a_panel_is_a_glitch_at_every_rate() {
        for hz in [20.0, 100.0, 1000.0] {
            let height = GLITCH_MIN_DEG.max(GLITCH_RATE_DEG_S / hz) * 1.5;
            for sign in [1.0, -1.0] {
                assert_eq!(
                    glitches(&run(90.0, hz, sign * height), 0),
                    vec![10],
                    "{hz} Hz"
                );
            }
        }
    }

    #[test]
    fn fast_motion_a_rebound_and_noise_are_no_glitch() {
        // A panel at 700 deg/s between 20 Hz samples: 35 deg a sample.
        assert!(glitches(&run(700.0, 20.0, 0.0), 0).is_empty());
        // A reading 20 deg off at 20 Hz: 400 deg/s out and back, a panel could.
        assert!(glitches(&run(90.0, 20.0, 20.0), 0).is_empty());
        // A rebound off a stop: out fast, back only part of the way.
        let mut r = run(0.0, 100.0, 0.0);
        r.phi_deg[0][9] = -40.0;
        r.phi_deg[0][10] = 0.0;
        r.phi_deg[0][11] = -25.0;
        assert!(glitches(&r, 0).is_empty());
    }

    #[test]
    fn the_rows_of_glitches_are_left_out_of_every_column() {
        let r = run(90.0, 100.0, 70.0);
        let w = warnings(&r, "r.csv", |i| i + 2);
        assert_eq!(w.len(), 1);
        assert!(w[0].starts_with("r.csv:12: column `phi1_deg`"), "{}", w[0]);
        let (clean, n) = without_glitches(r.clone());
        assert_eq!(n, 1);
        assert_eq!(clean.len(), r.len() - 1);
        assert_eq!(clean.latch[0].len(), clean.len());
        assert!(!clean.t_s.contains(&r.t_s[10]));
        assert!(glitches(&clean, 0).is_empty());
    }
}
