//! How long a condition has held: the timers of the latch tracker
//! ([`crate::monitor::latch`]) as two small types instead of hand-made
//! `since`/`run` pairs.
//!
//! - [`Held`]: a condition held since a time stamp \[s\] (the start of its
//!   current unbroken stretch), or the time of the last event.
//! - [`HeldSamples`]: a condition held for a number of consecutive samples.

/// A condition held since a time stamp \[s\]: the start of its current
/// unbroken stretch (or the time of the last event), or none while it does
/// not hold.
///
/// Four bytes: "does not hold" is a NaN start, which every comparison of
/// [`Held::at_least`] and [`Held::within`] answers with `false`, so the
/// timer costs no flag beside its time stamp.
#[derive(Clone, Copy, Debug)]
pub struct Held {
    /// Start of the current stretch \[s\], NaN while the condition does not
    /// hold.
    since: f32,
}

impl Default for Held {
    fn default() -> Self {
        Held::NEW
    }
}

/// Two timers are equal when both are off or both started at the same time.
impl PartialEq for Held {
    fn eq(&self, other: &Self) -> bool {
        self.since.to_bits() == other.since.to_bits()
            || (self.since.is_nan() && other.since.is_nan())
    }
}

impl Held {
    /// A condition that does not hold.
    pub const NEW: Held = Held { since: f32::NAN };

    /// Starts a stretch at `t_s` \[s\] unless one is under way.
    #[inline(always)]
    pub fn start(&mut self, t_s: f32) {
        if self.since.is_nan() {
            self.since = t_s;
        }
    }

    /// Starts a new stretch at `t_s` \[s\], ending any under way (an event:
    /// the time of the last one).
    #[inline(always)]
    pub fn restart(&mut self, t_s: f32) {
        self.since = t_s;
    }

    /// Ends the stretch.
    #[inline(always)]
    pub fn stop(&mut self) {
        self.since = f32::NAN;
    }

    /// Records the condition at time `t_s` \[s\]: a stretch starts at the
    /// first sample that holds and ends at the first that does not.
    #[inline(always)]
    pub fn update(&mut self, holds: bool, t_s: f32) {
        if holds {
            self.start(t_s);
        } else {
            self.stop();
        }
    }

    /// True while the condition holds.
    #[inline(always)]
    pub fn is_on(&self) -> bool {
        !self.since.is_nan()
    }

    /// True when the condition has held for at least `duration_s` \[s\] at
    /// time `t_s` \[s\].
    #[inline(always)]
    pub fn at_least(&self, t_s: f32, duration_s: f32) -> bool {
        t_s - self.since >= duration_s
    }

    /// True when the condition holds and started at most `duration_s` \[s\]
    /// before `t_s` \[s\] (the last event was that recent).
    #[inline(always)]
    pub fn within(&self, t_s: f32, duration_s: f32) -> bool {
        t_s - self.since <= duration_s
    }
}

/// A condition held for a number of consecutive samples (saturating).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct HeldSamples(u8);

impl HeldSamples {
    /// A condition that does not hold.
    pub const NEW: HeldSamples = HeldSamples(0);

    /// Records the condition at one sample.
    #[inline(always)]
    pub fn update(&mut self, holds: bool) {
        self.0 = if holds { self.0.saturating_add(1) } else { 0 };
    }

    /// Consecutive samples the condition has held.
    #[inline(always)]
    pub fn count(&self) -> u8 {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn held_measures_the_unbroken_stretch() {
        let mut h = Held::NEW;
        assert!(!h.is_on() && !h.at_least(1.0, 0.0) && !h.within(1.0, 10.0));
        h.update(true, 1.0);
        h.update(true, 1.5);
        assert!(h.is_on() && h.at_least(1.5, 0.5) && !h.at_least(1.5, 0.6));
        h.update(false, 1.6);
        assert!(!h.is_on() && !h.at_least(2.0, 0.0));
        h.update(true, 2.0);
        assert!(h.at_least(2.25, 0.25) && h.within(2.25, 0.25) && !h.within(2.5, 0.25));
        h.restart(3.0);
        assert!(h.within(3.0, 0.0) && !h.at_least(3.0, 0.1));
    }

    #[test]
    fn held_samples_count_and_saturate() {
        let mut n = HeldSamples::NEW;
        n.update(true);
        n.update(true);
        assert_eq!(n.count(), 2);
        n.update(false);
        assert_eq!(n.count(), 0);
        for _ in 0..300 {
            n.update(true);
        }
        assert_eq!(n.count(), u8::MAX);
    }
}
