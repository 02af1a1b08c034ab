//! Latch-state estimator of one joint: fuses the debounced latch switch with
//! the encoder.
//!
//! ```text
//!  Stowed ──moved > start_deg──▶ Deploying ──|φ| < latching_deg──▶ Latching
//!                                  ▲   │                              │
//!                    |ω| > 2 v_s   │   ▼ |ω| < v_s for stall_s        │ switch closed in 2 of the
//!                                  Stalled                            ▼ last 3 samples and
//!                                                                   Latched   |φ| < window_deg
//!  Fault: shown instead of the motion state while a sensor disagrees
//!  (switch closed far from the latch, encoder at the latch with the switch
//!  open, encoder missing for several samples). Latched holds (ideal latch)
//!  until switch and encoder both say the joint is out: the switch open and
//!  the reading beyond `at_latch_deg` for `debounce_s` is `Escaped`, flagged
//!  `latch_disagree` (the drawing's latch cannot open) until the latch is
//!  declared again. Never `Latched` while the tracker's own inputs say out.
//! ```
//!
//! A latch is declared only when the switch says so (so never before the
//! true latch instant: the switch closes at the latch) *and* the encoder
//! agrees: a switch that closes far from the latch angle, or an encoder at
//! the latch angle with the switch open, raises a fault flag instead. One
//! closed sample is never enough (two of the last three are needed), so a
//! single bad switch sample can neither declare nor — once confirmed — undo
//! a latch.
//!
//! With a physical latch configured ([`PhysicalLatch`]: a stop the joint
//! bounces off, a ball plunger it can escape over, a ramp it can stop on;
//! `docs/monitor.md` §4.1) the rule is the one of [`crate::monitor::bounce`]:
//! rebounds are not chatter, the latch is declared once the switch has held
//! closed for the bounce window with the encoder on the stop, an escape over
//! the plunger's crest is [`LatchState::Escaped`] (not latched, also after a
//! declaration, until the latch is declared again) and a joint at rest on the
//! ramp with the switch open is [`LatchState::StoppedShort`].
//!
//! A pawl ([`LockKind::Pawl`], `physics.md` §10.5) cannot open: once
//! declared, a rebound within its notch keeps the joint latched, and an
//! escape (out beyond the notch and the contact's give) is a broken pawl,
//! [`LatchState::Escaped`] flagged `latch_disagree` for the rest of the run:
//! a broken pawl locks nothing, so its joint is never declared latched
//! again, also where its spring holds it on the stop with the switch closed.

use crate::monitor::bounce::{Bounce, LatchEvent, StopLimits, StopReading};
use crate::monitor::faults::{Fault, FaultFlags};
use crate::monitor::held::{Held, HeldSamples};
use serde::{Deserialize, Serialize};

pub use crate::monitor::bounce::{LockKind, PhysicalLatch};

/// Slack on the bounce window of a physical latch \[s\]: the time stamps'
/// `f32` rounding (a few µs at 10 s) must not cost a sample; far below the
/// smallest time step the monitor accepts (0.1 ms).
const HOLD_ROUNDING_S: f32 = 1e-5;

/// Standard deviations of one encoder reading (noise and quantisation)
/// within which an ideal latch's joint reads "at the latch" for the
/// switch-open checks \[1\]: a reading of a joint held at the latch exceeds
/// it with probability 6·10⁻⁷, and a joint that friction stopped further
/// short (0.27° with σ = 0.02°) is resolved as not latched, its open switch
/// agreeing (`docs/monitor.md` §6.2).
const AT_LATCH_SIGMAS: f32 = 5.0;

/// The latch state of a joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LatchState {
    /// Not yet moved from the stowed angle.
    #[default]
    Stowed,
    /// Moving towards the latch.
    Deploying,
    /// Within the latching zone or the switch is closing (with a physical
    /// latch: also while the joint bounces off its stop).
    Latching,
    /// The latch is confirmed by switch and encoder (final for the ideal
    /// latch; with a physical latch until switch and encoder both say the
    /// joint has left the stop).
    Latched,
    /// Stopped short of the latch, outside the plunger's ramp.
    Stalled,
    /// A sensor disagrees; see the joint's fault flags.
    Fault,
    /// The joint went back over the plunger's crest after its switch had
    /// closed (an escape of a physical latch): not latched until the
    /// latch is declared again. An event of the mechanism, not a sensor
    /// fault. With an ideal latch drawn, a joint whose switch opened and
    /// whose encoder read beyond `at_latch_deg` for the debounce time after the
    /// declaration, flagged `latch_disagree` (the drawing's latch cannot
    /// open).
    Escaped,
    /// At rest on the plunger's ramp, short of the latch, with the switch
    /// open (physical latch only): neither latched nor a mid-stroke stall.
    StoppedShort,
}

impl LatchState {
    /// Every state.
    pub const ALL: [LatchState; 8] = [
        LatchState::Stowed,
        LatchState::Deploying,
        LatchState::Latching,
        LatchState::Latched,
        LatchState::Stalled,
        LatchState::Fault,
        LatchState::Escaped,
        LatchState::StoppedShort,
    ];

    /// The name used in telemetry CSV and reports.
    pub const fn as_str(self) -> &'static str {
        match self {
            LatchState::Stowed => "stowed",
            LatchState::Deploying => "deploying",
            LatchState::Latching => "latching",
            LatchState::Latched => "latched",
            LatchState::Stalled => "stalled",
            LatchState::Fault => "fault",
            LatchState::Escaped => "escaped",
            LatchState::StoppedShort => "stopped_short",
        }
    }

    /// The state of a name written by [`LatchState::as_str`].
    pub fn from_name(name: &str) -> Option<Self> {
        LatchState::ALL.iter().copied().find(|s| s.as_str() == name)
    }
}

impl core::fmt::Display for LatchState {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Thresholds of the latch-state estimator.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LatchConfig {
    /// The encoder must read within this of the latch angle for a closed
    /// switch to be a latch \[deg\].
    pub window_deg: f32,
    /// Closed switch samples needed among the last three (2 or 3).
    pub closed_votes: u8,
    /// Movement from the stowed angle that starts `Deploying` \[deg\].
    pub start_deg: f32,
    /// `|φ|` below which a deploying joint is `Latching` \[deg\].
    pub latching_deg: f32,
    /// Rate below which a deploying joint counts as stopped [deg/s].
    pub stall_rate_deg_s: f32,
    /// How long it must stay stopped to be `Stalled` \[s\].
    pub stall_time_s: f32,
    /// Encoder reading that counts as "at the latch" for the switch-open
    /// check \[deg\] (ideal latch, at most: before the latch the window is
    /// narrowed to 5 σ of one encoder reading when that is smaller; a
    /// physical latch uses its switch travel and the encoder noise
    /// instead).
    pub at_latch_deg: f32,
    /// How long the encoder may sit at the latch with the switch open
    /// before that is a fault \[s\].
    pub switch_timeout_s: f32,
    /// Consecutive missing encoder samples that make the joint `Fault`.
    pub missing_samples: u8,
    /// How long the switch must stay closed without a break to count on its
    /// own \[s\]: for a latch while the encoder is unavailable (missing or
    /// stuck), and for a switch closed far from the latch angle to be
    /// distrusted. Longer than the longest bounce (20 ms). Also the bounce
    /// window: two changes of the switch's state within it are chatter
    /// (with a physical latch, only when the encoder did not see the joint
    /// leave its stop).
    pub debounce_s: f32,
    /// How long a healthy encoder must read within `at_latch_deg` of the
    /// latch angle, while the switch stays open or is distrusted, for the
    /// latch to be confirmed by the encoder alone \[s\] (flagged). Longer
    /// than the stuck-encoder detection, so a reading frozen at the latch
    /// angle is caught first.
    pub encoder_confirm_s: f32,
    /// The latch as built (stop, plunger, ramp), `None` for the ideal latch
    /// of `physics.md` §5 (a permanent lock at 0, a switch that closes
    /// once).
    pub physical: Option<PhysicalLatch>,
}

impl Default for LatchConfig {
    fn default() -> Self {
        LatchConfig {
            window_deg: 2.0,
            closed_votes: 2,
            start_deg: 1.0,
            latching_deg: 3.0,
            stall_rate_deg_s: 1.0,
            stall_time_s: 1.0,
            at_latch_deg: 0.3,
            switch_timeout_s: 0.1,
            missing_samples: 5,
            debounce_s: 0.03,
            encoder_confirm_s: 0.3,
            physical: None,
        }
    }
}

impl LatchConfig {
    /// True when every threshold is finite and in range.
    pub(crate) fn is_valid(&self) -> bool {
        let pos = [
            self.window_deg,
            self.start_deg,
            self.latching_deg,
            self.stall_rate_deg_s,
            self.at_latch_deg,
        ];
        pos.iter().all(|v| v.is_finite() && *v > 0.0)
            && self.stall_time_s.is_finite()
            && self.stall_time_s >= 0.0
            && self.switch_timeout_s.is_finite()
            && self.switch_timeout_s >= 0.0
            && (2..=3).contains(&self.closed_votes)
            && self.missing_samples > 0
            && self.debounce_s.is_finite()
            && self.debounce_s >= 0.0
            && self.encoder_confirm_s.is_finite()
            && self.encoder_confirm_s > 0.0
            && self.physical.is_none_or(|p| p.is_valid())
    }
}

/// What the estimator sees of a joint at one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatchInput {
    /// Time stamp \[s\].
    pub t_s: f32,
    /// The latch switch (true = closed).
    pub switch: bool,
    /// The encoder reading \[deg\], `None` when missing or rejected.
    pub measured_deg: Option<f32>,
    /// The filtered angle \[deg\].
    pub angle_deg: f32,
    /// The filtered rate [deg/s].
    pub rate_deg_s: f32,
    /// The stowed angle \[deg\].
    pub stowed_deg: f32,
    /// True while the encoder is known to be stuck (its readings are then
    /// `None` in `measured_deg`): a switch that disagreed with it is
    /// trusted again.
    pub encoder_stuck: bool,
    /// Standard deviation of one encoder reading \[deg\] (noise and
    /// quantisation): how far "on the stop" reaches with a physical latch,
    /// and "at the latch" with the ideal one (`AT_LATCH_SIGMAS`).
    pub noise_sd_deg: f32,
    /// Another joint announced a latch impact at this sample or the
    /// previous one: its impulse may have changed this joint's rate between
    /// the two readings, so their speed says nothing of when this joint
    /// reaches its stop (`docs/monitor.md` §6.2).
    pub neighbour_impact: bool,
}

impl LatchInput {
    /// The sample as the physical-latch rule sees it.
    fn stop_reading(&self) -> StopReading {
        StopReading {
            t_s: self.t_s,
            switch: self.switch,
            off_deg: self.measured_deg.map(libm::fabsf),
            speed_known: !self.neighbour_impact,
        }
    }
}

impl LatchEvent {
    /// The state reported for the event.
    const fn state(self) -> LatchState {
        match self {
            LatchEvent::Escaped => LatchState::Escaped,
            LatchEvent::StoppedShort => LatchState::StoppedShort,
            LatchEvent::Rebound => LatchState::Latching,
        }
    }
}

/// The estimator's answer for one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatchOutput {
    /// The state to report.
    pub state: LatchState,
    /// True on the one sample at which the latch is declared.
    pub newly_latched: bool,
    /// True on the one sample at which a declared latch is found undone
    /// (physical latch: the joint left its stop or escaped).
    pub unlatched: bool,
    /// Faults found at this sample.
    pub faults: FaultFlags,
}

impl LatchOutput {
    /// A sample with no change of the latch.
    const fn state(state: LatchState, faults: FaultFlags) -> Self {
        LatchOutput {
            state,
            newly_latched: false,
            unlatched: false,
            faults,
        }
    }
}

/// Latch-state estimator of one joint.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct LatchTracker {
    motion: LatchState,
    latched: bool,
    /// Switch readings, newest in bit 0.
    history: u8,
    samples: u8,
    /// Slow stretch of the filtered rate (with hysteresis).
    slow: Held,
    /// With an ideal latch: the stretch of readings within the rest band
    /// of `rest_deg`, the reading that started it \[deg\].
    rest: Held,
    rest_deg: f32,
    /// Encoder at the latch with the switch open.
    at_latch: Held,
    open_at_latch: bool,
    missing: HeldSamples,
    switch_early: bool,
    /// Unbroken closed stretch of the switch.
    closed: Held,
    /// A debounced switch closed with the encoder far from the latch.
    early: Held,
    /// The switch closed far from the latch for `debounce_s`: it is not
    /// trusted (stuck closed) until the encoder is found stuck.
    switch_suspect: bool,
    /// Encoder at the latch angle with the switch open or distrusted.
    confirm: Held,
    /// The switch's last change of state.
    flip: Held,
    /// The physical latch's bounce, escape and ramp bookkeeping.
    bounce: Bounce,
}

impl LatchTracker {
    /// A joint in its stowed state.
    pub const fn new() -> Self {
        LatchTracker {
            motion: LatchState::Stowed,
            latched: false,
            history: 0,
            samples: 0,
            slow: Held::NEW,
            rest: Held::NEW,
            rest_deg: 0.0,
            at_latch: Held::NEW,
            open_at_latch: false,
            missing: HeldSamples::NEW,
            switch_early: false,
            closed: Held::NEW,
            early: Held::NEW,
            switch_suspect: false,
            confirm: Held::NEW,
            flip: Held::NEW,
            bounce: Bounce::NEW,
        }
    }

    /// True once the switch has been closed far from the latch angle for
    /// the debounce time: it is then not used for the latch decision.
    #[cfg(test)]
    pub fn switch_suspect(&self) -> bool {
        self.switch_suspect
    }

    /// True while the latch is confirmed.
    pub fn is_latched(&self) -> bool {
        self.latched
    }

    /// True when a reading `z_deg` \[deg\] brings the joint, not latched,
    /// within the crest of a physical latch's stop (it was beyond it at the
    /// previous reading, or its speed put it there by this one): it may hit
    /// the stop before the next sample, or has just hit it.
    pub fn enters_stop_zone(&self, z_deg: f32) -> bool {
        let off = libm::fabsf(z_deg);
        !self.latched && (self.bounce.enters_zone(off) || self.bounce.reaches(off))
    }

    /// True when a reading `z_deg` \[deg\] of a latched joint with a
    /// physical latch lies within the crest's reach (a pawl's notch): the
    /// joint may rebound there off its stop, held by its lock, so the
    /// reading is motion the lock allows, not an encoder spike. False for
    /// the ideal latch and before the latch.
    pub fn rebounds_within_lock(&self, z_deg: f32) -> bool {
        self.latched && self.bounce.within_reach(libm::fabsf(z_deg))
    }

    /// True while a physical latch's joint is out over the crest after an
    /// escape (not latched again yet).
    pub fn escaped(&self) -> bool {
        !self.latched && self.bounce.escaped()
    }

    /// True while the previous reading put the joint, not latched, within
    /// the crest of a physical latch's stop, where it may stop dead on the
    /// stop or the ramp, or bounce: a reading there is not judged by the
    /// smooth-motion checks of `plausibility.rs`.
    pub fn near_stop(&self) -> bool {
        !self.latched && self.bounce.in_zone()
    }

    /// True while a physical latch's joint, not latched, has been past the
    /// crest since it last escaped (a reading within it, or the switch
    /// closed at the latch): the hold ramp and the magnet pull it onto the
    /// stop, where it cannot stop on the entry ramp. False for an ideal
    /// latch and for a broken lock.
    pub fn past_crest(&self) -> bool {
        !self.latched && self.bounce.past_crest() && !self.bounce.lock_broken()
    }

    /// True once the joint's lock broke (a pawl out beyond its notch after
    /// its switch closed, `physics.md` §10.5): it is not latched again.
    pub fn lock_broken(&self) -> bool {
        self.bounce.lock_broken()
    }

    /// True while the encoder sits at the latch angle with the switch open
    /// (the joint is then held fixed by the dynamics model, but not latched).
    pub fn held_at_latch(&self) -> bool {
        self.open_at_latch
    }

    /// True while a latch that cannot open is out after its declaration
    /// (an ideal latch: switch open and encoder out for the debounce time;
    /// a pawl: escaped, i.e. broken): not latched, and a disagreement with
    /// the drawing, until the latch is declared again. With an ideal
    /// drawing nothing else makes the motion `Escaped`.
    fn left_ideal(&self, cfg: &LatchConfig) -> bool {
        // The motion first: it is rarely `Escaped` (the sample path's cost).
        self.motion == LatchState::Escaped && cfg.physical.is_none_or(|p| p.lock == LockKind::Pawl)
    }

    /// Declares the latch (`switch`: the switch's reading now).
    fn declare(&mut self, switch: bool, faults: FaultFlags, cfg: &LatchConfig) -> LatchOutput {
        self.latched = true;
        self.motion = LatchState::Latched;
        self.switch_early = false;
        self.open_at_latch = false;
        if cfg.physical.is_none() {
            // Reused after the declaration: switch open and encoder out.
            self.at_latch.stop();
        }
        self.bounce.latched(switch);
        LatchOutput {
            newly_latched: true,
            ..LatchOutput::state(LatchState::Latched, faults)
        }
    }

    /// One sample.
    pub fn step(&mut self, x: &LatchInput, cfg: &LatchConfig) -> LatchOutput {
        let mut faults = FaultFlags::EMPTY;
        let view = self.view(x, cfg);
        let votes = self.record_switch(x, cfg, view.physical, &mut faults);
        self.missing.update(x.measured_deg.is_none());
        if self.latched {
            return self.step_latched(x, cfg, view.left, faults);
        }
        if self.left_ideal(cfg) {
            faults.insert(Fault::LatchDisagree);
            // With a physical latch, a pawl out beyond its notch after its
            // switch closed: broken for good.
            if cfg.physical.is_some() {
                self.bounce.break_lock();
            }
        }
        if self.lock_broken() {
            // A broken pawl holds nothing: at its stop, switch closed, the
            // joint is pushed there by its spring, not locked.
            return LatchOutput::state(LatchState::Escaped, faults);
        }
        if let Some(out) = self.check_switch(x, cfg, votes, view.held, &mut faults) {
            return out;
        }
        if let Some(out) = self.confirm_by_encoder(x, cfg, view.at_latch, &mut faults) {
            return out;
        }
        self.check_open_at_latch(x, cfg, view.at_latch, &mut faults);
        let state = self.motion_state(x, cfg, view.event, view.at_latch);
        LatchOutput::state(state, faults)
    }

    /// What the configured latch makes of this sample's encoder reading:
    /// the ideal latch's thresholds, or the physical latch's rule
    /// ([`Bounce`]), which takes the sample here.
    fn view(&mut self, x: &LatchInput, cfg: &LatchConfig) -> LatchView {
        self.closed.update(x.switch, x.t_s);
        let Some(p) = cfg.physical else {
            // The encoder resolves a stop short of the latch beyond its
            // noise: the window is the narrower of the configured one and
            // `AT_LATCH_SIGMAS` readings' σ.
            let window = cfg.at_latch_deg.min(AT_LATCH_SIGMAS * x.noise_sd_deg);
            return LatchView {
                physical: false,
                at_latch: x.measured_deg.is_some_and(|m| libm::fabsf(m) <= window),
                held: true,
                left: None,
                event: None,
            };
        };
        let lim = StopLimits::new(&p, x.noise_sd_deg);
        let r = x.stop_reading();
        self.bounce.observe(&r, &lim, cfg.window_deg);
        let on_stop = r.off_deg.is_none_or(|d| d <= lim.on_stop_deg);
        let (left, event) = if self.latched {
            (self.bounce.left_stop(&r, &lim), None)
        } else {
            (None, self.bounce.event(x.t_s, cfg.stall_time_s))
        };
        LatchView {
            physical: true,
            at_latch: r.off_deg.is_some() && self.bounce.smoothed_off_deg() <= lim.at_rest_deg,
            held: on_stop
                && self
                    .closed
                    .at_least(x.t_s, p.bounce_window_s - HOLD_ROUNDING_S),
            left,
            event,
        }
    }

    /// A sample after the latch was declared: a switch that opens or an
    /// encoder that leaves the window is flagged and the latch kept; with
    /// a physical latch, the latch is undone when both say the joint has
    /// left its stop (`left`: a rebound after the declaration, or an
    /// escape).
    fn step_latched(
        &mut self,
        x: &LatchInput,
        cfg: &LatchConfig,
        left: Option<LatchEvent>,
        mut faults: FaultFlags,
    ) -> LatchOutput {
        if let Some(event) = left {
            let pawl = cfg.physical.is_some_and(|p| p.lock == LockKind::Pawl);
            if pawl && event == LatchEvent::Rebound {
                // Within the notch: the pawl holds.
                return LatchOutput::state(LatchState::Latched, faults);
            }
            let state = event.state();
            self.latched = false;
            self.motion = state;
            if pawl {
                faults.insert(Fault::LatchDisagree);
            }
            return LatchOutput {
                unlatched: true,
                ..LatchOutput::state(state, faults)
            };
        }
        let away = x
            .measured_deg
            .is_some_and(|m| libm::fabsf(m) > cfg.window_deg);
        if !x.switch || away {
            faults.insert(Fault::LatchDisagree);
        }
        // Never `latched` while the inputs say out: the switch open and a
        // valid reading beyond `at_latch_deg` (the ideal drawing has no
        // switch travel: the reading that counts as at the latch stands for
        // it), both for the debounce time (longer than any bounce). With an
        // ideal drawing that is a disagreement with the drawing.
        let out = x
            .measured_deg
            .is_some_and(|m| libm::fabsf(m) > cfg.at_latch_deg);
        // (`at_latch` times it: unused while latched; the monitor's RAM
        // budget has no byte for another timer.)
        if cfg.physical.is_some() {
            return LatchOutput::state(LatchState::Latched, faults);
        }
        self.at_latch.update(!x.switch && out, x.t_s);
        if self.at_latch.at_least(x.t_s, cfg.debounce_s) {
            self.latched = false;
            self.at_latch.stop();
            self.motion = LatchState::Escaped;
            return LatchOutput {
                unlatched: true,
                ..LatchOutput::state(LatchState::Escaped, faults)
            };
        }
        LatchOutput::state(LatchState::Latched, faults)
    }

    /// The state to report when no latch was declared: the motion state
    /// from the filtered angle and rate (with a physical latch: an escape,
    /// or a stop on the ramp, `event`, first), or `Fault` while a sensor
    /// disagrees. A joint at rest for `stall_time_s` (by its rate, or by
    /// its readings with an ideal latch, [`LatchTracker::rests_near`]) is
    /// `Stalled`, also within `latching_deg` of its latch unless the
    /// encoder puts it at the latch (`at_latch`) or its switch is closed:
    /// stopped short of the latch, the switch rightly open.
    fn motion_state(
        &mut self,
        x: &LatchInput,
        cfg: &LatchConfig,
        event: Option<LatchEvent>,
        at_latch: bool,
    ) -> LatchState {
        let moved = libm::fabsf(x.angle_deg - x.stowed_deg) > cfg.start_deg;
        let speed = libm::fabsf(x.rate_deg_s);
        if speed < cfg.stall_rate_deg_s {
            self.slow.start(x.t_s);
        } else if speed > 2.0 * cfg.stall_rate_deg_s {
            self.slow.stop();
        }
        // The rest band is kept at every sample ([`LatchTracker::at_rest_for`]
        // reads it), also while the rate alone says the joint is stopped.
        let near = self.rests_near(x, cfg);
        let stopped = self.slow.at_least(x.t_s, cfg.stall_time_s) || near;
        let in_window = libm::fabsf(x.measured_deg.unwrap_or(x.angle_deg)) <= cfg.window_deg;
        self.motion = match (event, self.motion) {
            (Some(event), _) => event.state(),
            (None, _) if self.left_ideal(cfg) => LatchState::Escaped,
            (None, LatchState::Stowed) if moved => LatchState::Deploying,
            (None, LatchState::Stowed) => LatchState::Stowed,
            _ if stopped && !at_latch && !x.switch => LatchState::Stalled,
            _ if libm::fabsf(x.angle_deg) < cfg.latching_deg || (x.switch && in_window) => {
                LatchState::Latching
            }
            _ if stopped => LatchState::Stalled,
            (None, LatchState::Stalled) if self.slow.is_on() => LatchState::Stalled,
            _ => LatchState::Deploying,
        };
        let fault = self.switch_early
            || self.switch_suspect
            || self.open_at_latch
            || self.missing.count() >= cfg.missing_samples;
        if fault {
            LatchState::Fault
        } else {
            self.motion
        }
    }
}

/// What the configured latch makes of one sample (see
/// [`LatchTracker::step`]).
#[derive(Clone, Copy, Debug)]
struct LatchView {
    /// A physical latch is configured.
    physical: bool,
    /// The encoder puts the joint at the latch: the reading within
    /// `at_latch_deg` (ideal latch), or the smoothed reading within the
    /// switch travel and one reading's noise of the stop (physical latch:
    /// a joint at rest on the ramp is not at the latch).
    at_latch: bool,
    /// The switch has held closed for the bounce window with the reading
    /// on the stop (always true for the ideal latch).
    held: bool,
    /// A declared physical latch left its stop at this sample.
    left: Option<LatchEvent>,
    /// What a physical latch reports instead of the motion state.
    event: Option<LatchEvent>,
}

mod rest;
mod switch;

#[cfg(test)]
mod tests;
