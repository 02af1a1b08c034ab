//! Claims set aside within the discrepancy, in the diagnosis summary,
//! report and JSON (`docs/diagnosis.md`, "Claims within the discrepancy").

use crate::analysis::diagnose::{FittedEffect, Outcome, SetAside};
use crate::model::findings::diagnosis::SetAsideJson;
use crate::model::findings::rounded;
use crate::report::markdown::table;
use std::fmt::Write as _;

/// A fitted effect in words: `coulomb_friction at joint 1 = 0.03350 N·m`.
pub fn effect_words(f: &FittedEffect) -> String {
    let e = f.candidate.effect(&f.params);
    let unit = match e.kind().unit() {
        "1" => String::new(),
        u => format!(" {u}"),
    };
    format!("{} = {:.5}{unit}", f.candidate.words(), e.value())
}

/// The claim set aside in words ([`effect_words`]).
fn claim_words(s: &SetAside) -> String {
    effect_words(&s.effect)
}

/// What took its place, in words: ` for coulomb_friction at joint 2`, or
/// nothing when it was dropped.
fn in_place(s: &SetAside) -> String {
    if s.replaced_by.is_empty() {
        return String::new();
    }
    let names: Vec<String> = s.replaced_by.iter().map(|c| c.words()).collect();
    format!(" for {}", names.join(" + "))
}

/// The summary's lines, one per claim set aside.
pub fn summary_lines(o: &Outcome) -> Vec<String> {
    o.set_aside
        .iter()
        .map(|s| {
            format!(
                "set aside: {}{} accounts for {:.4} deg RMS, less than the {:.4} deg left unexplained: the runs cannot tell it from that",
                claim_words(s),
                in_place(s),
                s.explained_deg,
                s.discrepancy_deg
            )
        })
        .collect()
}

/// The report's section (none when nothing was set aside).
pub fn report(md: &mut String, o: &Outcome) {
    if o.set_aside.is_empty() {
        return;
    }
    let _ = writeln!(md, "## Claims set aside within the discrepancy\n");
    let _ = writeln!(
        md,
        "The set found leaves a residual clearly above the noise: something the named effects do not hold is in the runs. A claim that accounts for less of the runs than that discrepancy (the RMS its loss adds, against the RMS of the residual above the noise) cannot be told from it, and is not claimed; a torque table whose shape beyond a named law at its joint accounts for less gives way to that law. Each was fitted and dropped (or exchanged) in turn, the rest refitted:\n"
    );
    let rows: Vec<Vec<String>> = o
        .set_aside
        .iter()
        .map(|s| {
            let ([lo, hi], _) = s.effect.value_ci();
            vec![
                claim_words(s),
                if s.replaced_by.is_empty() {
                    "dropped".to_string()
                } else {
                    in_place(s).trim_start_matches(" for ").to_string()
                },
                format!("{lo:.5} .. {hi:.5}"),
                format!("{:.4}", s.explained_deg),
                format!("{:.4}", s.discrepancy_deg),
            ]
        })
        .collect();
    md.push_str(&table(
        &[
            "claim",
            "in its place",
            "95 % CI",
            "accounts for [deg RMS]",
            "left unexplained [deg RMS]",
        ],
        &rows,
    ));
    let _ = writeln!(md);
}

/// The claims set aside in the JSON.
pub fn json(o: &Outcome) -> Vec<SetAsideJson> {
    o.set_aside
        .iter()
        .map(|s| {
            let e = s.effect.candidate.effect(&s.effect.params);
            let ([lo, hi], _) = s.effect.value_ci();
            SetAsideJson {
                name: e.kind().name().to_string(),
                joint: e.joint,
                value: rounded(e.value()),
                unit: e.kind().unit().to_string(),
                ci95: [rounded(lo), rounded(hi)],
                replaced_by: s.replaced_by.iter().map(|c| c.words()).collect(),
                explained_deg: rounded(s.explained_deg),
                discrepancy_deg: rounded(s.discrepancy_deg),
            }
        })
        .collect()
}
