//! Checking a run in memory and writing it as CSV.

use std::fmt::Write as _;
use std::path::Path;

use super::error::{RunError, RunErrorKind};
use super::parse::{format_time, push_fixed6, valid_meta_key};
use super::record::{
    run_header, ExtraKind, Run, EXTRA_COLUMNS, MAX_ANGLE_DEG, MAX_CHAIN_JOINTS,
    MISSING_SAMPLES_KEY, MISSING_SAMPLES_VALUE,
};

/// What is wrong with an angle of a run in memory, `None` for nothing: it
/// must be finite and within ±[`MAX_ANGLE_DEG`], or `NaN` where missing
/// samples are declared.
fn angle_problem(phi: f64, declares_missing: bool) -> Option<String> {
    if phi.is_nan() && declares_missing {
        None
    } else if !phi.is_finite() {
        Some(format!("{phi}; expected a finite angle"))
    } else if phi.abs() > MAX_ANGLE_DEG {
        Some(format!(
            "{phi}; expected an angle within ±{MAX_ANGLE_DEG} deg"
        ))
    } else {
        None
    }
}

impl Run {
    /// Checks that the run can be written and read back: 1 to
    /// [`MAX_CHAIN_JOINTS`] joints, as
    /// many latch series as angle series, every series as long as `t_s`, at
    /// least one sample, finite strictly increasing times that stay distinct
    /// when written with 6 decimals, angles finite and within
    /// ±[`MAX_ANGLE_DEG`] (or `NaN`, a missing reading, when the run declares
    /// `# missing_samples = "NaN"`), metadata keys without spaces or `=`.
    /// `file` names the run in the error.
    pub fn validate(&self, file: &str) -> Result<(), RunError> {
        self.check_shape()
            .and_then(|()| self.check_extra_and_keys())
            .and_then(|()| self.check_samples())
            .map_err(|reason| RunError::whole(file, RunErrorKind::Invalid { reason }))
    }

    /// The joint count and the length of every series.
    fn check_shape(&self) -> Result<(), String> {
        let n = self.joints();
        if n == 0 || n > MAX_CHAIN_JOINTS {
            return Err(format!("{n} joints; expected 1 to {MAX_CHAIN_JOINTS}"));
        }
        if self.latch.len() != n {
            return Err(format!(
                "{n} angle series but {} latch series; expected as many",
                self.latch.len()
            ));
        }
        if self.t_s.is_empty() {
            return Err("no samples; expected at least one".to_string());
        }
        for j in 0..n {
            if self.phi_deg[j].len() != self.len() || self.latch[j].len() != self.len() {
                return Err(format!(
                    "joint {} has {} angles and {} latch samples; expected {} (as many as t_s)",
                    j + 1,
                    self.phi_deg[j].len(),
                    self.latch[j].len(),
                    self.len()
                ));
            }
        }
        Ok(())
    }

    /// The extra columns and the metadata keys.
    fn check_extra_and_keys(&self) -> Result<(), String> {
        for (e, col) in self.extra.iter().enumerate() {
            if ExtraKind::of(&col.name) != Some(col.kind) {
                return Err(format!(
                    "extra column {:?}; expected one of the documented extra columns {EXTRA_COLUMNS}, named for what it holds",
                    col.name
                ));
            }
            if self.extra[..e].iter().any(|c| c.name == col.name) {
                return Err(format!(
                    "extra column {:?} twice; expected each column once",
                    col.name
                ));
            }
            if col.values.len() != self.len() {
                return Err(format!(
                    "extra column {:?} has {} samples; expected {} (as many as t_s)",
                    col.name,
                    col.values.len(),
                    self.len()
                ));
            }
            let bad = col.values.iter().position(|&x| {
                if col.kind.is_switch() {
                    x != 0.0 && x != 1.0
                } else {
                    angle_problem(x, false).is_some()
                }
            });
            if let Some(i) = bad {
                return Err(format!(
                    "sample {}: {} = {}; expected {}",
                    i + 1,
                    col.name,
                    col.values[i],
                    if col.kind.is_switch() {
                        "0 or 1"
                    } else {
                        "a finite angle within ±720 deg"
                    }
                ));
            }
        }
        for (k, _) in &self.metadata {
            if !valid_meta_key(k) {
                return Err(format!(
                    "metadata key {k:?}; expected a non-empty key without spaces or `=`"
                ));
            }
        }
        Ok(())
    }

    /// Every sample: finite increasing times, angles within range.
    fn check_samples(&self) -> Result<(), String> {
        let declares_missing = match self.meta(MISSING_SAMPLES_KEY) {
            None => false,
            Some(MISSING_SAMPLES_VALUE) => true,
            Some(other) => {
                return Err(format!(
                "metadata {MISSING_SAMPLES_KEY} = {other:?}; expected \"{MISSING_SAMPLES_VALUE}\""
            ))
            }
        };
        let mut prev: Option<String> = None;
        for (i, &t) in self.t_s.iter().enumerate() {
            if !t.is_finite() {
                return Err(format!(
                    "sample {}: t_s = {t}; expected a finite time",
                    i + 1
                ));
            }
            let text = format_time(t);
            if let Some(p) = &prev {
                let written = |s: &str| s.parse::<f64>().unwrap_or(f64::NAN);
                if t <= self.t_s[i - 1] || written(&text) <= written(p) {
                    return Err(format!(
                        "sample {}: t_s = {text} after {p}; expected strictly increasing times at least 1 µs apart",
                        i + 1
                    ));
                }
            }
            for (j, series) in self.phi_deg.iter().enumerate() {
                if let Some(what) = angle_problem(series[i], declares_missing) {
                    return Err(format!("sample {}: phi{}_deg = {what}", i + 1, j + 1));
                }
            }
            prev = Some(text);
        }
        Ok(())
    }

    /// The run as CSV text: metadata lines `# key = "json string"` in order,
    /// the header, one row per sample; `\n` line ends, one after every line.
    ///
    /// `t_s` is written with 6 decimals and trailing zeros trimmed down to
    /// 3 (`0.010`, `0.0125`, `1.000001`): exact for sample rates that divide
    /// 1 kHz, and to 1 µs for any other. Angles are written with 6 decimals,
    /// as `shared/reference` does; latches as `0` or `1`.
    ///
    /// Deterministic byte for byte. Reading the output with [`Run::parse`]
    /// gives the run back, times rounded to 1 µs and angles to 1e-6 deg.
    /// It does not check the run (see [`Run::validate`], which
    /// [`Run::write`] calls): missing samples are written as `NaN`, which
    /// only [`Run::parse_with`] accepts, and only in a run that declares
    /// them (`# missing_samples = "NaN"`).
    pub fn to_csv_string(&self) -> String {
        let n = self.joints();
        let mut out = String::with_capacity(64 + self.len() * (12 + 14 * n));
        for (k, v) in &self.metadata {
            let json = serde_json::to_string(v).unwrap_or_else(|_| "\"\"".to_string());
            let _ = writeln!(out, "# {k} = {json}");
        }
        out.push_str(&run_header(n));
        for col in &self.extra {
            out.push(',');
            out.push_str(&col.name);
        }
        out.push('\n');
        for (i, &t) in self.t_s.iter().enumerate() {
            out.push_str(&format_time(t));
            for series in &self.phi_deg {
                let phi = series.get(i).copied().unwrap_or(f64::NAN);
                push_fixed6(&mut out, phi);
            }
            for j in 0..n {
                let l = self.latch.get(j).and_then(|s| s.get(i));
                out.push_str(match l {
                    Some(true) => ",1",
                    Some(false) => ",0",
                    None => ",NaN",
                });
            }
            for col in &self.extra {
                let x = col.values.get(i).copied().unwrap_or(f64::NAN);
                if col.kind.is_switch() && (x == 0.0 || x == 1.0) {
                    let _ = write!(out, ",{x:.0}");
                } else {
                    push_fixed6(&mut out, x);
                }
            }
            out.push('\n');
        }
        out
    }

    /// The run checked ([`Run::validate`], errors naming `file`) as
    /// [`Run::to_csv_string`]: what a command stages for its output
    /// `file` ([`crate::report::files::Outputs`]), so that an error names
    /// the output, not the staging folder.
    pub fn checked_csv(&self, file: &str) -> Result<String, RunError> {
        self.validate(file)?;
        Ok(self.to_csv_string())
    }

    /// Checks the run ([`Run::validate`]) and writes
    /// [`Run::to_csv_string`] to `path`.
    pub fn write(&self, path: &Path) -> Result<(), RunError> {
        let csv = self.checked_csv(&path.display().to_string())?;
        std::fs::write(path, csv).map_err(|source| {
            RunError::whole(
                &path.display().to_string(),
                RunErrorKind::Io {
                    action: "cannot write",
                    source,
                },
            )
        })
    }
}
