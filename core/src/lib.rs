#![doc = include_str!("../README.md")]
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]
// The docs name the constants and helpers behind a figure, private ones
// too: they are built with `--document-private-items` (scripts/test.sh),
// where those links resolve.
#![allow(rustdoc::private_intra_doc_links)]
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

#[cfg(feature = "hal")]
pub mod hal;
#[cfg(feature = "internals")]
pub mod internals;
pub mod monitor;
pub mod physics;
pub mod telemetry;

// The chain model, at the crate root: one path per item. `physics` holds
// the rest of the physics (the latch hardware, the friction law's shape
// functions, the solver), `monitor` the on-board monitor.
pub use physics::chain::{
    Chain, ChainError, ChainState, GlobalEffects, Joint, JointEffects, JointTorque, Mode, Panel,
};
pub use physics::friction::Friction;
pub use physics::real::Real;
pub use physics::spring::{Branch, Curve, CurveError, Fold, Interp, Spring, TapePoints};
pub use physics::torque_table::{Table, TableError, TorqueTable};
