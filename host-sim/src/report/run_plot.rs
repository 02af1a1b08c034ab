//! The plot of a simulated run (`simulate --plot`): each joint's angle over
//! time, with its latch events; on a zero-g rig, each panel tip's lateral
//! position with the frame contacts beside them.

use crate::data::run::Run;
use crate::report::plot::{self, Mark, Panel, Series};
use crate::simulate::rig::RigRun;
use std::path::Path;

/// Draws a run's joint angles with its latch events.
pub fn plot_run(
    png: &Path,
    title: &str,
    run: &Run,
    latch_s: &[Option<f64>],
) -> Result<(), plot::PlotError> {
    let series = joint_angles(run);
    let markers = latch_markers(latch_s);
    plot::draw(
        png,
        &format!("{title}: joint angles"),
        "time [s]",
        &[Panel {
            title: "joint angle φ_j".into(),
            y_label: "angle [deg]".into(),
            series,
            markers,
        }],
    )
}

/// Draws the joint angles and each panel tip's lateral position, with the
/// latches and the frame contacts marked.
pub fn plot_rig_run(
    png: &Path,
    title: &str,
    run: &Run,
    rig: &RigRun,
) -> Result<(), plot::PlotError> {
    let angles = joint_angles(run);
    let lateral: Vec<Vec<f64>> = rig
        .tip_xy
        .iter()
        .map(|tip| tip.iter().map(|q| q[1] * 1e3).collect())
        .collect();
    let drift: Vec<Series> = lateral
        .iter()
        .enumerate()
        .map(|(p, y)| Series {
            label: format!("panel {} tip", p + 1),
            x: &rig.traj.t_s,
            y,
            mark: Mark::Line,
            color: p,
        })
        .collect();
    let latches = latch_markers(&rig.traj.latch_s);
    let contacts = rig
        .contacts
        .iter()
        .map(|c| (c.first_s, format!("panel {} hits {}", c.panel, c.frame)))
        .collect();
    plot::draw(
        png,
        &format!("{title}: on the zero-g rig"),
        "time [s]",
        &[
            Panel {
                title: "joint angle φ_j".into(),
                y_label: "angle [deg]".into(),
                series: angles,
                markers: latches,
            },
            Panel {
                title: "lateral drift of each panel tip (frame contacts marked)".into(),
                y_label: "y [mm]".into(),
                series: drift,
                markers: contacts,
            },
        ],
    )
}

/// Each joint's angle over time, a line each.
fn joint_angles(run: &Run) -> Vec<Series<'_>> {
    (0..run.joints())
        .map(|j| {
            Series::new(
                format!("joint {}", j + 1),
                &run.t_s,
                &run.phi_deg[j],
                Mark::Line,
                j,
            )
        })
        .collect()
}

/// The latch instant of each joint that latched, as a marker.
fn latch_markers(latch_s: &[Option<f64>]) -> Vec<(f64, String)> {
    latch_s
        .iter()
        .enumerate()
        .filter_map(|(j, l)| l.map(|t| (t, format!("latch {}", j + 1))))
        .collect()
}
