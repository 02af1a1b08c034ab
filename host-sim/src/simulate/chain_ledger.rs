//! The energy ledger of an ideal-latch chain run (`docs/simulator.md`,
//! "Energy ledger self-check"): kinetic energy plus the chain's potential
//! ([`deploywatch_core::Chain::potential_energy`]: springs on their
//! unfolding branch, harness, rig tilt) plus the work of every other torque
//! (friction, the tape springs' hysteresis, joint effects, air drag),
//! integrated on 3-point Gauss–Legendre nodes of each step's dense output,
//! plus the energy the events took (the latches' plastic impacts, the stick
//! rule's impulses) is the energy stored at the start, to the drift. A drift
//! beyond the run's tolerance ([`SimOptions::max_drift`],
//! [`MAX_LEDGER_DRIFT`] by default) of the stored energy stops the run with
//! [`SimError::EnergyDrift`]; a step over which the drift moves by more than
//! its [`step_budget`] is taken again shorter.

use crate::model::torque_table::HostChain;
use crate::simulate::latch_run::{ledger_step_factor, step_budget, LEDGER_MIN_STEP_S};
use crate::simulate::ode::{Dense, State};
#[cfg(doc)]
use crate::simulate::trajectory::MAX_LEDGER_DRIFT;
use crate::simulate::trajectory::{SimError, SimOptions};
use deploywatch_core::{Branch, Mode};

/// 3-point Gauss–Legendre nodes and weights on [0, 1] (exact to degree 5).
const GAUSS3: [(f64, f64); 3] = [
    (0.112_701_665_379_258_31, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

/// The running sums of an ideal-latch run's ledger \[J\].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChainLedger {
    /// Kinetic plus potential energy at the start.
    pub stored_j: f64,
    /// Dissipated by the non-conservative torques so far.
    pub dissipated_j: f64,
    /// Taken by the events (plastic latch impacts, sticks) so far.
    pub events_j: f64,
    /// Largest `|total − stored|` so far.
    pub worst_drift_j: f64,
    /// `total − stored` at the last check.
    pub now_j: f64,
    /// The run's duration \[s\] ([`step_budget`]).
    pub duration_s: f64,
    /// The run's tolerance ([`SimOptions::max_drift`]).
    pub max_drift: f64,
    /// The last step refused was cut at an event and is being taken again
    /// up to it ([`ChainLedger::book`]).
    pub to_event: bool,
}

/// What the ledger's booking of a step asks of the next attempt.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Booking {
    /// Booked; the next step is at most `cap` \[s\] (the ledger's own
    /// size, [`ledger_step_factor`]; unbounded after a step under
    /// [`LEDGER_MIN_STEP_S`] booked over its budget).
    Kept {
        /// The longest next step \[s\].
        cap: f64,
    },
    /// Not booked: the step is to be taken again, `h` \[s\] long.
    Retake {
        /// The step to try \[s\].
        h: f64,
    },
}

impl ChainLedger {
    /// The ledger of a run of `duration_s` \[s\] starting at `y0`, held
    /// to `opts`' [`SimOptions::max_drift`].
    pub fn start<const N: usize>(
        chain: &HostChain<N>,
        y0: &State<N>,
        duration_s: f64,
        opts: &SimOptions,
    ) -> Self {
        ChainLedger {
            stored_j: state_energy(chain, y0),
            duration_s,
            max_drift: opts.max_drift,
            ..ChainLedger::default()
        }
    }

    /// Books the work of the non-conservative torques over the step ending
    /// at `t1` in the state `y1` (joints free in `mode`), and returns
    /// whether it was booked with the ratio of the drift's move over the
    /// step to its [`step_budget`] (the step's size for the ledger:
    /// [`ledger_step_factor`]).
    /// Not booked when that ratio is over 1 and the step is longer than
    /// [`LEDGER_MIN_STEP_S`]: the step is to be taken again, shorter (the
    /// ledger as before). An error naming the joint whose work over the
    /// step was largest when the drift exceeds the run's tolerance
    /// ([`SimOptions::max_drift`]).
    pub fn step<const N: usize>(
        &mut self,
        chain: &HostChain<N>,
        mode: &Mode<N>,
        dense: &Dense<N>,
        t1: f64,
        y1: &State<N>,
    ) -> Result<(bool, f64), SimError> {
        let h = t1 - dense.t0;
        let mut trial = *self;
        let mut work = [0.0; N];
        for (s, w) in GAUSS3 {
            let y = dense.at(dense.t0 + s * h);
            let x = y.chain();
            trial.dissipated_j -= w * h * chain.drag_power(&x);
            for (j, jt) in chain.joints().iter().enumerate() {
                if mode.latched[j] {
                    continue;
                }
                let (phi, rate) = (y.q[j], y.v[j]);
                let total = chain.joint_torque(j, phi, rate, mode.branch[j]);
                let soft = 1.0 - jt.effects.spring_softening;
                let cons = soft * jt.spring.torque(phi, Branch::Unfold)
                    + jt.effects.harness_nm_per_rad * (jt.stowed_rad - phi);
                let p = (total - cons) * rate;
                trial.dissipated_j -= w * h * p;
                work[j] += w * h * p.abs();
            }
        }
        let energy = state_energy(chain, y1);
        let now = energy + trial.dissipated_j + trial.events_j - self.stored_j;
        let budget = step_budget(self.stored_j, h, self.duration_s, self.max_drift);
        let ratio = (now - self.now_j).abs() / budget;
        if ratio > 1.0 && h > LEDGER_MIN_STEP_S {
            return Ok((false, ratio));
        }
        *self = trial;
        let joint = (0..N).fold(0, |b, j| if work[j] > work[b] { j } else { b });
        self.check(energy, t1, joint + 1, || {
            format!(
                "its friction and effects' work over the step from {:.6} s",
                dense.t0
            )
        })?;
        Ok((true, ratio))
    }

    /// [`ChainLedger::step`] over the step from `dense.t0` to `t_end`, in
    /// the state `y_end` there (`cut`: the step was cut at an event), and
    /// the size of the next attempt. A step the ledger refuses is taken
    /// again as short as its drift asks ([`ledger_step_factor`]), except a
    /// step cut at an event: it is taken again once up to the event, so
    /// that its stages stay on this side of it (beyond a latch the spring's
    /// torque `−sign(φ)·T(|φ|)` is the curve's mirror, whose derivatives
    /// jump there).
    /// A step booked caps the next at the ledger's size.
    pub fn book<const N: usize>(
        &mut self,
        chain: &HostChain<N>,
        mode: &Mode<N>,
        dense: &Dense<N>,
        (t_end, y_end): (f64, &State<N>),
        cut: bool,
    ) -> Result<Booking, SimError> {
        let (booked, ratio) = self.step(chain, mode, dense, t_end, y_end)?;
        let ledger_h = (t_end - dense.t0) * ledger_step_factor(ratio);
        if !booked {
            let retake_to_event = cut && !self.to_event;
            self.to_event = retake_to_event;
            let h = match retake_to_event {
                true => t_end - dense.t0,
                false => ledger_h,
            };
            return Ok(Booking::Retake { h });
        }
        self.to_event = false;
        let cap = if ratio <= 1.0 {
            ledger_h
        } else {
            f64::INFINITY
        };
        Ok(Booking::Kept { cap })
    }

    /// Books what an event of joint `joint` (1-based) at `t` took from the
    /// state (`before` its energy there), then checks the drift.
    pub fn event<const N: usize>(
        &mut self,
        chain: &HostChain<N>,
        before: f64,
        y: &State<N>,
        t: f64,
        joint: usize,
    ) -> Result<(), SimError> {
        let energy = state_energy(chain, y);
        let taken = before - energy;
        self.events_j += taken;
        if taken < -self.max_drift * self.stored_j.abs() {
            // An event that gives energy is wrong whatever the ledger says.
            self.worst_drift_j = self.worst_drift_j.max(-taken);
        }
        self.check(energy, t, joint, || {
            format!("its event, which took {taken:.3e} J")
        })
    }

    /// The drift at a state of energy `energy` \[J\] (kinetic plus
    /// potential, [`state_energy`]) at time `t`, and the error when it
    /// exceeds the tolerance.
    fn check(
        &mut self,
        energy: f64,
        t: f64,
        joint: usize,
        cause: impl FnOnce() -> String,
    ) -> Result<(), SimError> {
        let total = energy + self.dissipated_j + self.events_j;
        self.now_j = total - self.stored_j;
        self.worst_drift_j = self.worst_drift_j.max(self.now_j.abs());
        if self.max_drift == f64::INFINITY
            || self.worst_drift_j <= self.max_drift * self.stored_j.abs()
        {
            return Ok(());
        }
        Err(SimError::EnergyDrift {
            joint,
            cause: cause(),
            t_s: t,
            drift_j: self.worst_drift_j,
            stored_j: self.stored_j,
            limit: self.max_drift,
        })
    }
}

/// Kinetic plus potential energy of the chain at `y` \[J\].
pub fn state_energy<const N: usize>(chain: &HostChain<N>, y: &State<N>) -> f64 {
    chain.kinetic_energy(&y.chain()) + chain.potential_energy(&y.q)
}
