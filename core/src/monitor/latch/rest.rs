//! A joint at rest short of its latch (`docs/monitor.md` §4): the states
//! that say so, how long its readings have held still, and the rest band
//! of an ideal latch's readings.

use super::{LatchConfig, LatchInput, LatchState, LatchTracker};

/// Half-width of the band, in standard deviations of one reading, within
/// which the readings of a joint with an ideal latch stay while it is at
/// rest \[1\]: two readings of a joint at rest differ by more than 8 σ
/// with probability 1.5·10⁻⁸. Inside `latching_deg` the rate filter
/// follows a snapping tape spring (`snap_zone_deg`, a jerk floor of 10⁷
/// rad²/s⁵) and its rate of a joint at rest swings by tens of degrees per
/// second, and mid-stroke the noise of the reference encoder moves it
/// across the stall rate: the readings tell the rest (`docs/monitor.md`
/// §4).
const REST_BAND_SIGMAS: f32 = 8.0;

impl LatchTracker {
    /// True while a physical latch's joint is at rest on the plunger's
    /// ramp with its switch open ([`LatchState::StoppedShort`]).
    pub fn stopped_short(&self) -> bool {
        self.motion == LatchState::StoppedShort
    }

    /// True while the joint, not latched, is at rest by its readings
    /// ([`LatchState::Stalled`] or [`LatchState::StoppedShort`]).
    pub fn at_rest(&self) -> bool {
        matches!(self.motion, LatchState::Stalled | LatchState::StoppedShort)
    }

    /// True while the joint is at rest short of its latch
    /// ([`LatchTracker::at_rest`]) and its readings have held still (an
    /// ideal latch's: within the rest band of one reading; a physical
    /// latch's: on the entry ramp, switch open) for at least `duration_s`
    /// \[s\] at `t_s` \[s\]. Not by its rate alone: a joint creeping
    /// towards its latch at a fraction of the stall rate leaves the band.
    pub fn at_rest_for(&self, t_s: f32, duration_s: f32) -> bool {
        self.at_rest()
            && (self.rest.at_least(t_s, duration_s) || self.bounce.on_ramp_for(t_s, duration_s))
    }

    /// True when a joint with an ideal latch has read within
    /// [`REST_BAND_SIGMAS`] readings' σ of one reading for `stall_time_s`
    /// (mid-stroke or short of its latch); the stretch restarts at a
    /// reading outside the band. Always false with a physical latch, whose
    /// stops short of the latch are the bounce rule's (on the ramp) and
    /// whose stalls the rate's.
    #[inline(always)]
    pub(super) fn rests_near(&mut self, x: &LatchInput, cfg: &LatchConfig) -> bool {
        if cfg.physical.is_some() {
            return false;
        }
        let Some(m) = x.measured_deg else {
            return self.rest.at_least(x.t_s, cfg.stall_time_s);
        };
        let band = REST_BAND_SIGMAS * x.noise_sd_deg;
        if !(libm::fabsf(m - self.rest_deg) <= band) || !self.rest.is_on() {
            self.rest_deg = m;
            self.rest.restart(x.t_s);
        }
        self.rest.at_least(x.t_s, cfg.stall_time_s)
    }
}
