//! The mechanisms compiled into the firmware, by the name their runs give in
//! their `mechanism` metadata.
//!
//! Each is the mechanism file of `data/mechanisms/` converted as the host
//! converts it (`deploywatch_sim::monitor_config::monitor_config`): panels
//! and springs in `f32`, the tape spring's θ_B as capture angle, the
//! friction in the file as prior mean (none here) with the default spread
//! (2 N·m Coulomb, 0.05 N·m·s/rad viscous), the file's `[run] duration_s`
//! as the deployment's deadline, and the default tuning.
//! `deploywatch-replay` checks the two conversions equal before every
//! replay, so a drift between this table and the files is an error, not a
//! silent difference.

use deploywatch_core::monitor::{JointConfig, MonitorConfig};
use deploywatch_core::observer::FrictionPrior;
use deploywatch_core::{Panel, Spring, TapePoints};

use crate::JOINTS;

/// Names of the built-in mechanisms.
pub const NAMES: [&str; 2] = ["seed001-T01", "seed001-T02"];

/// Seed 001 Table 1 tape-spring hinge types (`[tape."TS-n"]` of the files).
const TS1: TapePoints<f32> = TapePoints {
    a: (1.10, 69.39),
    b: (1.10, 1.50),
    d: (0.52, 37.0),
    m_90: 1.20,
    c_180: 2.32,
};
const TS2: TapePoints<f32> = TapePoints {
    a: (1.26, 58.20),
    b: (1.28, 0.86),
    d: (0.65, 26.0),
    m_90: 0.80,
    c_180: 1.46,
};
const TS3: TapePoints<f32> = TapePoints {
    a: (1.08, 33.43),
    b: (1.15, 0.46),
    d: (0.29, 11.07),
    m_90: 0.385,
    c_180: 0.74,
};

/// 800 × 800 mm dummy panel of 3.5 kg (seed 001).
const PANEL: Panel<f32> = Panel {
    length_m: 0.8,
    mass_kg: 3.5,
    com_m: 0.4,
    inertia_kgm2: 0.27,
};

/// The default friction prior: no friction expected, 2 N·m and
/// 0.05 N·m·s/rad of spread.
const PRIOR: FrictionPrior = FrictionPrior {
    coulomb_nm: 0.0,
    coulomb_sd_nm: 2.0,
    viscous_nms: 0.0,
    viscous_sd_nms: 0.05,
};

/// A tape-spring joint: `count` hinges of type `points`.
fn tape_joint(stowed_deg: f32, points: &TapePoints<f32>, count: f32) -> Option<JointConfig> {
    Some(JointConfig {
        stowed_deg,
        spring: Spring::tape(points, count).ok()?,
        capture_deg: points.b.0,
        prior: PRIOR,
    })
}

/// The monitor configuration of the built-in mechanism `name`; `None` for a
/// name not in [`NAMES`].
pub fn config(name: &str) -> Option<MonitorConfig<JOINTS>> {
    // Seed 001: T01 is the normal case (3 × TS-1 at joint 1), T02 the worst
    // case (2 × TS-3 at joint 1); joints 2 and 3 are the same in both. The
    // deadline is the file's `[run] duration_s` [s].
    let (joint1, deadline_s) = match name {
        "seed001-T01" => (tape_joint(-90.0, &TS1, 3.0)?, 6.0),
        "seed001-T02" => (tape_joint(-90.0, &TS3, 2.0)?, 12.0),
        _ => return None,
    };
    let joints = [
        joint1,
        tape_joint(180.0, &TS2, 2.0)?,
        tape_joint(-180.0, &TS3, 2.0)?,
    ];
    let mut config = MonitorConfig::new([PANEL; JOINTS], joints);
    config.margin.deadline_s = deadline_s;
    Some(config)
}
