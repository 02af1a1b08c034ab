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
//! the encoder stage of [`Monitor::update`](crate::Monitor::update), before
//! the rate filter takes the reading.

use crate::monitor::faults::Fault;
use crate::monitor::observer::RateFilter;

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
        }
    }

    /// True when a reading `z` \[rad\] lies within `tol` \[rad\] of where
    /// the parabola through the three readings before it puts it, or the
    /// cubic through the four before it: the joint's own accelerating
    /// motion (a tape spring's snap of a light panel, the whip of a chain
    /// whose neighbour is about to latch, where the acceleration itself
    /// doubles within a few samples), which a spike leaves by its size.
    /// False without three readings (the cubic: four).
    pub fn follows_readings(&self, z: f32, tol: f32) -> bool {
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
    /// every joint count.
    #[inline(never)]
    pub fn check_filter(&mut self, reading: &Reading, filter: &RateFilter, t_prev: f32) -> Verdict {
        self.check(reading, &Course::of(filter, t_prev))
    }

    /// Checks `reading` against `course`, the rate filter's state at the
    /// previous sample.
    pub fn check(&mut self, reading: &Reading, course: &Course) -> Verdict {
        // The previous reading's miss from its parabola (NaN when it had
        // none: it was not taken, or the run of readings broke).
        self.third = self.last[LINE_READINGS - 1].1 - self.parabola;
        self.parabola = f32::NAN;
        if !reading.moving_checks {
            self.pending = None;
            self.seen = 0;
            // A run of repeats that begins here is not judged as stale.
            self.repeat_rate = 0.0;
            return Verdict::Plausible;
        }
        let Some(z) = reading.angle else {
            self.age();
            return Verdict::Plausible;
        };
        let dt = reading.t_s - course.t_s;
        let line = self.line();
        self.parabola = self.parabola_next();
        if reading.repeats <= 1 {
            // The readings' own rate when the repeats began; none before
            // three readings (after a gap or an impact the rate filter's
            // rate is widened and may be far from the readings': a joint
            // at rest would read stale).
            self.repeat_rate = line.map_or(0.0, |l| l.rate);
            self.repeat_course = *course;
            self.repeat_ahead = self.step_ahead();
            self.repeat_moved = false;
        }
        if self.stale(reading, dt) {
            self.pending = None;
            // Not taken: no parabola to carry to the next reading.
            self.parabola = f32::NAN;
            return Verdict::Stale;
        }
        if let Some(d) = self.pending {
            let off = libm::fabsf(z - d.course.at(reading.t_s));
            self.push(reading.t_s, z);
            if off <= RETURN_FRACTION * libm::fabsf(d.jump) {
                self.pending = None;
                // Start the line afresh from the good reading.
                self.seen = 1;
                return Verdict::SpikeReturned;
            }
            self.age();
            return Verdict::Plausible;
        }
        if let Some(line) = line {
            let jump = z - line.at(reading.t_s);
            if libm::fabsf(jump) > DEPART_RAD && self.stands_out(jump) {
                self.pending = Some(Departure {
                    course: line,
                    jump,
                    samples: 1,
                });
            }
        }
        self.push(reading.t_s, z);
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
        self.last.rotate_left(1);
        self.last[LINE_READINGS - 1] = (t, z);
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
mod tests {
    use super::*;

    const DEG: f32 = core::f32::consts::PI / 180.0;
    const STEP: f32 = 360.0 / 16384.0 * DEG;

    fn reading(t: f32, deg: f32, repeats: u16) -> Reading {
        Reading {
            t_s: t,
            angle: Some(deg * DEG),
            repeats,
            step: STEP,
            moving_checks: true,
        }
    }

    /// A joint at −100°/s from 10° at t = 0.
    fn course(t: f32) -> Course {
        Course {
            t_s: t,
            angle: (10.0 - 100.0 * t) * DEG,
            rate: -100.0 * DEG,
            acc: 0.0,
        }
    }

    #[test]
    fn a_two_sample_spike_that_returns_is_flagged_when_it_returns() {
        let mut c = ReadingCheck::new();
        // 0.01–0.03: on course; 0.04, 0.05: at 0° (a spike to the latch
        // angle); 0.06: back on course (4°).
        for (t, deg) in [
            (0.01, 9.0),
            (0.02, 8.0),
            (0.03, 7.0),
            (0.04, 0.0),
            (0.05, 0.0),
        ] {
            assert_eq!(
                c.check(&reading(t, deg, 0), &course(t - 0.01)),
                Verdict::Plausible
            );
        }
        assert_eq!(
            c.check(&reading(0.06, 4.0, 0), &course(0.05)),
            Verdict::SpikeReturned
        );
    }

    #[test]
    fn a_rattle_at_the_nyquist_frequency_is_no_spike_a_spike_on_it_still_is() {
        // 100°/s with ±0.2° alternating every sample: the readings leave
        // and rejoin their line by 0.4° at every sample.
        let rattle = |k: usize| 10.0 - k as f32 + if k % 2 == 0 { 0.2 } else { -0.2 };
        let mut c = ReadingCheck::new();
        for k in 1..40 {
            let t = 0.01 * k as f32;
            let v = c.check(&reading(t, rattle(k), 0), &course(t - 0.01));
            assert_eq!(v, Verdict::Plausible, "sample {k}");
        }
        // The same departure on a smooth course is a spike when it returns.
        let mut c = ReadingCheck::new();
        let mut v = Vec::new();
        for k in 1..10 {
            let t = 0.01 * k as f32;
            let deg = 10.0 - k as f32 + if k == 6 { 0.4 } else { 0.0 };
            v.push(c.check(&reading(t, deg, 0), &course(t - 0.01)));
        }
        assert_eq!(v[6], Verdict::SpikeReturned, "{v:?}");
    }

    #[test]
    fn a_whip_follows_the_cubic_through_four_readings_a_spike_does_not() {
        // The angle of a joint whose acceleration doubles every two samples.
        let whip = |k: f32| 0.2 * libm::powf(2.0, 0.5 * k) * DEG;
        let mut c = ReadingCheck::new();
        for k in 0..6 {
            let t = 0.01 * (k + 1) as f32;
            c.check(&reading(t, whip(k as f32) / DEG, 0), &course(t - 0.01));
        }
        let (next, tol) = (whip(6.0), 0.02 * DEG);
        let mut spiked = c;
        // The monitor asks after the reading's own checks.
        c.check(&reading(0.07, next / DEG, 0), &course(0.06));
        assert!(libm::fabsf(next - c.parabola) > tol, "the parabola lags");
        assert!(c.follows_readings(next, tol));
        let spike = next + 3.0 * DEG;
        spiked.check(&reading(0.07, spike / DEG, 0), &course(0.06));
        assert!(!spiked.follows_readings(spike, tol));
    }

    #[test]
    fn a_stop_does_not_return_and_is_not_flagged() {
        let mut c = ReadingCheck::new();
        // The joint stops dead at 8° at 0.02 s and stays.
        let mut v = Vec::new();
        for (k, deg) in [9.0, 8.0, 8.01, 7.99, 8.0, 8.02].iter().enumerate() {
            let t = 0.01 * (k + 1) as f32;
            v.push(c.check(&reading(t, *deg, 0), &course(t - 0.01)));
        }
        assert!(v.iter().all(|x| *x == Verdict::Plausible), "{v:?}");
    }

    #[test]
    fn repeats_are_stale_only_while_moving() {
        // Moving at 100°/s: the first repeat is fused (the filter slows
        // down), the second is judged against the readings' motion before
        // it.
        let mut c = ReadingCheck::new();
        for (k, deg) in [11.0, 10.0, 9.0].iter().enumerate() {
            let t = 0.01 * (k + 1) as f32;
            assert_eq!(
                c.check(&reading(t, *deg, 0), &course(t - 0.01)),
                Verdict::Plausible
            );
        }
        assert_eq!(
            c.check(&reading(0.04, 9.0, 1), &course(0.03)),
            Verdict::Plausible
        );
        let slowed = Course {
            rate: -DEG,
            ..course(0.04)
        };
        // Fast (45 steps per sample): the second repeat is stale.
        assert_eq!(c.check(&reading(0.05, 9.0, 2), &slowed), Verdict::Stale);
        // 0.15° (7 steps) per sample: two repeats may be a turn, the third
        // is stale.
        let mut c = ReadingCheck::new();
        let slow = |t: f32| Course {
            t_s: t,
            angle: (10.0 - 15.0 * t) * DEG,
            rate: -15.0 * DEG,
            acc: 0.0,
        };
        for (k, deg) in [9.85, 9.70, 9.55].iter().enumerate() {
            let t = 0.01 * (k + 1) as f32;
            assert_eq!(
                c.check(&reading(t, *deg, 0), &slow(t - 0.01)),
                Verdict::Plausible
            );
        }
        assert_eq!(
            c.check(&reading(0.04, 9.55, 1), &slow(0.03)),
            Verdict::Plausible
        );
        assert_eq!(
            c.check(&reading(0.05, 9.55, 2), &slow(0.03)),
            Verdict::Plausible
        );
        assert_eq!(
            c.check(&reading(0.06, 9.55, 3), &slow(0.03)),
            Verdict::Stale
        );
        // Before three readings there is no motion to judge a repeat by.
        let mut c = ReadingCheck::new();
        c.check(&reading(0.01, 9.0, 0), &course(0.0));
        c.check(&reading(0.02, 9.0, 1), &course(0.01));
        assert_eq!(
            c.check(&reading(0.03, 9.0, 2), &course(0.02)),
            Verdict::Plausible
        );
        // At rest, repeats are what a quantised encoder does.
        let rest = Course {
            t_s: 0.01,
            angle: 8.0 * DEG,
            rate: 0.001,
            acc: 0.0,
        };
        let mut c = ReadingCheck::new();
        for k in 0..5u16 {
            let t = 0.02 + 0.01 * f32::from(k);
            let at = Course {
                t_s: t - 0.01,
                ..rest
            };
            assert_eq!(c.check(&reading(t, 8.0, k), &at), Verdict::Plausible);
        }
        let mut off = reading(0.02, 8.0, 2);
        off.moving_checks = false;
        assert_eq!(c.check(&off, &course(0.01)), Verdict::Plausible);
    }
}
