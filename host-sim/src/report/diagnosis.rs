//! The diagnosis report (Markdown) and its plots, beside the diagnosis
//! JSON: the headline numbers, the causes found, discovered torques, what
//! the baseline gets wrong, the residual torque, per-run plots, every
//! round of the search, and the next command to run
//! (`docs/diagnosis.md`).

use super::{diagnosis_latch, diagnosis_plots, diagnosis_torque};
use crate::analysis::diagnose::{Candidate, Outcome, MIN_DELTA_BIC};
use crate::analysis::diagnosis_details::{gain_ratio, Details};
use crate::analysis::evidence::JointEvidence;
use crate::data::campaign::Campaign;
use crate::report::diagnosis_outcome::what_words;
use crate::report::diagnosis_words::{ci_of, evidence_of};
use crate::report::evidence_words::evidence_words;
use crate::report::markdown::table;
use crate::report::plot::PlotError;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The Markdown report of `o` (with `d`, on campaign `c`), its plots drawn
/// into `dir` as `STEM_*.png` (the report's own folder, where it links
/// them), ending with `next` ([`next_step`]).
pub fn markdown(
    dir: &Path,
    stem: &str,
    c: &Campaign,
    o: &Outcome,
    d: &Details,
    next: &str,
) -> Result<String, PlotError> {
    let mut md = String::new();
    report_header(&mut md, c, o);
    super::diagnosis_delay::report(&mut md, c, o);
    super::diagnosis_flex::report(&mut md, o);
    diagnosis_latch::report(&mut md, c, o);
    report_causes(&mut md, o);
    super::diagnosis_set_aside::report(&mut md, o);
    super::diagnosis_free_play::report(&mut md, o);
    super::diagnosis_tolerance::report(&mut md, o);
    diagnosis_plots::report_tables(&mut md, dir, stem, o)?;
    report_evidence(&mut md, &d.before, &d.after);
    diagnosis_torque::report_torque(&mut md, dir, stem, &d.torque[0], &d.torque[1])?;
    let _ = writeln!(md, "\n## Plots\n");
    for (i, models) in d.runs.iter().enumerate() {
        diagnosis_plots::report_run_plots(&mut md, dir, stem, c, i, models)?;
    }
    report_rounds(&mut md, o);
    let _ = writeln!(md, "{} simulations in {:.2} s.\n", o.simulations, o.wall_s);
    md.push_str(next);
    Ok(md)
}

/// A path as one shell word: as it is when it holds only characters no
/// shell reads specially, else in single quotes.
fn shell_word(p: &Path) -> String {
    let s = p.display().to_string();
    let plain = |c: char| c.is_ascii_alphanumeric() || "-_./+=:,@%".contains(c);
    if !s.is_empty() && s.chars().all(plain) {
        s
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

/// The report's last section: what to run next with what was found (the
/// diagnosis JSON `json`) — the torque margins of each of `mechanisms`
/// with the diagnosis's resistances (`margin --from`), and the reliability
/// with them (`reliability --from`), each command as it runs. When the
/// diagnosis names no effect (`named` false: none found, or only what
/// stays unexplained), the two commands refuse the file or give the
/// mechanism's own figures (`docs/margin.md`, `docs/reliability.md`, "From
/// a diagnosis"): the section says so and gives the margins of the
/// mechanisms as given.
pub fn next_step(json: &Path, mechanisms: &[PathBuf], named: bool) -> String {
    let json = shell_word(json);
    if !named {
        let mut s = String::from(
            "## Next step\n\nThe diagnosis names no effect, so there is nothing to carry into \
             the margins or the reliability (`margin --from` and `reliability --from` say so). \
             The margins of each mechanism as given:\n\n```sh\n",
        );
        for m in mechanisms {
            let _ = writeln!(
                s,
                "deploywatch margin --mechanism {} --standard ecss-e-st-33-01c",
                shell_word(m)
            );
        }
        s.push_str("```\n");
        return s;
    }
    let mut s = String::from(
        "## Next step\n\nThe torque margins of each mechanism with the resistances found \
         (every named effect at the end of its 95 % interval that lowers the margin):\n\n```sh\n",
    );
    for m in mechanisms {
        let _ = writeln!(
            s,
            "deploywatch margin --mechanism {} --from {json} --standard ecss-e-st-33-01c",
            shell_word(m)
        );
    }
    s.push_str(
        "```\n\nThe probability of a failed deployment of each, every effect found drawn from \
         its 95 % interval (`docs/reliability.md`, \"From a diagnosis\"; add `--vary` for \
         other uncertain parameters):\n\n```sh\n",
    );
    for m in mechanisms {
        let _ = writeln!(
            s,
            "deploywatch reliability {} --from {json} --fail not_latched",
            shell_word(m)
        );
    }
    s.push_str("```\n");
    s
}

/// Title and headline numbers.
fn report_header(md: &mut String, c: &Campaign, o: &Outcome) {
    let runs: Vec<String> = c.runs.iter().map(|r| r.name()).collect();
    let _ = writeln!(md, "# Diagnosis: {}\n", runs.join(", "));
    let _ = writeln!(
        md,
        "Baseline RMS **{:.4}°** → extended **{:.4}°** (×{:.1}); noise floor estimated from the runs {:.4}°{}.\n",
        o.baseline.rms(),
        o.extended.rms(),
        gain_ratio(o),
        o.noise_sigma_deg,
        o.held_out_rms_deg
            .map(|h| format!("; held-out RMS (fit on the other runs) {h:.4}°"))
            .unwrap_or_default()
    );
}

/// The causes found, with values, intervals and evidence; and what stays
/// unexplained.
fn report_causes(md: &mut String, o: &Outcome) {
    let ext = o.extended.effects();
    let _ = writeln!(md, "## Causes found\n");
    if ext.is_empty() && o.unexplained.is_some() {
        let _ = writeln!(
            md,
            "None claimed, and the mechanisms as given leave the runs above the noise: see what stays unexplained below.\n"
        );
    } else if ext.is_empty() {
        let _ = writeln!(
            md,
            "None: the mechanisms as given explain the runs down to the sensor noise.\n"
        );
    } else {
        let rows = ext.iter().enumerate().map(|(k, e)| {
            let (lo, hi) = ci_of(o, k);
            // A tilt says its direction; a fitted table its shape.
            let extra = match e.tilt_alpha_deg() {
                Some(alpha_deg) => format!(" (α = {alpha_deg:.1}°)"),
                None => o
                    .extended
                    .table_of(k)
                    .map_or_else(String::new, |(_, shape, _)| format!(" (largest; {shape})")),
            };
            let unit = match e.kind().unit() {
                "1" => "(dimensionless)",
                u => u,
            };
            vec![
                format!("`{}`", e.kind()),
                e.joint.map(|j| j.to_string()).unwrap_or_else(|| "—".into()),
                format!("{:.5} {unit}{extra}", e.value()),
                format!("{lo:.5} … {hi:.5}"),
                evidence_of(o, k, o.extended.members[k].candidate),
            ]
        });
        md.push_str(&table(
            &["effect", "joint", "value", "95 % CI", "evidence"],
            rows,
        ));
        md.push('\n');
    }
    if let Some(u) = &o.unexplained {
        let _ = writeln!(md, "**Unexplained:** {u}.\n");
    }
}

/// Residual evidence before and after the extension.
fn report_evidence(md: &mut String, before: &[JointEvidence], after: &[JointEvidence]) {
    let _ = writeln!(md, "## What the baseline gets wrong\n");
    for e in before {
        let _ = writeln!(md, "- {}: {}", e.run, evidence_words(e));
    }
    let _ = writeln!(md, "\nAfter the extension:\n");
    for e in after {
        let _ = writeln!(md, "- {}: {}", e.run, evidence_words(e));
    }
}

/// Every candidate of every round, with its score and verdict.
fn report_rounds(md: &mut String, o: &Outcome) {
    let _ = writeln!(md, "## Why the winner won: every candidate, every round\n");
    let _ = writeln!(
        md,
        "An effect is kept only if it improves the BIC by more than {MIN_DELTA_BIC}, its 95 % interval excludes zero, and (with two or more runs) the set it joins predicts held-out runs at least 5 % better. When no single candidate passes, pairs are fitted jointly and the held-out check applies to the pair.\n"
    );
    for r in &o.rounds {
        let _ = writeln!(
            md,
            "### {} (start RMS {:.4}°)\n",
            what_words(r),
            r.start_rms_deg
        );
        md.push_str(&table(
            &[
                "candidate",
                "RMS [°]",
                "ΔBIC",
                "held-out RMS [°]",
                "verdict",
            ],
            r.scores.iter().map(|s| {
                vec![
                    labels_of(&s.fitted.candidates()),
                    format!("{:.4}", s.fitted.rms()),
                    format!("{:.1}", s.delta_bic),
                    s.held_out_rms_deg
                        .map(|h| format!("{h:.4}"))
                        .unwrap_or_else(|| "—".into()),
                    s.verdict.to_string(),
                ]
            }),
        ));
        md.push('\n');
    }
}

/// `a, b` of a set's labels.
fn labels_of(set: &[Candidate]) -> String {
    set.iter().map(|c| c.words()).collect::<Vec<_>>().join(", ")
}
