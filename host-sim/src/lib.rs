//! deploywatch host tools: the full deployment simulator, friction
//! identification, torque margins and diagnosis of measured runs.
//!
//! The chain equations are not written here: they live in
//! [`deploywatch_core::chain`], evaluated in `f64`.
#![deny(missing_docs)]

pub mod effect;
pub mod mechanism;
pub mod run;
