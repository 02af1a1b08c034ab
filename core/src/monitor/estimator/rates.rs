//! The sample path's rate filters: each joint's kinematic Kalman filter
//! predicts to the sample and fuses its reading, with the latch impact
//! expected when a switch closes (`docs/monitor.md` §2, §6.2); spikes are
//! flagged and gated out, a filter that fails restarts at the reading.

use super::clock::Clock;
use super::encoders::Readings;
use super::joint::{JointState, DEG, START_ACC_SD, START_RATE_SD};
use super::state::Monitor;
use crate::monitor::config::ObserverConfig;
use crate::monitor::faults::{Fault, FaultFlags};
use crate::monitor::rate_filter::{Fusion, RateFilter};
use crate::monitor::status::Sample;

/// A rate filter restarted after repeated rejections or a numerical
/// failure: the joint may be anywhere in its stroke.
mod reset {
    /// Consecutive gate rejections after which the rate filter restarts at
    /// the measurement.
    pub(super) const MAX_REJECTS: u8 = 3;
    /// Rate uncertainty of the restarted filter [rad/s].
    pub(super) const RATE_SD: f32 = 1.0;
    /// Acceleration uncertainty of the restarted filter [rad/s²].
    pub(super) const ACC_SD: f32 = 10.0;
}

/// Variance added to an acceleration after a latch impulse, an impact or a
/// gap [rad²/s⁴].
pub(super) const ACC_SHOCK_VAR: f32 = 100.0;

/// A gap in the time stamps.
mod gap {
    /// Variance added to a rate over a gap [rad²/s²] (the joint may have
    /// changed its rate by ≈ 1 rad/s while unobserved).
    pub(super) const RATE_VAR: f32 = 1.0;
    /// Variance added to the first reading after a gap \[rad²\].
    pub(super) const MEAS_VAR: f32 = 1.0;
}

/// The latch impact when a switch closes.
mod impact {
    /// Time after a latch switch closes during which a reading the rate
    /// filter rejects is the latch impact, not an outlier \[s\]: the impact
    /// is within a sample of the closing at 100 Hz, and a chattering switch
    /// (≤ 20 ms) closes again inside it.
    pub(super) const WINDOW_S: f32 = 0.03;
    /// Samples, from the one where a switch closes, whose prediction is
    /// widened for the impact.
    pub(super) const INFLATE_SAMPLES: u8 = 2;
    /// Rate variance added to every free joint at an impact [rad²/s²]: the
    /// plastic impulse changes the rates by up to about 2 rad/s.
    pub(super) const RATE_VAR: f32 = 4.0;
    /// Rate uncertainty of a filter restarted at an impact [rad/s].
    pub(super) const RATE_SD: f32 = 1.0;
}

/// Innovations up to this many gates are a manoeuvre (the filter restarts
/// at the reading, keeping its rate), beyond it a spike (flagged). At
/// σ ≈ 0.03° a gate is 0.17° and this 1°: a joint stopping under its
/// friction at 5 rad/s² misses the prediction by ½·a·t² ≈ 0.06° over 20 ms,
/// and the whip of a long chain (neighbours snapping to their latches
/// double an outer joint's rate within 45 ms, `docs/monitor.md` §6.2) by
/// 0.75°, while a spike is degrees off; a smaller spike that returns is
/// flagged by `plausibility.rs`.
const MANOEUVRE_GATE: f32 = 6.0;

/// A reading beyond the manoeuvre gate but within this of the parabola
/// through the joint's last three readings, or of the cubic through its
/// last four, is its own accelerating motion (a light outer panel's tape
/// spring snapping at hundreds of rad/s² outruns the white-jerk model by
/// degrees; a joint whose neighbour is about to latch, or nearing its own
/// latch at 1,800°/s, sees its acceleration double within a sample), not a
/// spike \[rad\]: 1.5°, 8 σ of the cubic's extrapolation (`σ √69` for the
/// reference encoder), where a spike is degrees off (one that comes back
/// is flagged by `plausibility.rs`).
const PARABOLA_TOL_RAD: f32 = 1.5 * DEG;

/// What the rate filters of one sample share (see [`JointState::track_rate`]).
struct RateContext<'a> {
    /// The clock's verdict on this sample.
    clock: Clock,
    /// Within the impact window after a switch closed.
    impact: bool,
    /// Widen the rate filter's prediction for the impact.
    inflate: bool,
    /// Variance of one reading \[rad²\] and its square root \[rad\].
    meas_var: f32,
    meas_sd: f32,
    /// The observer's tuning.
    observer: &'a ObserverConfig,
}

/// What a joint's rate filter made of its reading.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RateOutcome {
    /// Fused, or none to fuse.
    Used,
    /// Rejected as an outlier; the reading is not used.
    GatedOut,
    /// The filter restarted at the reading (impact or reset): the friction
    /// learning waits for the settling.
    Restarted,
}

/// A rate filter started at `phi_rad` \[rad\] with angle, rate and
/// acceleration deviations `sd` \[rad\], `sd_rate` [rad/s] and `sd_acc`
/// [rad/s²], and the jerk spectral density `jerk_psd` [rad²/s⁵].
fn fresh_filter(phi_rad: f32, sd: f32, sd_rate: f32, sd_acc: f32, jerk_psd: f32) -> RateFilter {
    let mut f = RateFilter::new(phi_rad, sd, sd_rate, sd_acc);
    f.set_jerk_psd(jerk_psd);
    f
}

/// The mean rate over the last interval `dt` \[s\] of a joint whose
/// reading missed the prediction of `kf` by `nu` \[rad\]: from the filter's
/// angle at the previous sample to the reading, `x₁ + ν/Δt − ½ Δt x₂`
/// [rad/s] (the prediction's rate when that is not finite). Out of line
/// and cold: only an escaped joint's manoeuvre takes it, and the sample
/// path of every other joint does none of its work.
#[cold]
#[inline(never)]
fn readings_rate(kf: &RateFilter, nu: f32, dt: f32) -> f32 {
    let mean = kf.rate() + nu / dt - 0.5 * dt * kf.acceleration();
    if mean.is_finite() {
        mean
    } else {
        kf.rate()
    }
}

/// A first reading within this of the stowed angle is a deployment
/// starting from its release \[rad\] (1°: 40 σ of the reference encoder).
const RELEASE_NEAR_RAD: f32 = 1.0 * DEG;

impl JointState {
    /// The rate filter at the first sample, at rest at its reading
    /// `phi0_rad` \[rad\] (deviation `sd` \[rad\], jerk spectral density
    /// `jerk_psd` [rad²/s⁵]). At the stowed angle the joint is released:
    /// its acceleration starts at the springs' release acceleration
    /// (seeded at configuration, `state.rs`), with that size as its
    /// deviation (friction may take any part of it); elsewhere (a monitor
    /// started mid-motion) at 0 as before.
    fn start_filter(&mut self, phi0_rad: f32, sd: f32, jerk_psd: f32) {
        let released = libm::fabsf(phi0_rad - self.stowed_deg * DEG) <= RELEASE_NEAR_RAD;
        let acc = if released {
            self.kf.acceleration()
        } else {
            0.0
        };
        let sd_acc = START_ACC_SD + libm::fabsf(acc);
        self.kf = fresh_filter(phi0_rad, sd, START_RATE_SD, sd_acc, jerk_psd);
        self.kf.set_acceleration(acc);
    }

    /// The joint's rate filter at one sample: prediction and fusion of its
    /// reading (see [`Monitor::track_rates`]; `docs/monitor.md` §2, §6.2).
    /// Not generic over the joint count, so the monitors of 2 and 3 joints
    /// share one copy in flash.
    #[inline(never)]
    fn track_rate(
        &mut self,
        reading: Option<f32>,
        stopping: bool,
        faults: &mut FaultFlags,
        ctx: &RateContext<'_>,
    ) -> RateOutcome {
        let r_meas = ctx.meas_var;
        let (observer, gap) = (ctx.observer, ctx.clock.gap);
        let gate2 = observer.gate_sigma * observer.gate_sigma;
        let zone = observer.snap_zone_deg * DEG;
        let latched = self.lt.is_latched();
        let kf = &mut self.kf;
        // An escaped joint (physical latch) moves as it is thrown about
        // between the plunger and its spring: followed as in the snap zone.
        let free_zone = libm::fabsf(kf.angle()) < zone || self.lt.escaped();
        let q_floor = if !latched && free_zone {
            observer.zone_jerk_psd
        } else {
            0.0
        };
        if ctx.inflate && !latched {
            kf.inflate(impact::RATE_VAR, ACC_SHOCK_VAR);
        }
        kf.predict(ctx.clock.dt, q_floor);
        if gap {
            kf.inflate(gap::RATE_VAR, ACC_SHOCK_VAR);
        }
        let Some(z) = reading else {
            return RateOutcome::Used;
        };
        let r = if gap { r_meas + gap::MEAS_VAR } else { r_meas };
        match kf.update(z, r, gate2, &observer.jerk_adaptation) {
            Fusion::Accepted => {
                self.rejects = 0;
                RateOutcome::Used
            }
            Fusion::Rejected => self.rejected(z, r, stopping, faults, ctx),
        }
    }

    /// A reading `z` \[rad\] (variance `r` \[rad²\]) the rate filter's
    /// gate rejected: an impact, a rebound within the lock or a manoeuvre
    /// restarts the filter at it, anything else is an outlier (flagged; the
    /// filter restarts after [`reset::MAX_REJECTS`] in a row). Judged only
    /// on a rejection: the filter is as it was predicted. `stopping`: this
    /// joint's own switch is closed or it announced the impact (it stops on
    /// its latch); another joint's impact leaves it moving.
    fn rejected(
        &mut self,
        z: f32,
        r: f32,
        stopping: bool,
        faults: &mut FaultFlags,
        ctx: &RateContext<'_>,
    ) -> RateOutcome {
        let (sd, observer) = (ctx.meas_sd, ctx.observer);
        let gate2 = observer.gate_sigma * observer.gate_sigma;
        let kf = &mut self.kf;
        // A reading beyond the gate but within `MANOEUVRE_GATE` gates of
        // the prediction is a manoeuvre the white-jerk model did not
        // foresee (a joint that sticks under its friction stops with a
        // step in acceleration), not a spike; so is one that follows the
        // readings' own course (`plausibility.rs`).
        let nu = z - kf.angle();
        // A latched joint's reading within the reach of its physical
        // latch's crest (a pawl's notch) is a rebound the lock allows: the
        // joint leaves its stop and comes back within a few samples, the
        // switch opening with it. Restarted at the reading like an impact,
        // not flagged; a spike beyond the reach still is.
        let rebound = self.lt.rebounds_within_lock(z / DEG);
        // On a joint its readings do not resolve (shaken faster than the
        // samples follow, `resolution.rs`) any reading is taken as a
        // manoeuvre: a spike cannot be told from its motion there.
        let manoeuvre = nu * nu <= MANOEUVRE_GATE * MANOEUVRE_GATE * gate2 * (kf.angle_var() + r)
            || self.plausibility.follows_readings(z, PARABOLA_TOL_RAD)
            || self.plausibility.unresolved();
        if ctx.impact || rebound || manoeuvre {
            // A manoeuvre keeps the joint's rate. An escaped joint's, as
            // the readings give it: the mean rate over the last interval,
            // from the filter's angle at the previous sample to this
            // reading (`x₁ + ν/Δt − ½ Δt x₂`, the predicted rate corrected
            // by the miss). Not the prediction's rate: thrown about
            // between its plunger and its spring, it bounces off its stop
            // between two readings, which leaves the filter with the
            // bounce as an acceleration of thousands of rad/s² and its
            // predicted rate thousands of degrees per second off. (On a
            // quiet joint the prediction's rate stays: a spike the
            // widened gate takes for a manoeuvre must not set it.) A
            // joint that stops on its latch restarts at rest; one that a
            // neighbour's impact threw (its impulse changes every free
            // joint's rate, physics.md §5) at the readings' rate: at rest,
            // a light panel whipped to 1,600°/s misses its next reading
            // by 20° at 100 Hz.
            let rate = if rebound || (ctx.impact && stopping) {
                0.0
            } else if ctx.impact || self.lt.escaped() {
                readings_rate(kf, nu, ctx.clock.dt)
            } else {
                kf.rate()
            };
            *kf = RateFilter::new(z, sd, impact::RATE_SD, START_ACC_SD);
            kf.set_rate(rate, 0.0);
            kf.set_jerk_psd(observer.jerk_psd);
            self.rejects = 0;
            return if ctx.impact || rebound {
                RateOutcome::Restarted
            } else {
                RateOutcome::Used
            };
        }
        faults.insert(Fault::EncoderOutlier);
        self.rejects = self.rejects.saturating_add(1);
        if self.rejects >= reset::MAX_REJECTS {
            *kf = RateFilter::new(z, sd, reset::RATE_SD, reset::ACC_SD);
            kf.set_jerk_psd(observer.jerk_psd);
            faults.insert(Fault::EstimatorReset);
            self.rejects = 0;
            RateOutcome::Restarted
        } else {
            RateOutcome::GatedOut
        }
    }
}

impl<const N: usize> Monitor<N> {
    /// Tracks the angles and rates: each rate filter predicts to the sample
    /// and fuses its reading, with the latch impact expected when a switch
    /// closes (`impacts`, the joints announcing one,
    /// [`Monitor::impact_announced`]; `docs/monitor.md` §6.2); spikes are
    /// flagged and gated out.
    pub(super) fn track_rates(
        &mut self,
        sample: &Sample<N>,
        clock: &Clock,
        impacts: u32,
        readings: &mut Readings<N>,
    ) {
        let (t, announced) = (clock.t, impacts != 0);
        if !self.timeline.started {
            let (sd, jerk_psd) = (self.tuning.meas_sd, self.tuning.observer.jerk_psd);
            for j in 0..N {
                let phi0 = readings[j].used.unwrap_or(self.joints[j].stowed_deg * DEG);
                self.joints[j].start_filter(phi0, sd, jerk_psd);
            }
            self.timeline.started = true;
            self.timeline.t_start = t;
        } else {
            // A latch switch closing (or, with a physical latch, a joint
            // coming within its crest) announces an impact: the latching
            // joint stops within a sample and the plastic impulse changes
            // the other joints' rates (physics.md §5). Over the next
            // `impact::WINDOW_S` the rate filters widen their gates, and a
            // reading they still cannot reconcile restarts the filter at
            // the reading: expected, not an outlier.
            if announced {
                self.windows.impact_until = t + impact::WINDOW_S;
                self.windows.impact_samples = impact::INFLATE_SAMPLES;
            }
            let impact = t <= self.windows.impact_until;
            let inflate = self.windows.impact_samples > 0;
            self.windows.impact_samples = self.windows.impact_samples.saturating_sub(1);
            let ctx = RateContext {
                clock: *clock,
                impact,
                inflate,
                meas_var: self.tuning.meas_var,
                meas_sd: self.tuning.meas_sd,
                observer: &self.tuning.observer,
            };
            for (j, js) in self.joints.iter_mut().enumerate() {
                let Some(r) = readings.get_mut(j) else {
                    continue;
                };
                let stopping = sample.latch[j] || impacts & 1u32.wrapping_shl(j as u32) != 0;
                match js.track_rate(r.used, stopping, &mut r.faults, &ctx) {
                    RateOutcome::Used => {}
                    RateOutcome::GatedOut => r.used = None,
                    RateOutcome::Restarted => {
                        self.windows.blank_until = t + self.tuning.observer.settle_s;
                    }
                }
            }
        }
        self.timeline.t_prev = t;
        for (js, s) in self.joints.iter_mut().zip(sample.latch.iter()) {
            js.switch_prev = *s;
        }
    }

    /// Health of the rate filters: nothing non-finite survives an update.
    /// A failed rate filter restarts at the reading.
    pub(super) fn check_health(&mut self, readings: &mut Readings<N>) {
        let (sd, jerk_psd) = (self.tuning.meas_sd, self.tuning.observer.jerk_psd);
        for j in 0..N {
            if !self.joints[j].kf.is_healthy() {
                let phi0 = readings[j].used.unwrap_or(self.joints[j].stowed_deg * DEG);
                self.joints[j].kf = fresh_filter(phi0, sd, reset::RATE_SD, reset::ACC_SD, jerk_psd);
                readings[j].faults.insert(Fault::EstimatorReset);
            }
        }
    }
}
