//! The length of a rollout's steps (`docs/monitor.md` §6, "The base step"
//! and "Glide"): the base step `dt_s`, halved where a step's own error
//! asks, and lengthened up to `glide_dt_s` while every free joint glides
//! or creeps slowly and smoothly.

use super::{Model, RolloutConfig, Stepper, MAX_HALVINGS};
use crate::physics::spring::Branch;

impl<const R: usize> Stepper<R> {
    /// The base step \[s\]: `cfg.dt_s` halved [`Stepper::halvings`] times.
    pub(super) fn base_step(&self, cfg: &RolloutConfig) -> f32 {
        let mut h = cfg.dt_s;
        for _ in 0..self.halvings.min(MAX_HALVINGS) {
            h *= 0.5;
        }
        h
    }

    /// Length of the next step \[s\]: the base step `base`, or longer, up to
    /// `cfg.glide_dt_s`, while every free joint glides or creeps slowly
    /// and smoothly (`docs/monitor.md` §6, the glide): over the step each
    /// free joint turns by at most [`GLIDE_TURN_RAD`], its rate changes by
    /// at most [`GLIDE_RATE_CHANGE`] of itself (of `ω_c` when slower), its
    /// spring torque at the step's end (at the present rate) differs from
    /// the present one by at most [`GLIDE_TORQUE_CHANGE`] of the larger of
    /// the two torques that balance in the glide, spring and Coulomb (a
    /// tape spring's snap-through peak is met at the base step), and it
    /// covers at most half of what is left to its capture angle (the latch
    /// too). A step is lengthened only from the full base step (no
    /// halving in force) and when these allow at least
    /// [`GLIDE_MIN_STEPS`] base steps at once.
    pub(super) fn step_length(&self, chain: &Model<'_, R>, cfg: &RolloutConfig, base: f32) -> f32 {
        let n = self.count();
        let wc = cfg.coulomb_threshold_rad_s;
        let mut h = cfg.glide_dt_s;
        for j in 0..n {
            if self.latched[j] {
                continue;
            }
            let w = libm::fabsf(self.x.phi_dot[j]);
            let left = libm::fabsf(self.x.phi[j]) - self.start.capture_rad[j];
            let limits = [
                GLIDE_TURN_RAD / w,
                0.5 * left / w,
                GLIDE_RATE_CHANGE * w.max(wc) / libm::fabsf(self.accel[j]),
            ];
            for limit in limits {
                // A NaN limit makes `h` NaN: a base step.
                if !(limit >= h) {
                    h = limit;
                }
            }
        }
        // Lengthened by at least GLIDE_MIN_STEPS base steps or not at all:
        // a swing is stepped exactly as with the fixed step; and not while
        // the base step is halved (its error is not small).
        if self.halvings > 0 || !(h >= GLIDE_MIN_STEPS * base) {
            return base;
        }
        for j in 0..n {
            let (false, Some(joint)) = (self.latched[j], chain.joints().get(j)) else {
                continue;
            };
            let (phi, w) = (self.x.phi[j], self.x.phi_dot[j]);
            let branch = Branch::select(phi, w);
            let scale = self.start.spring_scale[j];
            let now = scale * joint.spring.torque(phi, branch);
            let then = scale * joint.spring.torque(phi + w * h, branch);
            let balance = libm::fabsf(now).max(self.start.coulomb_nm[j]);
            if !(libm::fabsf(then - now) <= GLIDE_TORQUE_CHANGE * balance) {
                return base;
            }
        }
        h
    }
}

/// Most a free joint may turn in one lengthened step of the glide \[rad\]
/// (2°: the spring torque changes little over it).
pub const GLIDE_TURN_RAD: f32 = 0.035;

/// Most a free joint's rate may change in one lengthened step of the
/// glide, relative to the rate (to `ω_c` when slower) \[1\].
pub const GLIDE_RATE_CHANGE: f32 = 0.1;

/// Fewest base steps a lengthened step spans \[1\]: below, the base step.
pub const GLIDE_MIN_STEPS: f32 = 2.0;

/// Most a free joint's spring torque may change over one lengthened step
/// of the glide, relative to the larger of its spring and Coulomb torques
/// \[1\].
pub const GLIDE_TORQUE_CHANGE: f32 = 0.05;
