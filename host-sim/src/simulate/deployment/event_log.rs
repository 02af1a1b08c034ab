//! The events of an ideal-latch run so far that tell a joint sliding on
//! `φ̇ = 0` (Zeno chattering between the spring's branches) from one that
//! turns: [`EventLog`].

use crate::simulate::trajectory::SimError;

/// Most branch events one joint may have within [`BRANCH_BURST_WINDOW_S`]
/// before the simulation is declared to slide on `φ̇ = 0`.
pub const MAX_BRANCH_BURST: usize = 10;

/// The window of [`MAX_BRANCH_BURST`] \[s\]: 1 ms, a tenth of a sample at
/// 100 Hz; a spring switching branches more often than that is chattering,
/// not moving.
pub const BRANCH_BURST_WINDOW_S: f64 = 1e-3;

/// Most consecutive events at one instant before the simulation is declared
/// to slide: five per joint of the longest chain ([`MAX_CHAIN_JOINTS`](crate::model::mechanism::MAX_CHAIN_JOINTS)),
/// far more than a latch and a branch switch each.
pub const MAX_SAME_INSTANT_EVENTS: usize = 20;

/// Events closer than this are at the same instant \[s\]: the precision to
/// which [`ode::locate`](crate::simulate::ode::locate) finds an event time of seconds.
pub const SAME_INSTANT_S: f64 = 1e-12;

/// Events of the run so far that decide whether a joint slides on `φ̇ = 0`.
pub(super) struct EventLog<const N: usize> {
    /// Consecutive events at the same instant.
    pub(super) same_instant: usize,
    /// Per joint: the start of the last millisecond of branch events and
    /// their count (a burst is Zeno chattering between the branches).
    burst: [(f64, usize); N],
}

impl<const N: usize> EventLog<N> {
    pub(super) fn new() -> Self {
        EventLog {
            same_instant: 0,
            burst: [(f64::NEG_INFINITY, 0usize); N],
        }
    }

    /// Records an event at `t_end` of a step from `t`: a run of events at
    /// one instant grows.
    pub(super) fn event(&mut self, t: f64, t_end: f64) {
        self.same_instant = if (t_end - t).abs() < SAME_INSTANT_S {
            self.same_instant + 1
        } else {
            0
        };
    }

    /// Records a branch event of joint `j` at `t`; an error when the joint
    /// slides.
    pub(super) fn branch(&mut self, j: usize, t: f64) -> Result<(), SimError> {
        let (last, count) = self.burst[j];
        self.burst[j] = if t - last < BRANCH_BURST_WINDOW_S {
            (last, count + 1)
        } else {
            (t, 1)
        };
        if self.same_instant > MAX_SAME_INSTANT_EVENTS || self.burst[j].1 > MAX_BRANCH_BURST {
            return Err(SimError::Sliding {
                joint: j + 1,
                t_s: t,
            });
        }
        Ok(())
    }
}
