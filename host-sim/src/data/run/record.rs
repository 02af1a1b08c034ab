//! The run in memory: its samples, metadata, extra columns, header and
//! the limits a run file is held to.

pub use crate::model::mechanism::MAX_CHAIN_JOINTS;

/// Largest joint angle a run file may hold \[deg\], either sign: a hinge
/// angle beyond two turns is no reading of a deploying joint (the monitor's
/// `ENCODER_RANGE_DEG` flags the same bound on board).
pub const MAX_ANGLE_DEG: f64 = 720.0;

/// The metadata key that declares missing encoder readings: a run with
/// `# missing_samples = "NaN"` may have `NaN` in its `phi<j>_deg` fields,
/// each a reading the sensor did not deliver (a dropout, a parity error).
/// See [`ReadOptions::allow_missing`] and `docs/robustness.md`.
pub const MISSING_SAMPLES_KEY: &str = "missing_samples";

/// The one value of [`MISSING_SAMPLES_KEY`]: the field text of a missing
/// reading.
pub const MISSING_SAMPLES_VALUE: &str = "NaN";

/// Smallest change of a joint angle over a run that counts as motion \[deg\]:
/// fifty times the reference encoder noise, a hundredth of the shortest
/// stroke of the bundled mechanisms.
pub const MIN_MOTION_DEG: f64 = 1.0;

/// How strictly [`Run::parse_with`] reads a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReadOptions {
    /// Accept `NaN` in the angle columns of a run that declares
    /// `# missing_samples = "NaN"` (a run with injected sensor faults, for
    /// the monitor). Off by default: the analyses need every angle, and a
    /// file that does not declare missing samples never has them.
    pub allow_missing: bool,
}

/// One run: time stamps, joint angles and latch switches, with metadata.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Run {
    /// `# key = "value"` lines before the header, in file order (values decoded).
    pub metadata: Vec<(String, String)>,
    /// `t_s` (s), strictly increasing.
    pub t_s: Vec<f64>,
    /// `phi<j>_deg`: `phi_deg[j][i]` is joint j+1 at sample i (deg).
    pub phi_deg: Vec<Vec<f64>>,
    /// `latch<j>`: `latch[j][i]` is joint j+1's switch at sample i.
    pub latch: Vec<Vec<bool>>,
    /// The documented extra columns after the joint columns, in file order
    /// (a truss run's `psi_deg`, `knee<P>_deg`, `knee<P>`: see
    /// [`ExtraKind`]); empty for a plain run. Commands that do not use
    /// them ignore them; [`Run::to_csv_string`] writes them back.
    pub extra: Vec<ExtraColumn>,
}

/// What a documented extra column of a run holds (`docs/spec/formats.md`,
/// "Run: extra columns"): the truss wing's link angle and knees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExtraKind {
    /// `psi_deg`: link 3 against the inner panel \[deg\] (`truss-link.md`).
    Psi,
    /// `knee<P>_deg`: interior angle of knee `P` \[deg\] (180 when straight).
    KneeAngle,
    /// `knee<P>`: knee `P`'s lock switch, 0 or 1.
    KneeSwitch,
}

impl ExtraKind {
    /// True for the 0/1 switch columns (the others are angles in degrees).
    pub fn is_switch(self) -> bool {
        self == ExtraKind::KneeSwitch
    }

    /// The kind of a column name, `None` for a name the format does not
    /// document. A knee name `P` is 1 to 16 ASCII letters or digits
    /// ([`valid_knee_name`]), so `knee<P>_deg` and `knee<P>` cannot be
    /// confused.
    pub fn of(name: &str) -> Option<ExtraKind> {
        if name == "psi_deg" {
            return Some(ExtraKind::Psi);
        }
        let rest = name.strip_prefix("knee")?;
        match rest.strip_suffix("_deg") {
            Some(p) if valid_knee_name(p) => Some(ExtraKind::KneeAngle),
            Some(_) => None,
            None if valid_knee_name(rest) => Some(ExtraKind::KneeSwitch),
            None => None,
        }
    }
}

pub use crate::model::truss::valid_knee_name;

/// The documented extra columns, in words (for messages).
pub const EXTRA_COLUMNS: &str =
    "psi_deg, knee<P>_deg, knee<P> (P: a knee's name, 1 to 16 ASCII letters or digits)";

/// One documented extra column of a run: its name and samples (angles in
/// degrees, switches 0 or 1 as 0.0 or 1.0).
#[derive(Clone, Debug, PartialEq)]
pub struct ExtraColumn {
    /// The column's name (`psi_deg`, `kneeB_deg`, `kneeB`...).
    pub name: String,
    /// What it holds.
    pub kind: ExtraKind,
    /// One value per sample.
    pub values: Vec<f64>,
}

impl Run {
    /// Number of joints.
    pub fn joints(&self) -> usize {
        self.phi_deg.len()
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// True when the run has no samples.
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// A metadata value.
    pub fn meta(&self, key: &str) -> Option<&str> {
        self.metadata
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// Sets (or replaces) a metadata value.
    pub fn set_meta(&mut self, key: &str, value: &str) {
        match self.metadata.iter_mut().find(|(k, _)| k == key) {
            Some(kv) => kv.1 = value.to_string(),
            None => self.metadata.push((key.to_string(), value.to_string())),
        }
    }

    /// The `mechanism` metadata: the name of the mechanism this run belongs to.
    pub fn mechanism(&self) -> Option<&str> {
        self.meta("mechanism")
    }

    /// The extra column called `name`, if the run has it.
    pub fn extra(&self, name: &str) -> Option<&ExtraColumn> {
        self.extra.iter().find(|c| c.name == name)
    }
}

impl Run {
    /// The first sample at which a joint's angle is beyond ±[`MAX_ANGLE_DEG`]
    /// (two turns, what a run file holds): `(sample index, joint 1-based)`.
    pub fn first_past_two_turns(&self) -> Option<(usize, usize)> {
        (0..self.len()).find_map(|k| {
            self.phi_deg
                .iter()
                .position(|s| s.get(k).is_some_and(|x| x.abs() > MAX_ANGLE_DEG))
                .map(|j| (k, j + 1))
        })
    }

    /// Keeps the first `len` samples of every series.
    pub fn truncate(&mut self, len: usize) {
        self.t_s.truncate(len);
        for s in &mut self.phi_deg {
            s.truncate(len);
        }
        for s in &mut self.latch {
            s.truncate(len);
        }
        for c in &mut self.extra {
            c.values.truncate(len);
        }
    }

    /// The largest change of any joint's angle over the run \[deg\]: max − min
    /// of its readings, missing ones (`NaN`) left out; 0 for no reading.
    pub fn motion_deg(&self) -> f64 {
        self.phi_deg
            .iter()
            .map(|s| {
                let (lo, hi) = s
                    .iter()
                    .filter(|x| x.is_finite())
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                        (lo.min(x), hi.max(x))
                    });
                if hi >= lo {
                    hi - lo
                } else {
                    0.0
                }
            })
            .fold(0.0, f64::max)
    }
}

/// The header for `n` joints: `t_s,phi1_deg..phiN_deg,latch1..latchN`.
pub fn run_header(n: usize) -> String {
    run_columns(n).join(",")
}

/// The columns of [`run_header`].
pub fn run_columns(n: usize) -> Vec<String> {
    let mut cols = Vec::with_capacity(1 + 2 * n);
    cols.push("t_s".to_string());
    cols.extend((1..=n).map(|j| format!("phi{j}_deg")));
    cols.extend((1..=n).map(|j| format!("latch{j}")));
    cols
}
