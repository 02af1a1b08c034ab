//! deploywatch host tools: the full deployment simulator, friction
//! identification, torque margins, diagnosis of measured runs, reliability,
//! and the on-board monitor replayed on the host.
//!
//! The map of the modules — what each owns, what it may use, its
//! invariants, the data flow of each command — is `ARCHITECTURE.md` at the
//! repository root; its `layers` block is the layer order that
//! `tests/structure.rs` checks. In short, lowest first: the leaf utilities
//! (`paper`, `report::plot`, `report::files`, `report::progress`, …) ←
//! `model` ← `data` ← `simulate` ← `analysis` ∥ `onboard` ← `report` (the
//! report writers) ← [`cli`].
//!
//! The chain equations are not written here: they live in
//! [`deploywatch_core::Chain`], evaluated in `f64`.
//!
//! # The public API
//!
//! The layers are private to the crate. What a user of the library sees is
//! the modules below, one per thing worked with, each named for the module
//! of the crate that holds it (`deploywatch_sim::deployment` is the
//! simulator's `simulate::deployment`, `deploywatch_sim::reliability::auto`
//! is `analysis::reliability::auto`), with the items the Python package,
//! the fuzz targets, the cross-crate tests and the benches use; and
//! [`cli`], the command line the `deploywatch` binary runs
//! (`ARCHITECTURE.md`, "The public API").
#![deny(missing_docs)]
// The docs name the constants and helpers behind a figure, private ones
// too: they are built with `--document-private-items` (scripts/test.sh),
// where those links resolve.
#![allow(rustdoc::private_intra_doc_links)]
// `!(x > 0.0)` is deliberate: unlike `x <= 0.0` it is true for NaN, so bad
// numbers are rejected instead of slipping through a comparison.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Per-joint arrays are indexed in lockstep; index loops read like the
// equations they implement.
#![allow(clippy::needless_range_loop)]

mod analysis;
pub mod cli;
mod data;
mod model;
mod onboard;
mod paper;
mod report;
mod simulate;

// The public API: one module per thing a user of the library works with,
// each named for the module that holds it (`deploywatch_sim::deployment`
// is `simulate::deployment`), holding only what Python, the fuzz targets,
// the cross-crate tests and the benches use. Everything else is private to
// the crate (`ARCHITECTURE.md`, "The public API").

/// A mechanism read from its TOML file (`docs/spec/formats.md`).
pub mod mechanism {
    pub use crate::model::mechanism::{MassTolerance, Mechanism, SpringSpec};
}

/// The mechanism loader's errors and defaults.
pub mod mechanism_toml {
    pub use crate::model::mechanism_toml::{MechanismError, MechanismErrorKind, DEFAULT_SETTLE_S};
}

/// The named effects of `physics.md` §6.
pub mod effect {
    pub use crate::model::effect::{encoder_offsets_deg, to_core, Effect, EffectKind, Law};
}

/// The findings JSON that `identify` and `diagnose` write.
pub mod findings {
    pub use crate::model::findings::diagnosis::FoundEffect;
    pub use crate::model::findings::stand_in::StandIn;
    pub use crate::model::findings::{Diagnosis, Findings, FindingsError};
}

/// Mobility counts of planar and spatial linkages (seed 000).
pub mod kinematics {
    pub use crate::model::kinematics::{
        planar_mobility, spatial_mobility, truss_bodies_and_joints, FIXED_CONSTRAINTS,
        REVOLUTE_CONSTRAINTS,
    };
}

/// Flexible panels (`physics.md` §12): the first mode of a wing.
pub mod flex {
    pub use crate::model::flex::{PanelFlex, DEFAULT_DAMPING_RATIO, MAX_FLEXIBLE_PANELS};
}

/// A physical latch's tolerances.
pub mod latch {
    pub use crate::model::latch::{LatchTolerance, PlungerSpec};
}

/// Warnings about a mechanism that loads but is implausible.
pub mod plausibility {
    pub use crate::model::plausibility::{warnings, warnings_in};
}

/// Torque tables in `f64` (`torque_table` effect).
pub mod torque_table {
    pub use crate::model::torque_table::{HostChain, HostTable, HostTorqueTable, TablePoints};
}

/// A measured or simulated run (the run CSV of `docs/spec/formats.md`).
pub mod run {
    pub use crate::data::run::{
        check_analysable, pair_runs, ReadOptions, Run, RunError, RunErrorKind, MAX_ANGLE_DEG,
        MISSING_SAMPLES_KEY,
    };
}

/// Runs paired with their mechanisms.
pub mod campaign {
    pub use crate::data::campaign::Campaign;
}

/// The checks of a run's meaning before any work.
pub mod consistency {
    pub use crate::data::consistency::check;
}

/// One deployment simulated (Dormand–Prince 5(4), the core's chain in
/// `f64`).
pub mod deployment {
    pub use crate::simulate::deployment::{
        sample_grid, simulate, simulate_at, SimError, SimOptions, Trajectory,
    };
    pub use crate::simulate::trajectory::{SimStats, Stall, MAX_LEDGER_DRIFT};
}

/// A joint that swung back past its stowed angle, as a run reports it.
pub mod stowed {
    pub use crate::simulate::stowed::{PastStowed, STOWED_TOLERANCE_DEG};
}

/// The sample grid of a trajectory.
pub mod trajectory {
    pub use crate::simulate::trajectory::Samples;
}

/// The reference sensor model (noise, quantisation, switch bounce).
pub mod sensor {
    pub use crate::simulate::sensor::{measure, SensorModel};
}

/// Sensor faults a bench can inject.
pub mod fault_injection {
    pub use crate::simulate::fault_injection::{apply, DropoutMode, SensorFault, KINDS};
}

/// Deployments with physical latches (`physics.md` §10).
pub mod latch_deployment {
    pub use crate::simulate::latch_deployment::check_latch_effects;
    pub use crate::simulate::latch_deployment::{
        latches, run_from, simulate_physical, simulate_with, Keep, LatchEnd, LatchEventKind,
        LatchOutcome, LatchRun, PawlEnd, PlungerEnd,
    };
}

/// Closed-loop (truss) deployments.
pub mod multibody {
    pub use crate::simulate::multibody::{
        run, simulate_wing, wing_model, wing_options, Body, MbTrajectory, Model, Pin, PointSpring,
        System, WingRun, GOLDEN_COLUMNS, GOLDEN_LOCKS,
    };
    /// Building a multibody system.
    pub mod build {
        pub use crate::simulate::multibody::build::open_chain_system;
    }
}

/// The integrator's state.
pub mod ode {
    pub use crate::simulate::ode::State;
}

/// A deployment on the zero-g rig (`physics.md` §11).
pub mod rig {
    pub use crate::simulate::rig::{drag_trolley, simulate_rig};
}

/// Torque margins with the standards' factors.
pub mod design_margin {
    pub use crate::analysis::design_margin::{joint_margin, margin_pct, Standard};
}

/// Every joint's margins with its resistances.
pub mod joint_margins {
    pub use crate::analysis::joint_margins::latch_resistance;
}

/// The rig's share of the friction: the margin on orbit beside the margin
/// on the rig.
pub mod rig_margin {
    pub use crate::analysis::rig_margin::{
        split, torque_margin_pct, MechanismMargins, RigJoint, RigSplit,
    };
}

/// The equivalent friction torque (EFT) of each joint from measured runs.
pub mod identify {
    pub use crate::analysis::identify::{
        all_joints, BeyondDesign, DirectOptions, Identification, IdentifyError, JointEft, Method,
        RsmOptions, RsmResponse, SCAN_GRID_NM,
    };
    /// The response-surface method of seed 000.
    pub mod by_rsm {
        pub use crate::analysis::identify::by_rsm::{centre_beyond, identify_rsm, CENTRE_SAME_NM};
    }
    /// Direct least squares.
    pub mod direct {
        pub use crate::analysis::identify::direct::identify_direct;
    }
    /// The residuals an identification leaves.
    pub mod residual_check {
        pub use crate::analysis::identify::residual_check::{
            residual_warnings, synthetic_campaign, synthetic_run, SyntheticError,
            RESIDUAL_WARN_FACTOR,
        };
    }
    /// Central composite designs and quadratic surfaces.
    pub mod rsm {
        pub use crate::analysis::identify::rsm::{
            fit_quadratic, Ccd, CcdKind, Coding, Fit, Quadratic,
        };
    }
    /// Minimising a quadratic surface in a box.
    pub mod rsm_box {
        pub use crate::analysis::identify::rsm_box::{
            minimize_in_box, minimize_in_box_projected, minimize_weighted_in_box,
        };
    }
}

/// The diagnosis: the named causes of what the model gets wrong.
pub mod diagnose {
    pub use crate::analysis::diagnose::encoder_delay;
    pub use crate::analysis::diagnose::latch_finding::{LatchCause, LatchDifference};
    pub use crate::analysis::diagnose::{
        diagnose, DiagnoseOptions, FittedSet, Outcome, ToleranceShare, WithinTolerance,
        MIN_DELTA_BIC,
    };
}

/// The residual torque of each joint against a model.
pub mod residual_torque {
    pub use crate::analysis::residual_torque::residual_torque;
}

/// The monitor's export of a discovered torque table.
pub mod table_export {
    pub use crate::analysis::table_export::export_tables;
}

/// The probability that a deployment fails.
pub mod reliability {
    pub use crate::analysis::reliability::warning::{switch_open_warning, warnings};
    pub use crate::analysis::reliability::{
        verdict_options, Param, Problem, ReliabilityError, VERDICT_LEDGER_DRIFT, VERDICT_RTOL,
    };
    pub use crate::simulate::latch_deployment::Keep;
    /// The method chosen and its result.
    pub mod auto {
        pub use crate::analysis::reliability::auto::{agree, estimate, Method};
    }
    /// Correlated parameters.
    pub mod correlation {
        pub use crate::analysis::reliability::correlation::Correlation;
    }
    /// The failure criteria.
    pub mod criteria {
        pub use crate::analysis::reliability::criteria::{Criterion, Outcome};
    }
    /// An estimate of a failure probability.
    pub mod estimate {
        pub use crate::analysis::reliability::estimate::Estimate;
    }
    /// Parameters from what identify or diagnose found.
    pub mod identified {
        pub use crate::analysis::reliability::identified::{
            from_findings_json, FromFindings, StandInLaws,
        };
    }
    /// Crude Monte-Carlo.
    pub mod mc {
        pub use crate::analysis::reliability::mc::draw;
    }
    /// The standard normal distribution.
    pub mod normal {
        pub use crate::analysis::reliability::normal::{inverse_cdf, tail};
    }
    /// The parameters varied.
    pub mod params {
        pub use crate::analysis::reliability::params::{unique_labels, Dist, Fixed, Target, Vary};
    }
}

/// A mechanism as the on-board monitor's configuration.
pub mod monitor_config {
    pub use crate::onboard::monitor_config::{monitor_config, replay, samples};
}

/// A run replayed through the on-board monitor, on the host or under QEMU.
pub mod replay {
    pub use crate::onboard::firmware::{firmware_loop_on_host, firmware_supports};
    pub use crate::onboard::replay::{
        compare, decode_statuses, frames, load_run, prepare, summary, Prepared, ReplayError,
        StatusRow,
    };
}

/// Hardware in the loop over a serial line.
pub mod hil {
    pub use crate::onboard::hil::{
        against_full, inject, median_step, plan, reference, Fate, Inject,
    };
}

/// The truss-link synthesis of seed 000, apart from the simulator.
pub mod truss_synthesis {
    pub use crate::paper::truss_synthesis::{synthesize, TrussInput};
}

/// The progress sinks of long work.
pub mod progress {
    pub use crate::report::progress::{quiet, stderr, Progress};
}
