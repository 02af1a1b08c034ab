//! The identified friction of `deploywatch identify --json` as the laws of
//! a reliability analysis: the one reader of that JSON here, so that it can
//! follow the identify result's format in one place.

use super::params::{Dist, Target, Vary};
use crate::model::effect::EffectKind;

/// The identified Coulomb frictions of an identify JSON as normal laws:
/// `"joints": [{"joint": J, "coulomb_nm": T, "ci95": [lo, hi]}, ...]`
/// gives `coulomb_friction:joint=J:normal(T, (hi − lo)/(2·1.96))` (added to
/// the mechanism's own friction, as the identified effects are). The one
/// reader of the identify JSON in the reliability analysis.
pub fn from_identify_json(text: &str) -> Result<Vec<Vary>, String> {
    let doc: serde_json::Value =
        serde_json::from_str(text).map_err(|e| format!("not JSON ({e})"))?;
    let joints = doc
        .get("joints")
        .and_then(|j| j.as_array())
        .filter(|_| doc.get("method").is_some())
        .ok_or("expected the JSON of `deploywatch identify` (with \"method\" and \"joints\")")?;
    let mut out = Vec::new();
    for (i, j) in joints.iter().enumerate() {
        let at = |key: &str| format!("joints[{i}]: expected \"{key}\"");
        let joint = j
            .get("joint")
            .and_then(|v| v.as_u64())
            .filter(|&v| v >= 1)
            .ok_or_else(|| at("joint") + ", a joint number from 1")? as usize;
        let t = j
            .get("coulomb_nm")
            .and_then(|v| v.as_f64())
            .ok_or_else(|| at("coulomb_nm") + ", a number")?;
        let ci: Vec<f64> = j
            .get("ci95")
            .and_then(|v| v.as_array())
            .map(|a| a.iter().filter_map(|v| v.as_f64()).collect())
            .unwrap_or_default();
        let [lo, hi] = ci[..] else {
            return Err(at("ci95") + ", [lo, hi] in N·m");
        };
        let sd = (hi - lo) / (2.0 * 1.959963984540054);
        let dist = Dist::Normal { mean: t, sd };
        dist.check().map_err(|w| {
            format!("joints[{i}]: normal({t},{sd}) from the interval: expected {w}")
        })?;
        out.push(Vary {
            target: Target::Effect {
                kind: EffectKind::CoulombFriction,
                joint: Some(joint),
                alpha_deg: 0.0,
            },
            dist,
        });
    }
    Ok(out)
}
