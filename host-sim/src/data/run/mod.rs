//! A measured or simulated run: the run CSV of `docs/spec/formats.md`.
//!
//! [`record`] holds the run and its limits, [`parse`] reads the CSV (through
//! [`dialect`] for a spreadsheet's), [`validate`] checks a run in memory and
//! writes it, [`pair`] pairs runs with mechanisms, [`error`] says what is
//! wrong and where.

mod dialect;
mod error;
mod pair;
mod parse;
mod record;
mod validate;

pub use error::{RunError, RunErrorKind};
pub use pair::{check_analysable, check_run_of, pair_runs};
pub use record::{
    ExtraColumn, ExtraKind, ReadOptions, Run, MAX_ANGLE_DEG, MIN_MOTION_DEG, MISSING_SAMPLES_KEY,
    MISSING_SAMPLES_VALUE,
};
