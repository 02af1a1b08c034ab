//! Why a run file was rejected, or a run could not be paired or written.

use crate::model::located::Located;
use crate::model::mechanism::MAX_CHAIN_JOINTS;

use super::record::{run_header, EXTRA_COLUMNS};

/// Why a run file was rejected, or a run could not be paired or written:
/// where (`file`, `line`) and what ([`RunErrorKind`]).
///
/// `file` is the `source` given to [`super::Run::parse`] or the path given to
/// [`super::Run::load`]; `line` is 1-based and counts every line of the file,
/// metadata lines included (`None` for what concerns the whole file).
/// Displayed as `file:line: what was wrong; expected ...`.
pub type RunError = Located<RunErrorKind>;

impl RunError {
    /// An error about line `line` of `file`.
    pub(crate) fn at(file: &str, line: usize, kind: RunErrorKind) -> RunError {
        Located::new(file, Some(line), kind)
    }

    /// An error about the whole of `file`.
    pub(crate) fn whole(file: &str, kind: RunErrorKind) -> RunError {
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
    /// No such file, and its name reads as a number: a value of an option
    /// given apart from it (`--start 0.1 0.2` for `--start 0.1,0.2`).
    #[error("no such file, and its name reads as a number: a value of an option? Options that take several numbers take them separated by commas, with no space (`--start 0.1,0.2,0.3`)")]
    NumberForFile {
        /// The name given.
        name: String,
    },
    /// The file ends before the header line.
    #[error("expected a header line `t_s,phi1_deg,...,latch1,...`, found the end of the file")]
    NoHeader,
    /// The header line reads as another kind of input file (a mechanism
    /// TOML given where a run belongs, say).
    #[error("the file reads as {kind}, not a run CSV (`{found}`); expected the header `t_s,phi1_deg,...,latch1,...` (docs/spec/formats.md)")]
    OtherFormat {
        /// What the file reads as.
        kind: crate::model::file_kind::FileKind,
        /// The line (shortened).
        found: String,
    },
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
    /// More than [`MAX_CHAIN_JOINTS`] joints.
    #[error("{found} joints in the header; expected 1 to {MAX_CHAIN_JOINTS}")]
    TooManyJoints {
        /// Number of `phi<j>_deg` (or `latch<j>`) columns.
        found: usize,
    },
    /// A data row with the wrong number of fields.
    #[error("expected {expected} {} fields (as in the header), found {found}{}", separated(*separator), field_count_hint(*expected, *found, *trailing_separator, *separator))]
    FieldCount {
        /// Number of header columns.
        expected: usize,
        /// Number of fields in the row.
        found: usize,
        /// The row ends with its separator: its one field too many is empty.
        trailing_separator: bool,
        /// The file's field separator: `,`, or `;` in the spreadsheet
        /// dialect.
        separator: char,
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
    /// An angle beyond ±[`super::MAX_ANGLE_DEG`].
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
    /// A file that is not text (a binary file).
    #[error("not a text file (invalid UTF-8 at byte {offset}); expected a run CSV")]
    NotText {
        /// Offset of the first invalid byte.
        offset: usize,
    },
    /// A text file in another encoding than UTF-8 (UTF-16, Latin-1): where
    /// it stops being UTF-8 (the line in [`RunError`]) and what it looks
    /// like.
    #[error(
        "{found}; expected a run CSV in UTF-8: save it as UTF-8 (a spreadsheet's \"CSV UTF-8\")"
    )]
    NotUtf8 {
        /// Where, and the encoding it looks like.
        found: crate::model::file_kind::NotUtf8,
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
        crate::model::mechanism_error::list_or_none(given)
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
    /// Analysis: no joint moves by [`super::MIN_MOTION_DEG`] or more over the run.
    #[error("the run never moves (no joint's angle changes by more than {motion_deg:.3} deg over {duration_s:.3} s): nothing to analyse; expected a deployment, at least one joint moving by 1 deg or more (did the release fire, do the encoders read?)")]
    NeverMoves {
        /// The largest change of any joint's angle \[deg\].
        motion_deg: f64,
        /// The run's length \[s\].
        duration_s: f64,
    },
    /// Analysis: the run stops before every joint latched and before its
    /// mechanism's `duration_s` (a truncated file, or a recording stopped
    /// early).
    #[error("the run ends at {end_s} s with joint(s) {} not latched, before the mechanism's duration_s = {duration_s} s: truncated? expected a run to go on until every joint latched or to duration_s (docs/spec/formats.md)", joint_list(unlatched))]
    EndsEarly {
        /// Time of the last sample \[s\].
        end_s: f64,
        /// The mechanism's `duration_s` \[s\].
        duration_s: f64,
        /// Joints (1-based) whose switch is open at the last sample.
        unlatched: Vec<usize>,
    },
    /// Meaning: a joint's first sample is its stowed angle in radians
    /// ([`crate::data::consistency`]).
    #[error("column `phi{joint}_deg` (column {}): the run starts at {found} where joint {joint} is stowed at {stowed_deg} deg, {:.1} times less: angles in radians? expected degrees (multiply by 180/π = 57.2958)", joint + 1, stowed_deg / found)]
    AnglesInRadians {
        /// The joint (1-based).
        joint: usize,
        /// Its first reading, as written.
        found: f64,
        /// Its stowed angle \[deg\].
        stowed_deg: f64,
    },
    /// Meaning: a joint's first sample is minus its stowed angle.
    #[error("column `phi{joint}_deg` (column {}): the run starts at {found} deg where joint {joint} is stowed at {stowed_deg} deg: the sign is flipped, an encoder mounted mirrored? expected the project's sign convention (docs/spec/formats.md): negate the column", joint + 1)]
    MirroredEncoder {
        /// The joint (1-based).
        joint: usize,
        /// Its first reading \[deg\].
        found: f64,
        /// Its stowed angle \[deg\].
        stowed_deg: f64,
    },
    /// Meaning: two joints' readings start each at the other's stowed
    /// angle: their columns swapped.
    #[error("columns `phi{a}_deg` (column {}) and `phi{b}_deg` (column {}): the run starts at {} deg and {} deg where joint {a} is stowed at {} deg and joint {b} at {} deg, each at the other's stowed angle: the columns swapped? expected joint {a}'s readings in `phi{a}_deg` (docs/spec/formats.md): swap the columns `phi{a}_deg` and `phi{b}_deg` (and `latch{a}` and `latch{b}` if the switches are swapped too)", joints[0] + 1, joints[1] + 1, found[0], found[1], stowed_deg[0], stowed_deg[1], a = joints[0], b = joints[1])]
    SwappedColumns {
        /// The two joints (1-based), in column order.
        joints: [usize; 2],
        /// Their readings at the start \[deg\].
        found: [f64; 2],
        /// Their stowed angles \[deg\].
        stowed_deg: [f64; 2],
    },
    /// Meaning: two joints stowed at 180 and −180 deg read each the
    /// other's stowed angle at the start and then move towards 0 on that
    /// side: their columns swapped, or both encoders mirrored.
    #[error("columns `phi{a}_deg` (column {}) and `phi{b}_deg` (column {}): the run starts at {} deg and {} deg where joint {a} is stowed at {} deg and joint {b} at {} deg, and each moves towards 0 deg on the side it started: the columns swapped, or both encoders mounted mirrored? expected each joint's readings moving from its own stowed angle towards 0 (docs/spec/formats.md): swap the columns `phi{a}_deg` and `phi{b}_deg` (and `latch{a}` and `latch{b}` if the switches are swapped too), or negate both", joints[0] + 1, joints[1] + 1, found[0], found[1], stowed_deg[0], stowed_deg[1], a = joints[0], b = joints[1])]
    SwappedOrMirrored {
        /// The two joints (1-based), in column order.
        joints: [usize; 2],
        /// Their readings at the start \[deg\].
        found: [f64; 2],
        /// Their stowed angles \[deg\].
        stowed_deg: [f64; 2],
    },
    /// Meaning: a joint's readings start at 0 deg and move away from it by
    /// about its stowed angle: angles counted from the stowed pose (an
    /// incremental encoder zeroed at power-up), not from the latch.
    #[error("column `phi{joint}_deg` (column {}): the run starts at {found} deg where joint {joint} is stowed at {stowed_deg} deg, and moves away from 0 deg: angles counted from the stowed pose (an encoder zeroed at power-up)? expected 0 deg at the latch (docs/spec/formats.md): add {stowed_deg} to the column", joint + 1)]
    AnglesFromStowed {
        /// The joint (1-based).
        joint: usize,
        /// Its reading at the start \[deg\].
        found: f64,
        /// Its stowed angle \[deg\].
        stowed_deg: f64,
    },
    /// Meaning: a joint's reading jumps by about a turn between two
    /// samples (an encoder that wraps at ±180 deg or 0/360 deg).
    #[error("column `phi{joint}_deg` (column {}): joint {joint}'s reading jumps from {from} deg to {to} deg between two samples, about a whole turn: an encoder that wraps (at ±180 or 0/360 deg)? expected the angle unwrapped, continuous over the run (docs/spec/formats.md): add or subtract 360 deg from the readings past the jump", joint + 1)]
    AnglesWrap {
        /// The joint (1-based).
        joint: usize,
        /// The reading before the jump \[deg\].
        from: f64,
        /// The reading after it \[deg\].
        to: f64,
    },
    /// Meaning: a joint's readings are its angles shifted by whole turns
    /// (an encoder that counts 0 to 360 deg, or a turn counter).
    #[error("column `phi{joint}_deg` (column {}): the run starts at {found} deg where joint {joint} is stowed at {stowed_deg} deg, {turns} whole turn(s) away: an encoder counting 0 to 360 deg? expected the angle within a turn of the stowed angle (docs/spec/formats.md): subtract {} deg from the column", joint + 1, 360.0 * turns)]
    AnglesWholeTurnsOff {
        /// The joint (1-based).
        joint: usize,
        /// Its reading at the start \[deg\].
        found: f64,
        /// Its stowed angle \[deg\].
        stowed_deg: f64,
        /// Whole turns between the reading and the stowed angle (signed).
        turns: f64,
    },
    /// Meaning: the run lasts far longer than its mechanism's horizon.
    #[error("column `t_s` (column 1): the run spans {span_s} with samples {interval_s} apart, {factor:.0} times mechanism \"{mechanism}\"'s duration_s = {duration_s} s: time in milliseconds? expected seconds (divide t_s by 1000)")]
    TimeInMilliseconds {
        /// Last minus first time stamp, as written.
        span_s: f64,
        /// Median interval between samples, as written.
        interval_s: f64,
        /// `span_s / duration_s`.
        factor: f64,
        /// The mechanism's name.
        mechanism: String,
        /// Its `duration_s` \[s\].
        duration_s: f64,
    },
    /// Meaning: the run outlasts its mechanism's horizon with samples a
    /// hundred or a thousand times further apart than the mechanism's
    /// sample rate: times written in milliseconds, caught when
    /// `duration_s` is too long for [`RunErrorKind::TimeInMilliseconds`].
    #[error("column `t_s` (column 1): samples {interval_s} apart over {span_s}, {rate_factor:.0} times the interval of mechanism \"{mechanism}\"'s sample_hz = {sample_hz} Hz, and longer than its duration_s = {duration_s} s: time in milliseconds? expected seconds (divide t_s by 1000: samples {} s apart over {} s)", interval_s / 1000.0, span_s / 1000.0)]
    TimeInMillisecondsBySampleRate {
        /// Last minus first time stamp, as written.
        span_s: f64,
        /// Median interval between samples, as written.
        interval_s: f64,
        /// `interval_s × sample_hz`.
        rate_factor: f64,
        /// The mechanism's name.
        mechanism: String,
        /// Its `sample_hz` \[Hz\].
        sample_hz: f64,
        /// Its `duration_s` \[s\].
        duration_s: f64,
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

/// What [`RunErrorKind::FieldCount`] adds when a comma-separated row has
/// more fields than the header: the likely cause, numbers with a decimal
/// comma.
const DECIMAL_COMMA_HINT: &str = ": decimal commas? a spreadsheet's export with `,` as the decimal mark must separate fields with `;` (read as the spreadsheet dialect, docs/spec/formats.md), or be exported with `.` as the decimal mark";

/// The fields of a file separated by `separator`, in words:
/// `comma-separated`, or `` `;`-separated `` in the spreadsheet dialect.
pub(crate) fn separated(separator: char) -> String {
    match separator {
        ',' => "comma-separated".to_string(),
        other => format!("`{other}`-separated"),
    }
}

/// The hint of [`RunErrorKind::FieldCount`]: a row ending with its
/// separator, or decimal commas where a comma-separated row has more fields
/// than the header (in the spreadsheet dialect a decimal comma is no
/// separator).
fn field_count_hint(expected: usize, found: usize, trailing: bool, separator: char) -> String {
    if trailing {
        format!(": the row ends with `{separator}` (an empty last field): a trailing separator? expected no `{separator}` at the end of a row, as in the header")
    } else if found > expected && separator == ',' {
        DECIMAL_COMMA_HINT.to_string()
    } else {
        String::new()
    }
}

fn joint_list(joints: &[usize]) -> String {
    joints
        .iter()
        .map(|j| j.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// A line or field for a message: at most 60 characters.
pub(crate) fn shorten(s: &str) -> String {
    if s.chars().count() > 60 {
        let mut t: String = s.chars().take(57).collect();
        t.push_str("...");
        t
    } else {
        s.to_string()
    }
}
