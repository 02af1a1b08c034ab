//! deploywatch host tools: the full deployment simulator, friction
//! identification, torque margins, diagnosis of measured runs, reliability,
//! and the on-board monitor replayed on the host.
//!
//! The map of the modules — what each owns, what it may use, its
//! invariants, the data flow of each command — is `ARCHITECTURE.md` at the
//! repository root; its `layers` block is the layer order that
//! `tests/structure.rs` checks. In short, lowest first: the leaf utilities
//! ([`paper`], [`report::plot`], [`report::files`], [`report::progress`],
//! …) ← [`model`] ← [`data`] ← [`simulate`] ← [`analysis`] ∥ [`onboard`] ←
//! [`report`] (the report writers) ← [`cli`].
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

pub mod analysis;
pub mod cli;
pub mod data;
pub mod model;
pub mod onboard;
pub mod paper;
pub mod report;
pub mod simulate;
