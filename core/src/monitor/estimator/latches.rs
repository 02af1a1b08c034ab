//! The sample path's latch stage: each joint's latch state (switch fused
//! with encoder, [`crate::monitor::latch`]), and the plastic latch impulse
//! on the rate estimates when a joint latches (`physics.md` §5).

use super::clock::Clock;
use super::encoders::Readings;
use super::joint::DEG;
use super::rates::ACC_SHOCK_VAR;
use super::state::Monitor;
use crate::monitor::latch::{LatchInput, LatchState};
use crate::monitor::status::Sample;
use crate::physics::chain::ChainState;

/// Variance added to a rate after a latch impulse [rad²/s²].
const RATE_SHOCK_VAR: f32 = 0.04;

/// One joint's latch after this sample.
#[derive(Clone, Copy, Debug)]
pub(super) struct JointLatch {
    /// The joint's state.
    pub(super) state: LatchState,
    /// Declared latched at this sample.
    pub(super) newly: bool,
    /// The model sits the joint at 0 (latched or held at the latch).
    pub(super) locked: bool,
}

/// The latch states after this sample, one per joint.
pub(super) type Latches<const N: usize> = [JointLatch; N];

impl<const N: usize> Monitor<N> {
    /// Tracks the latch states (switch fused with encoder), and applies the
    /// plastic latch impulse to the rates when a joint latches. `impacts`:
    /// the joints announcing an impact at this sample, bit `j` for joint
    /// `j` ([`Monitor::impact_announced`]).
    pub(super) fn track_latches(
        &mut self,
        sample: &Sample<N>,
        clock: &Clock,
        impacts: u32,
        readings: &mut Readings<N>,
    ) -> Latches<N> {
        let t = clock.t;
        // A neighbour's impact at this sample or the previous one.
        let recent = impacts | self.windows.impacts_prev;
        self.windows.impacts_prev = impacts;
        let mut states = [LatchState::Stowed; N];
        let mut newly = [false; N];
        let mut unlatched = false;
        let noise_sd_deg = self.tuning.meas_sd / DEG;
        for (j, js) in self.joints.iter_mut().enumerate() {
            let out = js.lt.step(
                &LatchInput {
                    t_s: t,
                    switch: sample.latch[j],
                    measured_deg: readings[j].raw.map(|z| z / DEG),
                    angle_deg: js.kf.angle() / DEG,
                    rate_deg_s: js.kf.rate() / DEG,
                    stowed_deg: js.stowed_deg,
                    encoder_stuck: readings[j].stuck,
                    noise_sd_deg,
                    neighbour_impact: recent & !1u32.wrapping_shl(j as u32) != 0,
                },
                &js.latch_cfg,
            );
            states[j] = out.state;
            newly[j] = out.newly_latched;
            unlatched |= out.unlatched;
            readings[j].faults = readings[j].faults.union(out.faults);
        }
        let locked: [bool; N] = core::array::from_fn(|j| self.joints[j].locked());
        if newly.iter().any(|n| *n) {
            self.apply_latch_impulse(&newly, &locked);
            self.windows.blank_until = t + self.tuning.observer.settle_s;
        } else if unlatched {
            // A physical latch undone (a rebound or an escape after the
            // declaration): the joint is free again, the learning settles.
            self.windows.blank_until = t + self.tuning.observer.settle_s;
        }
        core::array::from_fn(|j| JointLatch {
            state: states[j],
            newly: newly[j],
            locked: locked[j],
        })
    }

    /// The plastic latch impulse of `physics.md` §5 applied to the rate
    /// estimates ([`crate::physics::chain::Chain::latch_impulse`] on the
    /// rate filters' state): the momentum of every joint that stays free is
    /// kept and the newly latched joints stop.
    fn apply_latch_impulse(&mut self, newly: &[bool; N], locked_after: &[bool; N]) {
        let locked_before: [bool; N] = core::array::from_fn(|j| locked_after[j] && !newly[j]);
        let pick = |j: usize, v: f32| if locked_before[j] { 0.0 } else { v };
        let before = ChainState {
            phi: core::array::from_fn(|j| pick(j, self.joints[j].kf.angle())),
            phi_dot: core::array::from_fn(|j| pick(j, self.joints[j].kf.rate())),
        };
        let Ok(after) = self.chain.latch_impulse(&before, locked_after) else {
            return;
        };
        for j in 0..N {
            if newly[j] {
                let a = self.joints[j].kf.angle();
                self.joints[j].kf.pin(a);
            } else if !locked_after[j] && after[j].is_finite() {
                self.joints[j].kf.set_rate(after[j], RATE_SHOCK_VAR);
                self.joints[j].kf.inflate(0.0, ACC_SHOCK_VAR);
            }
        }
    }
}
