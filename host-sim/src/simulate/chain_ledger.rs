//! The energy ledger of an ideal-latch chain run (`docs/simulator.md`,
//! "Energy ledger self-check"): kinetic energy plus the chain's potential
//! ([`deploywatch_core::Chain::potential_energy`]: springs on their
//! unfolding branch, harness, rig tilt) plus the work of every other torque
//! (friction, the tape springs' hysteresis, joint effects, air drag),
//! plus the energy the events took (the latches' plastic impacts, the stick
//! rule's impulses) is the energy stored at the start, to the drift. A drift
//! beyond the run's tolerance ([`SimOptions::max_drift`],
//! [`MAX_LEDGER_DRIFT`] by default) of the stored energy stops the run with
//! [`SimError::EnergyDrift`]; a step over which the drift moves by more than
//! its [`step_budget`] is taken again shorter.
//!
//! The work is integrated by each step's own Runge–Kutta weights
//! ([`ode::stage_integral`]): the power of those torques ([`power`]) is
//! taken from every evaluation of the equations of motion, from the same
//! joint torques ([`Chain::acceleration_with_torques`]), so the ledger
//! evaluates no torque of its own; a step cut at an event is booked to the
//! event by the step's continuous extension.

use crate::model::torque_table::HostChain;
use crate::simulate::latch_run::{ledger_step_factor, step_budget, LEDGER_MIN_STEP_S};
use crate::simulate::ode::{self, State};
#[cfg(doc)]
use crate::simulate::trajectory::MAX_LEDGER_DRIFT;
use crate::simulate::trajectory::{SimError, SimOptions};
#[cfg(doc)]
use deploywatch_core::Chain;
use deploywatch_core::{Branch, JointTorque, Mode};

/// The power of the non-conservative forces at one state \[W\]: of each
/// joint's torque less its conservative part (the spring on its unfolding
/// branch, scaled by any softening, and the harness), and of the air drag.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Power<const N: usize> {
    /// Per joint \[W\].
    pub joints: [f64; N],
    /// The air drag's \[W\].
    pub drag: f64,
}

impl<const N: usize> Power<N> {
    /// No power.
    pub const ZERO: Self = Power {
        joints: [0.0; N],
        drag: 0.0,
    };

    /// The sum \[W\].
    fn total(&self) -> f64 {
        self.joints.iter().fold(self.drag, |a, p| a + p)
    }
}

/// The power of the non-conservative forces at `y` \[W\], from the joint
/// torques `torques` the equations of motion were evaluated with there
/// ([`Chain::acceleration_with_torques`]) in `mode`; a joint latched (or
/// held) in `mode` does no work.
pub fn power<const N: usize>(
    chain: &HostChain<N>,
    mode: &Mode<N>,
    y: &State<N>,
    torques: &[JointTorque<f64>; N],
) -> Power<N> {
    // `drag_power` is 0 without drag: not called (once per evaluation).
    let drag = if chain.global().air_drag_kg_m2 == 0.0 {
        0.0
    } else {
        chain.drag_power(&y.chain())
    };
    let mut p = Power {
        joints: [0.0; N],
        drag,
    };
    for (j, jt) in chain.joints().iter().enumerate() {
        if mode.latched[j] {
            continue;
        }
        let phi = y.q[j];
        // On the unfolding branch the spring's term of the torque is its
        // conservative part (`(1 − s)·τ` and `τ` for `s = 0` are the
        // same bits); on the folding branch the difference is the
        // hysteresis' work.
        let spring = match mode.branch[j] {
            Branch::Unfold => torques[j].spring,
            Branch::Fold => {
                (1.0 - jt.effects.spring_softening) * jt.spring.torque(phi, Branch::Unfold)
            }
        };
        let cons = spring + jt.effects.harness_nm_per_rad * (jt.stowed_rad - phi);
        p.joints[j] = (torques[j].total - cons) * y.v[j];
    }
    p
}

/// The powers at a step's evaluations: `[0]` at its start (with `k1`),
/// then at each of its stages in order, `[6]` at its end (FSAL).
pub type StagePowers<const N: usize> = [Power<N>; 7];

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

    /// Books the work of the non-conservative torques over the step of
    /// `h` \[s\] from `t0` whose evaluations had the powers `powers`, up to
    /// `t1` (its end, or an event inside it) in the state `y1` (joints
    /// free in `mode`), and returns whether it was booked with the ratio
    /// of the drift's move over the step to its [`step_budget`] (the
    /// step's size for the ledger: [`ledger_step_factor`]).
    /// Not booked when that ratio is over 1 and the step is longer than
    /// [`LEDGER_MIN_STEP_S`]: the step is to be taken again, shorter (the
    /// ledger as before). An error naming the joint whose work over the
    /// step was largest when the drift exceeds the run's tolerance
    /// ([`SimOptions::max_drift`]).
    pub fn step<const N: usize>(
        &mut self,
        chain: &HostChain<N>,
        (t0, h, powers): (f64, f64, &StagePowers<N>),
        t1: f64,
        y1: &State<N>,
    ) -> Result<(bool, f64), SimError> {
        let s = (t1 - t0) / h;
        let work = |p: &dyn Fn(&Power<N>) -> f64| ode::stage_integral(h, &powers.map(|x| p(&x)), s);
        let mut trial = *self;
        trial.dissipated_j -= work(&Power::total);
        let energy = state_energy(chain, y1);
        let now = energy + trial.dissipated_j + trial.events_j - self.stored_j;
        let budget = step_budget(self.stored_j, t1 - t0, self.duration_s, self.max_drift);
        let ratio = (now - self.now_j).abs() / budget;
        if ratio > 1.0 && t1 - t0 > LEDGER_MIN_STEP_S {
            return Ok((false, ratio));
        }
        *self = trial;
        let joint = || {
            let w: [f64; N] = core::array::from_fn(|j| work(&|p| p.joints[j]).abs());
            (0..N).fold(0, |b, j| if w[j] > w[b] { j } else { b }) + 1
        };
        self.check(energy, t1, joint, || {
            format!("its friction and effects' work over the step from {t0:.6} s")
        })?;
        Ok((true, ratio))
    }

    /// [`ChainLedger::step`] over the step from `t0` (`h` long, its evaluations
    /// of power `powers`) to `t_end`, in
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
        (t0, h, powers): (f64, f64, &StagePowers<N>),
        (t_end, y_end): (f64, &State<N>),
        cut: bool,
    ) -> Result<Booking, SimError> {
        let (booked, ratio) = self.step(chain, (t0, h, powers), t_end, y_end)?;
        let ledger_h = (t_end - t0) * ledger_step_factor(ratio);
        if !booked {
            let retake_to_event = cut && !self.to_event;
            self.to_event = retake_to_event;
            let h = match retake_to_event {
                true => t_end - t0,
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
        self.check(
            energy,
            t,
            || joint,
            || format!("its event, which took {taken:.3e} J"),
        )
    }

    /// The drift at a state of energy `energy` \[J\] (kinetic plus
    /// potential, [`state_energy`]) at time `t`, and the error when it
    /// exceeds the tolerance.
    fn check(
        &mut self,
        energy: f64,
        t: f64,
        joint: impl FnOnce() -> usize,
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
            joint: joint(),
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::mechanism::Mechanism;
    use crate::simulate::deployment::simulate;

    fn t01() -> Mechanism {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../data/mechanisms/seed001_T01.toml");
        Mechanism::load(&path).expect("seed 001 T01")
    }

    /// Seed 001 T01 (tape springs with their hysteresis, friction at every
    /// joint, three latch impacts) closes its ledger to the reference's
    /// 1e-6 and to the verdict's 1e-4 (a drift beyond either stops the run).
    #[test]
    fn a_tape_spring_wing_closes_its_ledger() {
        let mech = t01();
        for max_drift in [crate::simulate::trajectory::MAX_LEDGER_DRIFT, 1e-4] {
            let opts = SimOptions {
                max_drift,
                ..SimOptions::default()
            };
            let run = simulate(&mech, &[], &opts).expect("closes");
            assert!(run.deployed(), "{max_drift}");
        }
    }

    /// The booking itself: a step over which the state's energy does not
    /// move but the torques dissipated 2 W at one joint for 10 ms (0.02 J
    /// unaccounted for) is refused, to be taken again shorter; the same
    /// 0.02 J over a step too short to retake is booked, and stops the run
    /// with a drift of 0.02 J at that joint.
    #[test]
    fn work_booked_without_the_energy_it_took_is_a_drift_at_its_joint() {
        let mech = t01();
        let chain = mech
            .chain::<3>(&[Default::default(); 3], Default::default())
            .expect("three joints");
        let y = State {
            q: core::array::from_fn(|j| chain.joints()[j].stowed_rad),
            v: [0.0; 3],
        };
        let mut ledger = ChainLedger::start(&chain, &y, 1.0, &SimOptions::default());
        let start = ledger;
        let powers = |watts: f64| {
            let mut at = Power::ZERO;
            at.joints[1] = -watts;
            [at; 7]
        };
        let (booked, ratio) = ledger
            .step(&chain, (0.0, 0.01, &powers(2.0)), 0.01, &y)
            .expect("refused, not an error");
        assert!(!booked && ratio > 1.0, "{booked} {ratio}");
        assert_eq!(ledger, start);
        let h = LEDGER_MIN_STEP_S / 2.0;
        let err = ledger
            .step(&chain, (0.0, h, &powers(0.02 / h)), h, &y)
            .map(|_| ())
            .expect_err("0.02 J unaccounted for");
        match err {
            SimError::EnergyDrift { joint, drift_j, .. } => {
                assert_eq!(joint, 2);
                assert!((drift_j - 0.02).abs() < 1e-12, "{drift_j}");
            }
            other => panic!("expected an energy drift, got {other:?}"),
        }
    }
}
