//! What the drawing's declared tolerances of mass, inertia and spring
//! torque add to the reported intervals, in the diagnosis summary, report
//! and JSON (`docs/diagnosis.md`, "What the drawing's tolerances add").

use crate::analysis::diagnose::{Outcome, WithinTolerance};
use crate::model::findings::diagnosis::{ToleranceJson, WithinToleranceJson};
use crate::model::findings::rounded;
use crate::report::markdown::table;
use std::fmt::Write as _;

/// The standard uncertainties of one effect, `±0.0021` or `±0.01, ±0.3`.
fn sds(sd: &[f64]) -> String {
    sd.iter()
        .map(|u| format!("±{u:.4}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The effect taken out in words: `rig_tilt = 0.00220 m/s²`, with what
/// took its place (`…, spring_softening at joint 4 in its place`).
fn claim_words(w: &WithinTolerance) -> String {
    let words = super::diagnosis_set_aside::effect_words(&w.effect);
    match w.in_its_place {
        Some(c) => format!("{words}, {} in its place", c.words()),
        None => words,
    }
}

/// What the tolerances alone move an effect's parameters by, at 95 %.
fn at_95(sd: &[f64]) -> String {
    sds(&sd
        .iter()
        .map(|u| crate::analysis::fit::Z_975 * u)
        .collect::<Vec<_>>())
}

/// The summary's lines: one per effect the tolerances alone could make,
/// then the shares of the effects found (none without a declared
/// tolerance).
pub fn summary_lines(o: &Outcome) -> Vec<String> {
    let mut out: Vec<String> = o
        .within_tolerance
        .iter()
        .map(|w| {
            format!(
                "within the drawing's tolerances (not an effect): {}; the drawing's declared tolerances of mass, inertia and spring torque alone move it by {} at 95 % (most: {})",
                claim_words(w),
                at_95(&w.share.sd),
                w.share.largest
            )
        })
        .collect();
    out.extend(summary_line(o));
    out
}

/// The line of the effects' shares (none without one).
fn summary_line(o: &Outcome) -> Option<String> {
    if o.tolerance.is_empty() {
        return None;
    }
    let parts: Vec<String> = o
        .tolerance
        .iter()
        .map(|t| format!("{} {}", t.effect, sds(&t.sd)))
        .collect();
    Some(format!(
        "intervals include the drawing's declared tolerances of mass, inertia and spring torque (standard uncertainty from them: {})",
        parts.join("; ")
    ))
}

/// The report's section (none without a declared tolerance).
pub fn report(md: &mut String, o: &Outcome) {
    if o.tolerance.is_empty() && o.within_tolerance.is_empty() {
        return;
    }
    let _ = writeln!(md, "## What the drawing's tolerances add\n");
    let _ = writeln!(
        md,
        "The mechanisms declare their panels' mass and inertia, or their springs' torque, to within a tolerance; the wing as built lies somewhere within it, and the effects' estimates move with them. The set found was fitted again with each declared property at its band's edge; taking each property uniform within its band, the moves give each parameter the standard uncertainty below, and the 95 % intervals above include it (each side widened in quadrature by 1.96 times it).\n"
    );
    let rows: Vec<Vec<String>> = o
        .tolerance
        .iter()
        .map(|t| vec![t.effect.clone(), sds(&t.sd), t.largest.clone()])
        .collect();
    if !rows.is_empty() {
        md.push_str(&table(
            &[
                "effect",
                "standard uncertainty from the tolerances (each parameter, its unit)",
                "the tolerance that moves it most",
            ],
            &rows,
        ));
        let _ = writeln!(md);
    }
    if o.within_tolerance.is_empty() {
        return;
    }
    let _ = writeln!(
        md,
        "Named effects the tolerances alone could make: each was found, but its value lies within what the drawing's tolerances move it by (its fit's interval widened by 1.96 times its share holds zero), so the runs cannot tell it from a wing built within its drawing. Each was taken out, the rest refitted (a Stribeck friction gives way to Coulomb friction at its kinetic level, named beside it); they are not claimed:\n"
    );
    let rows: Vec<Vec<String>> = o
        .within_tolerance
        .iter()
        .map(|w| vec![claim_words(w), at_95(&w.share.sd), w.share.largest.clone()])
        .collect();
    md.push_str(&table(
        &[
            "found",
            "the tolerances alone move it by, at 95 % (each parameter)",
            "the tolerance that moves it most",
        ],
        &rows,
    ));
    let _ = writeln!(md);
}

/// The effects taken out, in the JSON.
pub fn within_json(o: &Outcome) -> Vec<WithinToleranceJson> {
    o.within_tolerance
        .iter()
        .map(|w| {
            let e = w.effect.candidate.effect(&w.effect.params);
            WithinToleranceJson {
                name: e.kind().name().to_string(),
                joint: e.joint,
                value: rounded(e.value()),
                unit: e.kind().unit().to_string(),
                tolerance95: w
                    .share
                    .sd
                    .iter()
                    .map(|u| rounded(crate::analysis::fit::Z_975 * u))
                    .collect(),
                largest: w.share.largest.clone(),
                in_its_place: w.in_its_place.map(|c| c.words()),
            }
        })
        .collect()
}

/// The shares in the JSON.
pub fn json(o: &Outcome) -> Vec<ToleranceJson> {
    o.tolerance
        .iter()
        .map(|t| ToleranceJson {
            effect: t.effect.clone(),
            sd: t.sd.iter().map(|&u| rounded(u)).collect(),
            largest: t.largest.clone(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::diagnose::{Candidate, FittedEffect, ToleranceShare};
    use crate::model::effect::EffectKind;

    /// A Stribeck friction at joint 4 set apart with Coulomb friction in
    /// its place, or without anything in its place.
    fn set_apart(in_its_place: Option<Candidate>) -> WithinTolerance {
        let stribeck = Candidate {
            kind: EffectKind::StribeckFriction,
            joint: Some(4),
            table: None,
        };
        WithinTolerance {
            effect: FittedEffect::start(stribeck, vec![0.46, 0.2, 0.05]),
            in_its_place,
            share: ToleranceShare {
                candidate: stribeck,
                effect: stribeck.words(),
                sd: vec![0.3, 2.0, 0.2],
                largest: "joint 4's spring (±2 %) of w".to_string(),
            },
        }
    }

    #[test]
    fn what_took_a_set_apart_effects_place_is_named_beside_it() {
        let coulomb = Candidate {
            kind: EffectKind::CoulombFriction,
            joint: Some(4),
            table: None,
        };
        let words = claim_words(&set_apart(Some(coulomb)));
        assert!(
            words.starts_with("stribeck_friction at joint 4 = "),
            "{words}"
        );
        assert!(
            words.ends_with(", coulomb_friction at joint 4 in its place"),
            "{words}"
        );
        let alone = claim_words(&set_apart(None));
        assert!(!alone.contains("in its place"), "{alone}");
    }
}
