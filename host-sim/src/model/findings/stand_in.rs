//! The wing's own losses a diagnosis could not tell from the ground rig's
//! (`docs/margin.md`, "On orbit"): an ambiguity group of the diagnosis JSON
//! whose alternative set explains the runs without a rig-only effect of the
//! set found (air drag, a tilt; [`EffectKind::rig_only`]) and with a joint
//! effect that flies in its place. A flight margin that left the rig's
//! effect out and took nothing in its place would credit the wing with a
//! loss the runs may have shown to be its own.

use super::diagnosis::{AmbiguousSet, Diagnosis, FoundEffect};
use crate::model::effect::EffectKind;

/// A loss of the wing's own that may stand in for rig-only effects.
#[derive(Clone, Debug, PartialEq)]
pub struct StandIn {
    /// The rig-only effects of the set found it replaces (their kinds).
    pub replaces: Vec<EffectKind>,
    /// The joint effects the alternative adds, as fitted there.
    pub effects: Vec<FoundEffect>,
    /// The ambiguity group's joint (1-based).
    pub joint: usize,
    /// The alternative's BIC minus the set found's.
    pub delta_bic: Option<f64>,
}

/// `name` and `joint` of an entry of an ambiguous set, when it reads.
fn key(v: &serde_json::Value) -> Option<(EffectKind, Option<usize>)> {
    let kind = v.get("name")?.as_str()?.parse().ok()?;
    let joint = v
        .get("joint")
        .and_then(serde_json::Value::as_u64)
        .and_then(|j| usize::try_from(j).ok());
    Some((kind, joint))
}

/// The stand-in `alt` offers for what `found` holds, if it drops a
/// rig-only effect and adds a joint effect that flies.
fn stand_in(found: &AmbiguousSet, alt: &AmbiguousSet, joint: usize) -> Option<StandIn> {
    let keys = |s: &AmbiguousSet| -> Vec<(EffectKind, Option<usize>)> {
        s.effects.iter().filter_map(key).collect()
    };
    let (had, has) = (keys(found), keys(alt));
    let replaces: Vec<EffectKind> = had
        .iter()
        .filter(|k| k.0.rig_only() && !has.contains(k))
        .map(|k| k.0)
        .collect();
    let effects: Vec<FoundEffect> = alt
        .effects
        .iter()
        .filter(|v| key(v).is_some_and(|k| !k.0.rig_only() && k.1.is_some() && !had.contains(&k)))
        .filter_map(|v| serde_json::from_value(v.clone()).ok())
        .collect();
    (!replaces.is_empty() && !effects.is_empty()).then_some(StandIn {
        replaces,
        effects,
        joint,
        delta_bic: alt.delta_bic,
    })
}

impl Diagnosis {
    /// For each rig-only effect of the set found that an ambiguity group
    /// exchanges for a joint effect of the wing, the exchange that explains
    /// the runs best (the lowest BIC over every group), once: the loss the
    /// flight margins keep in the rig effect's place.
    pub fn flight_stand_ins(&self) -> Vec<StandIn> {
        let mut all: Vec<StandIn> = self
            .ambiguities
            .iter()
            .flat_map(|g| {
                let found = g.sets.first();
                g.sets
                    .iter()
                    .skip(1)
                    .filter_map(move |alt| found.and_then(|f| stand_in(f, alt, g.joint)))
            })
            .collect();
        all.sort_by(|a, b| {
            let d = |s: &StandIn| s.delta_bic.unwrap_or(f64::INFINITY);
            d(a).total_cmp(&d(b))
        });
        let mut out: Vec<StandIn> = Vec::new();
        for s in all {
            let new = s
                .replaces
                .iter()
                .any(|k| !out.iter().any(|o| o.replaces.contains(k)));
            if new {
                out.push(s);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::findings::diagnosis::AmbiguityGroup;
    use serde_json::json;

    fn set(effects: Vec<serde_json::Value>, delta_bic: f64) -> AmbiguousSet {
        AmbiguousSet {
            effects,
            rms_deg: Some(0.02),
            delta_bic: Some(delta_bic),
        }
    }

    fn air() -> serde_json::Value {
        json!({"name": "air_drag", "joint": null, "value": 2.9, "ci95": [2.8, 3.0]})
    }

    fn hinge(joint: usize, value: f64) -> serde_json::Value {
        json!({"name": "quadratic_damping", "joint": joint, "value": value, "ci95": [value * 0.9, value * 1.1]})
    }

    fn group(joint: usize, sets: Vec<AmbiguousSet>) -> AmbiguityGroup {
        AmbiguityGroup {
            joint,
            sets,
            separating_test: String::new(),
        }
    }

    #[test]
    fn air_drag_exchanged_for_a_hinge_loss_is_its_stand_in() {
        let d = Diagnosis {
            ambiguities: vec![group(
                1,
                vec![set(vec![air()], 0.0), set(vec![hinge(1, 0.3)], 0.4)],
            )],
            ..Diagnosis::default()
        };
        let s = d.flight_stand_ins();
        assert_eq!(s.len(), 1, "{s:?}");
        assert_eq!(s[0].replaces, vec![EffectKind::AirDrag]);
        assert_eq!(s[0].effects.len(), 1);
        assert_eq!(s[0].effects[0].name, "quadratic_damping");
        assert_eq!(s[0].effects[0].joint, Some(1));
    }

    #[test]
    fn the_best_exchange_of_one_rig_effect_is_taken_once() {
        let d = Diagnosis {
            ambiguities: vec![
                group(
                    1,
                    vec![set(vec![air()], 0.0), set(vec![hinge(1, 0.3)], 6.0)],
                ),
                group(
                    2,
                    vec![set(vec![air()], 0.0), set(vec![hinge(2, 0.1)], 2.0)],
                ),
            ],
            ..Diagnosis::default()
        };
        let s = d.flight_stand_ins();
        assert_eq!(s.len(), 1, "{s:?}");
        assert_eq!(s[0].joint, 2);
    }

    #[test]
    fn an_exchange_between_joint_effects_is_no_stand_in() {
        let coulomb =
            json!({"name": "coulomb_friction", "joint": 1, "value": 0.2, "ci95": [0.1, 0.3]});
        let d = Diagnosis {
            ambiguities: vec![group(
                1,
                vec![
                    set(vec![coulomb, air()], 0.0),
                    set(vec![hinge(1, 0.3), air()], 1.0),
                ],
            )],
            ..Diagnosis::default()
        };
        assert!(d.flight_stand_ins().is_empty());
    }
}
