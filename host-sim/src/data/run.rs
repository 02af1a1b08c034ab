//! A measured or simulated run: the run CSV of `docs/spec/formats.md`.

use std::fmt::Write as _;
use std::path::Path;

use crate::model::located::Located;
use crate::model::mechanism::{Mechanism, MAX_JOINTS};

/// Largest joint angle a run file may hold [deg], either sign: a hinge
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

/// Smallest change of a joint angle over a run that counts as motion [deg]:
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
    /// `psi_deg`: link 3 against the inner panel [deg] (`truss-link.md`).
    Psi,
    /// `knee<P>_deg`: interior angle of knee `P` [deg] (180 when straight).
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

/// True for a knee name that can name run columns (`knee<P>_deg`,
/// `knee<P>`): 1 to 16 ASCII letters or digits.
pub fn valid_knee_name(p: &str) -> bool {
    (1..=16).contains(&p.len()) && p.bytes().all(|b| b.is_ascii_alphanumeric())
}

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

// ---------------------------------------------------------------------------
// Reading and writing the run CSV.

/// Why a run file was rejected, or a run could not be paired or written:
/// where (`file`, `line`) and what ([`RunErrorKind`]).
///
/// `file` is the `source` given to [`Run::parse`] or the path given to
/// [`Run::load`]; `line` is 1-based and counts every line of the file,
/// metadata lines included (`None` for what concerns the whole file).
/// Displayed as `file:line: what was wrong; expected ...`.
pub type RunError = Located<RunErrorKind>;

impl RunError {
    /// An error about line `line` of `file`.
    fn at(file: &str, line: usize, kind: RunErrorKind) -> RunError {
        Located::new(file, Some(line), kind)
    }

    /// An error about the whole of `file`.
    fn whole(file: &str, kind: RunErrorKind) -> RunError {
        Located::new(file, None, kind)
    }
}

/// What was wrong with a run (the location is in [`RunError`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunErrorKind {
    /// The file could not be read or written.
    #[error("{action} the run file: {source}")]
    Io {
        /// `"cannot read"` or `"cannot write"`.
        action: &'static str,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The file ends before the header line.
    #[error("expected a header line `t_s,phi1_deg,...,latch1,...`, found the end of the file")]
    NoHeader,
    /// The file has a header but no data row.
    #[error("expected at least one data row after the header, found the end of the file")]
    NoSamples,
    /// A `#` line that is not `# key = "json string"`.
    #[error("bad metadata line: expected {expected}, found `{found}`")]
    BadMetadata {
        /// What the line should look like.
        expected: String,
        /// The line (shortened).
        found: String,
    },
    /// The same metadata key twice.
    #[error("metadata key `{key}` given twice (first on line {first}); expected each key once")]
    DuplicateMetadata {
        /// The key.
        key: String,
        /// The line where it was first given.
        first: usize,
    },
    /// A line that belongs nowhere: an empty line, or metadata after the header.
    #[error("expected {expected}, found `{found}`")]
    BadLine {
        /// What was expected there.
        expected: String,
        /// The line (shortened).
        found: String,
    },
    /// A column the header must have is absent.
    #[error("missing column `{column}`; expected the header `{expected_header}`")]
    MissingColumn {
        /// The missing column's name.
        column: String,
        /// The complete header expected for this number of joints.
        expected_header: String,
    },
    /// A column the header must not have (unknown name, or a latch column
    /// beyond the number of angle columns).
    #[error(
        "extra column `{column}` (column {position}); expected the header `{expected_header}`, optionally followed by the documented extra columns {EXTRA_COLUMNS} (docs/spec/formats.md)"
    )]
    ExtraColumn {
        /// The extra column's name.
        column: String,
        /// Its 1-based position in the header.
        position: usize,
        /// The complete header expected.
        expected_header: String,
    },
    /// A column whose name the format does not know, where the header for
    /// the joint count the file seems to have expects another one.
    #[error("unknown column `{column}` (column {position}): expected `{expected}` there; expected the header `{}` (for {joints} joint(s))", run_header(*joints))]
    UnknownColumn {
        /// The unknown column's name.
        column: String,
        /// Its 1-based position in the header.
        position: usize,
        /// The column expected at that position.
        expected: String,
        /// The joint count the header seems to be for.
        joints: usize,
    },
    /// A joint column (`t_s`, `phi<j>_deg`, `latch<j>`) after the first
    /// documented extra column.
    #[error("column `{column}` (column {position}) comes after the extra column `{first_extra}`; expected the header `t_s,phi1_deg,...,latch1,...` first and the extra columns after it")]
    AfterExtra {
        /// The misplaced column.
        column: String,
        /// Its 1-based position.
        position: usize,
        /// The first extra column.
        first_extra: String,
    },
    /// The same column twice.
    #[error("column `{column}` appears twice (columns {first} and {position}); expected each column once")]
    DuplicateColumn {
        /// The column's name.
        column: String,
        /// 1-based position of its first occurrence.
        first: usize,
        /// 1-based position of the repeat.
        position: usize,
    },
    /// All columns are there but not in the required order.
    #[error("wrong column order: column {position} is `{found}`, expected `{expected}` (header `{}`)", run_header(*joints))]
    ColumnOrder {
        /// 1-based position of the first misplaced column.
        position: usize,
        /// The column found there.
        found: String,
        /// The column expected there.
        expected: String,
        /// The joint count of the header.
        joints: usize,
    },
    /// More than [`MAX_JOINTS`] joints.
    #[error("{found} joints in the header; expected 1 to {MAX_JOINTS}")]
    TooManyJoints {
        /// Number of `phi<j>_deg` (or `latch<j>`) columns.
        found: usize,
    },
    /// A data row with the wrong number of fields.
    #[error("expected {expected} comma-separated fields (as in the header), found {found}")]
    FieldCount {
        /// Number of header columns.
        expected: usize,
        /// Number of fields in the row.
        found: usize,
    },
    /// A field that is not a finite number (unparsable, NaN or infinite).
    #[error("column `{column}`: expected a finite number, found `{found}`{hint}")]
    BadNumber {
        /// The column's name.
        column: String,
        /// The field (shortened).
        found: String,
        /// More help, or empty: for `NaN` in an angle column of a file that
        /// does not declare missing samples, how to declare them.
        hint: &'static str,
    },
    /// `t_s` not strictly increasing.
    #[error(
        "column `t_s`: expected a time after {previous} s (strictly increasing), found {found} s"
    )]
    NonMonotonicTime {
        /// The time of the row, as written.
        found: String,
        /// The time of the previous row, as written.
        previous: String,
    },
    /// An angle beyond ±[`MAX_ANGLE_DEG`].
    #[error("column `{column}`: expected an angle within ±720 deg, found {found}")]
    AngleRange {
        /// The column's name.
        column: String,
        /// The field (shortened).
        found: String,
    },
    /// A missing reading (`NaN`, which the file declares with
    /// `# missing_samples = "NaN"`) given to a reader that needs every angle.
    #[error("column `{column}`: a missing sample (`NaN`, declared by the file's `# missing_samples` metadata), but this command needs every angle: expected a finite number")]
    MissingSample {
        /// The column's name.
        column: String,
    },
    /// A file that is not UTF-8 text.
    #[error("not a text file (invalid UTF-8 at byte {offset}); expected a run CSV")]
    NotText {
        /// Offset of the first invalid byte.
        offset: usize,
    },
    /// A latch field other than `0` or `1`.
    #[error("column `{column}`: expected 0 or 1, found `{found}`")]
    BadLatch {
        /// The column's name.
        column: String,
        /// The field (shortened).
        found: String,
    },
    /// An in-memory run that the format cannot hold (on writing).
    #[error("cannot write the run: {reason}")]
    Invalid {
        /// What is wrong, for a person.
        reason: String,
    },
    /// Pairing: the run has no `mechanism` metadata.
    #[error("no `# mechanism = \"NAME\"` metadata line; expected the name of the run's mechanism")]
    NoMechanism,
    /// Pairing: no mechanism of the run's `mechanism` name was given.
    #[error(
        "mechanism \"{name}\" (from the run's metadata) was not given; expected one of: {}",
        crate::model::mechanism_toml::list_or_none(given)
    )]
    UnknownMechanism {
        /// The run's `mechanism` metadata.
        name: String,
        /// The names of the mechanisms given.
        given: Vec<String>,
    },
    /// Pairing: two different mechanisms of that name were given.
    #[error("{count} different mechanisms named \"{name}\" were given; expected one")]
    AmbiguousMechanism {
        /// The name.
        name: String,
        /// How many mechanisms carry it.
        count: usize,
    },
    /// Analysis: no joint moves by [`MIN_MOTION_DEG`] or more over the run.
    #[error("the run never moves (no joint's angle changes by more than {motion_deg:.3} deg over {duration_s:.3} s): nothing to analyse; expected a deployment, at least one joint moving by 1 deg or more (did the release fire, do the encoders read?)")]
    NeverMoves {
        /// The largest change of any joint's angle [deg].
        motion_deg: f64,
        /// The run's length [s].
        duration_s: f64,
    },
    /// Analysis: the run stops before every joint latched and before its
    /// mechanism's `duration_s` (a truncated file, or a recording stopped
    /// early).
    #[error("the run ends at {end_s} s with joint(s) {} not latched, before the mechanism's duration_s = {duration_s} s: truncated? expected a run to go on until every joint latched or to duration_s (docs/spec/formats.md)", joint_list(unlatched))]
    EndsEarly {
        /// Time of the last sample [s].
        end_s: f64,
        /// The mechanism's `duration_s` [s].
        duration_s: f64,
        /// Joints (1-based) whose switch is open at the last sample.
        unlatched: Vec<usize>,
    },
    /// Pairing: the run and its mechanism have different joint counts.
    #[error("the run has {run_joints} joints but mechanism \"{mechanism}\" has {mechanism_joints}; expected equal joint counts")]
    JointCountMismatch {
        /// The mechanism's name.
        mechanism: String,
        /// Joints in the run.
        run_joints: usize,
        /// Joints in the mechanism.
        mechanism_joints: usize,
    },
}

fn joint_list(joints: &[usize]) -> String {
    joints
        .iter()
        .map(|j| j.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// A line or field for a message: at most 60 characters.
fn shorten(s: &str) -> String {
    if s.chars().count() > 60 {
        let mut t: String = s.chars().take(57).collect();
        t.push_str("...");
        t
    } else {
        s.to_string()
    }
}

/// The header for `n` joints: `t_s,phi1_deg..phiN_deg,latch1..latchN`.
pub fn run_header(n: usize) -> String {
    run_columns(n).join(",")
}

fn run_columns(n: usize) -> Vec<String> {
    let mut cols = Vec::with_capacity(1 + 2 * n);
    cols.push("t_s".to_string());
    cols.extend((1..=n).map(|j| format!("phi{j}_deg")));
    cols.extend((1..=n).map(|j| format!("latch{j}")));
    cols
}

/// A header column.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Col {
    T,
    Phi(usize),
    Latch(usize),
    Other,
}

fn classify(name: &str) -> Col {
    let index = |s: &str| -> Option<usize> {
        if s.is_empty() || s.starts_with('0') || !s.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        s.parse().ok()
    };
    if name == "t_s" {
        Col::T
    } else if let Some(j) = name
        .strip_prefix("phi")
        .and_then(|r| r.strip_suffix("_deg"))
        .and_then(index)
    {
        Col::Phi(j)
    } else if let Some(j) = name.strip_prefix("latch").and_then(index) {
        Col::Latch(j)
    } else {
        Col::Other
    }
}

/// A metadata key: non-empty, without whitespace or `=`.
fn valid_meta_key(k: &str) -> bool {
    !k.is_empty() && !k.chars().any(|c| c.is_whitespace() || c == '=')
}

/// `t_s` as written: 6 decimals with trailing zeros trimmed down to 3.
fn format_time(t: f64) -> String {
    let mut s = format!("{t:.6}");
    if s.contains('.') && t.is_finite() {
        while s.ends_with('0') && s.len() - s.find('.').unwrap_or(0) > 4 {
            s.pop();
        }
    }
    s
}

/// Reads the `# key = "json string"` lines into `run.metadata` and returns
/// the header line (its number and text) and the line of each metadata key.
fn read_metadata<'t>(
    run: &mut Run,
    lines: &mut impl Iterator<Item = (usize, &'t str)>,
    file: &str,
) -> Result<(usize, &'t str, Vec<usize>), RunError> {
    let mut meta_lines: Vec<usize> = Vec::new();
    let mut last = 0;
    for (n, line) in lines.by_ref() {
        last = n;
        let Some(rest) = line.strip_prefix('#') else {
            return Ok((n, line, meta_lines));
        };
        let bad = |expected: &str| {
            RunError::at(
                file,
                n,
                RunErrorKind::BadMetadata {
                    expected: expected.to_string(),
                    found: shorten(line),
                },
            )
        };
        let Some((key, value)) = rest.split_once('=') else {
            return Err(bad("`# key = \"json string\"`"));
        };
        let key = key.trim();
        if !valid_meta_key(key) {
            return Err(bad("`# key = \"json string\"` with a key without spaces"));
        }
        let value: String = serde_json::from_str(value.trim())
            .map_err(|_| bad("`# key = \"json string\"` with the value a JSON string"))?;
        if let Some(i) = run.metadata.iter().position(|(k, _)| k == key) {
            let first = meta_lines[i];
            let key = key.to_string();
            return Err(RunError::at(
                file,
                n,
                RunErrorKind::DuplicateMetadata { key, first },
            ));
        }
        run.metadata.push((key.to_string(), value));
        meta_lines.push(n);
    }
    Err(RunError::at(file, last + 1, RunErrorKind::NoHeader))
}

/// True when the run declares `# missing_samples = "NaN"`; an error for
/// any other value of that key.
fn declares_missing(run: &Run, meta_lines: &[usize], file: &str) -> Result<bool, RunError> {
    match run.meta(MISSING_SAMPLES_KEY) {
        None => Ok(false),
        Some(MISSING_SAMPLES_VALUE) => Ok(true),
        Some(other) => {
            let i = run
                .metadata
                .iter()
                .position(|(k, _)| k == MISSING_SAMPLES_KEY)
                .unwrap_or(0);
            Err(RunError::at(
                file,
                meta_lines.get(i).copied().unwrap_or(1),
                RunErrorKind::BadMetadata {
                    expected: format!(
                        "`# {MISSING_SAMPLES_KEY} = \"{MISSING_SAMPLES_VALUE}\"` (the only value)"
                    ),
                    found: shorten(&format!("# {MISSING_SAMPLES_KEY} = {other:?}")),
                },
            ))
        }
    }
}

/// The data rows of a run file, read one at a time after the header.
struct RowReader<'f, 't> {
    file: &'f str,
    columns: Vec<String>,
    /// Joints: the angle columns are `1..=joints`.
    joints: usize,
    declares_missing: bool,
    allow_missing: bool,
    /// The previous row's time, as read and as written.
    prev_t: Option<(f64, &'t str)>,
}

impl<'t> RowReader<'_, 't> {
    /// Checks row `ln` and appends it to `run`.
    fn read(&mut self, run: &mut Run, ln: usize, line: &'t str) -> Result<(), RunError> {
        let err = |kind| RunError::at(self.file, ln, kind);
        if line.trim().is_empty() || line.starts_with('#') {
            return Err(err(RunErrorKind::BadLine {
                expected: format!(
                    "a data row of {} comma-separated fields (empty lines and metadata after the header are not allowed)",
                    self.columns.len()
                ),
                found: shorten(line),
            }));
        }
        let fields: Vec<&'t str> = line.split(',').map(str::trim).collect();
        if fields.len() != self.columns.len() {
            return Err(err(RunErrorKind::FieldCount {
                expected: self.columns.len(),
                found: fields.len(),
            }));
        }
        let t = self.time(&fields, ln)?;
        run.t_s.push(t);
        let n = run.phi_deg.len();
        for j in 0..n {
            let phi = self.angle(&fields, 1 + j, ln)?;
            run.phi_deg[j].push(phi);
        }
        for j in 0..n {
            let k = 1 + n + j;
            let latched = match fields[k] {
                "0" => false,
                "1" => true,
                other => {
                    return Err(err(RunErrorKind::BadLatch {
                        column: self.columns[k].clone(),
                        found: shorten(other),
                    }))
                }
            };
            run.latch[j].push(latched);
        }
        for (e, col) in run.extra.iter_mut().enumerate() {
            let k = 1 + 2 * n + e;
            let value = if col.kind.is_switch() {
                match fields[k] {
                    "0" => 0.0,
                    "1" => 1.0,
                    other => {
                        return Err(err(RunErrorKind::BadLatch {
                            column: self.columns[k].clone(),
                            found: shorten(other),
                        }))
                    }
                }
            } else {
                let x = self.number(&fields, k, ln)?;
                if x.abs() > MAX_ANGLE_DEG {
                    return Err(err(RunErrorKind::AngleRange {
                        column: self.columns[k].clone(),
                        found: shorten(fields[k]),
                    }));
                }
                x
            };
            col.values.push(value);
        }
        Ok(())
    }

    /// Field `k` as a finite number.
    fn number(&self, fields: &[&str], k: usize, ln: usize) -> Result<f64, RunError> {
        match fields[k].parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => {
                let is_angle = k >= 1 && k <= self.joints;
                let hint = if is_angle && fields[k] == MISSING_SAMPLES_VALUE {
                    MISSING_HINT
                } else {
                    ""
                };
                Err(RunError::at(
                    self.file,
                    ln,
                    RunErrorKind::BadNumber {
                        column: self.columns[k].clone(),
                        found: shorten(fields[k]),
                        hint,
                    },
                ))
            }
        }
    }

    /// `t_s`: a finite time after the previous row's.
    fn time(&mut self, fields: &[&'t str], ln: usize) -> Result<f64, RunError> {
        let t = self.number(fields, 0, ln)?;
        if let Some((p, ptext)) = self.prev_t {
            if t <= p {
                return Err(RunError::at(
                    self.file,
                    ln,
                    RunErrorKind::NonMonotonicTime {
                        found: shorten(fields[0]),
                        previous: shorten(ptext),
                    },
                ));
            }
        }
        self.prev_t = Some((t, fields[0]));
        Ok(t)
    }

    /// Angle field `k`: within ±[`MAX_ANGLE_DEG`], or `NaN` where the file
    /// declares missing samples and the reader accepts them.
    fn angle(&self, fields: &[&str], k: usize, ln: usize) -> Result<f64, RunError> {
        let column = || self.columns[k].clone();
        if self.declares_missing && fields[k] == MISSING_SAMPLES_VALUE {
            if !self.allow_missing {
                let kind = RunErrorKind::MissingSample { column: column() };
                return Err(RunError::at(self.file, ln, kind));
            }
            return Ok(f64::NAN);
        }
        let phi = self.number(fields, k, ln)?;
        if phi.abs() > MAX_ANGLE_DEG {
            let kind = RunErrorKind::AngleRange {
                column: column(),
                found: shorten(fields[k]),
            };
            return Err(RunError::at(self.file, ln, kind));
        }
        Ok(phi)
    }
}

/// The first column of a header of `n` joints that the format does not
/// know there: an unknown name (told with the column expected at its place,
/// or as extra past the end), or a latch column beyond the joints.
fn unknown_column(cols: &[Col], names: &[&str], n: usize) -> Option<RunErrorKind> {
    let expected = run_columns(n);
    cols.iter().enumerate().find_map(|(i, c)| {
        let extra = || RunErrorKind::ExtraColumn {
            column: shorten(names[i]),
            position: i + 1,
            expected_header: run_header(n),
        };
        match (*c, expected.get(i)) {
            (Col::Other, Some(want)) => Some(RunErrorKind::UnknownColumn {
                column: shorten(names[i]),
                position: i + 1,
                expected: want.clone(),
                joints: n,
            }),
            (Col::Other, None) => Some(extra()),
            (Col::Latch(j), _) if j > n => Some(extra()),
            _ => None,
        }
    })
}

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

/// What [`RunErrorKind::BadNumber`] adds for a `NaN` angle in a file that
/// does not declare missing samples.
const MISSING_HINT: &str = "; a missing reading may be written `NaN` only in a file that declares it: add the line `# missing_samples = \"NaN\"` before the header (docs/spec/formats.md)";

impl Run {
    /// Reads and validates a run CSV file.
    pub fn load(path: &Path) -> Result<Run, RunError> {
        Run::load_with(path, ReadOptions::default())
    }

    /// Reads and validates a run CSV file with the given options.
    pub fn load_with(path: &Path, options: ReadOptions) -> Result<Run, RunError> {
        let file = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|source| {
            RunError::whole(
                &file,
                RunErrorKind::Io {
                    action: "cannot read",
                    source,
                },
            )
        })?;
        let text = String::from_utf8(bytes).map_err(|e| {
            RunError::whole(
                &file,
                RunErrorKind::NotText {
                    offset: e.utf8_error().valid_up_to(),
                },
            )
        })?;
        Run::parse_with(&text, &file, options)
    }

    /// Parses and validates run CSV text (`docs/spec/formats.md`, "Run:
    /// CSV"); `source` names it in errors (usually the file's path).
    ///
    /// Accepted: `\n` or `\r\n` line ends, a final line with or without a
    /// line end, a UTF-8 byte-order mark, spaces around fields. Rejected with
    /// the line number: anything else, including empty lines, angles
    /// beyond ±[`MAX_ANGLE_DEG`], and `NaN` (see [`Run::parse_with`]).
    pub fn parse(text: &str, source: &str) -> Result<Run, RunError> {
        Run::parse_with(text, source, ReadOptions::default())
    }

    /// [`Run::parse`] with options: with [`ReadOptions::allow_missing`], an
    /// angle field `NaN` is a missing reading in a run that declares
    /// `# missing_samples = "NaN"`. Without the option such a field is a
    /// [`RunError::MissingSample`]; without the declaration, a
    /// [`RunError::BadNumber`] whatever the option.
    pub fn parse_with(text: &str, source: &str, options: ReadOptions) -> Result<Run, RunError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        // Blank lines at the end of the file are no data (editors add them).
        let body = text.trim_end_matches(|c: char| c.is_whitespace());
        let mut lines = body.lines().enumerate().map(|(i, l)| (i + 1, l));
        let mut run = Run::default();
        let (header_line, header, meta_lines) = read_metadata(&mut run, &mut lines, source)?;
        let declares_missing = declares_missing(&run, &meta_lines, source)?;
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        // The joint columns, then the documented extra ones (formats.md).
        let split = names
            .iter()
            .position(|c| ExtraKind::of(c).is_some())
            .unwrap_or(names.len());
        let n = Self::check_header(&names[..split], source, header_line)?;
        run.extra = Self::check_extra(&names, split, n, source, header_line)?;
        let mut columns = run_columns(n);
        columns.extend(run.extra.iter().map(|c| c.name.clone()));
        let mut rows = RowReader {
            file: source,
            columns,
            joints: n,
            declares_missing,
            allow_missing: options.allow_missing,
            prev_t: None,
        };
        run.phi_deg = vec![Vec::new(); n];
        run.latch = vec![Vec::new(); n];
        for (ln, line) in lines {
            rows.read(&mut run, ln, line)?;
        }
        if run.t_s.is_empty() {
            return Err(RunError::at(
                source,
                header_line + 1,
                RunErrorKind::NoSamples,
            ));
        }
        Ok(run)
    }

    /// Checks the header's extra columns, `names[split..]`: each a
    /// documented extra column ([`ExtraKind::of`]), once; no joint column
    /// among them. Returns them, without samples yet.
    fn check_extra(
        names: &[&str],
        split: usize,
        n: usize,
        file: &str,
        line: usize,
    ) -> Result<Vec<ExtraColumn>, RunError> {
        let mut out: Vec<ExtraColumn> = Vec::new();
        for (i, name) in names.iter().enumerate().skip(split) {
            let kind = match (ExtraKind::of(name), classify(name)) {
                (Some(kind), _) => kind,
                (None, Col::Other) => {
                    return Err(RunError::at(
                        file,
                        line,
                        RunErrorKind::ExtraColumn {
                            column: shorten(name),
                            position: i + 1,
                            expected_header: run_header(n),
                        },
                    ))
                }
                (None, _) => {
                    return Err(RunError::at(
                        file,
                        line,
                        RunErrorKind::AfterExtra {
                            column: shorten(name),
                            position: i + 1,
                            first_extra: names[split].to_string(),
                        },
                    ))
                }
            };
            if let Some(first) = names[split..i].iter().position(|c| c == name) {
                return Err(RunError::at(
                    file,
                    line,
                    RunErrorKind::DuplicateColumn {
                        column: name.to_string(),
                        first: split + first + 1,
                        position: i + 1,
                    },
                ));
            }
            out.push(ExtraColumn {
                name: name.to_string(),
                kind,
                values: Vec::new(),
            });
        }
        Ok(out)
    }

    /// Checks the header and returns the number of joints.
    fn check_header(names: &[&str], file: &str, line: usize) -> Result<usize, RunError> {
        let cols: Vec<Col> = names.iter().map(|s| classify(s)).collect();
        let n_phi = cols.iter().filter(|c| matches!(c, Col::Phi(_))).count();
        let n_latch = cols.iter().filter(|c| matches!(c, Col::Latch(_))).count();
        if n_phi.max(n_latch) > MAX_JOINTS {
            return Err(RunError::at(
                file,
                line,
                RunErrorKind::TooManyJoints {
                    found: n_phi.max(n_latch),
                },
            ));
        }
        // The joint count the header seems to be for: its angle columns,
        // its latch columns, or its width, whichever says more (a misspelt
        // column must not change the count).
        let half = (names.len().saturating_sub(1) / 2).min(MAX_JOINTS);
        let n = match n_phi.max(n_latch.min(half)) {
            0 => half.max(1),
            n => n,
        };
        let expected_header = run_header(n);
        let expected = run_columns(n);
        for (i, c) in cols.iter().enumerate() {
            if let Some(first) = cols[..i].iter().position(|d| d == c && *c != Col::Other) {
                let kind = RunErrorKind::DuplicateColumn {
                    column: names[i].to_string(),
                    first: first + 1,
                    position: i + 1,
                };
                return Err(RunError::at(file, line, kind));
            }
        }
        if let Some(kind) = unknown_column(&cols, names, n) {
            return Err(RunError::at(file, line, kind));
        }
        for want in &expected {
            if !names.contains(&want.as_str()) {
                return Err(RunError::at(
                    file,
                    line,
                    RunErrorKind::MissingColumn {
                        column: want.clone(),
                        expected_header,
                    },
                ));
            }
        }
        // Now the columns are exactly the expected ones (no duplicates, none
        // missing, none extra), so only their order can be wrong.
        for (i, (name, want)) in names.iter().zip(&expected).enumerate() {
            if name != want {
                return Err(RunError::at(
                    file,
                    line,
                    RunErrorKind::ColumnOrder {
                        position: i + 1,
                        found: name.to_string(),
                        expected: want.clone(),
                        joints: n,
                    },
                ));
            }
        }
        Ok(n)
    }

    /// Checks that the run can be written and read back: 1 to 4 joints, as
    /// many latch series as angle series, every series as long as `t_s`, at
    /// least one sample, finite strictly increasing times that stay distinct
    /// when written with 6 decimals, angles finite and within
    /// ±[`MAX_ANGLE_DEG`] (or `NaN`, a missing reading, when the run declares
    /// `# missing_samples = "NaN"`), metadata keys without spaces or `=`.
    /// `file` names the run in the error.
    pub fn validate(&self, file: &str) -> Result<(), RunError> {
        let invalid = |reason: String| RunError::whole(file, RunErrorKind::Invalid { reason });
        let n = self.joints();
        if n == 0 || n > MAX_JOINTS {
            return Err(invalid(format!("{n} joints; expected 1 to {MAX_JOINTS}")));
        }
        if self.latch.len() != n {
            return Err(invalid(format!(
                "{n} angle series but {} latch series; expected as many",
                self.latch.len()
            )));
        }
        if self.t_s.is_empty() {
            return Err(invalid("no samples; expected at least one".to_string()));
        }
        for j in 0..n {
            if self.phi_deg[j].len() != self.len() || self.latch[j].len() != self.len() {
                return Err(invalid(format!(
                    "joint {} has {} angles and {} latch samples; expected {} (as many as t_s)",
                    j + 1,
                    self.phi_deg[j].len(),
                    self.latch[j].len(),
                    self.len()
                )));
            }
        }
        for (e, col) in self.extra.iter().enumerate() {
            if ExtraKind::of(&col.name) != Some(col.kind) {
                return Err(invalid(format!(
                    "extra column {:?}; expected one of the documented extra columns {EXTRA_COLUMNS}, named for what it holds",
                    col.name
                )));
            }
            if self.extra[..e].iter().any(|c| c.name == col.name) {
                return Err(invalid(format!(
                    "extra column {:?} twice; expected each column once",
                    col.name
                )));
            }
            if col.values.len() != self.len() {
                return Err(invalid(format!(
                    "extra column {:?} has {} samples; expected {} (as many as t_s)",
                    col.name,
                    col.values.len(),
                    self.len()
                )));
            }
            let bad = col.values.iter().position(|&x| {
                if col.kind.is_switch() {
                    x != 0.0 && x != 1.0
                } else {
                    angle_problem(x, false).is_some()
                }
            });
            if let Some(i) = bad {
                return Err(invalid(format!(
                    "sample {}: {} = {}; expected {}",
                    i + 1,
                    col.name,
                    col.values[i],
                    if col.kind.is_switch() {
                        "0 or 1"
                    } else {
                        "a finite angle within ±720 deg"
                    }
                )));
            }
        }
        for (k, _) in &self.metadata {
            if !valid_meta_key(k) {
                return Err(invalid(format!(
                    "metadata key {k:?}; expected a non-empty key without spaces or `=`"
                )));
            }
        }
        let declares_missing = match self.meta(MISSING_SAMPLES_KEY) {
            None => false,
            Some(MISSING_SAMPLES_VALUE) => true,
            Some(other) => {
                return Err(invalid(format!(
                "metadata {MISSING_SAMPLES_KEY} = {other:?}; expected \"{MISSING_SAMPLES_VALUE}\""
            )))
            }
        };
        let mut prev: Option<String> = None;
        for (i, &t) in self.t_s.iter().enumerate() {
            if !t.is_finite() {
                return Err(invalid(format!(
                    "sample {}: t_s = {t}; expected a finite time",
                    i + 1
                )));
            }
            let text = format_time(t);
            if let Some(p) = &prev {
                let written = |s: &str| s.parse::<f64>().unwrap_or(f64::NAN);
                if t <= self.t_s[i - 1] || written(&text) <= written(p) {
                    return Err(invalid(format!(
                        "sample {}: t_s = {text} after {p}; expected strictly increasing times at least 1 µs apart",
                        i + 1
                    )));
                }
            }
            for (j, series) in self.phi_deg.iter().enumerate() {
                if let Some(what) = angle_problem(series[i], declares_missing) {
                    return Err(invalid(format!(
                        "sample {}: phi{}_deg = {what}",
                        i + 1,
                        j + 1
                    )));
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
                let _ = write!(out, ",{phi:.6}");
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
                    let _ = write!(out, ",{x:.6}");
                }
            }
            out.push('\n');
        }
        out
    }

    /// Checks the run ([`Run::validate`]) and writes
    /// [`Run::to_csv_string`] to `path`.
    pub fn write(&self, path: &Path) -> Result<(), RunError> {
        self.validate(&path.display().to_string())?;
        std::fs::write(path, self.to_csv_string()).map_err(|source| {
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

/// The mechanism a run belongs to: the one whose `name` equals the run's
/// `mechanism` metadata. `run_source` names the run in errors.
///
/// Errors: the run has no `mechanism` metadata; no mechanism of that name is
/// given (the message lists the names given); different mechanisms of that
/// name are given; the joint counts differ.
pub fn pair_runs<'a>(
    mechanisms: &'a [Mechanism],
    run: &Run,
    run_source: &str,
) -> Result<&'a Mechanism, RunError> {
    let file = run_source.to_string();
    let Some(name) = run.mechanism() else {
        return Err(RunError::whole(&file, RunErrorKind::NoMechanism));
    };
    let mut same = mechanisms.iter().filter(|m| m.name == name);
    let Some(m) = same.next() else {
        return Err(RunError::whole(
            &file,
            RunErrorKind::UnknownMechanism {
                name: name.to_string(),
                given: mechanisms.iter().map(|m| m.name.clone()).collect(),
            },
        ));
    };
    let others: Vec<&Mechanism> = same.collect();
    if others.iter().any(|o| *o != m) {
        return Err(RunError::whole(
            &file,
            RunErrorKind::AmbiguousMechanism {
                name: name.to_string(),
                count: 1 + others.len(),
            },
        ));
    }
    if m.joint_count() != run.joints() {
        return Err(RunError::whole(
            &file,
            RunErrorKind::JointCountMismatch {
                mechanism: m.name.clone(),
                run_joints: run.joints(),
                mechanism_joints: m.joint_count(),
            },
        ));
    }
    Ok(m)
}

/// Checks that a run can be of `mechanism`: its `mechanism` metadata, when
/// given, names it, and the joint counts agree. For the commands that take
/// one mechanism file and one run (`replay`); `file` names the run.
pub fn check_run_of(mechanism: &Mechanism, run: &Run, file: &str) -> Result<(), RunError> {
    if let Some(name) = run.mechanism().filter(|&n| n != mechanism.name) {
        return Err(RunError::whole(
            file,
            RunErrorKind::UnknownMechanism {
                name: name.to_string(),
                given: vec![mechanism.name.clone()],
            },
        ));
    }
    if mechanism.joint_count() != run.joints() {
        return Err(RunError::whole(
            file,
            RunErrorKind::JointCountMismatch {
                mechanism: mechanism.name.clone(),
                run_joints: run.joints(),
                mechanism_joints: mechanism.joint_count(),
            },
        ));
    }
    Ok(())
}

impl Run {
    /// The largest change of any joint's angle over the run [deg]: max − min
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

/// Checks that a run, paired with its mechanism, holds something to analyse
/// (identification, diagnosis), beyond what the format requires:
/// - some joint moves by [`MIN_MOTION_DEG`] or more
///   ([`RunError::NeverMoves`]);
/// - the run goes on until every latch switch reads closed, or to the
///   mechanism's `duration_s` within one and a half sample intervals
///   ([`RunError::EndsEarly`]: a file truncated at a line end, which the
///   reader cannot tell from a short run).
///
/// `file` names the run in the error. The monitor does not need this: a
/// run that never moves (a failed release) is one it must call a stall.
pub fn check_analysable(run: &Run, mechanism: &Mechanism, file: &str) -> Result<(), RunError> {
    let (Some(&first), Some(&end_s)) = (run.t_s.first(), run.t_s.last()) else {
        return Err(RunError::whole(
            file,
            RunErrorKind::Invalid {
                reason: "no samples; expected at least one".to_string(),
            },
        ));
    };
    let motion_deg = run.motion_deg();
    if motion_deg < MIN_MOTION_DEG {
        return Err(RunError::whole(
            file,
            RunErrorKind::NeverMoves {
                motion_deg,
                duration_s: end_s - first,
            },
        ));
    }
    let unlatched: Vec<usize> = run
        .latch
        .iter()
        .enumerate()
        .filter(|(_, l)| !l.last().copied().unwrap_or(false))
        .map(|(j, _)| j + 1)
        .collect();
    let dt = if run.len() > 1 {
        (end_s - first) / (run.len() - 1) as f64
    } else {
        0.0
    };
    if !unlatched.is_empty() && end_s < mechanism.duration_s - 1.5 * dt {
        return Err(RunError::whole(
            file,
            RunErrorKind::EndsEarly {
                end_s,
                duration_s: mechanism.duration_s,
                unlatched,
            },
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRUSS: &str = "# mechanism = \"w\"\n\
        t_s,phi1_deg,latch1,psi_deg,kneeB_deg,kneeB\n\
        0.000,90.0,0,-10.5,150.25,0\n\
        0.010,0.0,1,-20.0,180.0,1\n";

    #[test]
    fn documented_extra_columns_are_read_kept_and_written_back() {
        let run = Run::parse(TRUSS, "w.csv").unwrap();
        assert_eq!(run.joints(), 1);
        assert_eq!(run.phi_deg[0], [90.0, 0.0]);
        let names: Vec<&str> = run.extra.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["psi_deg", "kneeB_deg", "kneeB"]);
        assert_eq!(run.extra("kneeB_deg").unwrap().values, [150.25, 180.0]);
        assert_eq!(run.extra("kneeB").unwrap().kind, ExtraKind::KneeSwitch);
        assert_eq!(run.extra("kneeB").unwrap().values, [0.0, 1.0]);
        let text = run.to_csv_string();
        assert!(text.contains("t_s,phi1_deg,latch1,psi_deg,kneeB_deg,kneeB\n0.000,90.000000,0,-10.500000,150.250000,0\n"), "{text}");
        assert_eq!(Run::parse(&text, "again").unwrap(), run);
        run.validate("w.csv").unwrap();
    }

    fn error(text: &str) -> String {
        Run::parse(text, "w.csv").unwrap_err().to_string()
    }

    #[test]
    fn undocumented_or_misplaced_extra_columns_are_errors() {
        let e = error(&TRUSS.replace("kneeB\n", "kneeB,speed\n"));
        assert!(
            e.contains("w.csv:2") && e.contains("extra column `speed` (column 7)"),
            "{e}"
        );
        assert!(e.contains("psi_deg, knee<P>_deg, knee<P>"), "{e}");
        let e = error("t_s,phi1_deg,latch1,kneeB,phi2_deg\n0,1,0,0,1\n");
        assert!(
            e.contains("`phi2_deg` (column 5) comes after the extra column `kneeB`"),
            "{e}"
        );
        let e = error(&TRUSS.replace("kneeB_deg,kneeB", "kneeB,kneeB"));
        assert!(e.contains("column `kneeB` appears twice"), "{e}");
        let e = error(&TRUSS.replace("150.25,0", "150.25,2"));
        assert!(
            e.contains("w.csv:3") && e.contains("column `kneeB`: expected 0 or 1"),
            "{e}"
        );
        let e = error(&TRUSS.replace("150.25", "abc"));
        assert!(
            e.contains("column `kneeB_deg`: expected a finite number"),
            "{e}"
        );
        // A knee name with an underscore is not documented.
        let e = error(&TRUSS.replace("kneeB_deg", "knee_B_deg"));
        assert!(
            e.contains("extra column `knee_B_deg`") || e.contains("unknown column"),
            "{e}"
        );
        let mut run = Run::parse(TRUSS, "w.csv").unwrap();
        run.extra[0].values.pop();
        let e = run.validate("out.csv").unwrap_err().to_string();
        assert!(
            e.contains("extra column \"psi_deg\" has 1 samples; expected 2"),
            "{e}"
        );
    }
}
