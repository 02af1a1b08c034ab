//! The energy ledger of a physical-latch run (`docs/simulator.md`,
//! "Energy bookkeeping"): the state's energies, the power of the
//! dissipative torques integrated on Gauss–Legendre nodes of each step, and
//! the drift.

use super::{Ledger, Runner, Sim, GAUSS3};
use crate::simulate::latch_run::{step_budget, LEDGER_MIN_STEP_S};
use crate::simulate::ode::{Dense, State};
use crate::simulate::trajectory::SimError;
use deploywatch_core::physics::pawl::PawlState;
use deploywatch_core::Branch;

impl<const N: usize> Sim<'_, N> {
    /// Kinetic, chain and latch potential at a state \[J\].
    pub(super) fn energies(&self, y: &State<N>) -> (f64, f64, f64) {
        let mut spring = self.chain.potential_energy(&y.q);
        let mut latch = 0.0;
        for (j, l) in self.latch.iter().enumerate() {
            let (Some(l), Some(jt)) = (l, self.chain.joints().get(j)) else {
                continue;
            };
            latch += match l.pawl() {
                // A pawl's cam energy jumps at the drop: on its state.
                Some(_) => l.potential_energy_on(self.seg[j].plunger, self.seg[j].pawl, y.q[j]),
                None => l.potential_energy(y.q[j]),
            };
            let u = l.travel(y.q[j]);
            if u < 0.0 {
                // The spring continued into the stop with its torque at 0⁺.
                let soft = 1.0 - jt.effects.spring_softening;
                let t0 = jt
                    .spring
                    .torque(l.side * f64::MIN_POSITIVE, Branch::Unfold)
                    .abs();
                spring += soft * (t0 * u - jt.spring.release(0.0, y.q[j].abs()));
            }
        }
        (self.chain.kinetic_energy(&y.chain()), spring, latch)
    }

    /// Power of the non-conservative joint torques and of the stops' (and
    /// pawls' notches') damping at a state \[W\] (both ≤ 0 for a passive
    /// mechanism).
    fn power(&self, y: &State<N>) -> ([f64; N], [f64; N]) {
        let (mut joints, mut contact) = ([0.0; N], [0.0; N]);
        for (j, jt) in self.chain.joints().iter().enumerate() {
            if self.mode.latched[j] {
                continue;
            }
            let (phi, rate, branch) = (y.q[j], y.v[j], self.mode.branch[j]);
            let soft = 1.0 - jt.effects.spring_softening;
            let ext = self.spring_extension(j, phi, branch);
            let total = self.chain.joint_torque(j, phi, rate, branch) + ext;
            let ext_unfold = self.spring_extension(j, phi, Branch::Unfold);
            let cons = soft * jt.spring.torque(phi, Branch::Unfold)
                + ext_unfold
                + jt.effects.harness_nm_per_rad * (jt.stowed_rad - phi);
            joints[j] = (total - cons) * rate;
            if let Some(l) = &self.latch[j] {
                let (_, f, f_notch) = self.latch_torque(j, phi, rate);
                let elastic = l.stop_force(phi, rate).elastic_n;
                contact[j] = l.stop_torque(f - elastic) * rate;
                if self.seg[j].pawl == PawlState::Engaged {
                    let elastic = l.notch_force(phi, rate).elastic_n;
                    contact[j] += l.notch_torque(f_notch - elastic) * rate;
                }
            }
        }
        (joints, contact)
    }

    /// Adds the dissipation over `[t0, t1]` of a step (the joints' and the
    /// stops' work, and the air drag's, `Chain::drag_power`) to the ledger
    /// and closes it at `y1`; returns the joint (0-based) whose work over
    /// the step was largest.
    pub(super) fn account(
        &self,
        ledger: &mut Ledger,
        dense: &Dense<N>,
        t1: f64,
        y1: &State<N>,
    ) -> usize {
        let h = t1 - dense.t0;
        let mut work = [0.0; N];
        for (s, w) in GAUSS3 {
            let y = dense.at(dense.t0 + s * h);
            let (pj, pc) = self.power(&y);
            let drag = self.chain.drag_power(&y.chain());
            ledger.energy.friction_j -= w * h * (pj.iter().sum::<f64>() + drag);
            ledger.energy.contact_j -= w * h * pc.iter().sum::<f64>();
            for j in 0..N {
                work[j] += w * h * (pj[j] + pc[j]).abs();
            }
        }
        self.close_ledger(ledger, y1);
        (0..N).fold(0, |b, j| if work[j] > work[b] { j } else { b })
    }

    /// The ledger's state terms at `y` and the drift there.
    pub(super) fn close_ledger(&self, ledger: &mut Ledger, y: &State<N>) {
        let (k, s, l) = self.energies(y);
        let e = &mut ledger.energy;
        (e.kinetic_j, e.spring_j, e.latch_j) = (k, s, l);
        let total = k + s + l + e.friction_j + e.contact_j + e.impact_j;
        ledger.now_j = total - ledger.start_j;
        e.worst_drift_j = e.worst_drift_j.max(ledger.now_j.abs());
    }
}

impl Ledger {
    /// The ledger's check after a step or an event at `t`: a
    /// [`SimError::EnergyDrift`] at `joint` (1-based, `cause` says why that
    /// joint) when the drift exceeds the run's tolerance (`max_drift`) of the stored
    /// energy.
    pub(super) fn check(
        &self,
        t: f64,
        joint: usize,
        cause: impl FnOnce() -> String,
    ) -> Result<(), SimError> {
        let e = &self.energy;
        if self.max_drift == f64::INFINITY || e.worst_drift_j <= self.max_drift * e.stored_j.abs() {
            return Ok(());
        }
        Err(SimError::EnergyDrift {
            joint,
            cause: cause(),
            t_s: t,
            drift_j: e.worst_drift_j,
            stored_j: e.stored_j,
            limit: self.max_drift,
        })
    }
}

impl Runner<'_> {
    /// Books the step `[dense.t0, t1]` ending in `y1` on the ledger. False
    /// when the ledger's drift moved by more than its [`step_budget`] of the
    /// stored energy over it and it is longer than [`LEDGER_MIN_STEP_S`]:
    /// the step is to be taken again, shorter (the ledger as before). An
    /// error when the drift exceeds the run's tolerance. With it, the
    /// drift's move over the step / its budget \[1\]. A step booked is
    /// also shown to the joints' stowed-side watch
    /// ([`crate::simulate::stowed::StowedWatch`]).
    pub(super) fn book<const N: usize>(
        &mut self,
        sim: &mut Sim<'_, N>,
        dense: &Dense<N>,
        t1: f64,
        y1: &State<N>,
    ) -> Result<(bool, f64), SimError> {
        let mut trial = self.ledger;
        let joint = sim.account(&mut trial, dense, t1, y1);
        let moved = (trial.now_j - self.ledger.now_j).abs();
        let budget = step_budget(
            trial.energy.stored_j,
            t1 - dense.t0,
            trial.duration_s,
            trial.max_drift,
        );
        let ratio = moved / budget;
        if moved > budget && t1 - dense.t0 > LEDGER_MIN_STEP_S {
            return Ok((false, ratio));
        }
        self.ledger = trial;
        self.ledger.check(t1, joint + 1, || {
            format!(
                "its friction and contact work over the step from {:.6} s",
                dense.t0
            )
        })?;
        sim.watch.step(dense, dense.t0, t1, &sim.mode.latched);
        Ok((true, ratio))
    }
}
