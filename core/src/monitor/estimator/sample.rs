//! The sample-rate path, [`Monitor::update`]: each sample goes through the
//! clock ([`super::clock`]), the encoder checks ([`super::encoders`]), the
//! rate filters ([`super::rates`]) and the latch states
//! ([`super::latches`]), is queued for the slow path's learning
//! ([`super::learning`]), and gives the sample-rate half of the status.

use super::clock::Clock;
use super::encoders::Readings;
use super::joint::DEG;
use super::latches::Latches;
use super::learning::{JointLearning, Learning};
use super::state::Monitor;
use crate::monitor::faults::FaultFlags;
use crate::monitor::status::{Sample, Status};

impl<const N: usize> Monitor<N> {
    /// Processes one sample and returns the monitor's status.
    ///
    /// Never panics: a NaN or infinite reading is a missing measurement, a
    /// time stamp that does not increase or is not finite makes the sample
    /// unused, and each raises a [`crate::monitor::faults::Fault`] flag in
    /// the status.
    // Out of line: the sample-rate path is one function to measure, and its
    // frame is not merged into the caller's.
    #[inline(never)]
    pub fn update(&mut self, sample: &Sample<N>) -> &Status<N> {
        let clock = match self.timeline.check(sample.t_s, &self.tuning.observer) {
            Ok(clock) => clock,
            Err(faults) => return self.hold(faults),
        };
        // An impact under way: a latch switch closing, or a joint within a
        // physical latch's crest.
        let impacts = self.impact_announced(sample);
        let announced = impacts != 0;
        let mut readings = self.read_encoders(sample, &clock, announced);
        self.track_rates(sample, &clock, impacts, &mut readings);
        let latches = self.track_latches(sample, &clock, impacts, &mut readings);
        self.check_health(&mut readings);
        self.queue_for_learning(&clock, &readings, &latches);
        self.compose_status(clock.t, &readings, &latches);
        &self.status
    }

    /// The previous status with this sample's faults (a sample not used).
    fn hold(&mut self, faults: FaultFlags) -> &Status<N> {
        for js in self.status.joints.iter_mut() {
            js.faults = faults;
        }
        &self.status
    }

    /// Queues the sample for the friction learning of [`Monitor::learn_or_predict`].
    /// The settling after a snap or a gap starts here, on the sample's own
    /// angles. A full queue drops its oldest sample, counted in
    /// [`Monitor::learning_overruns`].
    fn queue_for_learning(&mut self, clock: &Clock, readings: &Readings<N>, latches: &Latches<N>) {
        let t = clock.t;
        let zone = self.tuning.observer.snap_zone_deg * DEG;
        let in_zone =
            (0..N).any(|j| !latches[j].locked && libm::fabsf(self.joints[j].kf.angle()) < zone);
        if in_zone || clock.gap {
            self.windows.blank_until = t + self.tuning.observer.settle_s;
        }
        let quiet = self.quiet(t);
        let sample = Learning {
            t,
            clean: quiet && !clock.gap && clock.dt > 0.0,
            quiet,
            joints: core::array::from_fn(|j| JointLearning {
                used: readings[j].used.unwrap_or(f32::NAN),
                locked: latches[j].locked,
                newly: latches[j].newly,
            }),
        };
        self.learner.push(&mut self.queue, sample);
    }

    /// True when no snap, latch or gap has happened for `settle_s`: the
    /// estimates have settled.
    pub(super) fn quiet(&self, t: f32) -> bool {
        t >= self.windows.blank_until
    }

    /// Composes the sample-rate part of every joint's status at time `t`
    /// \[s\]; the learned part is [`Monitor::refresh_estimates`]'.
    fn compose_status(&mut self, t: f32, readings: &Readings<N>, latches: &Latches<N>) {
        for j in 0..N {
            let (faults, state) = (readings[j].faults, latches[j].state);
            if !faults.is_empty() {
                debug!("joint {} faults {}", j + 1, faults.bits());
            }
            if let (Some(js), Some(out)) = (self.joints.get(j), self.status.joints.get_mut(j)) {
                js.sample_status(out, faults, state);
            }
        }
        self.status.t_s = t;
        self.status.samples = self.status.samples.saturating_add(1);
    }
}
