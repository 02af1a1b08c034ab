//! The monitor's internals, for tests that check them against the host
//! simulator (feature `internals`, off by default; `tests/` turns it on).
//!
//! Not part of the core's public surface: nothing here is stable, the
//! listing of that surface (`core/public-api.txt`, checked in CI by
//! `scripts/public-api.py`) is of the features a firmware or host crate
//! uses (`hal`, `defmt`), without this one.

pub use crate::monitor::rollout::{JointOutcome, Rollout, RolloutStart};
