//! The sample path's first stage: the time stamp of each sample against
//! the monitor's time line (NaN, backwards, gaps, jitter: [`Fault`] flags,
//! never a panic).

use crate::monitor::config::ObserverConfig;
use crate::monitor::faults::{Fault, FaultFlags};

/// Longest time step the filters propagate over a gap \[s\].
const MAX_GAP_STEP_S: f32 = 1.0;
/// Relative departure of a sample interval from the running mean beyond
/// which the time stamp is flagged `time_jitter` \[1\].
const JITTER_TOL: f32 = 0.2;
/// Weight of a new interval in the running mean \[1\].
const JITTER_WEIGHT: f32 = 0.05;
/// Consecutive non-increasing time stamps after which the monitor adopts them.
const RESYNC_SAMPLES: u8 = 3;

/// The monitor's time line: when it started, the last time stamp used and
/// what the clock has done lately.
#[derive(Clone, Copy, Debug)]
pub(super) struct Timeline {
    /// A first sample has been used.
    pub(super) started: bool,
    /// Time stamp of the first sample \[s\].
    pub(super) t_start: f32,
    /// Time stamp of the last sample used \[s\].
    pub(super) t_prev: f32,
    /// Consecutive time stamps that did not increase, and the last of them
    /// \[s\] (three in a row are adopted as the new time base).
    back_run: u8,
    t_back: f32,
    /// Running mean of the sample intervals \[s\] (0 before the first).
    dt_mean: f32,
}

/// The clock's verdict on a sample's time stamp.
#[derive(Clone, Copy, Debug)]
pub(super) struct Clock {
    /// Time stamp \[s\].
    pub(super) t: f32,
    /// Time step used by the filters \[s\] (0 at the first sample).
    pub(super) dt: f32,
    /// A gap (or a newly adopted time base) before this sample.
    pub(super) gap: bool,
    /// Time faults, raised on every joint.
    pub(super) faults: FaultFlags,
}

impl Timeline {
    /// Before the first sample.
    pub(super) const START: Timeline = Timeline {
        started: false,
        t_start: 0.0,
        t_prev: 0.0,
        back_run: 0,
        t_back: 0.0,
        dt_mean: 0.0,
    };

    /// Checks the time stamp `t` \[s\] with the limits of `observer`: the
    /// time step and the time faults, or `Err` with the faults of a sample
    /// that is not used (not finite, or backwards until [`RESYNC_SAMPLES`]
    /// in a row adopt the new time base). Inlined into the sample path of
    /// each joint count: the call and its returned `Result` through memory
    /// cost more than the copy.
    #[inline(always)]
    pub(super) fn check(&mut self, t: f32, observer: &ObserverConfig) -> Result<Clock, FaultFlags> {
        let mut faults = FaultFlags::EMPTY;
        if !t.is_finite() {
            faults.insert(Fault::TimeInvalid);
            return Err(faults);
        }
        let mut gap = false;
        let mut dt = 0.0f32;
        if self.started {
            let d = t - self.t_prev;
            if !(d >= observer.min_dt_s) {
                faults.insert(Fault::TimeBackwards);
                let chained = self.back_run > 0 && t - self.t_back >= observer.min_dt_s;
                self.back_run = if chained {
                    self.back_run.saturating_add(1)
                } else {
                    1
                };
                self.t_back = t;
                if self.back_run < RESYNC_SAMPLES {
                    return Err(faults);
                }
                // Adopt the new time base, as after a gap.
                gap = true;
                dt = observer.max_gap_s;
            } else if !(d <= observer.max_gap_s) {
                gap = true;
                dt = d.min(MAX_GAP_STEP_S);
            } else {
                dt = d;
                // Time-stamp jitter: an interval off the running mean.
                if self.dt_mean > 0.0 && libm::fabsf(d - self.dt_mean) > JITTER_TOL * self.dt_mean {
                    faults.insert(Fault::TimeJitter);
                }
                self.dt_mean = if self.dt_mean > 0.0 {
                    self.dt_mean + JITTER_WEIGHT * (d - self.dt_mean)
                } else {
                    d
                };
            }
        }
        self.back_run = 0;
        if gap {
            faults.insert(Fault::TimeGap);
        }
        Ok(Clock { t, dt, gap, faults })
    }
}
