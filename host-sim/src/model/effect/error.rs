//! Why an effect was rejected.

use super::kind::EffectKind;
use crate::model::torque_table::TableError;

/// Why an effect was rejected: its `--effect` text, or its joint or value.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EffectError {
    /// Not one of the names of `physics.md` section 6.
    #[error("unknown effect `{name}`: expected one of {}", effect_names())]
    UnknownName {
        /// The name given.
        name: String,
    },
    /// A part of the `--effect` text that is not `key=value`.
    #[error("`{part}` in `{text}`: expected key=value")]
    NotKeyValue {
        /// The part.
        part: String,
        /// The whole text.
        text: String,
    },
    /// A key other than `joint`, `value`, `alpha_deg`.
    #[error("unknown key `{key}` in `{text}`: expected joint, value or alpha_deg")]
    UnknownKey {
        /// The key.
        key: String,
        /// The whole text.
        text: String,
    },
    /// `stribeck_friction` without its shape (`excess_nm`, `stribeck_rad_s`).
    #[error("`{text}`: stribeck_friction needs excess_nm and stribeck_rad_s beside its value (e.g. `stribeck_friction:joint=1:value=0.2:excess_nm=0.4:stribeck_rad_s=0.05`; a --vary draws the value and keeps them)")]
    StribeckShapeMissing {
        /// The whole text.
        text: String,
    },
    /// A key given twice (the first value would be lost without a word).
    #[error("`{key}` given twice in `{text}`: expected each key once")]
    RepeatedKey {
        /// The key.
        key: String,
        /// The whole text.
        text: String,
    },
    /// A value that does not parse.
    #[error("`{key}={value}` in `{text}`: expected {expected}")]
    BadNumber {
        /// The key.
        key: String,
        /// The value as written.
        value: String,
        /// The whole text.
        text: String,
        /// What was expected.
        expected: &'static str,
    },
    /// A `torque_table` whose points are not a table.
    #[error("`{text}`: {source}")]
    Table {
        /// The whole text.
        text: String,
        /// What is wrong with the points.
        #[source]
        source: TableError,
    },
    /// Table keys on an effect other than `torque_table`.
    #[error("`{text}`: only torque_table takes angle_deg/torque_nm/rate_deg_s/rate_torque_nm")]
    TableOnNamedEffect {
        /// The whole text.
        text: String,
    },
    /// No `value=V`.
    #[error("`{text}`: missing value=V")]
    MissingValue {
        /// The whole text.
        text: String,
    },
    /// A per-joint effect without `joint=J`.
    #[error("{kind} acts on a joint: give joint=J")]
    NeedsJoint {
        /// The effect.
        kind: EffectKind,
    },
    /// A global effect given a joint.
    #[error("{kind} is global: it takes no joint")]
    GlobalWithJoint {
        /// The effect.
        kind: EffectKind,
    },
    /// A joint the mechanism does not have.
    #[error("{kind}: joint {joint} does not exist (the mechanism has {})", crate::report::text::one_to(*joints, "joint", "joints"))]
    NoSuchJoint {
        /// The effect.
        kind: EffectKind,
        /// The joint given.
        joint: usize,
        /// The mechanism's joint count.
        joints: usize,
    },
    /// A value outside [`EffectKind::allowed`].
    #[error("{kind}: value={value}: expected {} [{}]", kind.allowed().describe(), kind.unit())]
    OutOfRange {
        /// The effect.
        kind: EffectKind,
        /// The value given.
        value: f64,
    },
    /// `alpha_deg` not finite.
    #[error("{kind}: alpha_deg={alpha_deg}: expected a finite angle [deg]")]
    BadAlpha {
        /// The effect.
        kind: EffectKind,
        /// The angle given.
        alpha_deg: f64,
    },
}

fn effect_names() -> String {
    // The syntax reads every kind of the vocabulary.
    let names: Vec<_> = EffectKind::EVERY.iter().map(|k| k.name()).collect();
    names.join(", ")
}
