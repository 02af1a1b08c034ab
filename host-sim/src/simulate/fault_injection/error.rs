//! Why a fault was refused or could not be applied.

use super::fault::KINDS;

/// Why a `--fault` was refused, or a fault could not be applied to a run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FaultError {
    /// Not one of the fault kinds.
    #[error("unknown fault `{kind}` in `{text}`: expected one of {}", KINDS.join(", "))]
    UnknownKind {
        /// The kind given.
        kind: String,
        /// The whole `--fault` text.
        text: String,
    },
    /// A part that is not `key=value`.
    #[error("`{part}` in `{text}`: expected key=value")]
    NotKeyValue {
        /// The part.
        part: String,
        /// The whole `--fault` text.
        text: String,
    },
    /// A key the kind does not take.
    #[error("unknown key `{key}` in `{text}`: {kind} takes {}", allowed.join(", "))]
    UnknownKey {
        /// The key.
        key: String,
        /// The fault kind.
        kind: &'static str,
        /// The keys it takes.
        allowed: Vec<&'static str>,
        /// The whole `--fault` text.
        text: String,
    },
    /// A key given twice.
    #[error("key `{key}` given twice in `{text}`")]
    RepeatedKey {
        /// The key.
        key: String,
        /// The whole `--fault` text.
        text: String,
    },
    /// A required key is absent.
    #[error("`{text}`: missing {key}=...; {kind} needs {}", required.join(", "))]
    MissingKey {
        /// The key.
        key: &'static str,
        /// The fault kind.
        kind: &'static str,
        /// The keys it needs.
        required: &'static [&'static str],
        /// The whole `--fault` text.
        text: String,
    },
    /// A value that does not parse.
    #[error("`{key}={value}` in `{text}`: expected {expected}")]
    BadValue {
        /// The key.
        key: &'static str,
        /// The value as written.
        value: String,
        /// What was expected.
        expected: &'static str,
        /// The whole `--fault` text.
        text: String,
    },
    /// A parameter out of its range.
    #[error("{kind}: {key}={value}: expected {expected}")]
    BadParameter {
        /// The fault kind.
        kind: &'static str,
        /// The key.
        key: &'static str,
        /// The value.
        value: String,
        /// What was expected.
        expected: String,
    },
    /// [`FaultError::BadParameter`] found while parsing `text`.
    #[error("`{text}`: {source}")]
    InText {
        /// The whole `--fault` text.
        text: String,
        /// What was wrong.
        #[source]
        source: Box<FaultError>,
    },
    /// A joint the run or mechanism does not have.
    #[error("{kind}: joint {joint} does not exist (expected a joint from 1 to {joints})")]
    NoSuchJoint {
        /// The fault kind.
        kind: &'static str,
        /// The joint given.
        joint: usize,
        /// The joint count.
        joints: usize,
    },
    /// A fault that starts after the run's last sample (it would do nothing).
    #[error("{fault}: starts at {start_s} s, after the run ends ({end_s} s): expected a start from 0 to {end_s} s")]
    AfterEnd {
        /// The fault, in the `--fault` syntax.
        fault: String,
        /// Its start \[s\].
        start_s: f64,
        /// The run's last sample \[s\].
        end_s: f64,
    },
    /// The run has no samples.
    #[error("the run has no samples: expected at least one")]
    EmptyRun,
    /// The run's series differ in length.
    #[error("the run's series do not all have one value per time stamp")]
    RaggedRun,
    /// The gaps would remove every sample.
    #[error("the gaps remove every sample of the run: expected at least one left")]
    GapsRemoveAll,
}
