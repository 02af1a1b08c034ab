//! deploywatch host tools: the full deployment simulator, friction
//! identification, torque margins and diagnosis of measured runs.
//!
//! The modules follow the pipeline a mechanisms engineer runs:
//!
//! ```text
//!  model ──────────────► simulate ───────────► data ──────────► analysis ─────────► report
//!  mechanism TOML,        deployment (DOPRI5    run CSV,          fit, metrics,       plots,
//!  named effects,         + events), sensor,    campaign          identify (RSM,      JSON, Markdown
//!  kinematics             fault injection       (runs ↔ mech.)    direct), diagnose,  (cli/)
//!                                                  │              design_margin
//!                                                  ▼
//!                                               onboard: the core's monitor on a run
//!                                               (host or QEMU replay)
//! ```
//!
//! - [`model`]: what is simulated — a [`model::mechanism::Mechanism`] read from
//!   its TOML file, the named effects of `physics.md` §6, mobility.
//! - [`simulate`]: from a mechanism to a run — the chain integrated in `f64`,
//!   the encoder and switch model, injected sensor faults.
//! - [`data`]: runs as recorded (`formats.md`) and campaigns of runs.
//! - [`analysis`]: what the runs say — metrics, least squares, friction
//!   identification, diagnosis, design margins.
//! - [`onboard`]: the on-board monitor of `deploywatch_core` fed with a run.
//! - [`report`]: plots; [`paper`]: the seed papers' own tables.
//! - [`cli`]: the `deploywatch` command line, one module per subcommand.
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
