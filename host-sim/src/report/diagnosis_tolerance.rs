//! What the panels' declared mass-property tolerances add to the reported
//! intervals, in the diagnosis summary, report and JSON
//! (`docs/diagnosis.md`, "What the drawing's tolerances add").

use crate::analysis::diagnose::Outcome;
use crate::model::findings::diagnosis::ToleranceJson;
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

/// The summary's line (none without a declared tolerance).
pub fn summary_line(o: &Outcome) -> Option<String> {
    if o.mass_tolerance.is_empty() {
        return None;
    }
    let parts: Vec<String> = o
        .mass_tolerance
        .iter()
        .map(|t| format!("{} {}", t.effect, sds(&t.sd)))
        .collect();
    Some(format!(
        "intervals include the panels' declared mass-property tolerances (standard uncertainty from them: {})",
        parts.join("; ")
    ))
}

/// The report's section (none without a declared tolerance).
pub fn report(md: &mut String, o: &Outcome) {
    if o.mass_tolerance.is_empty() {
        return;
    }
    let _ = writeln!(md, "## What the drawing's tolerances add\n");
    let _ = writeln!(
        md,
        "The mechanisms declare their panels' mass and inertia to within a tolerance; the panels as built lie somewhere within it, and the effects' estimates move with them. The set found was fitted again with each declared property at its band's edge; taking each property uniform within its band, the moves give each parameter the standard uncertainty below, and the 95 % intervals above include it (each side widened in quadrature by 1.96 times it).\n"
    );
    let rows: Vec<Vec<String>> = o
        .mass_tolerance
        .iter()
        .map(|t| vec![t.effect.clone(), sds(&t.sd), t.largest.clone()])
        .collect();
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

/// The shares in the JSON.
pub fn json(o: &Outcome) -> Vec<ToleranceJson> {
    o.mass_tolerance
        .iter()
        .map(|t| ToleranceJson {
            effect: t.effect.clone(),
            sd: t.sd.iter().map(|&u| rounded(u)).collect(),
            largest: t.largest.clone(),
        })
        .collect()
}
