//! The stick rule of `docs/spec/physics.md` §4a in the ideal-latch
//! simulator: a joint at rest (at the start of the run, or at a turning
//! point) whose holding torque is inside its band sticks; a joint creeping
//! slower than [`creep::rest_rate`] with its holding torque inside its
//! kinetic band sticks too ([`crate::simulate::creep`]); a stuck joint
//! slips when the torque leaves its band (the `Slip` event).

use super::{Integrator, State};
use crate::simulate::creep;
use deploywatch_core::physics::stick::{holding_torques, StickBand};

/// A rate below this [rad/s] at a branch event is a turning point, where
/// the stick rule (`physics.md` §4a) applies.
const TURNING_RATE_RAD_S: f64 = 1e-6;

impl<const N: usize> Integrator<'_, N> {
    /// Joint `j`'s holding torque with it held too, and its band, at `y`.
    pub(super) fn holding(&self, j: usize, y: &State<N>) -> Option<(f64, StickBand<f64>)> {
        let r = self.holding_torque(j, y)?;
        Some((r, self.chain.stick_band(j, y.q[j])))
    }

    /// Joint `j`'s holding torque [N·m] with it held too, at `y`.
    fn holding_torque(&self, j: usize, y: &State<N>) -> Option<f64> {
        let mut mode = self.held();
        mode.latched[j] = true;
        let (m, rhs) = self.chain.equations(&y.chain(), &mode);
        let r = holding_torques(&m, &rhs, &mode.latched).ok()?[j];
        r.is_finite().then_some(r)
    }

    /// Joint `j` at a turning point sticks when its band holds it (its
    /// rate to zero by the impulse of that joint alone).
    pub(super) fn try_stick(&mut self, j: usize, y: &mut State<N>) -> bool {
        if y.v[j].abs() > TURNING_RATE_RAD_S || !self.chain.can_stick(j) {
            return false;
        }
        let Some((r, band)) = self.holding(j, y) else {
            return false;
        };
        band.margin(r) > 0.0 && self.hold(j, y)
    }

    /// Every free joint at rest at the start of the run that its band
    /// holds sticks there (in joint order; `physics.md` §4a: "a run
    /// starting at rest applies the rule at t = 0").
    pub(super) fn stick_at_start(&mut self, y: &mut State<N>) {
        for j in 0..N {
            if !self.mode.latched[j] && !self.stuck[j] && y.v[j] == 0.0 {
                self.try_stick(j, y);
            }
        }
    }

    /// Whether a free joint moves slower than its [`creep::rest_rate`] at
    /// `y` (the cheap test before [`Integrator::creep_sticks`]).
    pub(super) fn slow(&self, y: &State<N>) -> bool {
        creep::any_slow(
            self.chain,
            |j| !self.mode.latched[j] && !self.stuck[j],
            &y.v,
        )
    }

    /// Every free joint creeping at `y` (slower than its
    /// [`creep::rest_rate`], its holding torque inside its kinetic band,
    /// stopping short of its latch) sticks; the first such joint
    /// (0-based), or `None`.
    pub(super) fn creep_sticks(&mut self, y: &mut State<N>) -> Option<usize> {
        let mut first = None;
        for j in 0..N {
            let v = y.v[j];
            if self.mode.latched[j]
                || self.stuck[j]
                || !creep::is_slow(self.chain, j, v)
                || !self.chain.can_stick(j)
            {
                continue;
            }
            let Some(r) = self.holding_torque(j, y) else {
                continue;
            };
            let stopping = self.chain.kinetic_band(j, y.q[j]).margin(r);
            if !(stopping > 0.0) {
                continue;
            }
            let inertia = self.chain.mass_matrix(&y.q)[j][j];
            let short = creep::stops_short(y.q[j], v, stopping, inertia, self.latching[j]);
            if short && self.hold(j, y) {
                first = first.or(Some(j));
            }
        }
        first
    }

    /// Holds joint `j`: its rate to zero by the plastic impulse of that
    /// joint alone, the others' momenta kept. False when the impulse
    /// cannot be found (a singular mass matrix).
    fn hold(&mut self, j: usize, y: &mut State<N>) -> bool {
        let mut mode = self.held();
        mode.latched[j] = true;
        let Ok(v) = self.chain.latch_impulse(&y.chain(), &mode.latched) else {
            return false;
        };
        y.v = v;
        for k in 0..N {
            if mode.latched[k] {
                y.v[k] = 0.0;
            }
        }
        self.stuck[j] = true;
        true
    }
}
