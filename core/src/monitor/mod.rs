//! The on-board monitor: what the sensors say about a deployment while it
//! runs. The user's side: the [`Monitor`] with its two paths —
//! [`Monitor::update`], the sample path, and [`Monitor::learn_or_predict`],
//! one slice of the slow path (learning from a queued sample, or advancing
//! the latch / stall prediction) —, its configuration ([`MonitorConfig`]
//! and the structs it is made of; [`ConfigError`] names the parameter),
//! its input [`Sample`] and output [`Status`] (a [`JointStatus`] per joint:
//! [`FaultFlags`], [`LatchState`], [`Prediction`], [`Resolution`]), the
//! uncertainty factors of the standards ([`standards`]) and the encoder's
//! frame format ([`encoder`]).
//!
//! Inside, crate-private: `estimator` holds the monitor (one file per
//! concern); it is made of the friction observer (`observer`, on the joint
//! rates of `rate_filter` and the centred fit of `smoother`), the latch
//! tracker (`latch`, its timers in `held`, the physical latch's rule in
//! `bounce`), the reading checks (`plausibility`, `faults`, `encoder`) with
//! each joint's `resolution`, the torque margin (`margin`, the physical
//! latch's engagement in `latch_margin`) and the latch / stall prediction
//! (`predictor` over `rollout`, which ends in `creep`). `core/README.md`
//! maps the two paths.

pub(crate) mod bounce;
pub(crate) mod config;
pub(crate) mod creep;
pub mod encoder;
pub(crate) mod estimator;
pub(crate) mod faults;
pub(crate) mod held;
pub(crate) mod latch;
pub(crate) mod latch_margin;
pub(crate) mod margin;
pub(crate) mod observer;
pub(crate) mod plausibility;
pub(crate) mod predictor;
pub(crate) mod rate_filter;
pub(crate) mod resolution;
pub(crate) mod rollout;
mod serde_array;
pub(crate) mod smoother;
pub mod standards;
pub(crate) mod status;

pub use config::{
    ConfigError, JointConfig, JointParam, MarginConfig, MonitorConfig, ObserverConfig,
    SensorConfig, TuningParam, ENCODER_RANGE_DEG,
};
pub use estimator::{Monitor, LEARNING_QUEUE};
pub use faults::{Fault, FaultFlags};
pub use latch::{LatchConfig, LatchState, LockKind, PhysicalLatch};
pub use latch_margin::Engagement;
pub use margin::{UncertaintyFactors, MARGIN_CAP_PCT};
pub use observer::{FrictionPrior, ObserverTuning};
pub use predictor::Prediction;
pub use rate_filter::JerkAdaptation;
pub use rollout::RolloutConfig;
pub use status::{
    JointStatus, Observability, Resolution, Sample, Status, OBSERVED_PRIOR_SHARE,
    VISCOUS_RESOLVED_SD,
};
