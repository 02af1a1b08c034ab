//! The on-board deployment monitor: two paths, as flight software runs them.
//!
//! [`Monitor::update`]`(&Sample) -> &Status` is the sample-rate path (a
//! timer interrupt): each sample (time stamp, encoder angles, latch
//! switches) goes through
//!
//! 1. the time checks (NaN, backwards, gaps: [`crate::monitor::faults::Fault`] flags, never a panic);
//! 2. the encoder checks and a kinematic Kalman filter per joint: angle and
//!    rate from the 14-bit encoder, spikes gated out
//!    ([`crate::monitor::rate_filter::RateFilter`]);
//! 3. the latch-state estimator per joint, switch fused with encoder
//!    ([`crate::monitor::latch`]), and the plastic latch impulse on the rates;
//! 4. the sample queued for the friction learning (a bounded queue).
//!
//! [`Monitor::learn_or_predict`] is the slow path (the idle loop or a low-priority
//! task), in slices of bounded cost. A slice either learns from one queued
//! sample, oldest first —
//!
//! 5. the generalised-momentum disturbance observer and RLS friction
//!    estimate per free joint on the centred fit
//!    ([`crate::monitor::observer::FrictionObserver`]);
//! 6. the energy margin of the remaining stroke, one joint per learned
//!    sample in turn ([`crate::monitor::margin`]);
//!
//! — or, with the queue empty, advances the latch / stall prediction by one
//! unit of rollout work ([`crate::monitor::predictor`]).
//!
//! Everything is `f32`, fixed-size and heap-free; the RAM of
//! `Monitor<3>` is held to its budget by `monitor_fits_in_its_ram_budget`
//! (`tests/monitor/`). `docs/monitor.md` has the equations and the tuning.
//!
//! The files, one concern each: the [`Monitor`]'s state and its
//! construction (`state.rs`), one joint's state and status lines
//! (`joint.rs`); the sample path [`Monitor::update`] (`sample.rs`) and its
//! stages: the clock (`clock.rs`), the encoder checks (`encoders.rs`), the
//! rate filters (`rates.rs`), the latch states and impulse (`latches.rs`);
//! the slow path [`Monitor::learn_or_predict`] (`slow_path.rs`): the learning queue
//! (`learning.rs`), the energy margin (`energy.rs`) and the hand-over to
//! the prediction (`prediction.rs`).

mod clock;
mod encoders;
mod energy;
mod joint;
mod latches;
mod learning;
mod prediction;
mod rates;
mod sample;
mod slow_path;
mod state;

pub use self::learning::LEARNING_QUEUE;
pub use self::state::Monitor;

// The unit tests (`estimator/tests.rs`) name the monitor's other types.
#[cfg(test)]
use crate::monitor::config::*;
#[cfg(test)]
use crate::monitor::predictor::Prediction;
#[cfg(test)]
use crate::monitor::status::*;
/// A chain of `N` equal panels (0.8 m, 4 kg) on linear springs, stowed at
/// 90°, 100°, …, with the default tuning: the unit tests' mechanism.
#[cfg(test)]
pub(crate) fn example_config<const N: usize>() -> MonitorConfig<N> {
    let panel = crate::physics::chain::Panel {
        length_m: 0.8,
        mass_kg: 4.0,
        com_m: 0.4,
        inertia_kgm2: 0.3,
    };
    MonitorConfig::new(
        [panel; N],
        core::array::from_fn(|j| JointConfig {
            stowed_deg: 90.0 + 10.0 * j as f32,
            spring: crate::physics::spring::Spring::Linear {
                preload_nm: 1.0,
                stiffness_nm_per_rad: 0.5,
                count: 1.0,
            },
            capture_deg: 0.0,
            prior: crate::monitor::observer::FrictionPrior {
                coulomb_nm: 0.0,
                coulomb_sd_nm: 2.0,
                viscous_nms: 0.0,
                viscous_sd_nms: 0.05,
            },
            latch: crate::monitor::latch_margin::Engagement::IDEAL,
            physical: None,
        }),
    )
}

#[cfg(test)]
mod tests;
