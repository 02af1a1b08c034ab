//! The identified friction of `deploywatch identify --json` as the laws of
//! a reliability analysis: the one reader of that JSON here, so that it can
//! follow the identify result's format in one place.

use super::params::{Dist, Target, Vary};
use crate::analysis::fit::Z_975;
use crate::model::effect::EffectKind;
use crate::model::findings::{Findings, FindingsError};

/// The identified Coulomb frictions of an identify JSON as normal laws:
/// `"joints": [{"joint": J, "coulomb_nm": T, "ci95": [lo, hi]}, ...]`
/// gives `coulomb_friction:joint=J:normal(T, (hi − lo)/(2·1.96))` (added to
/// the mechanism's own friction, as the identified effects are). The one
/// reader of the identify JSON in the reliability analysis.
pub fn from_identify_json(text: &str) -> Result<Vec<Vary>, String> {
    let expected = "expected the JSON of `deploywatch identify` (with \"method\" and \"joints\")";
    let id = match Findings::from_json_str(text) {
        Ok(Findings::Identify(id)) => id,
        Ok(Findings::Diagnosis(_)) | Err(FindingsError::Unknown) => return Err(expected.into()),
        Err(e) => return Err(e.to_string()),
    };
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
            target: Target::Effect {
                kind: EffectKind::CoulombFriction,
                joint: Some(j.joint),
                alpha_deg: 0.0,
            },
            dist,
        });
    }
    Ok(out)
}
