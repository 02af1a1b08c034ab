//! Whether a joint's readings resolve its motion at the sampling rate: the
//! [`Resolution`] of each joint's status, decided from the readings only.
//!
//! A joint shaken by a rattling pawl or a bouncing plunger next to it
//! changes its rate by tens of degrees per second from one sample to the
//! next and back: its readings leave the line through the readings before
//! them and come back, as a spike does, and at 100 Hz the two cannot be
//! told apart. The readings show the shaking in their change of step
//! `b = z₀ − 2 z₁ + z₂` (three readings in a row): a joint whose `b`
//! reached [`UNRESOLVED_BEND_DEG`] in both signs within the last
//! [`RESOLUTION_READINGS`] readings is [`Resolution::Unresolved`], and stays
//! so while they still reach [`RESOLVED_BEND_DEG`] both ways (hysteresis:
//! a joint shaken on and off does not flicker). A smooth course, however
//! hard it accelerates (a tape spring's snap, the whip before a
//! neighbour's latch, a joint its spring drives on after an impact),
//! bends one way over a few samples; a spike on a quiet joint is kept out
//! of the history (`plausibility.rs` leaves a departure's readings out of
//! a quiet joint's history and forgets them when they return), so it does
//! not make its own joint unresolved. The readings are followed whether
//! or not the reading checks apply (an impact under way), but not where
//! the joint's own latch holds it (latched, switch closed, within the
//! physical latch's reach of its stop): it is reported resolved there.
//! The monitor follows it on a wing with a physical latch only (the source
//! of the shaking); on a wing of ideal latches every joint is resolved and
//! the sample path does none of this (`Reading::follow`).
//!
//! The history is 4 bits per reading (at or beyond each threshold upwards and
//! downwards) in one `u32`, with the last two readings: a change of step,
//! a shift, an or and two mask tests per reading on the sample path.

use crate::monitor::status::{
    Resolution, RESOLUTION_READINGS, RESOLVED_BEND_DEG, UNRESOLVED_BEND_DEG,
};

/// One degree \[rad\].
const DEG: f32 = core::f32::consts::PI / 180.0;
/// Changes of step \[rad\] to whole [`RESOLVED_BEND_DEG`]s: the
/// thresholds are 1 and 2 of them (a table look-up on the sample path).
const PER_RAD: f32 = 1.0 / (RESOLVED_BEND_DEG * DEG);
const _: () = assert!(UNRESOLVED_BEND_DEG == 2.0 * RESOLVED_BEND_DEG);

/// Bits per reading in the history: 1 at or beyond [`UNRESOLVED_BEND_DEG`]
/// upwards, 2 downwards, 4 at or over [`RESOLVED_BEND_DEG`] upwards, 8
/// downwards.
const BITS: u32 = 4;
/// The history's bits of the last [`RESOLUTION_READINGS`] readings.
const HISTORY: u32 = (1u32 << (BITS * RESOLUTION_READINGS)) - 1;
/// Bit `bit` of every reading in the history.
const fn every(bit: u32) -> u32 {
    let mut m = 0u32;
    let mut k = 0;
    while k < RESOLUTION_READINGS {
        m |= bit << (BITS * k);
        k += 1;
    }
    m
}
/// The bits of a change of step of `q` whole [`RESOLVED_BEND_DEG`]s
/// (clamped to ±2), at index `q + 2`.
const CODES: [u8; 5] = [2 | 8, 8, 0, 4, 1 | 4];
/// The readings' changes of step at or beyond [`UNRESOLVED_BEND_DEG`]
/// upwards and downwards, and at or beyond [`RESOLVED_BEND_DEG`] upwards
/// and downwards.
const UP: u32 = every(1);
const DOWN: u32 = every(2);
const LIVELY_UP: u32 = every(4);
const LIVELY_DOWN: u32 = every(8);

/// The changes of step of a joint's last readings, and whether they make
/// it unresolved.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Shaking {
    /// The last two readings, older first \[rad\]; NaN for one lost (a
    /// missing reading, a gap: the changes of step through it count as
    /// quiet).
    z: [f32; 2],
    /// 4 bits per reading, newest lowest.
    history: u32,
    /// The verdict as of the last [`Shaking::judge`].
    unresolved: bool,
}

impl Shaking {
    /// No change of step seen: resolved.
    pub const NEW: Shaking = Shaking {
        z: [f32::NAN; 2],
        history: 0,
        unresolved: false,
    };

    /// Takes the reading `z` \[rad\]; its change of step with the two
    /// before it goes into the history when `record` (a departure's
    /// readings stay out of a quiet joint's: `plausibility.rs`).
    #[inline(always)]
    pub fn read(&mut self, z: f32, record: bool) {
        let [z0, z1] = self.z;
        if record {
            self.record(z0 - 2.0 * z1 + z);
        }
        self.z = [z1, z];
    }

    /// A reading lost, or the time stamps broke (a gap): the next two
    /// changes of step count as quiet.
    #[inline(always)]
    pub fn lose(&mut self) {
        self.z = [f32::NAN; 2];
    }

    /// Starts afresh from the reading `z` \[rad\] (it ends a spike that
    /// returned: the spike's readings are forgotten).
    #[inline(always)]
    pub fn restart(&mut self, z: f32) {
        self.history = 0;
        self.z = [f32::NAN, z];
    }

    /// Adds the change of step `bend` \[rad\] of the newest three readings
    /// (NaN: quiet).
    #[inline(always)]
    pub fn record(&mut self, bend: f32) {
        // Whole 0.1°s, towards 0 (NaN: 0), at most 2 either way: its bits
        // from a table (a load, not four comparisons, on the sample path).
        let q = ((bend * PER_RAD) as i32).clamp(-2, 2);
        let code = CODES.get((q + 2) as usize).copied().unwrap_or(0);
        self.history = (self.history << BITS | u32::from(code)) & HISTORY;
    }

    /// The verdict on the history so far, kept until the next call: a
    /// resolved joint becomes unresolved when the recent changes of step
    /// reached [`UNRESOLVED_BEND_DEG`] both ways; an unresolved one
    /// stays so while they still reach [`RESOLVED_BEND_DEG`] both ways (a
    /// smooth course bends one way, however hard it accelerates: after an
    /// impact, a joint its spring accelerates hard is resolved again).
    #[inline(always)]
    pub fn judge(&mut self) -> bool {
        let h = self.history;
        let (up, down) = if self.unresolved {
            (LIVELY_UP, LIVELY_DOWN)
        } else {
            (UP, DOWN)
        };
        self.unresolved = h & up != 0 && h & down != 0;
        self.unresolved
    }

    /// Resolved until the next [`Shaking::judge`] (the joint's own latch
    /// holds it), the history kept.
    #[inline(always)]
    pub fn pause(&mut self) {
        self.unresolved = false;
    }

    /// True when a recent change of step reached the threshold either
    /// way: the joint is not quiet, and a departure's readings are its
    /// motion as much as a spike's (`plausibility.rs` records them).
    #[inline(always)]
    pub fn shaken(&self) -> bool {
        self.history & (UP | DOWN) != 0
    }

    /// The verdict as of the last [`Shaking::judge`].
    #[inline(always)]
    pub fn resolution(&self) -> Resolution {
        Resolution::of(self.unresolved)
    }

    /// True when unresolved as of the last [`Shaking::judge`].
    #[inline(always)]
    pub fn unresolved(&self) -> bool {
        self.unresolved
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn judged(bends_deg: &[f32]) -> Vec<bool> {
        let mut s = Shaking::NEW;
        bends_deg
            .iter()
            .map(|b| {
                s.record(b * DEG);
                s.judge()
            })
            .collect()
    }

    #[test]
    fn both_signs_within_five_readings_open_it_quiet_ones_close_it() {
        // One way only (a snap, a whip): resolved however large.
        assert!(judged(&[0.5, 1.0, 2.0, 3.0, 0.05]).iter().all(|u| !u));
        // Both ways within five readings: unresolved; it stays so while
        // changes of step over 0.1° both ways are within the last five.
        let v = judged(&[0.3, 0.05, -0.25, 0.15, 0.05, 0.05, 0.05, 0.05, 0.05]);
        assert_eq!(
            v,
            [false, false, true, true, true, true, true, false, false]
        );
        // An impact, then hard smooth acceleration (0.2° a step², 35
        // rad/s²): unresolved at the turn, resolved once the impact's
        // change of step is five readings old.
        let v = judged(&[0.0, -2.0, 0.25, 0.2, 0.2, 0.2, 0.2, 0.2, 0.2]);
        assert_eq!(
            v,
            [false, false, true, true, true, true, false, false, false]
        );
        // Both ways but six readings apart: resolved.
        assert!(judged(&[0.3, 0.0, 0.0, 0.0, 0.0, -0.3]).iter().all(|u| !u));
        // Hysteresis: moderate changes of step (0.1–0.2°) keep it
        // unresolved, never open it.
        let v = judged(&[0.3, -0.3, 0.15, -0.15, 0.15, -0.15, 0.15, -0.15, 0.15]);
        assert!(v[1..].iter().all(|u| *u), "{v:?}");
        assert!(judged(&[0.15, -0.15, 0.15, -0.15, 0.15]).iter().all(|u| !u));
    }

    #[test]
    fn pausing_reports_resolved_and_keeps_the_history() {
        let mut s = Shaking::NEW;
        for b in [0.3, -0.3] {
            s.record(b * DEG);
        }
        assert!(s.judge());
        s.pause();
        assert_eq!(s.resolution(), Resolution::Resolved);
        assert!(s.judge());
        s.restart(0.0);
        assert!(!s.judge());
    }
}
