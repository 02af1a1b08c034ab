//! The plot of `deploywatch margin --plot FILE.png` (`docs/margin.md`,
//! "Along the stroke"): per joint, the static torque margin [%] against the
//! joint angle \[deg\] over the stroke
//! ([`crate::analysis::stroke_margin`]), the required minimum as a
//! horizontal line, the worst position marked and labelled with its
//! margin. [`curves`] is the data fed to the plot, so that a test can hold
//! it against the printed table; [`plot_margins`] draws it.

use crate::analysis::joint_margins::Row;
use crate::report::margin::joint_angle_deg;
use crate::report::plot::{draw_panels, Mark, Panel, PlotError, Series, YAxis};
use std::path::Path;

/// One joint's margin along the stroke, as plotted.
#[derive(Clone, Debug, PartialEq)]
pub struct MarginCurve {
    /// 1-based joint.
    pub joint: usize,
    /// The joint angle of each position \[deg\] (0 latched).
    pub angle_deg: Vec<f64>,
    /// The static margin there [%] (`+∞` where nothing resists: not drawn).
    pub margin_pct: Vec<f64>,
    /// The worst position marked: its angle \[deg\] and margin [%]
    /// ([`crate::analysis::stroke_margin::StrokeMargin::worst_point`]).
    pub worst: Option<(f64, f64)>,
    /// The required minimum margin, drawn as a line [%].
    pub required_pct: f64,
}

/// The curves of every joint of `rows`, as [`plot_margins`] draws them.
pub fn curves(rows: &[Row]) -> Vec<MarginCurve> {
    rows.iter()
        .map(|row| {
            let points = &row.stroke.points;
            MarginCurve {
                joint: row.joint,
                angle_deg: points
                    .iter()
                    .map(|p| joint_angle_deg(row, p.from_latch_rad))
                    .collect(),
                margin_pct: points.iter().map(|p| p.margin_pct).collect(),
                worst: row
                    .stroke
                    .worst_point()
                    .map(|w| (joint_angle_deg(row, w.from_latch_rad), w.margin_pct)),
                required_pct: row.stroke.required_pct,
            }
        })
        .collect()
}

/// The label of a worst position: `worst: φ = -0.00°, margin -12.47 %`,
/// with the table's rounding.
pub fn worst_label((angle_deg, margin_pct): (f64, f64)) -> String {
    if margin_pct.is_finite() {
        format!("worst: φ = {angle_deg:.2}°, margin {margin_pct:.2} %")
    } else {
        format!("worst: φ = {angle_deg:.2}°, margin inf % (nothing resists)")
    }
}

/// The y range of a panel: its finite margins and the required minimum,
/// with 5 % of air.
fn y_limits(c: &MarginCurve) -> (f64, f64) {
    let finite = c.margin_pct.iter().copied().filter(|m| m.is_finite());
    let (lo, hi) = finite
        .chain([c.required_pct])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), m| {
            (lo.min(m), hi.max(m))
        });
    let pad = (0.05 * (hi - lo)).max(1.0);
    (lo - pad, hi + pad)
}

/// Draws the margin along the stroke of every joint of `rows`, one panel
/// per joint, into the PNG at `png`, titled with `mechanism` and
/// `standard` (the standard's name).
pub fn plot_margins(
    png: &Path,
    mechanism: &str,
    standard: &str,
    rows: &[Row],
) -> Result<(), PlotError> {
    let curves = curves(rows);
    let worst: Vec<([f64; 1], [f64; 1])> = curves
        .iter()
        .map(|c| {
            let (x, y) = c.worst.unwrap_or((f64::NAN, f64::NAN));
            ([x], [y])
        })
        .collect();
    let panels: Vec<(Panel, YAxis, &str)> = curves
        .iter()
        .zip(&worst)
        .map(|(c, (wx, wy))| {
            let label = c.worst.map(worst_label).unwrap_or_default();
            let panel = Panel {
                title: format!("joint {}: static torque margin along the stroke", c.joint),
                y_label: "margin [%]".into(),
                series: vec![
                    Series::new("static margin", &c.angle_deg, &c.margin_pct, Mark::Line, 0),
                    Series::new(label, wx, wy, Mark::Dots, 1),
                ],
                // A vertical line through the worst position, labelled in
                // the legend (a label at the frame would be cut).
                markers: c.worst.map(|w| (w.0, String::new())).into_iter().collect(),
            };
            let axis = YAxis {
                limits: Some(y_limits(c)),
                lines: vec![(
                    c.required_pct,
                    format!("required minimum {} %", c.required_pct),
                )],
            };
            (panel, axis, "joint angle φ [deg] (0 = latched)")
        })
        .collect();
    draw_panels(
        png,
        &format!("{mechanism}: margin along the stroke ({standard})"),
        &panels,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::design_margin::{DataSource, Standard};
    use crate::analysis::joint_margins::margins;
    use crate::analysis::resistances::Resistances;
    use crate::analysis::stroke_margin::Allowance;
    use crate::model::mechanism::Mechanism;
    use crate::report::margin::{table, MarginReport};

    /// Seed 000 case 1 with its identified friction under ECSS: what the
    /// plot marks as each joint's worst is the worst the table prints, and
    /// the lowest margin it draws.
    #[test]
    fn the_plotted_worst_is_the_printed_worst() {
        let file =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms/seed000_case1.toml");
        let mech = Mechanism::load(&file).unwrap();
        let mut r = Resistances::of_mechanism(&mech, "--friction".into());
        r.coulomb_nm = vec![0.54, 0.472];
        let standard = Standard::EcssEST3301C;
        let factors = standard.factors();
        let allowance = Allowance::default();
        let rows = margins(&mech, &r, standard, &factors, &allowance).unwrap();
        let report = MarginReport {
            file: &file,
            mech: &mech,
            standard,
            factors: &factors,
            resistances: &r,
            rows: &rows,
            allowance: &allowance,
            data_source: DataSource::Analysis,
            dynamic: &crate::analysis::dynamic_margin::DynamicMargins::NotComputed,
            nominal: &Err("not simulated here".into()),
        };
        let printed = table(&report);
        let plotted = curves(&rows);
        assert_eq!(plotted.len(), 2);
        for c in &plotted {
            let (angle, margin) = c.worst.unwrap();
            let lowest = c.margin_pct.iter().copied().fold(f64::INFINITY, f64::min);
            assert_eq!(
                margin, lowest,
                "joint {}: the mark is the lowest drawn",
                c.joint
            );
            let i = c.margin_pct.iter().position(|m| *m == lowest).unwrap();
            assert_eq!(angle, c.angle_deg[i]);
            let line = format!("worst at φ = {angle:.2}°");
            let with = format!("margin {margin:.2} % (FAIL)");
            let row = printed
                .lines()
                .find(|l| l.contains(&line) && l.contains(&with));
            assert!(
                row.is_some(),
                "joint {}: {line} … {with} not in\n{printed}",
                c.joint
            );
            assert!(margin < 0.0, "joint {}: fails at the latch end", c.joint);
        }
        let dir = tempfile::tempdir().unwrap();
        let png = dir.path().join("m.png");
        plot_margins(&png, &mech.name, standard.name(), &rows).unwrap();
        let bytes = std::fs::read(&png).unwrap();
        assert!(bytes.starts_with(b"\x89PNG"), "a PNG");
    }
}
