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
//!  open, encoder missing for several samples). Latched is final.
//! ```
//!
//! A latch is declared only when the switch says so (so never before the
//! true latch instant: the switch closes at the latch) *and* the encoder
//! agrees: a switch that closes far from the latch angle, or an encoder at
//! the latch angle with the switch open, raises a fault flag instead. One
//! closed sample is never enough (two of the last three are needed), so a
//! single bad switch sample can neither declare nor — once confirmed — undo
//! a latch.

use crate::monitor::faults::{Fault, FaultFlags};
use crate::monitor::held::Held;
use serde::{Deserialize, Serialize};

/// The latch state of a joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LatchState {
    /// Not yet moved from the stowed angle.
    #[default]
    Stowed,
    /// Moving towards the latch.
    Deploying,
    /// Within the latching zone or the switch is closing.
    Latching,
    /// The latch is confirmed by switch and encoder (final).
    Latched,
    /// Stopped short of the latch.
    Stalled,
    /// A sensor disagrees; see the joint's fault flags.
    Fault,
}

impl LatchState {
    /// Every state.
    pub const ALL: [LatchState; 6] = [
        LatchState::Stowed,
        LatchState::Deploying,
        LatchState::Latching,
        LatchState::Latched,
        LatchState::Stalled,
        LatchState::Fault,
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
    /// switch to be a latch [deg].
    pub window_deg: f32,
    /// Closed switch samples needed among the last three (2 or 3).
    pub closed_votes: u8,
    /// Movement from the stowed angle that starts `Deploying` [deg].
    pub start_deg: f32,
    /// `|φ|` below which a deploying joint is `Latching` [deg].
    pub latching_deg: f32,
    /// Rate below which a deploying joint counts as stopped [deg/s].
    pub stall_rate_deg_s: f32,
    /// How long it must stay stopped to be `Stalled` [s].
    pub stall_time_s: f32,
    /// Encoder reading that counts as "at the latch" for the switch-open
    /// check [deg].
    pub at_latch_deg: f32,
    /// How long the encoder may sit at the latch with the switch open
    /// before that is a fault [s].
    pub switch_timeout_s: f32,
    /// Consecutive missing encoder samples that make the joint `Fault`.
    pub missing_samples: u8,
    /// How long the switch must stay closed without a break to count on its
    /// own [s]: for a latch while the encoder is unavailable (missing or
    /// stuck), and for a switch closed far from the latch angle to be
    /// distrusted. Longer than the longest bounce (20 ms). Also the bounce
    /// window: two changes of the switch's state within it are chatter.
    pub debounce_s: f32,
    /// How long a healthy encoder must read within `at_latch_deg` of the
    /// latch angle, while the switch stays open or is distrusted, for the
    /// latch to be confirmed by the encoder alone [s] (flagged). Longer
    /// than the stuck-encoder detection, so a reading frozen at the latch
    /// angle is caught first.
    pub encoder_confirm_s: f32,
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
        }
    }
}

impl LatchConfig {
    /// True when every threshold is finite and in range.
    pub fn is_valid(&self) -> bool {
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
    }
}

/// What the estimator sees of a joint at one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatchInput {
    /// Time stamp [s].
    pub t_s: f32,
    /// The latch switch (true = closed).
    pub switch: bool,
    /// The encoder reading [deg], `None` when missing or rejected.
    pub measured_deg: Option<f32>,
    /// The filtered angle [deg].
    pub angle_deg: f32,
    /// The filtered rate [deg/s].
    pub rate_deg_s: f32,
    /// The stowed angle [deg].
    pub stowed_deg: f32,
    /// True while the encoder is known to be stuck (its readings are then
    /// `None` in `measured_deg`): a switch that disagreed with it is
    /// trusted again.
    pub encoder_stuck: bool,
}

/// The estimator's answer for one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatchOutput {
    /// The state to report.
    pub state: LatchState,
    /// True on the one sample at which the latch is declared.
    pub newly_latched: bool,
    /// Faults found at this sample.
    pub faults: FaultFlags,
}

/// Latch-state estimator of one joint.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct LatchTracker {
    motion: LatchState,
    latched: bool,
    /// Switch readings, newest in bit 0.
    history: u8,
    samples: u8,
    /// The filtered rate below the stall rate (with hysteresis: it ends
    /// above twice that rate).
    slow: Held,
    /// The encoder at the latch angle with the switch open.
    open: Held,
    open_at_latch: bool,
    /// Consecutive samples without an encoder reading.
    missing_run: u8,
    switch_early: bool,
    /// An unbroken closed stretch of the switch.
    closed: Held,
    /// A debounced switch closed with the encoder far from the latch.
    early: Held,
    /// The switch closed far from the latch for `debounce_s`: it is not
    /// trusted (stuck closed) until the encoder is found stuck.
    switch_suspect: bool,
    /// The encoder at the latch angle with the switch open or distrusted.
    confirm: Held,
    /// The switch's last change of state (an event).
    flip: Held,
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
            open: Held::NEW,
            open_at_latch: false,
            missing_run: 0,
            switch_early: false,
            closed: Held::NEW,
            early: Held::NEW,
            switch_suspect: false,
            confirm: Held::NEW,
            flip: Held::NEW,
        }
    }

    /// True once the switch has been closed far from the latch angle for
    /// the debounce time: it is then not used for the latch decision.
    pub fn switch_suspect(&self) -> bool {
        self.switch_suspect
    }

    /// True once the latch is confirmed.
    pub fn is_latched(&self) -> bool {
        self.latched
    }

    /// True while the encoder sits at the latch angle with the switch open
    /// (the joint is then held fixed by the dynamics model, but not latched).
    pub fn held_at_latch(&self) -> bool {
        self.open_at_latch
    }

    /// Declares the latch (final).
    fn declare(&mut self, faults: FaultFlags) -> LatchOutput {
        self.latched = true;
        self.motion = LatchState::Latched;
        self.switch_early = false;
        self.open_at_latch = false;
        LatchOutput {
            state: LatchState::Latched,
            newly_latched: true,
            faults,
        }
    }

    /// One sample.
    pub fn step(&mut self, x: &LatchInput, cfg: &LatchConfig) -> LatchOutput {
        let mut faults = FaultFlags::EMPTY;
        let votes = self.read_switch(x, cfg, &mut faults);
        if x.measured_deg.is_some() {
            self.missing_run = 0;
        } else {
            self.missing_run = self.missing_run.saturating_add(1);
        }
        let angle = x.measured_deg.unwrap_or(x.angle_deg);
        let in_window = libm::fabsf(angle) <= cfg.window_deg;
        if self.latched {
            return Self::hold(x, cfg, faults);
        }
        if self.switch_declares(x, cfg, votes, in_window, &mut faults) {
            return self.declare(faults);
        }
        if self.encoder_declares(x, cfg, &mut faults) {
            return self.declare(faults);
        }
        self.check_open_at_latch(x, cfg, &mut faults);
        self.track_motion(x, cfg, in_window);
        let fault = self.switch_early
            || self.switch_suspect
            || self.open_at_latch
            || self.missing_run >= cfg.missing_samples;
        LatchOutput {
            state: if fault {
                LatchState::Fault
            } else {
                self.motion
            },
            newly_latched: false,
            faults,
        }
    }

    /// Shifts the switch reading into the history and flags chatter;
    /// returns the closed votes of the last three samples.
    #[inline(always)]
    fn read_switch(&mut self, x: &LatchInput, cfg: &LatchConfig, faults: &mut FaultFlags) -> u8 {
        self.history = (self.history << 1) | u8::from(x.switch);
        self.samples = self.samples.saturating_add(1);
        let last3 = self.history & 0b111;
        if self.samples >= 3 && (last3 == 0b101 || last3 == 0b010) {
            faults.insert(Fault::SwitchChatter);
        }
        // Any reversal within the bounce time of the previous change of
        // state is chatter, however many samples the bounce held (a clean
        // switch closes once, at the latch, and stays closed).
        if self.samples >= 2 && (last3 & 0b01 != 0) != (last3 & 0b10 != 0) {
            if self.flip.within(x.t_s, cfg.debounce_s) {
                faults.insert(Fault::SwitchChatter);
            }
            self.flip.restart(x.t_s);
        }
        last3.count_ones() as u8
    }

    /// A declared latch is final: a switch that opens, or an encoder away
    /// from the latch, is a disagreement.
    #[inline(always)]
    fn hold(x: &LatchInput, cfg: &LatchConfig, mut faults: FaultFlags) -> LatchOutput {
        let away = x
            .measured_deg
            .is_some_and(|m| libm::fabsf(m) > cfg.window_deg);
        if !x.switch || away {
            faults.insert(Fault::LatchDisagree);
        }
        LatchOutput {
            state: LatchState::Latched,
            newly_latched: false,
            faults,
        }
    }

    /// The switch's case: true when a debounced closed switch declares the
    /// latch. Switch closed (debounced): a latch if a valid encoder reading
    /// agrees, or, with no valid reading, only once the switch has stayed
    /// closed for the whole debounce time — the filtered angle alone is not
    /// evidence (two corrupted samples, a spurious closure and a missing
    /// reading, must not make a latch). A distrusted switch declares
    /// nothing; a switch closed far from the latch for the debounce time
    /// becomes distrusted.
    #[inline(always)]
    fn switch_declares(
        &mut self,
        x: &LatchInput,
        cfg: &LatchConfig,
        votes: u8,
        in_window: bool,
        faults: &mut FaultFlags,
    ) -> bool {
        self.closed.update(x.switch, x.t_s);
        let closed_long = self.closed.at_least(x.t_s, cfg.debounce_s);
        if x.encoder_stuck {
            // The disagreement was the encoder's.
            self.switch_suspect = false;
            self.early.stop();
        }
        let closed = x.switch && votes >= cfg.closed_votes;
        let agrees = match x.measured_deg {
            Some(_) => in_window,
            None => closed_long,
        };
        if closed && agrees && !self.switch_suspect {
            return true;
        }
        self.switch_early = closed && !agrees;
        if self.switch_early {
            faults.insert(Fault::SwitchEarly);
            if x.measured_deg.is_some() {
                self.early.start(x.t_s);
                if self.early.at_least(x.t_s, cfg.debounce_s) {
                    self.switch_suspect = true;
                }
            }
        } else {
            self.early.stop();
        }
        if self.switch_suspect {
            faults.insert(Fault::SwitchEarly);
        }
        false
    }

    /// The encoder alone: true when it has been at the latch angle for the
    /// confirmation time while the switch stays open or is distrusted.
    #[inline(always)]
    fn encoder_declares(
        &mut self,
        x: &LatchInput,
        cfg: &LatchConfig,
        faults: &mut FaultFlags,
    ) -> bool {
        let encoder_at_latch = (!x.switch || self.switch_suspect)
            && x.measured_deg
                .is_some_and(|m| libm::fabsf(m) <= cfg.at_latch_deg);
        self.confirm.update(encoder_at_latch, x.t_s);
        if encoder_at_latch && self.confirm.at_least(x.t_s, cfg.encoder_confirm_s) {
            if !x.switch {
                faults.insert(Fault::SwitchOpenAtLatch);
            }
            return true;
        }
        false
    }

    /// The encoder at the latch while the switch stays open for the switch
    /// timeout: a switch fault.
    #[inline(always)]
    fn check_open_at_latch(&mut self, x: &LatchInput, cfg: &LatchConfig, faults: &mut FaultFlags) {
        let at_latch = !x.switch
            && x.measured_deg
                .is_some_and(|m| libm::fabsf(m) <= cfg.at_latch_deg);
        self.open.update(at_latch, x.t_s);
        self.open_at_latch = at_latch && self.open.at_least(x.t_s, cfg.switch_timeout_s);
        if self.open_at_latch {
            faults.insert(Fault::SwitchOpenAtLatch);
        }
    }

    /// The motion state from the filtered angle and rate.
    #[inline(always)]
    fn track_motion(&mut self, x: &LatchInput, cfg: &LatchConfig, in_window: bool) {
        let moved = libm::fabsf(x.angle_deg - x.stowed_deg) > cfg.start_deg;
        let speed = libm::fabsf(x.rate_deg_s);
        if speed < cfg.stall_rate_deg_s {
            self.slow.start(x.t_s);
        } else if speed > 2.0 * cfg.stall_rate_deg_s {
            self.slow.stop();
        }
        let stopped = self.slow.at_least(x.t_s, cfg.stall_time_s);
        self.motion = match self.motion {
            LatchState::Stowed if moved => LatchState::Deploying,
            LatchState::Stowed => LatchState::Stowed,
            _ if libm::fabsf(x.angle_deg) < cfg.latching_deg || (x.switch && in_window) => {
                LatchState::Latching
            }
            _ if stopped => LatchState::Stalled,
            LatchState::Stalled if self.slow.is_on() => LatchState::Stalled,
            _ => LatchState::Deploying,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(t: f32, switch: bool, deg: f32) -> LatchInput {
        LatchInput {
            t_s: t,
            switch,
            measured_deg: Some(deg),
            angle_deg: deg,
            rate_deg_s: -50.0,
            stowed_deg: 90.0,
            encoder_stuck: false,
        }
    }

    fn run(tr: &mut LatchTracker, samples: &[(bool, f32)]) -> LatchOutput {
        let cfg = LatchConfig::default();
        let mut out = None;
        for (i, &(sw, deg)) in samples.iter().enumerate() {
            out = Some(tr.step(&input(i as f32 * 0.01, sw, deg), &cfg));
        }
        out.unwrap()
    }

    #[test]
    fn given_switch_and_encoder_agree_when_closed_twice_then_latched() {
        let mut tr = LatchTracker::new();
        let out = run(&mut tr, &[(false, 80.0), (false, 1.0), (true, 0.0)]);
        assert_eq!(
            out.state,
            LatchState::Latching,
            "one closed sample is not a latch"
        );
        let out = tr.step(&input(0.03, true, 0.01), &LatchConfig::default());
        assert!(out.newly_latched);
        assert_eq!(out.state, LatchState::Latched);
    }

    #[test]
    fn given_switch_closed_far_from_latch_then_fault_not_latch() {
        let mut tr = LatchTracker::new();
        let out = run(
            &mut tr,
            &[(false, 60.0), (true, 59.0), (true, 58.0), (true, 57.0)],
        );
        assert_eq!(out.state, LatchState::Fault);
        assert!(out.faults.contains(Fault::SwitchEarly));
        assert!(!tr.is_latched());
    }

    #[test]
    fn given_encoder_at_latch_with_switch_open_then_fault_not_latch() {
        let mut tr = LatchTracker::new();
        let samples: [(bool, f32); 20] = [(false, 0.01); 20];
        let out = run(&mut tr, &samples);
        assert_eq!(out.state, LatchState::Fault);
        assert!(out.faults.contains(Fault::SwitchOpenAtLatch));
        assert!(!tr.is_latched());
    }

    #[test]
    fn given_confirmed_latch_when_switch_opens_then_latch_kept_and_flagged() {
        let mut tr = LatchTracker::new();
        run(&mut tr, &[(true, 0.0), (true, 0.0)]);
        assert!(tr.is_latched());
        let out = tr.step(&input(1.0, false, 0.0), &LatchConfig::default());
        assert_eq!(out.state, LatchState::Latched);
        assert!(out.faults.contains(Fault::LatchDisagree));
        let out = tr.step(
            &LatchInput {
                measured_deg: None,
                ..input(1.01, true, 0.0)
            },
            &LatchConfig::default(),
        );
        assert_eq!(out.state, LatchState::Latched);
    }

    #[test]
    fn given_switch_open_when_encoder_at_latch_for_confirm_time_then_latched_and_flagged() {
        let mut tr = LatchTracker::new();
        let samples: [(bool, f32); 32] = [(false, 0.01); 32];
        let out = run(&mut tr, &samples);
        assert!(out.newly_latched && tr.is_latched());
        assert!(out.faults.contains(Fault::SwitchOpenAtLatch));
    }

    #[test]
    fn given_switch_stuck_closed_then_no_latch_until_encoder_confirms() {
        let mut tr = LatchTracker::new();
        // Closed far from the latch for the debounce time: distrusted.
        let mut samples: std::vec::Vec<(bool, f32)> =
            (0..10).map(|i| (true, 60.0 - i as f32)).collect();
        // The encoder crosses the 2° window: not a latch with that switch.
        samples.extend([(true, 1.5), (true, 0.8), (true, 0.2)]);
        let out = run(&mut tr, &samples);
        assert!(tr.switch_suspect() && !tr.is_latched());
        assert_eq!(out.state, LatchState::Fault);
        // At the latch angle for the confirmation time: latched.
        samples.extend([(true, 0.0); 32]);
        let mut tr = LatchTracker::new();
        let out = run(&mut tr, &samples);
        assert!(tr.is_latched());
        assert_eq!(out.state, LatchState::Latched);
    }

    #[test]
    fn given_stuck_encoder_then_switch_alone_latches_after_debounce() {
        let cfg = LatchConfig::default();
        let mut tr = LatchTracker::new();
        let stuck = |t: f32, sw: bool| LatchInput {
            measured_deg: None,
            encoder_stuck: true,
            ..input(t, sw, 20.0)
        };
        tr.step(&stuck(0.0, false), &cfg);
        for k in 1..=3 {
            let out = tr.step(&stuck(0.01 * k as f32, true), &cfg);
            assert!(!tr.is_latched(), "{k}: {out:?}");
        }
        let out = tr.step(&stuck(0.04, true), &cfg);
        assert!(out.newly_latched);
    }

    #[test]
    fn given_chatter_then_flagged() {
        let mut tr = LatchTracker::new();
        let out = run(&mut tr, &[(false, 50.0), (true, 49.0), (false, 48.0)]);
        assert!(out.faults.contains(Fault::SwitchChatter));
    }

    #[test]
    fn names_round_trip() {
        for s in LatchState::ALL {
            assert_eq!(LatchState::from_name(s.as_str()), Some(s));
        }
    }
}
