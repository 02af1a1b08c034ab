//! One effect to its entry of the diagnosis JSON and back
//! (`docs/spec/formats.md`, "Diagnosis: JSON"): the one place that knows
//! which parameters each effect kind carries in the file. The reader goes
//! through the effect syntax (`--effect`, [`Effect`]'s `FromStr`), so a
//! finding read back is checked as a user's `--effect` is.

use super::diagnosis::{Diagnosis, FoundEffect};
use super::numbers::exact;
use crate::model::effect::{Effect, EffectError, EffectKind, Key};

/// Why an entry of `effects` is not an effect the simulator can replay.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FoundEffectError {
    /// A parameter its kind needs is absent or `null`.
    #[error("effects[{index}] ({name}): expected \"{key}\", a number")]
    Missing {
        /// Position in `effects`, from 0.
        index: usize,
        /// The entry's `name`.
        name: String,
        /// The key missing.
        key: &'static str,
    },
    /// The parameters do not make the effect (out of range, a bad table).
    #[error("effects[{index}] ({name}): {source}")]
    Bad {
        /// Position in `effects`, from 0.
        index: usize,
        /// The entry's `name`.
        name: String,
        /// What the effect syntax says of it.
        source: EffectError,
    },
    /// A name that is neither an effect of `physics.md` section 6 nor
    /// `"unexplained"` (a misspelt or a newer kind): refused, never left
    /// out in silence.
    #[error(
        "effects[{index}] ({name}): not an effect this version knows: expected one of {known}, or \"unexplained\""
    )]
    Unknown {
        /// Position in `effects`, from 0.
        index: usize,
        /// The entry's `name`.
        name: String,
        /// The names this version reads, comma-separated.
        known: String,
    },
}

/// The `name` of an entry that is no effect: what no effect of the
/// vocabulary explains (`formats.md`, "Diagnosis: JSON").
pub const UNEXPLAINED: &str = "unexplained";

impl FoundEffect {
    /// The entry of `effect` without interval or evidence: name, joint,
    /// value, unit and every parameter its kind carries (`rig_tilt`'s
    /// `alpha_deg`, `stribeck_friction`'s `excess_nm` and `stribeck_rad_s`,
    /// a `torque_table`'s tables), each in full ([`exact`]: read back, it is the same `f64`).
    pub fn of_effect(e: &Effect) -> FoundEffect {
        let all = |x: &[f64]| x.iter().map(|y| exact(*y)).collect::<Vec<_>>();
        let mut v = FoundEffect {
            name: e.kind().name().to_string(),
            joint: e.joint,
            value: exact(e.value()),
            unit: Some(e.kind().unit().to_string()),
            ..FoundEffect::default()
        };
        for (key, xs) in e.law.keys() {
            let one = xs.first().and_then(|x| exact(*x));
            match key {
                Key::AlphaDeg => v.alpha_deg = one,
                Key::ExcessNm => v.excess_nm = one,
                Key::StribeckRadS => v.stribeck_rad_s = one,
                Key::AngleDeg => v.angle_deg = Some(all(&xs)),
                Key::TorqueNm => v.torque_nm = Some(all(&xs)),
                Key::RateDegS => v.rate_deg_s = Some(all(&xs)),
                Key::RateTorqueNm => v.rate_torque_nm = Some(all(&xs)),
            }
        }
        v
    }

    /// The effect this entry names, read from the file alone (`index`: its
    /// position in `effects`, for the error); `None` for the entry that is
    /// no effect of the vocabulary ([`UNEXPLAINED`]); any other name is
    /// refused ([`FoundEffectError::Unknown`]).
    pub fn to_effect(&self, index: usize) -> Result<Option<Effect>, FoundEffectError> {
        let Ok(kind) = self.name.parse::<EffectKind>() else {
            if self.name == UNEXPLAINED {
                return Ok(None);
            }
            let known: Vec<&str> = EffectKind::EVERY.iter().map(|k| k.name()).collect();
            return Err(FoundEffectError::Unknown {
                index,
                name: self.name.clone(),
                known: known.join(", "),
            });
        };
        let missing = |key| FoundEffectError::Missing {
            index,
            name: self.name.clone(),
            key,
        };
        let num = |x: Option<f64>, key| x.ok_or_else(|| missing(key));
        let list = |x: &Option<Vec<Option<f64>>>, key| -> Result<Option<String>, _> {
            let Some(x) = x else { return Ok(None) };
            let x: Option<Vec<String>> = x.iter().map(|y| y.map(|y| y.to_string())).collect();
            x.map(|x| Some(x.join(","))).ok_or_else(|| missing(key))
        };
        let mut text = kind.name().to_string();
        if let Some(j) = self.joint {
            text += &format!(":joint={j}");
        }
        if kind == EffectKind::TorqueTable {
            for (x, key) in [
                (&self.angle_deg, "angle_deg"),
                (&self.torque_nm, "torque_nm"),
                (&self.rate_deg_s, "rate_deg_s"),
                (&self.rate_torque_nm, "rate_torque_nm"),
            ] {
                if let Some(l) = list(x, key)? {
                    text += &format!(":{key}={l}");
                }
            }
        } else {
            text += &format!(":value={}", num(self.value, "value")?);
        }
        if kind == EffectKind::RigTilt {
            text += &format!(":alpha_deg={}", num(self.alpha_deg, "alpha_deg")?);
        }
        if kind == EffectKind::StribeckFriction {
            let ex = num(self.excess_nm, "excess_nm")?;
            let st = num(self.stribeck_rad_s, "stribeck_rad_s")?;
            text += &format!(":excess_nm={ex}:stribeck_rad_s={st}");
        }
        text.parse::<Effect>()
            .map(Some)
            .map_err(|source| FoundEffectError::Bad {
                index,
                name: self.name.clone(),
                source,
            })
    }
}

impl FoundEffect {
    /// An entry that is no effect, in words: `unexplained: DESCRIPTION`.
    pub fn no_effect_words(&self) -> String {
        match &self.description {
            Some(d) => format!("{}: {d}", self.name),
            None => self.name.clone(),
        }
    }
}

impl Diagnosis {
    /// The diagnosis's answer in words when it names no effect of the
    /// vocabulary (none found, or only [`UNEXPLAINED`]); `None` when it
    /// names one (a name this version does not know counts as one: its
    /// reader refuses it by name).
    pub fn answer_without_effect(&self) -> Option<String> {
        let named =
            (self.effects.iter().enumerate()).any(|(i, f)| !matches!(f.to_effect(i), Ok(None)));
        if named {
            return None;
        }
        Some(match self.effects.first() {
            None => "no effect found (the mechanisms as given explain the runs)".to_string(),
            Some(f) => f.no_effect_words(),
        })
    }

    /// The effects of the extended model, read from the file alone, in the
    /// file's order (entries that are no effect, `"unexplained"`, left out):
    /// what `deploywatch simulate --from` replays.
    pub fn extended_effects(&self) -> Result<Vec<Effect>, FoundEffectError> {
        let mut out = Vec::new();
        for (i, e) in self.effects.iter().enumerate() {
            if let Some(e) = e.to_effect(i)? {
                out.push(e);
            }
        }
        Ok(out)
    }
}
