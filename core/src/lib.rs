#![doc = include_str!("../README.md")]
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]
#![forbid(unsafe_code)]
// `!(x > 0.0)` is deliberate throughout the core: unlike `x <= 0.0` it is
// true for NaN, which is how a NaN input becomes "missing" instead of
// slipping through a comparison.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Fixed-size matrix code indexes several arrays in lockstep; index loops
// read like the equations they implement.
#![allow(clippy::needless_range_loop)]

#[macro_use]
mod fmt;

pub mod chain;
pub mod encoder;
pub mod faults;
pub mod friction;
#[cfg(feature = "hal")]
pub mod hal;
pub mod latch;
pub mod linalg;
pub mod margin;
pub mod monitor;
pub mod observer;
pub mod plausibility;
pub mod predictor;
pub mod real;
pub mod rollout;
pub mod smoother;
pub mod spring;
pub mod standards;
pub mod telemetry;
pub mod torque_table;
pub mod trig;

pub use chain::{Chain, ChainError, ChainState, GlobalEffects, Joint, JointEffects, Mode, Panel};
pub use friction::Friction;
pub use real::Real;
pub use spring::{Branch, Curve, Fold, Interp, Spring, TapePoints};
pub use torque_table::{Table, TableError, TorqueTable};

pub use faults::{Fault, FaultFlags};
pub use latch::LatchState;
pub use monitor::{
    JointConfig, JointStatus, Monitor, MonitorConfig, Observability, Prediction, Sample, Status,
};
