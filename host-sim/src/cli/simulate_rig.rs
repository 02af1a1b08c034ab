//! `deploywatch simulate` on a mechanism with a zero-g rig (`[rig]`,
//! `physics.md` §11): what the rig did — each panel's lateral drift, the
//! frame contacts, the energy balance — and, with `--plot`, the lateral
//! positions and the contacts beside the joint angles.

use super::{outln, CliError};
use crate::data::run::Run;
use crate::model::effect::Effect;
use crate::model::mechanism::Mechanism;
use crate::report::plot::{self, Mark, Panel, Series};
use crate::simulate::deployment::{self, SimOptions};
use crate::simulate::rig::{simulate_rig, RigRun};
use std::path::Path;

/// Simulates `mech` on its rig on `opts`' grid and prints what the rig did.
pub fn report(mech: &Mechanism, effects: &[Effect], opts: &SimOptions) -> Result<RigRun, CliError> {
    let failed = |e: deployment::SimError| CliError::failed(e.to_string());
    let grid = deployment::sample_grid(mech, opts).map_err(failed)?;
    let times: Vec<f64> = (0..).map_while(|k| grid.get(k)).collect();
    let rig = simulate_rig(mech, effects, opts, &times).map_err(failed)?;
    for (p, tip) in rig.tip_xy.iter().enumerate() {
        let (lo, hi) = tip
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), q| (a.min(q[1]), b.max(q[1])));
        let end = tip.last().map_or(f64::NAN, |q| q[1]);
        outln!(
            "  panel {} tip lateral (y) drift: {:.1} to {:.1} mm, at the end {:.1} mm",
            p + 1,
            lo * 1e3,
            hi * 1e3,
            end * 1e3
        );
    }
    if rig.contacts.is_empty() {
        outln!("  frame contacts: none");
    }
    for c in &rig.contacts {
        outln!(
            "  frame contact: panel {} meets `{}` at {:.3} s (deepest {:.3} mm, largest force {:.1} N)",
            c.panel, c.frame, c.first_s, c.max_depth_mm, c.max_force_n
        );
    }
    Ok(rig)
}

/// Draws the joint angles and each panel tip's lateral position, with the
/// latches and the frame contacts marked.
pub fn plot(png: &Path, title: &str, run: &Run, rig: &RigRun) -> Result<(), plot::PlotError> {
    let angles: Vec<Series> = (0..run.joints())
        .map(|j| Series {
            label: format!("joint {}", j + 1),
            x: &run.t_s,
            y: &run.phi_deg[j],
            mark: Mark::Line,
            color: j,
        })
        .collect();
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
    let latches = rig
        .traj
        .latch_s
        .iter()
        .enumerate()
        .filter_map(|(j, l)| l.map(|t| (t, format!("latch {}", j + 1))))
        .collect();
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
