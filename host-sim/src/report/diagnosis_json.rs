//! The diagnosis JSON (`docs/spec/formats.md`), with the extra fields the
//! project adds (noise floor, candidates, evidence, residual torque, the
//! monitor's tables, latches, ambiguities).

use super::diagnosis_outcome::what_words;
use super::diagnosis_words::{ci_of, evidence_of};
use super::evidence_words::evidence_words;
use super::{diagnosis_latch, diagnosis_torque};
use crate::analysis::diagnose::Outcome;
use crate::analysis::diagnosis_details::{above_noise, gain_ratio, Details};
use crate::analysis::evidence::{JointEvidence, CORRELATES};
use crate::analysis::table_export::TableExport;
use crate::data::campaign::Campaign;
use crate::model::effect::EffectKind;
use crate::model::findings::diagnosis::{
    Diagnosis, Evidence, Fit, FoundEffect, Gain, MonitorTable, Named, ResidualTorque, Round, Score,
};
use crate::model::findings::numbers::exact;
use crate::model::findings::rounded;
use crate::model::torque_table::HostTorqueTable;

/// The diagnosis JSON as text (pretty-printed, a final newline).
pub fn json_text(c: &Campaign, o: &Outcome, d: &Details) -> Result<String, serde_json::Error> {
    let mut doc = to_json(c, o, d);
    add_monitor_tables(&mut doc.effects, &d.exports);
    doc.residual_torque = Some(ResidualTorque {
        baseline: diagnosis_torque::torque_json(&d.torque[0]),
        extended: diagnosis_torque::torque_json(&d.torque[1]),
    });
    Ok(serde_json::to_string_pretty(&doc)? + "\n")
}

/// A table's knots for the JSON, each in full ([`exact`]): the model.
fn exact_all(x: &[f64]) -> Vec<Option<f64>> {
    x.iter().map(|y| exact(*y)).collect()
}

/// A list of numbers for the JSON, each [`rounded`].
fn rounded_all(x: &[f64]) -> Vec<Option<f64>> {
    x.iter().map(|y| rounded(*y)).collect()
}

/// A discovered `torque_table` in the JSON (`docs/spec/formats.md`): its
/// tables, the 95 % band of each knot, and the shape in one sentence.
fn add_tables(v: &mut FoundEffect, shape: &str, t: &[HostTorqueTable; 3]) {
    if let (Some(f), Some(lo), Some(hi)) = (&t[0].angle, &t[1].angle, &t[2].angle) {
        v.angle_deg = Some(exact_all(f.xs()));
        v.torque_nm = Some(exact_all(f.ys()));
        v.torque_ci95_nm = Some([rounded_all(lo.ys()), rounded_all(hi.ys())]);
    }
    if let (Some(g), Some(lo), Some(hi)) = (&t[0].rate, &t[1].rate, &t[2].rate) {
        v.rate_deg_s = Some(exact_all(g.xs()));
        v.rate_torque_nm = Some(exact_all(g.ys()));
        v.rate_torque_ci95_nm = Some([rounded_all(lo.ys()), rounded_all(hi.ys())]);
    }
    v.shape = Some(shape.to_string());
}

/// Puts each table's monitor export beside its `torque_table` in the JSON.
fn add_monitor_tables(effects: &mut [FoundEffect], exports: &[TableExport]) {
    for x in exports {
        let Some(v) = effects
            .iter_mut()
            .find(|e| e.name == EffectKind::TorqueTable.name() && e.joint == Some(x.joint))
        else {
            continue;
        };
        let xs = |t: &Option<deploywatch_core::Table<f64>>| t.as_ref().map(|t| rounded_all(t.xs()));
        let ys = |t: &Option<deploywatch_core::Table<f64>>| t.as_ref().map(|t| rounded_all(t.ys()));
        v.monitor_table = Some(MonitorTable {
            angle_deg: xs(&x.table.angle),
            torque_nm: ys(&x.table.angle),
            rate_deg_s: xs(&x.table.rate),
            rate_torque_nm: ys(&x.table.rate),
            compressed: x.compressed,
            torque_rms_diff_nm: rounded(x.torque_rms_nm),
            torque_max_diff_nm: rounded(x.torque_max_nm),
            angle_rms_diff_deg: x.angle_rms_deg.and_then(rounded),
        });
    }
}

/// Every round's candidates with their scores, for the JSON.
fn candidates_json(o: &Outcome) -> Vec<Round> {
    o.rounds
        .iter()
        .map(|r| Round {
            round: what_words(r),
            start_rms_deg: rounded(r.start_rms_deg),
            scores: r
                .scores
                .iter()
                .map(|s| Score {
                    candidate: s.candidate.label(),
                    rms_deg: rounded(s.fitted.rms()),
                    delta_bic: rounded(s.delta_bic),
                    held_out_rms_deg: s.held_out_rms_deg.and_then(rounded),
                    verdict: s.verdict.to_string(),
                })
                .collect(),
        })
        .collect()
}

/// The evidence of each run and joint before the diagnosis, for the JSON.
fn evidence_json(before: &[JointEvidence]) -> Vec<Evidence> {
    before
        .iter()
        .map(|e| Evidence {
            run: e.run.clone(),
            joint: e.joint,
            rms_deg: rounded(e.rms_deg),
            stroke_thirds_rms_deg: rounded_all(&e.stroke_thirds_rms_deg),
            near_latch_rms_deg: rounded(e.near_latch_rms_deg),
            at_release_mean_deg: rounded(e.at_release_mean_deg),
            after_latch_mean_deg: rounded(e.after_latch_mean_deg),
            latch_lead_s: e.latch_lead_s.and_then(rounded),
            correlation: Named(
                CORRELATES
                    .iter()
                    .zip(e.correlation)
                    .map(|(n, r)| (n.to_string(), rounded(r)))
                    .collect(),
            ),
            summary: evidence_words(e),
        })
        .collect()
}

/// The effects found, for the JSON: each with its interval and evidence,
/// then the residual none of them explains.
fn effects_json(o: &Outcome, before: &[JointEvidence]) -> Vec<FoundEffect> {
    let mut effects: Vec<FoundEffect> = o
        .extended
        .effects()
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let (lo, hi) = ci_of(o, k);
            let mut v = FoundEffect {
                ci95: Some([rounded(lo), rounded(hi)]),
                evidence: evidence_of(o, k, o.extended.members[k].candidate),
                ..FoundEffect::of_effect(e)
            };
            if let Some((_, shape, t)) = o.extended.table_of(k) {
                add_tables(&mut v, &shape, &t);
            }
            if e.kind() == EffectKind::RigTilt {
                if let (_, Some(ci)) = o.extended.effect_ci(k) {
                    v.alpha_ci95_deg = Some([rounded(ci[0]), rounded(ci[1])]);
                }
            }
            if e.kind() == EffectKind::StribeckFriction {
                // Parameters T_C, ΔT, ω_st (`EffectKind::bounds`): the intervals of
                // the last two.
                let ci = o.extended.effect_params(k).map(|(_, ci)| ci);
                let band = |i: usize| {
                    ci.and_then(|c| c.get(i))
                        .map(|c| [rounded(c[0]), rounded(c[1])])
                };
                v.excess_ci95_nm = band(1);
                v.stribeck_ci95_rad_s = band(2);
            }
            v
        })
        .collect();
    if let Some(u) = &o.unexplained {
        effects.push(FoundEffect {
            name: "unexplained".to_string(),
            description: Some(u.to_string()),
            evidence: above_noise(before, o.noise_sigma_deg)
                .map(|e| format!("{}: {}", e.run, evidence_words(e)))
                .collect::<Vec<_>>()
                .join("; "),
            ..FoundEffect::default()
        });
    }
    effects
}

/// The diagnosis JSON without the residual torque and the monitor's tables
/// ([`json_text`] adds them).
fn to_json(c: &Campaign, o: &Outcome, d: &Details) -> Diagnosis {
    let te =
        |v: &[Option<f64>]| -> Vec<Option<f64>> { v.iter().map(|v| v.and_then(rounded)).collect() };
    let mut mechs: Vec<String> = c.runs.iter().map(|r| r.mechanism.name.clone()).collect();
    mechs.dedup();
    Diagnosis {
        mechanism: mechs.first().cloned().unwrap_or_default(),
        mechanisms: mechs,
        runs: c.runs.iter().map(|r| r.name()).collect(),
        noise_sigma_deg: rounded(o.noise_sigma_deg),
        baseline: Fit {
            rms_deg: rounded(o.baseline.rms()),
            trajectory_error_pct: te(&d.trajectory_error_pct[0]),
        },
        effects: effects_json(o, &d.before),
        extended: Fit {
            rms_deg: rounded(o.extended.rms()),
            trajectory_error_pct: te(&d.trajectory_error_pct[1]),
        },
        gain: Gain {
            rms_ratio: rounded(gain_ratio(o)),
            held_out_rms_deg: o.held_out_rms_deg.and_then(rounded),
        },
        candidates: candidates_json(o),
        evidence: evidence_json(&d.before),
        simulations: o.simulations,
        wall_s: rounded(o.wall_s),
        residual_torque: None,
        partial: o.partial.map(|p| p.to_string()),
        encoder_delay: super::diagnosis_delay::json(c, o),
        flexible_panels: super::diagnosis_flex::json(o),
        free_window: diagnosis_latch::windows_json(c, o.free_window.as_deref()),
        fitted_whole: o.fitted_whole,
        fitted_window: diagnosis_latch::windows_json(c, o.fitted_to.as_deref()),
        whole_run: diagnosis_latch::whole_run_json(o),
        latches: diagnosis_latch::latches_json(o),
        ambiguities: diagnosis_latch::ambiguities_json(o),
        set_aside: super::diagnosis_set_aside::json(o),
        free_play: super::diagnosis_free_play::json(o),
        tolerance: super::diagnosis_tolerance::json(o),
        within_tolerance: super::diagnosis_tolerance::within_json(o),
    }
}
