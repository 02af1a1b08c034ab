//! Reading the run CSV (`docs/spec/formats.md`, "Run: CSV").

use std::path::Path;

use super::error::{separated, shorten};
use super::error::{RunError, RunErrorKind};
use super::record::{run_columns, run_header};
use super::record::{
    ExtraColumn, ExtraKind, ReadOptions, Run, MAX_ANGLE_DEG, MISSING_SAMPLES_KEY,
    MISSING_SAMPLES_VALUE,
};
use crate::model::file_kind::{utf8_text, Encoding, FileKind};
use crate::model::mechanism::MAX_CHAIN_JOINTS;

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
pub(super) fn valid_meta_key(k: &str) -> bool {
    !k.is_empty() && !k.chars().any(|c| c.is_whitespace() || c == '=')
}

/// `t_s` as written: 6 decimals with trailing zeros trimmed down to 3.
pub(super) fn format_time(t: f64) -> String {
    let mut s = format!("{t:.6}");
    if s.contains('.') && t.is_finite() {
        while s.ends_with('0') && s.len() - s.find('.').unwrap_or(0) > 4 {
            s.pop();
        }
    }
    s
}

/// `,x` with 6 decimals appended to `out`; a value that rounds to zero is
/// written `0.000000`, never `-0.000000`.
pub(super) fn push_fixed6(out: &mut String, x: f64) {
    use std::fmt::Write as _;
    let at = out.len();
    let _ = write!(out, ",{x:.6}");
    if &out[at..] == ",-0.000000" {
        out.replace_range(at.., ",0.000000");
    }
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
        let value: String = serde_json::from_str(value.trim()).map_err(|_| {
            bad(if value.trim().ends_with(',') {
                "`# key = \"json string\"` with nothing after the string (no comma at the end)"
            } else {
                "`# key = \"json string\"` with the value a JSON string"
            })
        })?;
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
    /// The file's field separator as written: `,`, or `;` in the
    /// spreadsheet dialect (its rows read here converted to commas).
    separator: char,
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
                    "a data row of {} {} fields (empty lines and metadata after the header are not allowed)",
                    self.columns.len(),
                    separated(self.separator)
                ),
                found: shorten(line),
            }));
        }
        let fields: Vec<&'t str> = line.split(',').map(str::trim).collect();
        if fields.len() != self.columns.len() {
            let trailing_separator = fields.len() == self.columns.len() + 1
                && fields.last().is_some_and(|f| f.is_empty());
            return Err(err(RunErrorKind::FieldCount {
                expected: self.columns.len(),
                found: fields.len(),
                trailing_separator,
                separator: self.separator,
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

/// What [`RunErrorKind::BadNumber`] adds for a `NaN` angle in a file that
/// does not declare missing samples.
const MISSING_HINT: &str = "; a missing reading may be written `NaN` only in a file that declares it: add the line `# missing_samples = \"NaN\"` before the header (docs/spec/formats.md)";

/// The joint count a header seems to be for: its angle columns, its latch
/// columns, or its width, whichever says more (a misspelt column must not
/// change the count).
fn header_joint_count(cols: &[Col], width: usize, n_phi: usize, n_latch: usize) -> usize {
    let half = (width.saturating_sub(1) / 2).min(MAX_CHAIN_JOINTS);
    // Angle columns numbered past their count (`phi4_deg` among three
    // angles) say a lower one is missing: the run is for that many
    // joints, and the missing angle is what the message names.
    let highest_phi = cols
        .iter()
        .filter_map(|c| match c {
            Col::Phi(j) => Some(*j),
            _ => None,
        })
        .max()
        .unwrap_or(0);
    // A number far past the columns is a misspelling, not a count.
    let highest_phi = if highest_phi <= n_latch.max(n_phi + 1) {
        highest_phi.min(MAX_CHAIN_JOINTS)
    } else {
        0
    };
    match n_phi.max(n_latch.min(half)).max(highest_phi) {
        0 => half.max(1),
        n => n,
    }
}

/// The error of a header `line` (line `n` of `file`) that ends with its
/// `separator`.
fn trailing_separator(file: &str, n: usize, line: &str, separator: char) -> RunError {
    let at_end = if separator == ',' { "a comma" } else { "a `;`" };
    let kind = RunErrorKind::BadLine {
        expected: format!("a header without {at_end} at its end (the rows without one too)"),
        found: shorten(line),
    };
    RunError::at(file, n, kind)
}

impl Run {
    /// Reads and validates a run CSV file.
    pub fn load(path: &Path) -> Result<Run, RunError> {
        Run::load_with(path, ReadOptions::default())
    }

    /// Reads and validates a run CSV file with the given options.
    pub fn load_with(path: &Path, options: ReadOptions) -> Result<Run, RunError> {
        let file = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|source| {
            let kind = if source.kind() == std::io::ErrorKind::NotFound
                && file.trim().parse::<f64>().is_ok()
            {
                RunErrorKind::NumberForFile { name: file.clone() }
            } else {
                RunErrorKind::Io {
                    action: "cannot read",
                    source,
                }
            };
            RunError::whole(&file, kind)
        })?;
        let text = utf8_text(bytes).map_err(|found| match found.encoding {
            Encoding::Binary => RunError::whole(
                &file,
                RunErrorKind::NotText {
                    offset: found.offset,
                },
            ),
            _ => RunError::at(&file, found.line, RunErrorKind::NotUtf8 { found }),
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
    /// [`RunErrorKind::MissingSample`]; without the declaration, a
    /// [`RunErrorKind::BadNumber`] whatever the option.
    pub fn parse_with(text: &str, source: &str, options: ReadOptions) -> Result<Run, RunError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let (written, separator) = (text, super::dialect::separator(text));
        let text = super::dialect::to_comma_dialect(text, source)?;
        // Blank lines at the end of the file are no data (editors add them).
        let body = text.trim_end_matches(|c: char| c.is_whitespace());
        let mut lines = body.lines().enumerate().map(|(i, l)| (i + 1, l));
        let mut run = Run::default();
        // Another kind of input file, whatever its comments say first.
        if let Some((ln, line)) = FileKind::first_line(body) {
            if let Some(kind @ (FileKind::MechanismToml | FileKind::Json)) = FileKind::of_line(line)
            {
                let found = shorten(line);
                return Err(RunError::at(
                    source,
                    ln,
                    RunErrorKind::OtherFormat { kind, found },
                ));
            }
        }
        let (header_line, header, meta_lines) = read_metadata(&mut run, &mut lines, source)?;
        if header.trim().is_empty() {
            let expected = "the header `t_s,phi1_deg,...,latch1,...` here: an empty line may not \
                            come before it (only metadata lines `# key = \"json string\"` may)";
            return Err(RunError::at(
                source,
                header_line,
                RunErrorKind::BadLine {
                    expected: expected.to_string(),
                    found: String::new(),
                },
            ));
        }
        let declares_missing = declares_missing(&run, &meta_lines, source)?;
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        if names.len() > 1 && names.last().is_some_and(|c| c.is_empty()) {
            // The line as written, not as the dialect's reader turned it.
            let line = written.lines().nth(header_line - 1).unwrap_or(header);
            return Err(trailing_separator(source, header_line, line, separator));
        }
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
            separator,
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
        if n_phi.max(n_latch) > MAX_CHAIN_JOINTS {
            return Err(RunError::at(
                file,
                line,
                RunErrorKind::TooManyJoints {
                    found: n_phi.max(n_latch),
                },
            ));
        }
        let n = header_joint_count(&cols, names.len(), n_phi, n_latch);
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
}

#[cfg(test)]
mod tests;
