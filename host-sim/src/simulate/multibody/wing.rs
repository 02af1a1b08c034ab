//! A wing with a truss: from a [`Mechanism`] with a `[truss]` to a sampled
//! multibody run.

use super::integrate::{run, MbTrajectory};
use super::kin::Model;
use crate::model::mechanism::Mechanism;
use crate::simulate::trajectory::{grid_count, SimError, SimOptions, MAX_SAMPLES};

/// A truss deployment: the multibody run and the names of its pins.
#[derive(Clone, Debug, PartialEq)]
pub struct WingRun {
    /// Pin names, in the order of the run's series (hinges first: `hinge 1`,
    /// `hinge 2`...; knees by their point name; `P:L` a link `L` on a body at
    /// point `P`; `P:R-L` link `L` against link `R` at node `P`).
    pub pins: Vec<String>,
    /// The run.
    pub run: MbTrajectory,
}

impl WingRun {
    /// The series of the pin called `name`: angles \[deg\] and lock flags.
    pub fn series(&self, name: &str) -> Option<(&[f64], &[bool])> {
        let p = self.pins.iter().position(|n| n == name)?;
        Some((&self.run.angle_deg[p], &self.run.locked[p]))
    }

    /// Lock instant of the pin called `name` \[s\].
    pub fn lock_s(&self, name: &str) -> Option<f64> {
        let p = self.pins.iter().position(|n| n == name)?;
        self.run.lock_s[p]
    }
}

/// Relative tolerance of a wing deployment by default ([`wing_options`]).
///
/// The truss goldens are met to 0.01° (hinges) and 1 ms (locks); at 1e-6 the
/// case 2 EFT run is within 6e-6° of its golden hinge angles, 3e-5° of its
/// knee angles and 1 µs of its lock instants (`benches/truss.rs` prints
/// them), three orders of magnitude inside those bounds, at 1270 instead of
/// 2260 evaluations for the chain's 1e-8 (`docs/performance.md`).
pub const WING_RTOL: f64 = 1e-6;

/// Absolute tolerance of a wing deployment by default [rad, rad/s].
pub const WING_ATOL: f64 = 1e-8;

/// The default options of a wing deployment: [`SimOptions::default`] with
/// the truss tolerances [`WING_RTOL`], [`WING_ATOL`].
pub fn wing_options() -> SimOptions {
    SimOptions {
        rtol: WING_RTOL,
        atol: WING_ATOL,
        ..SimOptions::default()
    }
}

/// The multibody model of a mechanism with a truss.
pub fn wing_model(mech: &Mechanism) -> Result<Model, SimError> {
    let truss = mech
        .truss
        .as_ref()
        .ok_or_else(|| SimError::Invalid(format!("mechanism `{}` has no [truss]", mech.name)))?;
    let sys = crate::simulate::multibody::build::wing_system(truss, mech)
        .map_err(|e| SimError::Invalid(e.to_string()))?;
    Model::new(sys).map_err(|e| SimError::Invalid(e.to_string()))
}

/// Simulates a mechanism with a truss from the stowed pose at rest, sampled
/// at the mechanism's (or the options') rate.
pub fn simulate_wing(mech: &Mechanism, opts: &SimOptions) -> Result<WingRun, SimError> {
    let model = wing_model(mech)?;
    let duration = opts.duration_s.unwrap_or(mech.duration_s);
    let rate = opts.sample_hz.unwrap_or(mech.sample_hz);
    if !(duration > 0.0 && rate > 0.0 && duration.is_finite() && rate.is_finite()) {
        return Err(SimError::Invalid(format!(
            "duration ({duration} s) and sample rate ({rate} Hz) must be positive"
        )));
    }
    let count = grid_count(duration, rate);
    if count > MAX_SAMPLES {
        return Err(SimError::TooManySamples { t_s: duration });
    }
    let times: Vec<f64> = (0..count).map(|k| k as f64 / rate).collect();
    let run = run(&model, &times, opts)?;
    Ok(WingRun {
        pins: model.sys.pins.iter().map(|p| p.name.clone()).collect(),
        run,
    })
}

/// The golden trajectories of the truss wing (`data/reference/truss/`,
/// `truss-link.md`): each angle column, the simulator's pin it is compared
/// with and the RMS bound \[deg\] it must meet.
pub const GOLDEN_COLUMNS: [(&str, &str, f64); 6] = [
    ("phi1_deg", "hinge 1", 0.01),
    ("phi2_deg", "hinge 2", 0.01),
    ("psi_deg", "C:3", 0.05),
    ("kneeB_deg", "B", 0.05),
    ("kneeE_deg", "E", 0.05),
    ("kneeH_deg", "H", 0.05),
];

/// The lock names of the golden JSON files and the simulator's pins.
pub const GOLDEN_LOCKS: [(&str, &str); 5] = [
    ("O", "hinge 1"),
    ("I", "hinge 2"),
    ("B", "B"),
    ("E", "E"),
    ("H", "H"),
];
