#![doc = include_str!("../README.md")]
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod chain;
pub mod friction;
pub mod linalg;
pub mod real;
pub mod spring;

pub use chain::{Chain, ChainError, ChainState, GlobalEffects, Joint, JointEffects, Mode, Panel};
pub use friction::Friction;
pub use real::Real;
pub use spring::{Branch, Curve, Fold, Interp, Spring, TapePoints};
