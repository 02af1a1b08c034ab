//! The slow path, [`Monitor::learn_or_predict`], in slices of bounded cost: a slice
//! learns from one queued sample (the friction observers on the centred
//! fit, the energy margin of one joint, the start of the next rollout, the
//! status's learned half) or, with the queue empty, advances the latch /
//! stall prediction by one unit of rollout work.

use super::joint::JointState;
use super::learning::{Fitted, Learning};
use super::state::Monitor;
use crate::monitor::faults::Fault;
use crate::monitor::observer::{momentum_terms_n, FrictionObserver, ObserverInput, ObserverTuning};
use crate::monitor::status::{JointStatus, Sample, Status};
use crate::physics::chain::{ChainRef, Coefficients};
use crate::physics::spring::{Branch, Spring};

impl<const N: usize> Monitor<N> {
    /// One slice of the slow path. With samples queued by
    /// [`Monitor::update`], it learns from the oldest one: the friction
    /// observers, the energy margin of one joint, the start of the next
    /// rollout, and the learned part of [`Monitor::status`] (friction,
    /// margin, prediction). With the queue empty it advances the rollout
    /// in progress by up to `margin.rollout.steps_per_slice` units of work
    /// (a step of the chain, or a bounded piece of the creep quadrature:
    /// [`crate::monitor::rollout::Stepper::advance`]), starts the next one when it
    /// ends, and refreshes the prediction in the status.
    ///
    /// The sample-rate path ([`Monitor::update`]) neither learns nor runs a
    /// rollout: the application calls this at a lower priority (the idle
    /// loop, a low-priority task), as often as it has time for, and at
    /// least once per sample on average, or the queue overflows
    /// ([`Monitor::learning_overruns`]). Its cost is bounded by the slice
    /// (`docs/performance.md`). Returns true when a rollout finished in
    /// this slice.
    #[inline(never)]
    pub fn learn_or_predict(&mut self) -> bool {
        if !self.timeline.started {
            return false;
        }
        if let Some(sample) = self.queue.pop_front() {
            self.learn(&sample);
            return false;
        }
        if self.tuning.margin.rollout.steps_per_slice == 0 {
            return false;
        }
        let finished = self.advance_rollouts();
        if finished {
            self.refresh_estimates(self.status.t_s);
        }
        finished
    }

    /// [`Monitor::update`], then `margin.rollout.slices_per_sample` slices
    /// of [`Monitor::learn_or_predict`]: the schedule of a replay, fixed so that the
    /// host and the MCU compute the same statuses. Returns the status after
    /// the slices.
    pub fn replay_step(&mut self, sample: &Sample<N>) -> Status<N> {
        self.update(sample);
        for _ in 0..self.tuning.margin.rollout.slices_per_sample {
            self.learn_or_predict();
        }
        self.status
    }

    /// The slow path's learning from one queued sample: the friction
    /// observers on the centred fit, the energy margin of one joint, the
    /// start of the next rollout, and the status's learned part.
    fn learn(&mut self, sample: &Learning<N>) {
        for (j, joint) in sample.joints.iter().enumerate() {
            if joint.newly {
                info!("joint {} latched at t = {} s", j + 1, sample.t);
            }
        }
        // The chain's coefficients for the learning's code written once
        // for every joint count, copied once per learned sample.
        let store = self.chain.coefficients();
        let fitted = self.learn_friction(sample, &store);
        let locked = sample.locked_padded();
        self.evaluate_margin(sample, &store, &locked);
        self.hand_over_to_prediction(sample, &locked, fitted.as_ref());
        self.refresh_estimates(sample.t);
    }

    /// Friction learning, half a window back, on the centred fit of the
    /// readings (no lag, little noise): only samples outside the snap
    /// zones and the settling after a snap, latch or gap, with every free
    /// joint measured (`smoother.rs`). The observers restart whenever the
    /// run of fits breaks; an observer that fails restarts at its prior
    /// (`estimator_reset` in the status). `store`: the chain's
    /// [`crate::physics::chain::Chain::coefficients`]. Returns the fit, if
    /// any.
    fn learn_friction(
        &mut self,
        sample: &Learning<N>,
        store: &Coefficients<f32, N>,
    ) -> Option<Fitted<N>> {
        let learner = &mut self.learner;
        learner
            .fit
            .push(sample.t, &sample.used(), sample.clean, &sample.locked());
        let Some(fitted) = learner.fit.centre_with(self.tuning.meas_var, Fitted::of) else {
            learner.fit_run = false;
            return None;
        };
        learn_joints(
            &self.chain.counted_with(store),
            &fitted,
            !learner.fit_run,
            &mut self.joints,
            &mut self.status.joints,
            &self.tuning.observer.tuning,
        );
        learner.fit_run = true;
        Some(fitted)
    }
}

/// The friction observers of `joints` stepped on the centred fit `c`
/// (`restart`: the run of fits broke), with the momentum terms of `chain`
/// at the fit; a joint whose observer fails has `EstimatorReset` set in
/// its status line of `out`. Not generic over the joint count: one copy in
/// flash for every monitor.
#[inline(never)]
fn learn_joints<const R: usize>(
    chain: &ChainRef<'_, f32, R>,
    c: &Fitted<R>,
    restart: bool,
    joints: &mut [JointState],
    out: &mut [JointStatus],
    tuning: &ObserverTuning,
) {
    let n = chain.joint_count();
    let terms = momentum_terms_n(chain, &c.phi, &c.rate);
    for j in 0..n {
        if c.locked[j] {
            continue;
        }
        let mut p = 0.0f32;
        for k in 0..n {
            p += terms.mass[j][k] * c.rate[k];
        }
        let (Some(js), Some(joint)) = (joints.get_mut(j), chain.joints().get(j)) else {
            continue;
        };
        let healthy = learn_joint(
            &mut js.fo,
            restart,
            &joint.spring,
            c.phi[j],
            ObserverInput {
                momentum: p,
                spring_torque_nm: 0.0,
                beta_nm: terms.beta[j],
                rate_rad_s: c.rate[j],
                rate_var: c.rate_var[j],
                dt_s: c.dt_s,
                learn: true,
            },
            tuning,
        );
        if !healthy {
            if let Some(out) = out.get_mut(j) {
                out.faults.insert(Fault::EstimatorReset);
            }
        }
    }
}

/// One joint's friction observer on the centred fit: restarted first when
/// `restart` (the run of fits broke), then stepped on `input` with the
/// spring torque of `spring` at `phi` \[rad\] (on the branch of the fit's
/// rate) filled in; an observer that fails restarts at its prior. Returns
/// whether it was healthy. Not generic over the joint count: one copy in
/// flash for every monitor.
#[inline(never)]
fn learn_joint(
    fo: &mut FrictionObserver,
    restart: bool,
    spring: &Spring<f32>,
    phi: f32,
    input: ObserverInput,
    tuning: &ObserverTuning,
) -> bool {
    if restart {
        fo.restart();
    }
    let branch = Branch::select(phi, input.rate_rad_s);
    fo.step(
        &ObserverInput {
            spring_torque_nm: spring.torque(phi, branch),
            ..input
        },
        tuning,
    );
    // An observer changes only when it steps.
    let healthy = fo.is_healthy();
    if !healthy {
        fo.reset_parameters();
    }
    healthy
}
