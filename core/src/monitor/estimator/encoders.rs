//! The sample path's encoder checks: missing, out of range, stuck or stale
//! readings are flagged and not used, a spike that returned is flagged
//! (`plausibility.rs`).

use super::clock::Clock;
use super::joint::{JointState, DEG};
use super::state::Monitor;
use crate::monitor::config::ENCODER_RANGE_DEG;
use crate::monitor::faults::{Fault, FaultFlags};
use crate::monitor::plausibility::{Reading, Verdict};
use crate::monitor::status::Sample;

/// One joint's encoder reading at this sample, as the stages of
/// [`Monitor::update`] make it out.
#[derive(Clone, Copy, Debug)]
pub(super) struct JointReading {
    /// Faults raised so far.
    pub(super) faults: FaultFlags,
    /// The reading the rate filter used \[rad\]: `None` when missing, out of
    /// range, stuck or gated out.
    pub(super) used: Option<f32>,
    /// The reading as it came, range-checked \[rad\]: the latch estimator
    /// compares it with the switch even when the rate filter gated it out
    /// (a joint stopping dead at its latch looks like a spike to it; the
    /// switch must agree anyway).
    pub(super) raw: Option<f32>,
    /// The encoder is frozen for longer than the noise allows.
    pub(super) stuck: bool,
}

/// This sample's encoder readings, one per joint.
pub(super) type Readings<const N: usize> = [JointReading; N];

/// What the encoder checks of one sample share (see
/// [`JointState::read_encoder`]).
struct ReadingContext {
    /// Time stamp of this sample and of the last one used \[s\].
    t: f32,
    t_prev: f32,
    /// Encoder quantisation step \[rad\].
    step_rad: f32,
    /// Repeats of one value that make an encoder stuck (0: never).
    stuck_limit: u16,
    /// The plausibility checks are off (first sample, gap, impact).
    no_checks: bool,
    /// They are off for an impact alone (`Reading::through_impact`).
    impact: bool,
    /// The joints' resolution is followed (a wing with a physical latch).
    follow: bool,
}

impl JointState {
    /// Checks one encoder reading `z` \[deg\] (the joint's latch switch
    /// `switch`): missing, out of range, stuck or stale readings are flagged
    /// and not used, a spike that returned is flagged (`plausibility.rs`).
    /// Returns the reading to use \[rad\], the faults and whether the encoder
    /// is frozen. Not generic over the joint count (one copy in flash).
    #[inline(never)]
    fn read_encoder(
        &mut self,
        z: f32,
        switch: bool,
        ctx: &ReadingContext,
    ) -> (Option<f32>, FaultFlags, bool) {
        let mut faults = FaultFlags::EMPTY;
        if !z.is_finite() {
            faults.insert(Fault::EncoderMissing);
            self.plausibility.lose_reading();
            return (None, faults, false);
        }
        if libm::fabsf(z) > ENCODER_RANGE_DEG {
            faults.insert(Fault::EncoderRange);
            self.plausibility.lose_reading();
            return (None, faults, false);
        }
        // A reading frozen to the same value for longer than the noise
        // allows is a stuck (or stale) encoder: not used.
        if z == self.last_raw {
            self.same_run = self.same_run.saturating_add(1);
        } else {
            self.same_run = 0;
            self.last_raw = z;
        }
        // A latched joint's encoder reads a constant by rights (a
        // noise-free or coarse encoder repeats exactly): the check ends
        // with the latch, whose declaration is final.
        let latched = self.lt.is_latched();
        // The joint's own latch holds it, or may: its readings are the
        // latch's (`Reading::free`).
        let free = !latched && !switch && !self.lt.near_stop();
        // Stale while moving (not used) or a spike that returned (flagged):
        // `plausibility.rs`. Runs before the rate filter's step, on its
        // prediction from the last sample.
        let verdict = self.plausibility.check_filter(
            &Reading {
                t_s: ctx.t,
                angle: Some(z * DEG),
                repeats: self.same_run,
                step: ctx.step_rad,
                moving_checks: !ctx.no_checks && free,
                free,
                through_impact: ctx.impact && !self.lt.escaped(),
                follow: ctx.follow,
            },
            &self.kf,
            ctx.t_prev,
        );
        if let Some(f) = verdict.fault() {
            faults.insert(f);
        }
        let stale = verdict == Verdict::Stale;
        let limit = ctx.stuck_limit;
        if !latched && limit > 0 && (stale || self.same_run.saturating_add(1) >= limit) {
            faults.insert(Fault::EncoderStuck);
            (None, faults, true)
        } else {
            (Some(z * DEG), faults, false)
        }
    }
}

impl<const N: usize> Monitor<N> {
    /// Checks each joint's encoder reading of `sample` (time faults of
    /// `clock` raised on every joint; `announced` when a joint announces an
    /// impact at this sample, [`Monitor::impact_announced`]).
    pub(super) fn read_encoders(
        &mut self,
        sample: &Sample<N>,
        clock: &Clock,
        announced: bool,
    ) -> Readings<N> {
        // The plausibility checks (`plausibility.rs`) are off across a
        // gap and at or after an announced impact (a switch closing, or a
        // physical latch's joint coming within its crest: a joint may stop
        // dead).
        let impact = clock.t <= self.windows.impact_until || announced;
        let restart = !self.timeline.started || clock.gap;
        let no_checks = restart || impact;
        let ctx = ReadingContext {
            t: clock.t,
            t_prev: self.timeline.t_prev,
            step_rad: self.tuning.sensor.encoder_step_deg * DEG,
            stuck_limit: self.tuning.sensor.stuck_samples,
            no_checks,
            impact: impact && !restart,
            follow: self.tuning.follow_resolution,
        };
        // Index loops on the sample path: at the firmware's `opt-level =
        // "z"` an iterator adapter is a call per element.
        let mut readings = [JointReading {
            faults: clock.faults,
            used: None,
            raw: None,
            stuck: false,
        }; N];
        if clock.gap && ctx.follow {
            // The resolution's changes of step are of equally spaced
            // readings.
            for js in self.joints.iter_mut() {
                js.plausibility.lose_reading();
            }
        }
        for (j, js) in self.joints.iter_mut().enumerate() {
            let (z, switch) = (sample.phi_deg[j], sample.latch[j]);
            let (reading, flags, frozen) = js.read_encoder(z, switch, &ctx);
            readings[j] = JointReading {
                faults: clock.faults.union(flags),
                used: reading,
                raw: reading,
                stuck: frozen,
            };
        }
        readings
    }

    /// The joints that announce an impact at `sample`, bit `j` for joint
    /// `j` (0-based; [`super::joint::JointState::announces_impact`]: a latch
    /// switch closes, or a reading comes within a physical latch's crest);
    /// 0 when none does.
    pub(super) fn impact_announced(&self, sample: &Sample<N>) -> u32 {
        let mut mask = 0u32;
        for j in 0..N {
            if self.joints[j].announces_impact(sample.latch[j], sample.phi_deg[j]) {
                mask |= 1u32.wrapping_shl(j as u32);
            }
        }
        mask
    }
}
