//! What `deploywatch identify --json` and `deploywatch diagnose --json`
//! found, as the laws of a reliability analysis (`reliability --from`): the
//! one reader of those files here, so that it follows their format in one
//! place. A diagnosis's effects are read by the findings' own reader
//! ([`FoundEffect::to_effect`](crate::model::findings::diagnosis::FoundEffect::to_effect)),
//! so the law of each is centred on the value fitted, its other parameters
//! (joint, direction, Stribeck shape) as fitted.

use super::params::{Dist, Target, Vary};
use crate::analysis::fit::Z_975;
use crate::model::effect::{Effect, EffectKind};
use crate::model::findings::{Diagnosis, Findings, FindingsError, Identification};

/// The laws of an identify or a diagnose JSON ([`from_identification`],
/// [`from_diagnosis`]).
pub fn from_findings_json(text: &str) -> Result<Vec<Vary>, String> {
    let expected = "expected the JSON of `deploywatch identify` (with \"method\" and \"joints\") \
                    or of `deploywatch diagnose` (with \"effects\")";
    match Findings::from_json_str(text) {
        Ok(Findings::Identify(id)) => from_identification(&id),
        Ok(Findings::Diagnosis(d)) => from_diagnosis(&d),
        Err(FindingsError::Unknown) => Err(expected.into()),
        Err(e) => Err(e.to_string()),
    }
}

/// The identified Coulomb frictions of an identify JSON as normal laws:
/// `"joints": [{"joint": J, "coulomb_nm": T, "ci95": [lo, hi]}, ...]`
/// gives `coulomb_friction:joint=J:normal(T, (hi − lo)/(2·1.96))` (added to
/// the mechanism's own friction, as the identified effects are).
pub fn from_identification(id: &Identification) -> Result<Vec<Vary>, String> {
    let mut out = Vec::new();
    for (i, j) in id.joints.iter().enumerate() {
        let at = |key: &str| format!("joints[{i}]: expected \"{key}\"");
        if j.joint < 1 {
            return Err(at("joint") + ", a joint number from 1");
        }
        let t = j.coulomb_nm;
        let Some([lo, hi]) = j.ci95 else {
            return Err(at("ci95") + ", [lo, hi] in N·m");
        };
        let sd = (hi - lo) / (2.0 * Z_975);
        let dist = Dist::Normal { mean: t, sd };
        dist.check().map_err(|w| {
            format!("joints[{i}]: normal({t},{sd}) from the interval: expected {w}")
        })?;
        out.push(Vary {
            target: Target::of_effect(&Effect::joint(EffectKind::CoulombFriction, j.joint, t)),
            dist,
        });
    }
    Ok(out)
}

/// The named effects of a diagnosis as normal laws: each effect's value
/// centred on the value fitted with the standard deviation of its 95 %
/// interval, `(hi − lo)/(2·1.96)`, every other parameter as fitted. An
/// entry that is no named effect (`"unexplained"`) has no law and is left
/// out; a `torque_table` (tables, not one value) or an effect without an
/// interval is refused, naming it.
pub fn from_diagnosis(d: &Diagnosis) -> Result<Vec<Vary>, String> {
    let mut out = Vec::new();
    for (i, f) in d.effects.iter().enumerate() {
        let Some(e) = f.to_effect(i).map_err(|e| e.to_string())? else {
            continue;
        };
        let at = format!("effects[{i}] ({})", f.name);
        if e.kind == EffectKind::TorqueTable {
            return Err(format!(
                "{at}: a torque table has no one value to draw; give its joint's friction \
                 with --vary instead (margin --from takes the table as found)"
            ));
        }
        let Some([Some(lo), Some(hi)]) = f.ci95 else {
            return Err(format!(
                "{at}: expected \"ci95\", [lo, hi] in {}",
                e.kind.unit()
            ));
        };
        let sd = (hi - lo) / (2.0 * Z_975);
        let dist = Dist::Normal { mean: e.value, sd };
        dist.check().map_err(|w| {
            format!(
                "{at}: normal({},{sd}) from the interval: expected {w}",
                e.value
            )
        })?;
        out.push(Vary {
            target: Target::of_effect(&e),
            dist,
        });
    }
    Ok(out)
}
