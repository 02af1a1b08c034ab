//! `deploywatch simulate` on a mechanism with a zero-g rig (`[rig]`,
//! `physics.md` §11): what the rig did — each panel's lateral drift, the
//! frame contacts, the energy balance. With `--plot`, the lateral positions
//! and the contacts beside the joint angles
//! ([`crate::report::run_plot::plot_rig_run`]).

use super::{outln, CliError};
use crate::model::effect::Effect;
use crate::model::mechanism::Mechanism;
use crate::simulate::deployment::{self, SimOptions};
use crate::simulate::rig::{simulate_rig, RigRun};

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
