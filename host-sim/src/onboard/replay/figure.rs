//! The figure of a status stream: joint angles, Coulomb estimates and the
//! energy margin, with the latch instants.

use std::path::Path;

use deploywatch_core::monitor::JointStatus;

use super::status::StatusRow;
use super::summary::{summary, JointSummary};
use crate::report::plot::{self, Mark, Panel, Series};

/// Draws the status stream: joint angles, Coulomb estimates and the
/// energy margin of the remaining stroke, with the latch instants.
pub fn plot(png: &Path, title: &str, statuses: &[StatusRow]) -> Result<(), plot::PlotError> {
    let joints = statuses.first().map_or(0, |s| s.joints.len());
    let t: Vec<f64> = statuses.iter().map(|s| f64::from(s.t_s)).collect();
    let col = |f: fn(&JointStatus) -> f64| -> Vec<Vec<f64>> {
        (0..joints)
            .map(|j| statuses.iter().map(|s| f(&s.joints[j])).collect())
            .collect()
    };
    let phi = col(|s| f64::from(s.phi_deg));
    let coulomb = col(|s| f64::from(s.coulomb_nm));
    let margin = col(|s| s.margin_pct.map_or(f64::NAN, f64::from));
    let markers: Vec<(f64, String)> = summary(statuses)
        .iter()
        .flat_map(JointSummary::latch_marks)
        .collect();
    let upper = margin_axis_top_pct(&margin);
    plot::draw_with_axes(
        png,
        &format!("{title}: on-board monitor"),
        "time [s]",
        &[
            (
                panel(
                    "joint angle φ_j (filtered)",
                    "angle [deg]",
                    &t,
                    &phi,
                    &markers,
                ),
                plot::YAxis::default(),
            ),
            (
                panel(
                    "Coulomb friction estimate",
                    "T_C [N·m]",
                    &t,
                    &coulomb,
                    &markers,
                ),
                plot::YAxis::default(),
            ),
            (
                panel(
                    &format!(
                        "energy margin of the remaining stroke (axis clipped at {upper:.0} %; \
                         the monitor caps at {:.0} %)",
                        deploywatch_core::monitor::MARGIN_CAP_PCT
                    ),
                    "margin [%]",
                    &t,
                    &margin,
                    &markers,
                ),
                plot::YAxis {
                    limits: Some((MARGIN_AXIS_BOTTOM_PCT, upper)),
                    lines: vec![(0.0, "0 % (no reserve)".into())],
                },
            ),
        ],
    )
}

/// The bottom of the margin axis [%]: the monitor's margin never goes
/// below −100 % (no driving energy left).
const MARGIN_AXIS_BOTTOM_PCT: f64 = -100.0;

/// The top of the margin axis [%]: 1.2 × the largest margin below the
/// monitor's cap, between 100 % and 1000 %, so that the cap (the joint
/// inside its capture zone, or no resistance yet) does not flatten the
/// margins that matter, near 0 %.
fn margin_axis_top_pct(margin: &[Vec<f64>]) -> f64 {
    let cap = f64::from(deploywatch_core::monitor::MARGIN_CAP_PCT);
    let largest = margin
        .iter()
        .flatten()
        .copied()
        .filter(|m| m.is_finite() && *m < cap)
        .fold(0.0, f64::max);
    (1.2 * largest).clamp(100.0, 1000.0)
}

fn panel<'a>(
    title: &str,
    y_label: &str,
    t: &'a [f64],
    ys: &'a [Vec<f64>],
    markers: &[(f64, String)],
) -> Panel<'a> {
    Panel {
        title: title.into(),
        y_label: y_label.into(),
        series: ys
            .iter()
            .enumerate()
            .map(|(j, y)| Series {
                label: format!("joint {}", j + 1),
                x: t,
                y: y.as_slice(),
                mark: Mark::Line,
                color: j,
            })
            .collect(),
        markers: markers.to_vec(),
    }
}
