//! Plausibility of each encoder reading against the joint's own motion: the
//! two encoder faults that the rate filter's innovation gate cannot see.
//!
//! - **A stale reading** (a frozen or dropped-out encoder that repeats its
//!   last value): the same reading, to the bit, as the previous one while
//!   the readings before had the joint moving by more than
//!   [`STALE_MOTION_STEPS`] quantisation steps per interval when the
//!   repeats began (the slope of the last three readings) and the rate
//!   filter's course (angle, rate and acceleration at the first reading of
//!   the repeats) has since taken it more than that far from where it
//!   was: a joint decelerating to a turn comes back to the code it left
//!   (a rebound off a stop elsewhere in the chain turns a joint round
//!   mid-stroke; the line through the readings before it does not see
//!   the turn). A healthy
//!   encoder moving that far cannot repeat its code: with the encoder's
//!   noise σ ≈ 0.9 step, the difference of two readings is
//!   `N(m, (0.9·√2)²)` steps for a motion of `m` steps, and it rounds to
//!   the same code with probability `Φ((0.5 − m)/1.27)`, 2·10⁻⁴ for
//!   `m = 5`; [`STALE_REPEATS`] = 3 repeats in a row make it about 10⁻¹¹ per
//!   sample ([`STALE_REPEATS_FAST`] = 2 when the readings moved, and their
//!   parabola still steps on, by more than twice that: then 10⁻²⁷). Three,
//!   not two, at the limit: a joint turned round mid-stroke (by a
//!   neighbour's rebound, a pawl's rattle or its own spring) after moving
//!   faster than that sits within a code or two of its turning point for
//!   two intervals (at 700°/s² it moves 0.04° in the 10 ms either side of
//!   the turn), and the readings before the turn, noisy, can hide the
//!   braking; three readings in a row repeating their code where it
//!   would have moved on are beyond a turn at any braking that stopped
//!   it from that speed. The gate cannot see it: a stale value is within half a degree
//!   of a slow joint's prediction, and the stuck-encoder count
//!   (`SensorConfig::stuck_samples`, 20 repeats) is for a joint at rest.
//! - **A spike that returns**: a reading that leaves the prediction by more
//!   than [`DEPART_RAD`] and, within [`SPIKE_SAMPLES`] samples, comes back
//!   to within [`RETURN_FRACTION`] of that jump of where the joint was
//!   going before it left: the line through the three readings before the
//!   jump, extrapolated. A departure counts only when it is larger than
//!   the joint's recent changes of step (`|z₀ − 2 z₁ + z₂|` of each three
//!   readings in a row, their peak decaying by [`WIGGLE_DECAY`] per
//!   sample): a joint shaken near the Nyquist frequency (a pawl rattling
//!   in its notch next to it) leaves and rejoins its line by as much every
//!   sample or two, and a spike of that size there cannot be told from its
//!   motion at this sampling rate; one on a smooth course stands out (the readings themselves, not the rate filter,
//!   whose gate near a latch is wide open and whose rate there follows
//!   every reading). Inside a tape spring's
//!   snap zone the filter's gate is wide open (the model cannot follow the
//!   snap), so a 2-sample spike there can be accepted as motion; it is
//!   flagged when the readings come back. A real change of motion — the
//!   latch impact that stops a joint, the impulse that changes the others'
//!   rates — leaves the old trajectory and does not return to it.
//!
//! Per joint, a few floating-point operations per sample: the checks run in
//! the encoder stage of [`Monitor::update`](crate::monitor::Monitor::update), before
//! the rate filter takes the reading.

use crate::monitor::faults::Fault;
use crate::monitor::rate_filter::RateFilter;
use crate::monitor::resolution::Shaking;
use crate::monitor::status::Resolution;

/// Predicted motion over one sample interval above which a repeated
/// reading is stale [quantisation steps].
pub const STALE_MOTION_STEPS: f32 = 5.0;
/// Consecutive repeats (while moving) that make a reading stale.
pub const STALE_REPEATS: u16 = 3;
/// Consecutive repeats that make a reading stale while the joint moves by
/// more than twice [`STALE_MOTION_STEPS`] per interval and its readings'
/// parabola still steps on by that much (a stale stretch just before a
/// latch has few samples before the impact turns the checks off).
pub const STALE_REPEATS_FAST: u16 = 2;
/// Departure from the filter's extrapolation that may start a spike \[rad\]
/// (0.2°: 7 σ of the reference encoder; a departure alone flags nothing).
pub const DEPART_RAD: f32 = 0.2 * core::f32::consts::PI / 180.0;
/// Samples, from the first that departs, a spike may last.
pub const SPIKE_SAMPLES: u8 = 2;
/// A reading back within this fraction of the jump from the old
/// trajectory has returned \[1\].
pub const RETURN_FRACTION: f32 = 0.3;

/// Readings of the line a spike is judged against.
const LINE_READINGS: usize = 3;
/// Share of the joint's last step between two readings within which a
/// reading still follows the readings' course
/// (`ReadingCheck::follows_readings`), where that is more than its
/// tolerance \[1\].
pub const WHIP_STEP_SHARE: f32 = 0.15;

/// A departure counts only when it exceeds this many times the joint's
/// recent peak change of step ([`ReadingCheck`]'s `wiggle`) \[1\].
const DEPART_OVER_CURVATURE: f32 = 1.0;
/// Decay per sample of the peak change of step (a time constant of about
/// ten samples) \[1\].
pub const WIGGLE_DECAY: f32 = 0.9;

/// The rate filter's state at the previous sample: where the joint was
/// going.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Course {
    /// Time of the previous sample \[s\].
    pub t_s: f32,
    /// Angle \[rad\].
    pub angle: f32,
    /// Rate [rad/s].
    pub rate: f32,
    /// Acceleration [rad/s²].
    pub acc: f32,
}

impl Course {
    /// The course of `filter`, whose last sample was at `t_s` \[s\].
    pub fn of(filter: &RateFilter, t_s: f32) -> Self {
        Course {
            t_s,
            angle: filter.angle(),
            rate: filter.rate(),
            acc: filter.acceleration(),
        }
    }

    /// The angle extrapolated to `t` \[rad\].
    fn at(&self, t: f32) -> f32 {
        let tau = t - self.t_s;
        self.angle + tau * (self.rate + 0.5 * tau * self.acc)
    }
}

/// One encoder reading as the checks see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reading {
    /// Time stamp \[s\].
    pub t_s: f32,
    /// The reading \[rad\], in range and finite; `None` when missing.
    pub angle: Option<f32>,
    /// How many samples in a row have repeated it exactly.
    pub repeats: u16,
    /// The encoder's quantisation step \[rad\].
    pub step: f32,
    /// False where motion checks do not apply: the joint is latched, its
    /// switch closed or an impact is under way (the joint may stop dead),
    /// or the sample follows a gap.
    pub moving_checks: bool,
    /// False where the joint itself is latched, its switch closed or it is
    /// within its physical latch's reach of the stop: its readings are of
    /// the latch, and its resolution is not judged (reported resolved).
    /// True elsewhere, an impact under way included: the resolution
    /// follows the readings whether or not the checks apply.
    pub free: bool,
    /// The checks are off for an impact under way elsewhere in the chain
    /// (not a gap, not the first sample): the readings still go into the
    /// history, so that once the impact's window closes the course of a
    /// joint the impulse threw (the whip of its neighbour's latch) is the
    /// readings' since the impact, not one broken off until three more.
    pub through_impact: bool,
    /// The resolution is followed at all: on a wing with a physical latch
    /// (the rattling pawl or bouncing plunger that shakes a joint beyond
    /// what the samples resolve); on one of ideal latches every joint is
    /// resolved, at no cost on the sample path.
    pub follow: bool,
}

/// What the checks say of one reading.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Nothing wrong seen.
    Plausible,
    /// The reading repeats a stale value: not to be used (as a stuck one,
    /// [`Fault::EncoderStuck`]).
    Stale,
    /// The last readings were a spike that has now returned: flag
    /// [`Fault::EncoderOutlier`] (this reading is good).
    SpikeReturned,
}

impl Verdict {
    /// The fault to raise, if any.
    pub fn fault(self) -> Option<Fault> {
        match self {
            Verdict::Plausible => None,
            Verdict::Stale => Some(Fault::EncoderStuck),
            Verdict::SpikeReturned => Some(Fault::EncoderOutlier),
        }
    }
}

/// A departure from the course, waiting to see whether it returns.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Departure {
    /// The course before it.
    course: Course,
    /// Its size \[rad\].
    jump: f32,
    /// Samples since it started, the departing one included.
    samples: u8,
}

/// The plausibility checks of one encoder.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ReadingCheck {
    pending: Option<Departure>,
    /// The last readings, (time \[s\], angle \[rad\]), newest last; the last
    /// `seen` of them valid.
    last: [(f32, f32); LINE_READINGS],
    seen: u8,
    /// The filter's rate when the current run of repeats began [rad/s]:
    /// the first repeat is fused as a stop, so the later ones are judged
    /// against the motion before it.
    repeat_rate: f32,
    /// The rate filter's course at the first reading of the current run of
    /// repeats: a joint whose own course turns it round (or slows it to
    /// under [`STALE_MOTION_STEPS`]) since then may repeat its code.
    repeat_course: Course,
    /// Where the parabola through the three readings before this one puts
    /// this one \[rad\] (NaN: fewer than three, or the checks are off).
    parabola: f32,
    /// The previous reading's miss from its own parabola \[rad\]: the third
    /// difference of the four readings up to it (NaN: none). The cubic
    /// through those four puts this reading at `parabola + third`.
    third: f32,
    /// The readings' own next step at the first reading of the repeats
    /// ([`ReadingCheck::step_ahead`]) \[rad\].
    repeat_ahead: f32,
    /// The rate filter's course has taken the joint more than
    /// [`STALE_MOTION_STEPS`] from where the current run of repeats began.
    repeat_moved: bool,
    /// The recent peak of the readings' change of step `|z₀ − 2 z₁ + z₂|`
    /// \[rad\], decaying by [`WIGGLE_DECAY`] per reading.
    wiggle: f32,
    /// The readings' recent changes of step, signed, and whether they
    /// leave the joint unresolved (`resolution.rs`).
    shaking: Shaking,
}

impl ReadingCheck {
    /// A check with nothing pending.
    pub const fn new() -> Self {
        ReadingCheck {
            pending: None,
            last: [(0.0, 0.0); LINE_READINGS],
            seen: 0,
            repeat_rate: 0.0,
            repeat_course: Course {
                t_s: 0.0,
                angle: 0.0,
                rate: 0.0,
                acc: 0.0,
            },
            repeat_ahead: 0.0,
            parabola: f32::NAN,
            third: f32::NAN,
            wiggle: 0.0,
            repeat_moved: false,
            shaking: Shaking::NEW,
        }
    }

    /// True when a reading `z` \[rad\] lies within `tol` \[rad\] of where
    /// the parabola through the three readings before it puts it, or the
    /// cubic through the four before it: the joint's own accelerating
    /// motion (a tape spring's snap of a light panel, the whip of a chain
    /// whose neighbour is about to latch, where the acceleration itself
    /// doubles within a few samples), which a spike leaves by its size.
    /// False without three readings (the cubic: four). Where the joint
    /// moves by more than `tol / WHIP_STEP_SHARE` between two readings the
    /// samples hardly resolve its motion and the cubic misses by more:
    /// the tolerance is [`WHIP_STEP_SHARE`] of the last step (an outer
    /// panel whipped to 2,200°/s at 100 Hz, 16° and then 22° a sample,
    /// misses the cubic by 2.3°; a spike on a joint moving less than 10° a
    /// sample keeps `tol`).
    pub fn follows_readings(&self, z: f32, tol: f32) -> bool {
        let [_, (_, z1), (_, z2)] = self.last;
        let tol = tol.max(WHIP_STEP_SHARE * libm::fabsf(z2 - z1));
        if libm::fabsf(z - self.parabola) <= tol {
            return true;
        }
        libm::fabsf(z - self.parabola - self.third) <= tol
    }

    /// The parabola through the last three readings one sample interval
    /// after the newest (`z₀ − 3 z₁ + 3 z₂`, readings equally spaced:
    /// three operations on the sample path), NaN before three readings.
    fn parabola_next(&self) -> f32 {
        if usize::from(self.seen) < LINE_READINGS {
            return f32::NAN;
        }
        let [(_, z0), (_, z1), (_, z2)] = self.last;
        z0 + 3.0 * (z2 - z1)
    }

    /// Checks `reading` against the joint's rate filter as it stood after
    /// the previous sample, at `t_prev` \[s\]. Out of line: one copy for
    /// every joint count. Where the checks are off, the filter's course is
    /// not even read.
    #[inline(never)]
    pub fn check_filter(&mut self, reading: &Reading, filter: &RateFilter, t_prev: f32) -> Verdict {
        if !reading.moving_checks {
            self.pass(reading);
            return Verdict::Plausible;
        }
        self.check(reading, &Course::of(filter, t_prev))
    }

    /// A reading lost (missing or out of range) or a gap in the time
    /// stamps: the resolution's change of step waits for two readings in
    /// a row again.
    pub fn lose_reading(&mut self) {
        self.shaking.lose();
    }

    /// A reading the checks do not apply to (`Reading::moving_checks`
    /// false): the line, a departure and a run of repeats start afresh
    /// (the resolution follows the readings all the same).
    #[inline(always)]
    fn pass(&mut self, reading: &Reading) {
        self.pending = None;
        // A run of repeats that begins here is not judged as stale.
        self.repeat_rate = 0.0;
        match reading.angle {
            Some(z) if reading.through_impact && reading.free => {
                // The history goes on: the parabola for this reading, its
                // miss carried to the next one (`check`).
                self.third = self.last[LINE_READINGS - 1].1 - self.parabola;
                self.parabola = self.parabola_next();
                self.push(reading.t_s, z);
            }
            _ => {
                // No parabola: `follows_readings` is false (the miss
                // `third` is NaN again at the next reading checked).
                self.parabola = f32::NAN;
                self.seen = 0;
            }
        }
        if !reading.follow {
            return;
        }
        match reading.angle {
            Some(z) if reading.free => {
                self.shaking.judge();
                self.shaking.read(z, true);
            }
            _ => {
                self.shaking.pause();
                self.shaking.lose();
            }
        }
    }

    /// Whether the joint's readings resolve its motion, as judged at the
    /// last reading, on the readings before it ([`Resolution::Unresolved`]: a departure that
    /// returns is not flagged, and the rate filter takes a reading its gate
    /// rejects as a manoeuvre).
    #[inline(always)]
    pub fn resolution(&self) -> Resolution {
        self.shaking.resolution()
    }

    /// True when [`ReadingCheck::resolution`] is unresolved.
    #[inline(always)]
    pub fn unresolved(&self) -> bool {
        self.shaking.unresolved()
    }

    /// Checks `reading` against `course`, the rate filter's state at the
    /// previous sample. On an unresolved joint (judged on the readings
    /// before this one) a spike that returns is not flagged: its readings
    /// cannot tell one from the joint's motion.
    ///
    /// The previous reading's miss from its parabola is kept (NaN when it
    /// had none: it was not taken, or the run of readings broke). When the
    /// repeats begin, the readings' own rate is kept; none before three
    /// readings (after a gap or an impact the rate filter's rate is widened
    /// and may be far from the readings': a joint at rest would read
    /// stale). A stale reading is not taken: no parabola to carry to the
    /// next reading, no change of step.
    pub fn check(&mut self, reading: &Reading, course: &Course) -> Verdict {
        if !reading.moving_checks {
            self.pass(reading);
            return Verdict::Plausible;
        }
        self.third = self.last[LINE_READINGS - 1].1 - self.parabola;
        self.parabola = f32::NAN;
        let follow = reading.follow;
        let unresolved = follow && self.shaking.judge();
        let Some(z) = reading.angle else {
            self.age();
            self.shaking.lose();
            return Verdict::Plausible;
        };
        let dt = reading.t_s - course.t_s;
        let line = self.line();
        self.parabola = self.parabola_next();
        if reading.repeats <= 1 {
            self.repeat_rate = line.map_or(0.0, |l| l.rate);
            self.repeat_course = *course;
            self.repeat_ahead = self.step_ahead();
            self.repeat_moved = false;
        }
        if self.stale(reading, dt) {
            self.pending = None;
            self.parabola = f32::NAN;
            self.shaking.lose();
            return Verdict::Stale;
        }
        if let Some(d) = self.pending {
            let off = libm::fabsf(z - d.course.at(reading.t_s));
            // A departure's readings stay out of the history of a quiet
            // joint (a spike does not make its own joint unresolved), not
            // of one already shaken.
            let record = unresolved || self.shaking.shaken();
            self.push(reading.t_s, z);
            if off <= RETURN_FRACTION * libm::fabsf(d.jump) {
                self.pending = None;
                // Start the line afresh from the good reading.
                self.seen = 1;
                // On a joint that is not quiet, the departure and its
                // return are judged with the rest of its motion: bent both
                // ways, they are motion the samples do not resolve.
                if follow && record {
                    self.shaking.read(z, true);
                    if self.shaking.judge() {
                        return Verdict::Plausible;
                    }
                }
                // The spike's readings leave the history with it.
                self.shaking.restart(z);
                return Verdict::SpikeReturned;
            }
            if follow {
                self.shaking.read(z, record);
            }
            self.age();
            return Verdict::Plausible;
        }
        let mut departs = false;
        if let Some(line) = line {
            let jump = z - line.at(reading.t_s);
            if libm::fabsf(jump) > DEPART_RAD && self.stands_out(jump) {
                self.pending = Some(Departure {
                    course: line,
                    jump,
                    samples: 1,
                });
                departs = true;
            }
        }
        let record = !departs || unresolved || self.shaking.shaken();
        self.push(reading.t_s, z);
        if follow {
            self.shaking.read(z, record);
        }
        Verdict::Plausible
    }

    /// True when `reading`, `dt` \[s\] after the previous sample, repeats
    /// a stale value: repeated [`STALE_REPEATS`] times (or
    /// [`STALE_REPEATS_FAST`]) while the readings before the repeats, the
    /// rate filter's course since their start and the readings' own next
    /// step all had the joint moving more than [`STALE_MOTION_STEPS`].
    fn stale(&mut self, reading: &Reading, dt: f32) -> bool {
        let motion = libm::fabsf(self.repeat_rate) * dt;
        // Where the filter's course (angle, rate, acceleration at the first
        // reading of the repeats) has taken the joint since: a joint
        // decelerating to a turn (a rebound elsewhere in the chain turns it
        // round mid-stroke) comes back to the code it left.
        let c = &self.repeat_course;
        let path = libm::fabsf(c.at(reading.t_s) - c.angle);
        let limit = STALE_MOTION_STEPS * reading.step;
        // Once the course has taken the joint that far during the repeats
        // it has moved on (a course noisy in a snap zone may bend back
        // later: the third repeat is judged by the farthest it went).
        self.repeat_moved |= path > limit;
        // Fast (twice the limit by every measure): a turn within two
        // intervals would have shown as braking; two repeats are stale.
        let fast = motion > 2.0 * limit && self.repeat_ahead > 2.0 * limit;
        let needed = if fast {
            STALE_REPEATS_FAST
        } else {
            STALE_REPEATS
        };
        reading.repeats >= needed
            && motion > limit
            && self.repeat_moved
            && self.repeat_ahead > limit - 0.5 * reading.step
    }

    /// The step the last three readings' own parabola makes next, in the
    /// direction they were moving \[rad\]: `d₁ + (d₁ − d₀)` with `d₀`, `d₁`
    /// their two steps; a repeat is stale only when it is over
    /// [`STALE_MOTION_STEPS`] (a joint braking hard enough to turn within
    /// a few intervals, as a pawl's rattle or a neighbour's rebound turns
    /// it, may repeat its code at the turn); at most 0 when they
    /// were braking to a stop within an interval (a joint stopped dead elsewhere than at its latch, by a
    /// plunger's ramp or a neighbour's impulse, then repeats its code;
    /// a frozen encoder in steady motion does not). 0 before three
    /// readings.
    fn step_ahead(&self) -> f32 {
        if usize::from(self.seen) < LINE_READINGS {
            return 0.0;
        }
        let [(_, z0), (_, z1), (_, z2)] = self.last;
        let (d0, d1) = (z1 - z0, z2 - z1);
        let ahead = d1 + (d1 - d0);
        if d1 < 0.0 {
            -ahead
        } else {
            ahead
        }
    }

    /// The line through the last three readings: the slope of the outer
    /// two, through their mean (the least-squares line of three equally
    /// spaced readings), at the newest one's time.
    fn line(&self) -> Option<Course> {
        if usize::from(self.seen) < LINE_READINGS {
            return None;
        }
        let [(t0, z0), (t1, z1), (t2, z2)] = self.last;
        if !(t2 > t0) {
            return None;
        }
        let rate = (z2 - z0) / (t2 - t0);
        const THIRD: f32 = 1.0 / 3.0;
        let (tm, zm) = ((t0 + t1 + t2) * THIRD, (z0 + z1 + z2) * THIRD);
        Some(Course {
            t_s: t2,
            angle: zm + rate * (t2 - tm),
            rate,
            acc: 0.0,
        })
    }

    /// True when a departure `jump` \[rad\] exceeds
    /// [`DEPART_OVER_CURVATURE`] times the joint's recent peak change of
    /// step: it stands out of the joint's own motion.
    fn stands_out(&self, jump: f32) -> bool {
        libm::fabsf(jump) > DEPART_OVER_CURVATURE * self.wiggle
    }

    fn push(&mut self, t: f32, z: f32) {
        // Element by element: `rotate_left` is a call into the generic
        // rotation at the firmware's `opt-level = "z"`.
        let [_, a, b] = self.last;
        self.last = [a, b, (t, z)];
        self.seen = self.seen.saturating_add(1).min(LINE_READINGS as u8);
        let [(_, z0), (_, z1), (_, z2)] = self.last;
        let bend = if usize::from(self.seen) >= LINE_READINGS {
            libm::fabsf(z0 - 2.0 * z1 + z2)
        } else {
            0.0
        };
        self.wiggle = bend.max(WIGGLE_DECAY * self.wiggle);
    }

    /// One more sample without a return; past [`SPIKE_SAMPLES`] the
    /// departure was real motion.
    fn age(&mut self) {
        if let Some(d) = &mut self.pending {
            d.samples = d.samples.saturating_add(1);
            if d.samples > SPIKE_SAMPLES {
                self.pending = None;
            }
        }
    }
}

#[cfg(test)]
mod tests;
