//! `deploywatch margin --all-standards` (`docs/margin.md`, "The seeds'
//! margins beside the standards'"): the same wing and resistances under
//! every [`Standard`] side by side, one line per joint and form: the
//! torque form at the stowed angle (seed 001 Eq. 7 with the standard's
//! factors), the energy form over the stroke (seed 000 Eqs. 17–21), and
//! the static margin at the worst position along the stroke, with that
//! position.

use crate::analysis::design_margin::{DataSource, Standard};
use crate::analysis::joint_margins::Row;
use crate::report::margin::joint_angle_deg;
use std::fmt::Write as _;

/// A margin [%] for the table: `inf` when nothing resists.
fn pct(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.2}")
    } else {
        "inf".into()
    }
}

/// The worst position along the stroke, `-12.47 @ 0.00°`.
fn worst(row: &Row) -> String {
    row.stroke.worst_point().map_or("-".into(), |w| {
        format!(
            "{} @ {:.2}°",
            pct(w.margin_pct),
            joint_angle_deg(row, w.from_latch_rad)
        )
    })
}

/// How one form's cell is written from a joint's row.
type Cell = fn(&Row) -> String;

/// The side-by-side table of `by_standard` (each standard with its rows,
/// the same joints in each, the factors of `source`'s row), headed by
/// `title`.
pub fn side_by_side(
    title: &str,
    by_standard: &[(Standard, Vec<Row>)],
    source: DataSource,
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{title}");
    for (std, _) in by_standard {
        let _ = writeln!(
            s,
            "  {}: {} (source: {})",
            std.name(),
            std.reference_for(source),
            std.confirmation()
        );
    }
    let _ = writeln!(s);
    let _ = write!(s, "{:>5}  {:<28}", "joint", "margin [%]");
    for (std, _) in by_standard {
        let _ = write!(s, " {:>20}", std.name());
    }
    let _ = writeln!(s);
    let joints = by_standard.first().map_or(0, |(_, rows)| rows.len());
    let forms: [(&str, Cell); 3] = [
        ("torque, stowed (Eq. 7)", |r| {
            pct(r.margin.torque_margin_pct())
        }),
        ("energy, stroke (Eq. 21)", |r| {
            pct(r.margin.energy_margin_pct())
        }),
        ("worst along the stroke @ φ", worst),
    ];
    for j in 0..joints {
        for (name, value) in &forms {
            let _ = write!(s, "{:>5}  {name:<28}", j + 1);
            for (_, rows) in by_standard {
                let cell = rows.get(j).map_or("-".into(), value);
                let _ = write!(s, " {cell:>20}");
            }
            let _ = writeln!(s);
        }
    }
    s
}
