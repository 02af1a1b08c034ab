//! deploywatch host tools: the full deployment simulator, friction
//! identification, torque margins and diagnosis of measured runs.
//!
//! The chain equations are not written here: they live in
//! [`deploywatch_core::chain`], evaluated in `f64`.
#![deny(missing_docs)]
// `!(x > 0.0)` is deliberate: unlike `x <= 0.0` it is true for NaN, so bad
// numbers are rejected instead of slipping through a comparison.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Per-joint arrays are indexed in lockstep; index loops read like the
// equations they implement.
#![allow(clippy::needless_range_loop)]

pub mod campaign;
pub mod cli;
pub mod diagnose;
pub mod effect;
pub mod evidence;
pub mod faults;
pub mod fit;
pub mod identify;
pub mod kinematics;
pub mod margin;
pub mod mechanism;
pub mod mechanism_toml;
pub mod metrics;
pub mod monitor_config;
pub mod ode;
pub mod plot;
pub mod replay;
pub mod rsm;
pub mod run;
pub mod sensor;
pub mod sim;
pub mod truss;
