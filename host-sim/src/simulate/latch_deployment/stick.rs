//! The stick rule of `docs/spec/physics.md` §4a in the physical-latch
//! simulator: a joint whose rate reaches rest with its holding torque
//! inside the band of its set-valued laws (tape-spring branches, static
//! friction) is held until the torque leaves the band
//! ([`deploywatch_core::physics::stick`]); an ideal latch's plastic
//! impulse (`physics.md` section 5), which frees a stuck joint.

use super::{branch_at, classify, Runner, Sim};
use crate::simulate::creep;
use crate::simulate::latch_run::LatchEventKind;
use crate::simulate::ode::State;
use crate::simulate::trajectory::SimError;
use deploywatch_core::physics::stick::{holding_torques, StickBand};

/// A rate below this [rad/s] is a turning point (a branch event there is
/// a turn too).
const TURNING_RATE_RAD_S: f64 = 1e-6;

/// A joint at rest within this distance of a mark of its latch's travel
/// \[rad\] is at the mark for the stick rule ([`Sim::holding_range`]).
const MARK_NEAR_RAD: f64 = 1e-7;

impl<const N: usize> Sim<'_, N> {
    /// Joint `j`'s holding torque [N·m] with it and the joints already
    /// held out of the coordinates, and its band, at `y`: the torque of the
    /// range it can take ([`Sim::holding_range`]) the band holds best.
    fn holding(&self, j: usize, y: &State<N>) -> Option<(f64, StickBand<f64>)> {
        let ([a, b], band) = self.holding_range(j, y)?;
        let mid = 0.5 * (band.lo + band.hi);
        Some((mid.clamp(a, b), band))
    }

    /// The holding torques [N·m] joint `j` can take at `y`, `[low, high]`,
    /// and its band. Off a mark of its latch's travel this is one torque.
    /// Within [`MARK_NEAR_RAD`] of a mark where the latch's law jumps (a
    /// preloaded plunger's ramp, the magnet's reach) it is every torque
    /// between the two sides' (Filippov's convex hull): a joint at rest
    /// against the jump is held there by a contact force between the two
    /// laws', as against a stop, instead of crossing back and forth.
    fn holding_range(&self, j: usize, y: &State<N>) -> Option<([f64; 2], StickBand<f64>)> {
        let mut held = self.held();
        held[j] = true;
        let (m, mut rhs) = self.system(y, &held);
        let band = self.chain.stick_band(j, y.q[j]);
        let at = |rhs: &[f64; N]| -> Option<f64> {
            let r = holding_torques(&m, rhs, &held).ok()?[j];
            r.is_finite().then_some(r)
        };
        let r = at(&rhs)?;
        let mut range = [r, r];
        if let Some(l) = &self.latch[j] {
            let (phi, rate) = (y.q[j], y.v[j]);
            let own = self.latch_torque(j, phi, rate).0;
            for side in [-1.0, 1.0] {
                let s = classify(l, phi + side * MARK_NEAR_RAD, 0.0, self.seg[j]);
                let jump = self.latch_torque_on(j, &s, phi, rate).0 - own;
                if jump != 0.0 {
                    let base = rhs[j];
                    rhs[j] = base + jump;
                    let r_side = at(&rhs)?;
                    rhs[j] = base;
                    range = [range[0].min(r_side), range[1].max(r_side)];
                }
            }
        }
        Some((range, band))
    }

    /// How far a stuck joint's holding torque is inside its band (the
    /// event function of [`super::Ev::Slip`]).
    pub(super) fn slip_margin(&self, j: usize, y: &State<N>) -> f64 {
        self.holding(j, y).map_or(-1.0, |(r, band)| band.margin(r))
    }

    /// The event function of [`super::Ev::Turn`]: the rate on the side the
    /// step started on.
    pub(super) fn turn_g(&self, j: usize, y: &State<N>) -> f64 {
        let (sign, rest) = self.turn[j];
        if sign == 0.0 {
            return 1.0;
        }
        sign * y.v[j] - rest
    }

    /// Arms each free joint's turn event for a step from `y0`: fires where
    /// its rate crosses zero.
    pub(super) fn arm_turns(&mut self, y0: &State<N>) {
        for j in 0..N {
            self.turn[j] = (0.0, 0.0);
            if self.mode.latched[j] || self.stuck[j] || !self.chain.can_stick(j) {
                continue;
            }
            let v = y0.v[j];
            let sign = if v > 0.0 {
                1.0
            } else if v < 0.0 {
                -1.0
            } else {
                0.0
            };
            self.turn[j] = (sign, 0.0);
        }
    }

    /// Joint `j` at rest at `y` sticks when its band holds it: its rate
    /// goes to zero in a plastic impulse on it alone (the other joints'
    /// momenta kept). Returns the kinetic energy that took \[J\].
    fn try_stick(&mut self, j: usize, y: &mut State<N>) -> Option<f64> {
        if self.mode.latched[j] || self.stuck[j] || !self.chain.can_stick(j) {
            return None;
        }
        let (r, band) = self.holding(j, y)?;
        if !(band.margin(r) > 0.0) {
            return None;
        }
        self.hold_joint(j, y)
    }

    /// Holds joint `j`: its rate to zero in a plastic impulse on it alone
    /// (the other joints' momenta kept). Returns the kinetic energy that
    /// took \[J\].
    fn hold_joint(&mut self, j: usize, y: &mut State<N>) -> Option<f64> {
        let before = self.chain.kinetic_energy(&y.chain());
        let mut held = self.held();
        held[j] = true;
        let v = self.chain.latch_impulse(&y.chain(), &held).ok()?;
        y.v = v;
        for k in 0..N {
            if held[k] {
                y.v[k] = 0.0;
            }
        }
        self.stuck[j] = true;
        Some(before - self.chain.kinetic_energy(&y.chain()))
    }

    /// Whether a free joint moves slower than its [`creep::rest_rate`] at
    /// `y` (the cheap test before [`Sim::try_creep_stick`]).
    pub(super) fn slow(&self, y: &State<N>) -> bool {
        creep::any_slow(
            self.chain,
            |j| !self.mode.latched[j] && !self.stuck[j],
            &y.v,
        )
    }

    /// Joint `j` creeping at `y` sticks ([`crate::simulate::creep`]): slower
    /// than its rest rate, the holding torque the band of its kinetic level
    /// holds best inside that band, and stopping short of its stop. Returns
    /// the kinetic energy that took \[J\].
    pub(super) fn try_creep_stick(&mut self, j: usize, y: &mut State<N>) -> Option<f64> {
        let v = y.v[j];
        if self.mode.latched[j]
            || self.stuck[j]
            || !creep::is_slow(self.chain, j, v)
            || !self.chain.can_stick(j)
        {
            return None;
        }
        let ([a, b], _) = self.holding_range(j, y)?;
        let band = self.chain.kinetic_band(j, y.q[j]);
        let r = (0.5 * (band.lo + band.hi)).clamp(a, b);
        let stopping = band.margin(r);
        let inertia = self.chain.mass_matrix(&y.q)[j][j];
        if !(stopping > 0.0) || !creep::stops_short(y.q[j], v, stopping, inertia, true) {
            return None;
        }
        self.hold_joint(j, y)
    }

    /// A stuck joint slips: free again, on the spring branch of the
    /// direction its holding torque left the band by.
    pub(super) fn slip(&mut self, j: usize, y: &State<N>) {
        let dir = self
            .holding(j, y)
            .map_or(1.0, |(r, band)| band.slip_direction(r));
        self.stuck[j] = false;
        self.mode.branch[j] = branch_at(y.q[j], dir);
    }

    /// At the start of a run at rest: each joint the band holds sticks
    /// (in joint order).
    pub(super) fn stick_at_rest(&mut self, y: &State<N>) {
        for j in 0..N {
            if y.v[j] == 0.0 {
                let mut y = *y;
                self.try_stick(j, &mut y);
            }
        }
    }
}

impl Runner<'_> {
    /// A turn of joint `j`: it sticks, or moves on.
    pub(super) fn turn<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        j: usize,
        y: &mut State<N>,
    ) -> LatchEventKind {
        match sim.try_stick(j, y) {
            Some(lost) => {
                self.booked_stick(lost);
                LatchEventKind::Stick
            }
            None => {
                sim.mode.branch[j] = branch_at(y.q[j], y.v[j]);
                LatchEventKind::Turn
            }
        }
    }

    /// A branch event of joint `j` at a turning point: the stick rule
    /// there (`None`: not at rest, or not held).
    pub(super) fn turn_at_rest<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        j: usize,
        y: &mut State<N>,
    ) -> Option<LatchEventKind> {
        if y.v[j].abs() > TURNING_RATE_RAD_S {
            return None;
        }
        let lost = sim.try_stick(j, y)?;
        self.booked_stick(lost);
        Some(LatchEventKind::Stick)
    }

    /// The joints creeping at `y` (the end of an accepted step at `t`)
    /// stick ([`crate::simulate::creep`]), each logged as a stick and its
    /// energy booked; true when one did (the integration restarts).
    pub(super) fn creep<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        y: &mut State<N>,
        t: f64,
    ) -> Result<bool, SimError> {
        if !sim.slow(y) {
            return Ok(false);
        }
        let mut any = false;
        for j in 0..N {
            let Some(lost) = sim.try_creep_stick(j, y) else {
                continue;
            };
            any = true;
            self.booked_stick(lost);
            self.out.traj.stats.events += 1;
            self.log(sim, j, LatchEventKind::Stick, y, t);
            sim.close_ledger(&mut self.ledger, y);
            self.ledger
                .check(t, j + 1, || "its creep to rest (a stick)".to_string())?;
        }
        Ok(any)
    }

    /// Books the kinetic energy a stick took as the set-valued law's
    /// dissipation.
    fn booked_stick(&mut self, lost_j: f64) {
        let e = &mut self.ledger.energy;
        e.friction_j += lost_j;
        e.stick_j += lost_j;
        e.sticks += 1;
    }

    /// An ideal latch of joint `fired` at `t`: it and every other free ideal
    /// joint at its latch angle lock in one plastic impulse (`physics.md`
    /// section 5).
    pub(super) fn ideal_latch<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        y: &mut State<N>,
        t: f64,
        fired: usize,
    ) -> Result<(), SimError> {
        let mut after = sim.mode.latched;
        for j in 0..N {
            let at_latch = j == fired || sim.side[j] * y.q[j] <= 1e-12;
            if sim.latch[j].is_none() && !after[j] && at_latch {
                after[j] = true;
            }
        }
        let before = sim.chain.kinetic_energy(&y.chain());
        y.v = sim
            .chain
            .latch_impulse(&y.chain(), &after)
            .map_err(|_| SimError::Singular { t_s: t })?;
        for j in 0..N {
            if after[j] {
                y.v[j] = 0.0;
            } else if sim.stuck[j] {
                // An impulsive torque is beyond any static band: a stuck
                // joint moves with the impulse (was: kept frozen at the
                // rate the impulse gave it, its friction booked on it).
                sim.stuck[j] = false;
                sim.mode.branch[j] = branch_at(y.q[j], y.v[j]);
            }
        }
        // The locked joints' springs keep their energy at φ = 0 (none).
        for j in 0..N {
            if after[j] && !sim.mode.latched[j] {
                y.q[j] = 0.0;
            }
        }
        sim.mode.latched = after;
        self.ledger.energy.impact_j += before - sim.chain.kinetic_energy(&y.chain());
        Ok(())
    }
}
