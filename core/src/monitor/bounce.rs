//! The physical latch as the latch tracker ([`crate::monitor::latch`]) sees
//! it: a stop the joint bounces off, a ball plunger whose crest it can go
//! back over (an escape), and the plunger's ramp it can come to rest on
//! short of the latch (`docs/monitor.md` §4.1).
//!
//! The rule, with `σ` the standard deviation of one encoder reading, `s`
//! the switch travel, `d = |φ|` the encoder's distance from the stop and
//! `d̄` its low-pass (time constant [`REST_FILTER_S`]):
//!
//! - **on the stop**: a reading `d ≤ s + 4σ` ([`STOP_SIGMAS`]); a joint at
//!   rest with `d̄ ≤ s + σ`;
//! - **seen leaving the stop**: after the switch had closed at the latch,
//!   an open stretch of the switch whose `n` readings sum to `Σ (d − s) >
//!   4σ√n` (a joint at rest on the stop drifts below 0); before it, the
//!   switch open and `d > s + 4σ` later than `1.5 d₀/v₀` after the joint
//!   came within the crest's reach at `d₀` with speed `v₀`, or was at the
//!   speed of its last two readings to come within it by the next reading
//!   (it would have reached the stop by then: it has been there and left,
//!   so it has also been past the crest, but not when another joint's
//!   latch impact fell between the readings: its impulse changes this
//!   joint's speed, a neighbour's latch can cut it by half within a
//!   sample). Once seen,
//!   changes of the switch are rebounds until the latch is declared;
//!   without it, they are chatter (judged when the switch closes again);
//! - **latched**: the switch closed without a break for the bounce window,
//!   the reading on the stop;
//! - **escaped**: after the joint was past the crest (a reading `d ≤
//!   crest − 4σ`, the switch closed at the latch, or the arrival time's
//!   evidence above; with a pawl only the switch closed at the latch: its
//!   joint may ride the cam within the crest's reach, slowed by it, before
//!   the pawl drops into its notch), or after the latch
//!   was declared, the switch open and `d > crest + 4σ`; until the latch is
//!   declared again;
//! - **left the stop after the latch**: the switch opens (a latch declared
//!   with it closed): a rebound, not latched (`Latching`) until the switch
//!   has held again; the switch open at two samples in a row with both
//!   readings over the crest: `Escaped` (also after a latch the encoder
//!   confirmed alone);
//! - **stopped short**: the switch open and `s + σ < d̄ ≤ ramp + σ` at
//!   every sample for the stall time (a joint moving in or out crosses the
//!   ramp's span in a fraction of it).

use crate::monitor::held::{Held, HeldSamples};
use serde::{Deserialize, Serialize};

/// Standard deviations of one reading beyond the switch travel (or the
/// crest) at which the encoder says the joint is off the stop (or over the
/// crest) \[1\]: a reading of a joint at the stop exceeds it with
/// probability 3·10⁻⁵.
pub const STOP_SIGMAS: f32 = 4.0;
/// Time constant of the low-pass of the encoder's distance from the stop
/// by which the rest position is judged \[s\]: its noise is `σ √(Δt/2τ)`,
/// a fifth of `σ` at 100 Hz.
pub const REST_FILTER_S: f32 = 0.1;
/// How much later than its speed allows a joint may reach the stop \[1\]:
/// off the stop after `t + 1.5 d/v` (`d`, `v` where it came within the
/// crest's reach), it has bounced.
pub const ARRIVAL_SLACK: f32 = 1.5;
/// Longest bounce window accepted \[s\]: a latch must be declared within
/// 50 ms of the last rebound, one sample interval after the window.
pub const MAX_BOUNCE_WINDOW_S: f32 = 0.04;

/// One sample as the physical-latch rule sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopReading {
    /// Time stamp \[s\].
    pub t_s: f32,
    /// The latch switch (true = closed).
    pub switch: bool,
    /// The encoder's distance from the stop `|φ|` \[deg\], `None` when the
    /// reading is missing or rejected.
    pub off_deg: Option<f32>,
    /// The joint's speed between the previous reading and this one was
    /// its own: false when another joint's latch impact (its impulse
    /// changes every rate, `physics.md` §5) fell between them, and the
    /// arrival time then does not put the joint past the crest.
    pub speed_known: bool,
}

/// What a physical latch reports instead of the motion state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatchEvent {
    /// Over the crest after the switch had closed, not latched again.
    Escaped,
    /// At rest on the ramp with the switch open.
    StoppedShort,
    /// A declared latch left its stop short of the crest (a rebound).
    Rebound,
}

/// What holds a physical latch's joint against a return, as the monitor
/// needs it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LockKind {
    /// A ball plunger: the joint can escape back over its crest.
    Detent,
    /// A pawl (`physics.md` §10.5): once latched the joint cannot leave by
    /// more than the notch (`crest_deg`) unless the pawl breaks, so a
    /// rebound within it keeps the latch and an escape is a broken pawl,
    /// flagged `latch_disagree`.
    Pawl,
}

/// The latch as built, in the monitor's configuration
/// (`LatchConfig::physical`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PhysicalLatch {
    /// Switch travel \[deg\]: the switch reads closed while the joint is
    /// within this of its stop.
    pub switch_travel_deg: f32,
    /// Angle of the plunger's crest from the stop \[deg\]: a joint that goes
    /// back beyond it after its switch closed has escaped.
    pub crest_deg: f32,
    /// Angular span of the plunger's ramp short of the latch \[deg\]: a joint
    /// at rest within it with the switch open has stopped short.
    pub ramp_deg: f32,
    /// How long the switch must stay closed without a break, the encoder on
    /// the stop, for the latch to be declared \[s\]: longer than the joint
    /// stays in contact between two rebounds.
    pub bounce_window_s: f32,
    /// A ball plunger or a pawl (with a pawl, `crest_deg` is the farthest
    /// its notch lets the joint go back, the contact's give included).
    pub lock: LockKind,
}

impl PhysicalLatch {
    /// True when every angle is finite, the travel is at least 0 and below
    /// the ramp and the crest, and the bounce window is positive and at
    /// most [`MAX_BOUNCE_WINDOW_S`].
    pub(crate) fn is_valid(&self) -> bool {
        let t = self.switch_travel_deg;
        t.is_finite()
            && t >= 0.0
            && self.ramp_deg.is_finite()
            && self.ramp_deg > t
            && self.crest_deg.is_finite()
            && self.crest_deg > t
            && self.bounce_window_s > 0.0
            && self.bounce_window_s <= MAX_BOUNCE_WINDOW_S
    }
}

/// The thresholds of [`PhysicalLatch`] for an encoder of a given noise
/// \[deg\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopLimits {
    /// A reading within this of the stop is on it \[deg\].
    pub on_stop_deg: f32,
    /// A joint at rest whose smoothed reading is within this is on the stop
    /// \[deg\].
    pub at_rest_deg: f32,
    /// A reading beyond this is over the crest \[deg\].
    pub escape_deg: f32,
    /// A reading within this is past the crest, towards the stop \[deg\].
    pub inside_deg: f32,
    /// A joint at rest whose smoothed reading is within this (and off the
    /// stop) is on the ramp \[deg\].
    pub ramp_deg: f32,
    /// The switch travel \[deg\].
    pub travel_deg: f32,
    /// Standard deviation of one reading \[deg\].
    pub sd_deg: f32,
    /// The lock is a pawl: neither a reading within the crest's reach (its
    /// notch and the contact's give) nor the arrival time's evidence puts
    /// the joint past it, the pawl may still ride its cam there (the cam
    /// slows the joint down); it is in its notch once the switch has
    /// closed at the latch.
    pub pawl: bool,
}

impl StopLimits {
    /// The limits of `latch` for readings of standard deviation `sd_deg`.
    pub fn new(latch: &PhysicalLatch, sd_deg: f32) -> Self {
        let sd = if sd_deg.is_finite() {
            libm::fabsf(sd_deg)
        } else {
            0.0
        };
        StopLimits {
            on_stop_deg: latch.switch_travel_deg + STOP_SIGMAS * sd,
            at_rest_deg: latch.switch_travel_deg + sd,
            escape_deg: latch.crest_deg + STOP_SIGMAS * sd,
            inside_deg: latch.crest_deg - STOP_SIGMAS * sd,
            ramp_deg: latch.ramp_deg + sd,
            travel_deg: latch.switch_travel_deg,
            sd_deg: sd,
            pawl: latch.lock == LockKind::Pawl,
        }
    }
}

/// What the tracker keeps of a physical latch between samples.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Bounce {
    /// The switch has closed near the latch since the joint last left it:
    /// the joint reached its stop.
    contact: bool,
    /// The joint has been past the crest (a reading within it, or the
    /// switch closed at the latch) since it last escaped.
    inside: bool,
    /// The encoder has seen the joint leave its stop since then.
    seen: bool,
    /// The joint went over the crest and has not latched again.
    escaped: bool,
    /// The latch was declared with the switch closed (the switch may then
    /// undo it).
    switch_declared: bool,
    /// Distance of the previous reading from the stop \[deg\] (NaN: none).
    prev_off: f32,
    /// Where the previous reading put the joint by the next one at its
    /// speed then, `2 d − d_prev` \[deg\] (NaN: none).
    lead_prev: f32,
    /// Low-pass of the distance from the stop \[deg\] (NaN: none yet).
    smooth_off: f32,
    /// Time of the previous reading \[s\].
    t_prev: f32,
    /// The switch open and the low-pass on the ramp, off the stop.
    ramp: Held,
    /// Samples in a row with the switch open and the reading off the stop.
    off_stop: HeldSamples,
    /// The crest's reach \[deg\] ([`StopLimits::escape_deg`]; NaN before the
    /// first reading).
    zone_deg: f32,
    /// The joint came within the crest's reach fast enough to cross the
    /// crest before the next reading.
    through: bool,
    /// When the joint reaches the stop at the speed it came within the
    /// crest's reach with \[s\].
    arrive_by: f32,
    /// `Σ (d − s)` over the switch's current open stretch \[deg\].
    open_sum: f32,
    /// Readings in it.
    open_n: u16,
    /// The lock broke (a pawl out beyond its notch after its switch
    /// closed, `physics.md` §10.5): nothing locks the joint again.
    broken: bool,
}

impl Bounce {
    /// Nothing seen yet.
    pub const NEW: Bounce = Bounce {
        contact: false,
        inside: false,
        seen: false,
        escaped: false,
        switch_declared: false,
        prev_off: f32::NAN,
        lead_prev: f32::NAN,
        smooth_off: f32::NAN,
        t_prev: 0.0,
        ramp: Held::NEW,
        off_stop: HeldSamples::NEW,
        zone_deg: f32::NAN,
        through: false,
        arrive_by: f32::INFINITY,
        open_sum: 0.0,
        open_n: 0,
        broken: false,
    };

    /// True once the encoder has seen the joint leave its stop in this
    /// approach to the latch: changes of the switch are rebounds.
    pub fn seen(&self) -> bool {
        self.seen
    }

    /// True once the joint has been past the crest (a reading within it,
    /// or the switch closed at the latch) since it last escaped: the hold
    /// ramp and the magnet pull it in.
    pub fn past_crest(&self) -> bool {
        self.inside
    }

    /// True when the joint has been on the entry ramp, switch open, for at
    /// least `duration_s` \[s\] at `t_s` \[s\].
    pub fn on_ramp_for(&self, t_s: f32, duration_s: f32) -> bool {
        self.ramp.at_least(t_s, duration_s)
    }

    /// True after an escape, until the latch is declared again.
    pub fn escaped(&self) -> bool {
        self.escaped
    }

    /// True when a reading `off_deg` \[deg\] from the stop puts the joint
    /// within the crest's reach by the next reading ([`Bounce::lead`]) and
    /// the previous one did not (false when no physical latch is tracked).
    pub fn enters_zone(&self, off_deg: f32) -> bool {
        self.lead(off_deg) <= self.zone_deg && !self.in_zone()
    }

    /// Where a reading `off_deg` \[deg\] puts the joint by the next reading
    /// at the speed since the previous one, `2 d − d_prev` \[deg\] (NaN
    /// without a previous reading): a joint fast enough to pass the crest
    /// and hit the stop between two readings is within the crest's reach
    /// one reading early.
    fn lead(&self, off_deg: f32) -> f32 {
        2.0 * off_deg - self.prev_off
    }

    /// True when a reading `off_deg` \[deg\] from the stop is within the
    /// crest's reach and the previous reading was not (or was missing): the
    /// joint has come to its stop since, and may have hit it (a pawl's or
    /// plunger's impact, whose impulse changes the other joints' rates).
    pub fn reaches(&self, off_deg: f32) -> bool {
        self.within_reach(off_deg) && !self.within_reach(self.prev_off)
    }

    /// True when a reading `off_deg` \[deg\] from the stop is within the
    /// crest's reach ([`StopLimits::escape_deg`]: the crest, or a pawl's
    /// notch, and the encoder's noise); false when no physical latch is
    /// tracked.
    pub fn within_reach(&self, off_deg: f32) -> bool {
        off_deg <= self.zone_deg
    }

    /// True while the previous reading put the joint within the crest's
    /// reach by this one.
    pub fn in_zone(&self) -> bool {
        self.lead_prev <= self.zone_deg
    }

    /// The low-pass of the reading's distance from the stop \[deg\] (NaN
    /// before the first reading).
    pub fn smoothed_off_deg(&self) -> f32 {
        self.smooth_off
    }

    /// Takes one sample (before the latch decision); `window_deg` is the
    /// latch window of a closed switch \[deg\].
    pub fn observe(&mut self, x: &StopReading, lim: &StopLimits, window_deg: f32) {
        let Some(off) = x.off_deg else {
            self.prev_off = f32::NAN;
            self.lead_prev = f32::NAN;
            self.off_stop.update(false);
            self.ramp.stop();
            return;
        };
        self.zone_deg = lim.escape_deg;
        self.smooth(off, x.t_s);
        let d = self.smooth_off;
        let on_ramp = !x.switch && d > lim.at_rest_deg && d <= lim.ramp_deg;
        self.ramp.update(on_ramp, x.t_s);
        if x.switch && off <= window_deg {
            self.contact = true;
            self.inside = true;
        }
        if off <= lim.inside_deg && !lim.pawl {
            self.inside = true;
        }
        if self.enters_zone(off) {
            // A new approach.
            self.arrive_by = f32::INFINITY;
            self.through = false;
        }
        if self.lead(off) <= self.zone_deg {
            self.arrival(off, x.t_s, lim.inside_deg);
        }
        if !x.speed_known {
            // A neighbour's impulse: the readings' speed is not the
            // joint's own, and does not put it past the crest.
            self.through = false;
        }
        let left = !x.switch && off > lim.on_stop_deg;
        self.off_stop.update(left);
        self.open_stretch(x.switch, off, lim);
        if left {
            if !self.contact && x.t_s > self.arrive_by {
                // It has been on the stop between two readings, and past
                // the crest when it came fast enough to cross it within one.
                self.seen = true;
                // (A pawl not so: it may be riding its cam, short of its
                // notch.)
                self.inside |= self.through && !lim.pawl;
            }
            if self.inside && off > lim.escape_deg {
                self.escape();
            }
        }
        self.lead_prev = self.lead(off);
        self.prev_off = off;
        self.t_prev = x.t_s;
    }

    /// The low-pass of the distance `off` \[deg\] at `t_s` \[s\].
    fn smooth(&mut self, off: f32, t_s: f32) {
        let dt = t_s - self.t_prev;
        if !self.smooth_off.is_finite() || !(dt > 0.0) {
            self.smooth_off = off;
            return;
        }
        let a = (dt * (1.0 / REST_FILTER_S)).min(1.0);
        self.smooth_off += a * (off - self.smooth_off);
    }

    /// A reading `off` \[deg\] at `t_s` \[s\] within the crest's reach (or
    /// one reading from it): at the speed since the previous reading the
    /// joint reaches the stop by `arrive_by`, the earliest such time of the
    /// approach (with [`ARRIVAL_SLACK`] on the time from the crest's
    /// reach); off the stop later, it has bounced. `inside_deg` \[deg\]: past
    /// the crest within it ([`StopLimits`]); the joint crosses it before
    /// the next reading at this speed when `off − fall` is within it. A
    /// reading that does not come closer changes nothing.
    fn arrival(&mut self, off: f32, t_s: f32, inside_deg: f32) {
        let (dt, fall) = (t_s - self.t_prev, self.prev_off - off);
        if !(dt > 0.0 && fall > 0.0) {
            return;
        }
        let reach = if off < self.zone_deg {
            off
        } else {
            self.zone_deg
        };
        let by = t_s + (off + (ARRIVAL_SLACK - 1.0) * reach) * dt / fall;
        if by < self.arrive_by {
            self.arrive_by = by;
        }
        self.through |= off - fall <= inside_deg;
    }

    /// The evidence of the switch's open stretch after the joint touched
    /// its stop: `Σ (d − s)` over its readings, against
    /// [`STOP_SIGMAS`] `σ √n` (a joint at rest on the stop makes the sum
    /// drift below 0; one in flight beyond the travel above it).
    fn open_stretch(&mut self, switch: bool, off: f32, lim: &StopLimits) {
        if switch || !self.contact {
            self.open_sum = 0.0;
            self.open_n = 0;
            return;
        }
        self.open_sum += off - lim.travel_deg;
        self.open_n = self.open_n.saturating_add(1);
        let bound2 = STOP_SIGMAS * STOP_SIGMAS * lim.sd_deg * lim.sd_deg * f32::from(self.open_n);
        if self.open_sum > 0.0 && self.open_sum * self.open_sum > bound2 {
            self.seen = true;
        }
    }

    /// The latch was declared at this sample (`switch`: closed or not).
    pub fn latched(&mut self, switch: bool) {
        self.seen = false;
        self.escaped = false;
        self.contact = true;
        self.inside = true;
        self.switch_declared = switch;
    }

    /// The lock broke: from now on [`Bounce::lock_broken`].
    pub fn break_lock(&mut self) {
        self.broken = true;
    }

    /// True once the lock broke ([`Bounce::break_lock`]).
    pub fn lock_broken(&self) -> bool {
        self.broken
    }

    /// The joint went over the crest.
    fn escape(&mut self) {
        self.escaped = true;
        self.contact = false;
        self.inside = false;
    }

    /// After a declared latch: `Escaped` when switch and encoder both say
    /// the joint is over the crest at this and the previous sample;
    /// `Rebound` when the switch opens after a latch declared with it
    /// closed (the joint is off its stop by more than the travel: not
    /// latched until the switch holds again).
    pub fn left_stop(&mut self, x: &StopReading, lim: &StopLimits) -> Option<LatchEvent> {
        let escaped = x.off_deg.is_some_and(|d| d > lim.escape_deg) && self.off_stop.count() >= 2;
        if escaped {
            self.escape();
            Some(LatchEvent::Escaped)
        } else if self.switch_declared && !x.switch {
            self.seen = true;
            Some(LatchEvent::Rebound)
        } else {
            None
        }
    }

    /// What a physical latch reports when no latch is declared at `t_s`
    /// \[s\]: `StoppedShort` after `rest_s` \[s\] on the ramp with the switch
    /// open, `Escaped` after an escape, otherwise `None` (the motion
    /// state).
    pub fn event(&self, t_s: f32, rest_s: f32) -> Option<LatchEvent> {
        if self.ramp.at_least(t_s, rest_s) {
            Some(LatchEvent::StoppedShort)
        } else if self.escaped {
            Some(LatchEvent::Escaped)
        } else {
            None
        }
    }
}
