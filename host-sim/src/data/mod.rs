//! Runs as they are recorded (the run CSV of `docs/spec/formats.md`) and a
//! campaign: several runs, each paired with its mechanism.
pub mod campaign;
pub mod consistency;
pub mod glitch;
pub mod inputs;
pub mod resolution;
pub mod run;
