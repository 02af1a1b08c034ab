//! The diagnosis in words: one line per effect found, its evidence, the
//! monitor's export of a discovered table, and the summary `diagnose`
//! prints on stdout.

use super::diagnosis_latch;
use super::diagnosis_outcome::what_words;
use crate::analysis::diagnose::{Candidate, Outcome};
use crate::analysis::diagnosis_details::{alternatives, gain_ratio, Details};
use crate::analysis::table_export::TableExport;
use crate::model::effect::{Effect, EffectKind};
use std::fmt::Write as _;
use std::path::Path;

/// ` N·m` after a value, or `, a dimensionless fraction` for unit `1` (as
/// `simulate --help` says it).
fn unit_words(kind: EffectKind) -> String {
    match kind.unit() {
        "1" => ", a dimensionless fraction".to_string(),
        u => format!(" {u}"),
    }
}

/// The k-th effect found, its value and 95 % interval in one line.
fn effect_line(e: &Effect, o: &Outcome, k: usize) -> String {
    let (lo, hi) = ci_of(o, k);
    let mut s = format!(
        "{}{} = {:.5}{} (95 % CI {:.5} .. {:.5})",
        e.kind(),
        e.joint
            .map(|j| format!(" at joint {j}"))
            .unwrap_or_default(),
        e.value(),
        unit_words(e.kind()),
        lo,
        hi
    );
    if let Some(alpha_deg) = e.tilt_alpha_deg() {
        s += &format!(", alpha {alpha_deg:.1} deg");
    }
    if let Some((_, shape, _)) = o.extended.table_of(k) {
        s += &format!(" (largest torque; {shape})");
    }
    if e.kind().is_rig() {
        s += " — of the test rig, not of the flight unit";
    }
    s
}

/// The 95 % interval of the k-th selected effect's value.
pub fn ci_of(o: &Outcome, k: usize) -> (f64, f64) {
    let ([lo, hi], _) = o.extended.effect_ci(k);
    (lo, hi)
}

/// The evidence of the k-th effect found (candidate `c`): the round that
/// chose it, what the extended model loses without it, the candidates
/// nearly as good.
pub fn evidence_of(o: &Outcome, k: usize, c: Candidate) -> String {
    let mut s = String::new();
    for r in &o.rounds {
        if let Some(win) = r.scores.iter().find(|s| s.accepted() && s.candidate == c) {
            let _ = write!(
                s,
                "{}: RMS {:.4} -> {:.4} deg, BIC gain {:.1}",
                what_words(r),
                r.start_rms_deg,
                win.fitted.rms(),
                win.delta_bic
            );
            if let Some(h) = win.held_out_rms_deg {
                let _ = write!(s, ", held-out RMS {h:.4} deg");
            }
        }
    }
    let _ = write!(
        s,
        "; without it the extended model's RMS is {:.4} deg",
        o.strength_rms_deg.get(k).copied().unwrap_or(f64::NAN)
    );
    let alt = alternatives(o, c);
    if !alt.is_empty() {
        let names: Vec<String> = alt
            .iter()
            .map(|(a, d)| format!("{} (BIC {d:.1} worse)", a.words()))
            .collect();
        let _ = write!(s, "; nearly as good: {}", names.join(", "));
    }
    s
}

/// The monitor's export of a discovered table, in one line.
fn export_line(x: &TableExport) -> String {
    let points = |t: &Option<deploywatch_core::Table<f64>>| t.as_ref().map_or(0, |t| t.xs().len());
    let (na, nr) = (points(&x.table.angle), points(&x.table.rate));
    if !x.compressed {
        return format!(
            "monitor table at joint {}: as found ({na} angle and {nr} rate points), no loss",
            x.joint
        );
    }
    format!(
        "monitor table at joint {}: compressed to {na} angle and {nr} rate points; torque difference RMS {:.4} N·m (max {:.4}), re-simulated angles RMS {} deg",
        x.joint,
        x.torque_rms_nm,
        x.torque_max_nm,
        x.angle_rms_deg
            .map_or("n/a".to_string(), |a| format!("{a:.4}"))
    )
}

/// The result `diagnose` prints on stdout, line by line: the headline
/// numbers, the causes found, what is unexplained, the latch and
/// ambiguity findings, the exported tables, where the files went.
pub fn summary(o: &Outcome, d: &Details, json: &Path, report: &Path) -> Vec<String> {
    let ext_effects = o.extended.effects();
    let mut out = vec![format!(
        "baseline RMS {:.4} deg -> extended {:.4} deg (x{:.1}); noise floor {:.4} deg",
        o.baseline.rms(),
        o.extended.rms(),
        gain_ratio(o),
        o.noise_sigma_deg
    )];
    for (k, e) in ext_effects.iter().enumerate() {
        out.push(format!("  {}", effect_line(e, o, k)));
    }
    if ext_effects.is_empty() && o.unexplained.is_none() {
        out.push("  no effect: the mechanisms as given explain the runs to the noise".into());
    }
    if let Some(u) = &o.unexplained {
        out.push(format!("  unexplained: {u}"));
    }
    if let Some(line) = super::diagnosis_delay::summary_line(o) {
        out.push(format!("  {line}"));
    }
    if let Some(line) = super::diagnosis_flex::summary_line(o) {
        out.push(format!("  {line}"));
    }
    for line in super::diagnosis_set_aside::summary_lines(o) {
        out.push(format!("  {line}"));
    }
    for line in super::diagnosis_free_play::summary_lines(o) {
        out.push(format!("  {line}"));
    }
    for line in super::diagnosis_tolerance::summary_lines(o) {
        out.push(format!("  {line}"));
    }
    for line in diagnosis_latch::summary_lines(o) {
        out.push(format!("  {line}"));
    }
    for x in &d.exports {
        out.push(format!("  {}", export_line(x)));
    }
    out.push(format!(
        "{} simulations in {:.2} s; JSON {}; report {}",
        o.simulations,
        o.wall_s,
        json.display(),
        report.display()
    ));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dimensionless_value_is_said_in_words_not_unit_1() {
        assert_eq!(
            unit_words(EffectKind::SpringSoftening),
            ", a dimensionless fraction"
        );
        assert_eq!(unit_words(EffectKind::CoulombFriction), " N·m");
    }
}
