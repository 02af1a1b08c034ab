//! The margin table printed by `deploywatch margin` and its `--json`
//! (`docs/margin.md`): the header (mechanism, resistances, standard and
//! factors), one row per joint with its margins and verdict, a line per
//! effect counted and per latch engagement.

use crate::analysis::design_margin::{
    Factors, JointMargin, LatchResistance, Resistance, Standard, LATCH_KIND,
};
use crate::analysis::effect_margin::Counted;
use crate::analysis::joint_margins::Row;
use crate::analysis::resistances::Resistances;
use crate::model::effect::Effect;
use crate::model::mechanism::Mechanism;
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::path::Path;

/// What the margin table shows.
#[derive(Clone, Copy, Debug)]
pub struct MarginReport<'a> {
    /// The mechanism file, as given.
    pub file: &'a Path,
    /// The mechanism.
    pub mech: &'a Mechanism,
    /// The standard whose factors and minimum apply.
    pub standard: Standard,
    /// The factors applied (the standard's, or overridden).
    pub factors: &'a Factors,
    /// The resistances and where they come from.
    pub resistances: &'a Resistances,
    /// The margins of each joint.
    pub rows: &'a [Row],
}

/// A margin [%] for the table: `inf` when there is no resistance.
fn pct(v: f64) -> String {
    if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.to_string()
    } else {
        format!("{v:.2}")
    }
}

fn verdict(m: &JointMargin) -> &'static str {
    match (m.torque_pass(), m.energy_pass()) {
        (true, true) => "pass",
        (false, true) => "FAIL (torque)",
        (true, false) => "FAIL (energy)",
        (false, false) => "FAIL",
    }
}

/// The header lines: mechanism, source of the resistances, standard.
fn table_header(m: &MarginReport) -> String {
    let (mech, r, factors) = (m.mech, m.resistances, m.factors);
    let mut s = String::new();
    let custom = *factors != m.standard.factors();
    let _ = writeln!(
        s,
        "torque margins of `{}` ({})",
        mech.name,
        m.file.display()
    );
    let _ = writeln!(s, "resistances from: {}", r.source);
    if !r.ignored.is_empty() {
        let _ = writeln!(
            s,
            "not a named effect, not in these margins: {}",
            r.ignored.join(", ")
        );
    }
    let _ = writeln!(
        s,
        "standard: {}{}",
        m.standard.reference(),
        if custom { " (factors overridden)" } else { "" }
    );
    if m.standard != Standard::None || custom {
        let list: Vec<String> = Resistance::ALL
            .iter()
            .map(|r| format!("{r} {}", factors.get(*r)))
            .collect();
        let _ = writeln!(s, "uncertainty factors: {}", list.join(", "));
        let _ = writeln!(
            s,
            "applied to the friction: {} ; to a latch's engagement ({}): {} ; required minimum margin: {:.0} %",
            factors.get(Resistance::Friction),
            LATCH_KIND,
            factors.get(LATCH_KIND),
            m.standard.required_margin() * 100.0
        );
        let _ = writeln!(
            s,
            "margins below: D / (FoS_friction · R + FoS_{LATCH_KIND} · R_latch) − 1"
        );
    } else {
        let _ = writeln!(
            s,
            "margins below: D / R − 1 (seed 001 Eq. 7, seed 000 Eq. 21); pass at ≥ 0 %"
        );
    }
    if mech.has_physical_latch() {
        let _ = writeln!(
            s,
            "R includes a physical latch's engagement (T_e in the torque form, E_eng in the energy form)"
        );
    }
    if !r.others.is_empty() {
        let _ = writeln!(
            s,
            "R includes every other effect found, each with its kind's factor (a line under its joint); a spring_softening scales D"
        );
    }
    if r.viscous_nms.iter().any(|f| *f != 0.0) {
        let _ = writeln!(
            s,
            "E_R includes E_visc, the energy the viscous damping dissipates on the simulated deployment"
        );
    }
    s
}

/// The table printed on the terminal.
pub fn table(report: &MarginReport) -> String {
    let (factors, rows) = (report.factors, report.rows);
    let mut s = table_header(report);
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "{:>5} {:>10} {:>9} {:>9} {:>11} {:>9} {:>9} {:>9} {:>11}  result",
        "joint",
        "stowed_deg",
        "T_D_Nm",
        "T_R_Nm",
        "TM_torque_%",
        "E_D_J",
        "E_visc_J",
        "E_R_J",
        "TM_energy_%",
    );
    for row in rows {
        let m = &row.margin;
        let _ = writeln!(
            s,
            "{:>5} {:>10.2} {:>9.4} {:>9.4} {:>11} {:>9.4} {:>9.4} {:>9.4} {:>11}  {}",
            row.joint,
            row.stowed_deg,
            m.driving_torque_nm,
            m.resisting_torque_nm,
            pct(m.torque_margin_pct()),
            m.driving_energy_j,
            row.viscous_energy_j,
            m.resisting_energy_j,
            pct(m.energy_margin_pct()),
            verdict(m)
        );
        for (e, c) in &row.counted {
            let _ = writeln!(s, "{:>5} {}", "", counted_line(e, c, factors));
        }
        if m.latch != LatchResistance::default() {
            let _ = writeln!(
                s,
                "{:>5} latch engagement ({LATCH_KIND}, factor {}): T_e {:.4} N·m in the torque form, E_eng {:.4} J in the energy form",
                "",
                m.latch_factor,
                m.latch.entry_torque_nm,
                m.latch.engagement_energy_j,
            );
        }
    }
    s
}

/// How an effect found is counted, for the table: e.g. `harness_stiffness
/// 0.5 N·m/rad (harness, factor 3): 1.5708 N·m in the torque form, 1.2337 J
/// in the energy form`.
fn counted_line(e: &Effect, c: &Counted, factors: &Factors) -> String {
    let what = format!("{} {} {}", e.kind, e.value, e.kind.unit());
    match c {
        Counted::Resistance {
            kind,
            torque_nm,
            energy_j,
        } => format!(
            "{what} ({kind}, factor {}): {torque_nm:.4} N·m in the torque form, {energy_j:.4} J in the energy form",
            factors.get(*kind)
        ),
        Counted::Driving { scale } => {
            format!("{what}: the driving spring × {scale:.4} (T_D and E_D above)")
        }
        Counted::Sensor => format!("{what}: a sensor effect, no torque (0 in both forms)"),
    }
}

/// How an effect found is counted, for `--json`.
fn counted_json(e: &Effect, c: &Counted) -> Value {
    let (counts_as, torque, energy, scale) = match c {
        Counted::Resistance {
            kind,
            torque_nm,
            energy_j,
        } => (kind.name(), *torque_nm, *energy_j, 1.0),
        Counted::Driving { scale } => ("driving", 0.0, 0.0, *scale),
        Counted::Sensor => ("sensor", 0.0, 0.0, 1.0),
    };
    json!({
        "effect": e.kind.name(),
        "value": e.value,
        "counts_as": counts_as,
        "torque_nm": torque,
        "energy_j": energy,
        "driving_scale": scale,
    })
}

/// The margins as JSON (`--json`); an infinite margin (no resistance) is
/// `null`.
pub fn to_json(report: &MarginReport) -> Value {
    let (m, mech, r, factors, rows) = (
        report,
        report.mech,
        report.resistances,
        report.factors,
        report.rows,
    );
    let finite = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
    json!({
        "mechanism": mech.name,
        "mechanism_file": m.file.display().to_string(),
        "resistances_from": r.source,
        "not_included": r.ignored,
        "standard": m.standard.name(),
        "factors": Resistance::ALL
            .iter()
            .map(|k| (k.name().to_string(), json!(factors.get(*k))))
            .collect::<serde_json::Map<_, _>>(),
        "required_margin_pct": m.standard.required_margin() * 100.0,
        "joints": rows.iter().map(|row| {
            let m = &row.margin;
            json!({
                "joint": row.joint,
                "stowed_deg": row.stowed_deg,
                "coulomb_nm": m.resisting_torque_nm,
                "viscous_nms": row.viscous_nms,
                "driving_torque_nm": m.driving_torque_nm,
                "torque_margin_pct": finite(m.torque_margin_pct()),
                "driving_energy_j": m.driving_energy_j,
                "viscous_energy_j": row.viscous_energy_j,
                "resisting_energy_j": m.resisting_energy_j,
                "latch_entry_torque_nm": m.latch.entry_torque_nm,
                "latch_engagement_energy_j": m.latch.engagement_energy_j,
                "energy_margin_pct": finite(m.energy_margin_pct()),
                "counted": row.counted.iter().map(|(e, c)| counted_json(e, c)).collect::<Vec<_>>(),
                "pass": m.torque_pass() && m.energy_pass(),
            })
        }).collect::<Vec<_>>(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn infinite_margins_print_as_inf() {
        assert_eq!(pct(f64::INFINITY), "inf");
        assert_eq!(pct(12.345), "12.35");
    }
}
