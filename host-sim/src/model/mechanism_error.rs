//! Why a mechanism file was rejected, and where.

use crate::model::located::Located;
use crate::model::mechanism::MAX_CHAIN_JOINTS;
use deploywatch_core::CurveError;

/// Why a mechanism file was rejected: where (`file`, `line`) and what
/// ([`MechanismErrorKind`]).
///
/// `file` is the `source` given to [`crate::model::mechanism::Mechanism::from_toml_str`] or the path
/// given to [`crate::model::mechanism::Mechanism::load`]; `line` is the 1-based line of the offending
/// value when the TOML parser reports a position for it. Displayed as
/// `file:line: what was wrong; expected ...` (`file: ...` without a line).
pub type MechanismError = Located<MechanismErrorKind>;

/// What was wrong with a mechanism file (the location is in
/// [`MechanismError`]); `key` is a key path such as `joint[2].spring.kind`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MechanismErrorKind {
    /// The file could not be read.
    #[error("cannot read the mechanism file: {source}")]
    Io {
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The file is not UTF-8: a text file in another encoding (UTF-16,
    /// Latin-1; the line in [`MechanismError`]), or no text at all.
    #[error("{found}; expected a mechanism TOML in UTF-8: save it as UTF-8")]
    NotUtf8 {
        /// Where, and the encoding it looks like.
        found: crate::model::file_kind::NotUtf8,
    },
    /// The file could not be written.
    #[error("cannot write the mechanism file: {source}")]
    Write {
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The text is not valid TOML (or repeats a key).
    #[error("invalid TOML{}: {message}", at_column(*column))]
    Syntax {
        /// 1-based column (in characters) of the error, if known.
        column: Option<usize>,
        /// The TOML parser's message, on one line.
        message: String,
    },
    /// A key the format does not define.
    #[error("unknown key `{key}`; expected one of: {expected}")]
    UnknownKey {
        /// Key path of the unknown key.
        key: String,
        /// The keys allowed at that place, comma separated.
        expected: String,
    },
    /// A key of a joint written below its `[joint.latch]` header, where
    /// TOML gives it to the latch.
    #[error("unknown key `{key}`: `{name}` is a key of the [[joint]], but every key below the `[joint.latch]` line, up to the next header, belongs to the latch; expected it above the `[joint.latch]` line (the latch's keys: {expected})")]
    JointKeyInLatch {
        /// Key path of the key (`joint[1].latch.friction`).
        key: String,
        /// The key itself (`friction`).
        name: String,
        /// The latch's keys, comma separated.
        expected: String,
    },
    /// A dotted header that numbers a table of an array of tables
    /// (`[joint.2.latch]`), which TOML does not do.
    #[error("`{key}`: TOML does not number the [[{array}]] tables; expected the sub-table's header without the number (e.g. `[{array}.latch]`) below the [[{array}]] it belongs to")]
    NumberedTable {
        /// Key path of the number (`joint[2].2`).
        key: String,
        /// The array of tables (`joint`).
        array: String,
    },
    /// A required key is absent.
    #[error("missing key `{key}`: expected {expected}")]
    MissingKey {
        /// Key path of the missing key.
        key: String,
        /// What the key should hold.
        expected: String,
    },
    /// A value has the wrong TOML type (a string where a number belongs...).
    #[error("`{key}`: expected {expected}, found {found}")]
    WrongType {
        /// Key path of the value.
        key: String,
        /// What the key should hold.
        expected: String,
        /// The TOML type found.
        found: String,
    },
    /// The `[truss]` table is invalid (`crate::model::truss_toml`).
    #[error("{source}")]
    Truss {
        /// What is wrong, with its key path.
        #[source]
        source: crate::model::truss::TrussError,
    },
    /// A value of the right type is out of range or otherwise invalid.
    #[error("`{key}`: expected {expected}, found {found}")]
    InvalidValue {
        /// Key path of the value.
        key: String,
        /// What the key should hold.
        expected: String,
        /// The value found, as written back in TOML.
        found: String,
    },
    /// An enabled `[rig]` on a wing with a physical latch (`[joint.latch]`):
    /// the rig is simulated with ideal latches only (`formats.md`, "Rig").
    #[error(
        "`rig`: a [rig] is simulated with ideal latches only, but joint(s) {} have a \
         physical latch ([joint.latch]); expected `rig.enabled = false`, no [rig], or \
         ideal latches",
        join_joints(joints)
    )]
    RigWithPhysicalLatch {
        /// The joints (1-based) with a physical latch.
        joints: Vec<usize>,
    },
    /// `[flexible_panels]` on a wing the flexible chain does not simulate
    /// (`formats.md`, "Flexible panels"): a physical latch, a truss, an
    /// enabled rig, or more than [`crate::model::flex::MAX_FLEXIBLE_PANELS`]
    /// panels.
    #[error(
        "`flexible_panels`: flexible panels are simulated on an open chain of at most {} \
         panels with ideal latches, no truss and no enabled rig, but {why}",
        crate::model::flex::MAX_FLEXIBLE_PANELS
    )]
    FlexibleUnsupported {
        /// What the wing has that the flexible chain does not simulate.
        why: String,
    },
    /// `spring.kind` is not one of the known kinds.
    #[error(
        "`{key}`: unknown spring kind \"{found}\" for joint {joint}; expected one of \"linear\", \"tape\", \"curve\""
    )]
    UnknownSpringKind {
        /// Key path, `joint[j].spring.kind`.
        key: String,
        /// The joint, 1-based.
        joint: usize,
        /// The kind found.
        found: String,
    },
    /// A tape spring's `type` has no `[tape."NAME"]` table.
    #[error(
        "`{key}`: tape type \"{found}\" is not defined; expected a [tape.\"{found}\"] table (defined: {})",
        list_or_none(defined)
    )]
    UnknownTapeType {
        /// Key path, `joint[j].spring.type`.
        key: String,
        /// The type name found.
        found: String,
        /// The tape types the file defines.
        defined: Vec<String>,
    },
    /// Not 1 to 4 `[[panel]]` tables.
    #[error("expected 1 to {MAX_CHAIN_JOINTS} [[panel]] tables, found {found}")]
    PanelCount {
        /// Number of `[[panel]]` tables.
        found: usize,
    },
    /// The number of `[[joint]]` tables differs from the number of panels.
    #[error(
        "expected one [[joint]] table per [[panel]] table ({panels}), found {joints} [[joint]] tables"
    )]
    JointCount {
        /// Number of `[[panel]]` tables.
        panels: usize,
        /// Number of `[[joint]]` tables.
        joints: usize,
    },
    /// A tabulated curve (a curve spring's branch or a tape type's points)
    /// rejected by the core.
    #[error(
        "`{key}`: expected 2 to 16 points [deg, N·m] with finite values and strictly increasing angles: {source}"
    )]
    BadCurve {
        /// Key path of the curve.
        key: String,
        /// The core's reason.
        #[source]
        source: CurveError,
    },
}

impl MechanismError {
    /// The key path the error is about, when there is one.
    pub fn key(&self) -> Option<&str> {
        match &self.kind {
            MechanismErrorKind::UnknownKey { key, .. }
            | MechanismErrorKind::JointKeyInLatch { key, .. }
            | MechanismErrorKind::NumberedTable { key, .. }
            | MechanismErrorKind::MissingKey { key, .. }
            | MechanismErrorKind::WrongType { key, .. }
            | MechanismErrorKind::InvalidValue { key, .. }
            | MechanismErrorKind::UnknownSpringKind { key, .. }
            | MechanismErrorKind::UnknownTapeType { key, .. }
            | MechanismErrorKind::BadCurve { key, .. } => Some(key),
            MechanismErrorKind::Truss { source } => Some(&source.key),
            _ => None,
        }
    }
}

fn at_column(column: Option<usize>) -> String {
    column
        .map(|c| format!(" at column {c}"))
        .unwrap_or_default()
}

/// `"a", "b"` of `names` for an error message, or `none`.
pub(crate) fn list_or_none(names: &[String]) -> String {
    if names.is_empty() {
        "none".to_string()
    } else {
        names
            .iter()
            .map(|n| format!("\"{n}\""))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// `[2, 4]` as `2, 4`.
fn join_joints(joints: &[usize]) -> String {
    joints
        .iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}
