//! The findings JSON: what `deploywatch identify --json` and `deploywatch
//! diagnose --json` write and what `deploywatch margin --from` and
//! `deploywatch reliability --from` read back, one schema of serde-derived
//! structs (`docs/spec/formats.md`, "Diagnosis: JSON" and "Findings JSON").
//!
//! - [`identify`]: the identification ([`Identification`]): the EFT of each
//!   joint and how well the runs are reproduced before and after.
//! - [`diagnosis`]: the diagnosis ([`Diagnosis`]): the effects found, the
//!   baseline and extended fits, the candidates of every round, the evidence.
//! - [`effects`]: one effect to its JSON entry and back, the one writer and
//!   reader of every parameter an effect kind carries.
//! - [`stand_in`]: the wing's own losses an ambiguity group puts in place
//!   of a ground rig's effect, which the flight margins keep.
//!
//! Both are written by serde and read by serde. On reading, only what tells
//! the file's kind is required (`method` and `joints` of an identification,
//! `effects` of a diagnosis); everything else defaults, so that the minimal
//! files of `formats.md` and files of earlier versions read. serde_json
//! writes a number that is not finite as `null`; where a result may be one,
//! it reads `null` back as NaN ([`numbers::nan_if_null`]). A field added to either
//! schema is `#[serde(default, skip_serializing_if = ...)]`: absent from the
//! files that have nothing to say there, and from every older file.

pub mod diagnosis;
pub mod effects;
pub mod identify;
pub mod numbers;
pub mod stand_in;

pub use diagnosis::Diagnosis;
pub use identify::Identification;
pub use numbers::{exact, rounded};

use serde::Deserialize;

/// A findings file of either kind.
#[derive(Clone, Debug, PartialEq)]
pub enum Findings {
    /// `deploywatch identify --json`.
    Identify(Box<Identification>),
    /// `deploywatch diagnose --json`.
    Diagnosis(Box<Diagnosis>),
}

/// Why a findings file cannot be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FindingsError {
    /// Not JSON, or a field of the wrong type (serde's message gives the
    /// line and column).
    #[error("not JSON ({0})")]
    Json(#[from] serde_json::Error),
    /// JSON, but neither identify's nor diagnose's.
    #[error(
        "expected the JSON of `deploywatch identify` (with \"method\" and \"joints\") \
         or of `deploywatch diagnose` (with \"effects\")"
    )]
    Unknown,
}

/// The keys that tell the two kinds apart.
#[derive(Deserialize)]
struct Kind {
    method: Option<serde::de::IgnoredAny>,
    effects: Option<serde::de::IgnoredAny>,
}

impl Findings {
    /// Reads a findings JSON: an identification if it has `"method"`, a
    /// diagnosis if it has `"effects"`.
    pub fn from_json_str(text: &str) -> Result<Findings, FindingsError> {
        let kind: Kind = serde_json::from_str(text)?;
        if kind.method.is_some() {
            Ok(Findings::Identify(Box::new(serde_json::from_str(text)?)))
        } else if kind.effects.is_some() {
            Ok(Findings::Diagnosis(Box::new(serde_json::from_str(text)?)))
        } else {
            Err(FindingsError::Unknown)
        }
    }
}
