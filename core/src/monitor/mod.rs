//! The on-board monitor: what the sensors say about a deployment while it
//! runs. [`estimator`] holds the [`Monitor`] (its configuration, the sample
//! path `update` and the slow path `predict`); it is made of the friction
//! observer ([`observer`], on the joint rates of [`rate_filter`] and the
//! centred fit of [`smoother`]), the latch
//! tracker ([`latch`]), the reading checks ([`plausibility`], [`faults`],
//! [`encoder`]) with each joint's [`resolution`], the torque margin ([`margin`], factors of [`standards`], the
//! physical latch's engagement in [`latch_margin`])
//! and the latch / stall prediction ([`predictor`] over [`rollout`], which ends in [`creep`]).
//! `core/README.md` maps the two paths.

pub mod bounce;
pub mod config;
pub mod creep;
pub mod encoder;
pub mod estimator;
pub mod faults;
pub mod held;
pub mod latch;
pub mod latch_margin;
pub mod margin;
pub mod observer;
pub mod plausibility;
pub mod predictor;
pub mod rate_filter;
pub mod resolution;
pub mod rollout;
pub(crate) mod serde_array;
pub mod smoother;
pub mod standards;
pub mod status;

pub use estimator::*;
