//! The margin table printed by `deploywatch margin` and its `--json`
//! (`docs/margin.md`): the header (mechanism, resistances, standard and
//! factors), one row per joint with its margins and verdict, a line per
//! effect counted and per latch engagement.

use crate::analysis::design_margin::{
    DataSource, FactoredExtra, Factors, LatchResistance, Resistance, Standard, LATCH_KIND,
};
use crate::analysis::dynamic_margin::{clause, DynamicMargins};
use crate::analysis::effect_margin::Counted;
use crate::analysis::joint_margins::Row;
use crate::analysis::nominal_deployment::NominalDeployment;
use crate::analysis::resistances::Resistances;
use crate::analysis::stroke_margin::{Allowance, Profile};
use crate::model::effect::Effect;
use crate::model::effect::EffectKind;
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
    /// The reductions of the driving springs applied.
    pub allowance: &'a Allowance,
    /// Where the resistances' values come from (the row of factors).
    pub data_source: DataSource,
    /// The dynamic margins (`--deploy-time`), or that they are not computed.
    pub dynamic: &'a DynamicMargins,
    /// The nominal deployment of the same chain, or why it could not be
    /// simulated.
    pub nominal: &'a Result<NominalDeployment, String>,
}

/// A margin [%] for the table: `inf` when there is no resistance.
fn pct(v: f64) -> String {
    if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.to_string()
    } else {
        format!("{v:.2}")
    }
}

/// A joint's verdict; `dynamic_pass` false when its dynamic margin fails.
fn verdict(row: &Row, dynamic_pass: bool) -> &'static str {
    let m = &row.margin;
    match (m.torque_pass(), m.energy_pass(), row.stroke.pass()) {
        (true, true, true) if !m.latching_pass() => "FAIL (latching)",
        (true, true, true) if !dynamic_pass => "FAIL (dynamic)",
        (true, true, true) => "pass",
        (true, true, false) => "FAIL (along the stroke)",
        (false, true, _) => "FAIL (torque)",
        (true, false, _) => "FAIL (energy)",
        (false, false, _) => "FAIL",
    }
}

/// A position `from_latch_rad` \[rad\] from the latch as joint `row`'s
/// angle \[deg\] (the sign of its stowed side).
pub fn joint_angle_deg(row: &Row, from_latch_rad: f64) -> f64 {
    row.stowed_deg.signum() * from_latch_rad.to_degrees() + 0.0
}

/// The line of a joint's worst position along the stroke.
fn stroke_line(row: &Row) -> String {
    let Some(w) = row.stroke.worst_point() else {
        return "along the stroke: no position".into();
    };
    let from = if row.stroke.from_rad > 0.0 {
        format!(
            "from {:.2}° from the latch: nearer, the spring's torque falls to 0 and the latching margin applies; ",
            row.stroke.from_rad.to_degrees()
        )
    } else {
        String::new()
    };
    format!(
        "along the stroke (static, {from}{} positions): worst at φ = {:.2}° ({:.2}° from the latch): D_min {:.4} N·m against factored R {:.4} N·m, margin {} % ({})",
        row.stroke.points.len(),
        joint_angle_deg(row, w.from_latch_rad),
        w.from_latch_rad.to_degrees(),
        w.driving_nm,
        w.resisting_nm,
        pct(w.margin_pct),
        if row.stroke.pass() { "pass at every position" } else { "FAIL" }
    )
}

/// The header line of the dynamic margin: its requirement and clause, or
/// why it is not computed.
fn dynamic_header(m: &MarginReport) -> String {
    match m.dynamic {
        DynamicMargins::NotComputed => "dynamic margin: not computed (no required deploy time: give --deploy-time T in s)".into(),
        DynamicMargins::Computed { deploy_time_s, .. } => format!(
            "dynamic margin: the stroke S from rest in {deploy_time_s} s (--deploy-time) at constant acceleration, α = 2 S / T²; I = the largest M_jj of the chain over the stroke (all joints at the same fraction of their stroke); {}",
            clause(m.standard)
        ),
    }
}

/// The line of joint `index`'s (0-based) dynamic margin at its worst
/// position, if computed.
fn dynamic_line(m: &MarginReport, index: usize, row: &Row) -> Option<String> {
    let d = m.dynamic.joint(index)?;
    Some(format!(
        "dynamic ({}): I {:.4} kg·m², α {:.5} rad/s², I α {:.4} N·m × {}; worst at φ = {:.2}°: D {:.4} N·m, factored R {:.4} N·m, margin {} % (required {:.0} %, {})",
        m.standard.name(),
        d.inertia_kgm2,
        d.accel_rad_s2,
        d.inertia_torque_nm(),
        d.inertia_factor,
        joint_angle_deg(row, d.from_latch_rad),
        d.driving_nm,
        d.resisting_nm,
        pct(d.margin_pct),
        d.required_pct,
        if d.pass() { "pass" } else { "FAIL" }
    ))
}

/// Joint `index`'s (0-based) dynamic margin for `--json` (`null` when not
/// computed).
fn dynamic_json(m: &MarginReport, index: usize, row: &Row) -> Value {
    let finite = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
    m.dynamic.joint(index).map_or(Value::Null, |d| {
        json!({
            "clause": clause(m.standard),
            "inertia_kgm2": d.inertia_kgm2,
            "accel_rad_s2": d.accel_rad_s2,
            "inertia_torque_nm": d.inertia_torque_nm(),
            "inertia_factor": d.inertia_factor,
            "worst_angle_deg": joint_angle_deg(row, d.from_latch_rad),
            "driving_nm": d.driving_nm,
            "resisting_nm": d.resisting_nm,
            "margin_pct": finite(d.margin_pct),
            "required_pct": d.required_pct,
            "pass": d.pass(),
        })
    })
}

/// The lines of the terms along the stroke, unfactored, with their factor.
fn term_lines(row: &Row, factors: &Factors) -> Vec<String> {
    row.terms
        .iter()
        .map(|t| {
            let how = match t.profile {
                Profile::Constant => format!("{:.4} N·m everywhere", t.torque_nm),
                Profile::FromStowed {
                    stiffness_nm_per_rad,
                } => format!(
                    "{stiffness_nm_per_rad} N·m/rad × the angle from stowed ({:.4} N·m at the latch)",
                    t.at(0.0, row.stroke.stroke_rad)
                ),
                Profile::Band { from_rad, to_rad } => format!(
                    "{:.4} N·m from {:.2}° to {:.2}° from the latch",
                    t.torque_nm,
                    from_rad.to_degrees(),
                    to_rad.to_degrees()
                ),
            };
            format!("  R: {} ({}, factor {}): {how}", t.name, t.kind, factors.get(t.kind))
        })
        .collect()
}

/// The line saying what the driving springs are reduced by: one figure
/// when every joint has the same, else one per joint, with where the
/// tolerance came from.
fn allowance_line(m: &MarginReport) -> String {
    let a = m.allowance;
    let softened = m
        .resistances
        .others
        .iter()
        .any(|e| e.kind() == EffectKind::SpringSoftening);
    let n = a.declared_pct.len().max(1);
    let scales: Vec<f64> = (0..n).map(|j| a.scale(j)).collect();
    let tolerances: Vec<f64> = (0..n).map(|j| a.tolerance_pct(j)).collect();
    let same = tolerances.iter().all(|&t| t == tolerances[0]);
    let declared = a.declared_pct.iter().any(|&t| t > 0.0);
    let source = match (declared, a.spring_tolerance_pct > 0.0) {
        (false, false) => "--spring-tolerance or each joint's spring_tolerance_pct: none given",
        (false, true) => "--spring-tolerance",
        (true, false) => "each joint's spring_tolerance_pct in the mechanism file",
        (true, true) => "the larger of each joint's spring_tolerance_pct and --spring-tolerance",
    };
    let (scale, tolerance) = if same {
        (format!("{:.4}", scales[0]), format!("{} %", tolerances[0]))
    } else {
        let list = |v: &[f64], f: &dyn Fn(f64) -> String| {
            v.iter()
                .enumerate()
                .map(|(j, &x)| format!("joint {} {}", j + 1, f(x)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        (
            format!("({})", list(&scales, &|x| format!("{x:.4}"))),
            format!("{} %", list(&tolerances, &|x| format!("{x}"))),
        )
    };
    format!(
        "along the stroke: D_min(θ) = {scale} × the spring's unfolding branch (its hysteresis included); spring tolerance {tolerance} ({source}), end of life {} % (--end-of-life){}",
        a.end_of_life_pct,
        if softened { ", × a softening found" } else { "" }
    )
}

/// The lines saying at which end of its interval each effect found is
/// taken (none without `--from`).
fn taken_at_lines(r: &Resistances) -> String {
    if r.taken_at.is_empty() {
        return String::new();
    }
    let mut s =
        "each effect found at the end of its 95 % interval that lowers the margin:\n".to_string();
    for t in &r.taken_at {
        let _ = writeln!(s, "  {t}");
    }
    s
}

/// The header lines: mechanism, source of the resistances, standard.
fn table_header(m: &MarginReport) -> String {
    let (mech, r, factors) = (m.mech, m.resistances, m.factors);
    let mut s = String::new();
    let custom = *factors != m.standard.factors_for(m.data_source);
    let _ = writeln!(
        s,
        "torque margins of `{}` ({})",
        mech.name,
        m.file.display()
    );
    let _ = writeln!(s, "resistances from: {}", r.source);
    s += &taken_at_lines(r);
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
        m.standard.reference_for(m.data_source),
        if custom { " (factors overridden)" } else { "" }
    );
    let _ = writeln!(
        s,
        "source of the standard: {}; data source: {}",
        m.standard.confirmation(),
        m.data_source.name()
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
    let _ = writeln!(s, "{}", allowance_line(m));
    let _ = writeln!(s, "{}", dynamic_header(m));
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
    for (index, row) in rows.iter().enumerate() {
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
            verdict(row, report.dynamic.pass(index))
        );
        let _ = writeln!(s, "{:>5} {}", "", stroke_line(row));
        if let Some(line) = dynamic_line(report, index, row) {
            let _ = writeln!(s, "{:>5} {line}", "");
        }
        for line in term_lines(row, factors) {
            let _ = writeln!(s, "{:>5} {line}", "");
        }
        for (e, c) in &row.counted {
            let _ = writeln!(s, "{:>5} {}", "", counted_line(e, c, factors));
        }
        if m.factored_extra != FactoredExtra::default() {
            let _ = writeln!(
                s,
                "{:>5} every resistance of the row factored, the margins' denominators: {:.4} N·m in the torque form, {:.4} J in the energy form",
                "",
                m.factored_resisting_torque_nm(),
                m.factored_resisting_energy_j(),
            );
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
            let _ = writeln!(
                s,
                "{:>5} latching margin (an energy balance, not a standard's clause): E_arrive = E_D − factored E_R = {:.4} J against {} × E_eng: {} %",
                "",
                m.arriving_energy_j(),
                m.latch_factor,
                m.latching_margin_pct().map_or("-".into(), pct),
            );
        }
    }
    let _ = writeln!(s, "{}", nominal_line(report.nominal));
    s
}

/// The nominal deployment in words: every joint held and by when, or the
/// joints not held and where they ended, or why it was not simulated.
pub fn nominal_line(nominal: &Result<NominalDeployment, String>) -> String {
    let d = match nominal {
        Ok(d) => d,
        Err(e) => return format!("nominal deployment: not simulated: {e}"),
    };
    let head = format!(
        "nominal deployment{} (the nominal springs, these resistances unfactored, simulated to {} s)",
        if d.on_rig { " on the rig" } else { "" },
        d.duration_s
    );
    if let Some(t) = d.all_held_s() {
        return format!("{head}: every joint held by its latch by {t:.3} s");
    }
    let joints = d.not_held();
    let names: Vec<String> = joints.iter().map(|j| j.to_string()).collect();
    let ends: Vec<String> = joints
        .iter()
        .map(|&j| match d.end_deg.get(j - 1) {
            Some(e) => format!("{:.2}°", e.abs()),
            None => "?".to_string(),
        })
        .collect();
    format!(
        "{head}: joint(s) {} NOT held by their latch at the end (ended {} from the latch); \
         the margins above are joint by joint and do not see the chain's dynamics \
         (`deploywatch simulate` with these resistances shows the run)",
        names.join(", "),
        ends.join(", ")
    )
}

/// The nominal deployment as JSON: `duration_s`, `held_s` (`null` where
/// not held), `end_deg`, `not_held` (1-based), `on_rig`, `unsettled`
/// (1-based), or `error`.
fn nominal_json(nominal: &Result<NominalDeployment, String>) -> Value {
    match nominal {
        Ok(d) => json!({
            "duration_s": d.duration_s,
            "held_s": d.held_s,
            "end_deg": d.end_deg,
            "not_held": d.not_held(),
            "on_rig": d.on_rig,
            "unsettled": d.unsettled,
        }),
        Err(e) => json!({ "error": e }),
    }
}

/// How an effect found is counted, for the table: e.g. `harness_stiffness
/// 0.5 N·m/rad (harness, factor 3): 1.5708 N·m in the torque form, 1.2337 J
/// in the energy form`.
fn counted_line(e: &Effect, c: &Counted, factors: &Factors) -> String {
    let what = format!("{} {} {}", e.kind(), e.value(), e.kind().unit());
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
        "effect": e.kind().name(),
        "value": e.value(),
        "counts_as": counts_as,
        "torque_nm": torque,
        "energy_j": energy,
        "driving_scale": scale,
    })
}

/// The margin along the stroke for `--json`: the worst position and every
/// position's angle \[deg\], driving and factored resisting torque \[N·m\] and
/// margin [%].
fn stroke_json(row: &Row) -> Value {
    let finite = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
    let w = row.stroke.worst_point();
    json!({
        "driving_scale": row.stroke.driving_scale,
        "static_from_deg": row.stroke.from_rad.to_degrees(),
        "worst_angle_deg": w.map(|w| joint_angle_deg(row, w.from_latch_rad)),
        "worst_from_latch_deg": w.map(|w| w.from_latch_rad.to_degrees()),
        "worst_margin_pct": w.map(|w| finite(w.margin_pct)),
        "pass": row.stroke.pass(),
        "terms": row.terms.iter().map(|t| json!({
            "name": t.name,
            "kind": t.kind.name(),
            "torque_nm": t.torque_nm,
            "at_latch_nm": t.at(0.0, row.stroke.stroke_rad),
        })).collect::<Vec<_>>(),
        "points": row.stroke.points.iter().map(|p| json!({
            "angle_deg": joint_angle_deg(row, p.from_latch_rad),
            "driving_nm": p.driving_nm,
            "resisting_nm": p.resisting_nm,
            "margin_pct": finite(p.margin_pct),
        })).collect::<Vec<_>>(),
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
        "taken_at": r.taken_at,
        "standard": m.standard.name(),
        "standard_reference": m.standard.reference_for(m.data_source),
        "standard_confirmation": m.standard.confirmation(),
        "data_source": m.data_source.name(),
        "factors": Resistance::ALL
            .iter()
            .map(|k| (k.name().to_string(), json!(factors.get(*k))))
            .collect::<serde_json::Map<_, _>>(),
        "required_margin_pct": m.standard.required_margin() * 100.0,
        "spring_tolerance_pct": m.allowance.spring_tolerance_pct,
        "end_of_life_pct": m.allowance.end_of_life_pct,
        "deploy_time_s": match report.dynamic {
            DynamicMargins::NotComputed => Value::Null,
            DynamicMargins::Computed { deploy_time_s, .. } => json!(deploy_time_s),
        },
        "joints": rows.iter().enumerate().map(|(index, row)| {
            let allowance = report.allowance;
            let m = &row.margin;
            json!({
                "joint": row.joint,
                "stowed_deg": row.stowed_deg,
                "spring_tolerance_pct": allowance.tolerance_pct(index),
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
                "factored_resisting_torque_nm": m.factored_resisting_torque_nm(),
                "factored_resisting_energy_j": m.factored_resisting_energy_j(),
                "counted": row.counted.iter().map(|(e, c)| counted_json(e, c)).collect::<Vec<_>>(),
                "stroke": stroke_json(row),
                "arriving_energy_j": m.arriving_energy_j(),
                "latching_margin_pct": m.latching_margin_pct().map(finite),
                "dynamic": dynamic_json(report, index, row),
                "pass": m.torque_pass() && m.energy_pass() && row.stroke.pass() && m.latching_pass() && report.dynamic.pass(index),
            })
        }).collect::<Vec<_>>(),
        "nominal_deployment": nominal_json(report.nominal),
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
