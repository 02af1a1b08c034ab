//! deploywatch host tools: the full deployment simulator, friction
//! identification, torque margins and diagnosis of measured runs.
//!
//! The chain equations are not written here: they live in
//! [`deploywatch_core::chain`], evaluated in `f64`.
#![deny(missing_docs)]

pub mod campaign;
pub mod diagnose;
pub mod effect;
pub mod evidence;
pub mod faults;
pub mod fit;
pub mod identify;
pub mod mechanism;
pub mod ode;
pub mod plot;
pub mod run;
pub mod sensor;
pub mod sim;
pub mod cli;
pub mod mechanism_toml;
pub mod kinematics;
pub mod margin;
pub mod metrics;
pub mod monitor_config;
pub mod rsm;
pub mod truss;
