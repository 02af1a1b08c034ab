//! The end of a rollout by quadrature: once every free joint creeps
//! quasi-statically, each joint's outcome is its
//! `creep`(crate::monitor::creep::creep) time against the
//! time left (`docs/monitor.md` §6), computed a slice at a time.

use super::{mass_matrix, Model, RolloutConfig, Settle, Stepper};
use crate::monitor::creep::{Creep, CreepJoint, CreepRun};
use crate::physics::linalg::articulated_inertias_n;

impl<const R: usize> Stepper<R> {
    /// Starts the creep quadrature, which runs in the next units of work;
    /// undecided (a joint breaks free in time), the integration goes on
    /// and looks again after another hold, not at every step (the
    /// quadrature and the snap-through cost up to a few hundred spring
    /// evaluations).
    pub(super) fn begin_settle(&mut self, chain: &Model<'_, R>, cfg: &RolloutConfig) {
        let m = mass_matrix(chain, &self.x.phi);
        let inertia = articulated_inertias_n(self.count(), &m, &self.latched);
        self.settle = Some(Settle {
            time_left: cfg.horizon_s - self.t_s,
            inertia: core::array::from_fn(|j| inertia[j].unwrap_or(m[j][j])),
            after: [f32::INFINITY; R],
            joint: 0,
            run: None,
        });
        self.creeping_s = 0.0;
    }

    /// Ends the rollout by quadrature once every free joint creeps
    /// quasi-statically and none can break free: each joint's outcome is
    /// then its `creep`(crate::monitor::creep::creep) time against the time left. Runs at most `evals`
    /// spring evaluations and resumes at the next call; when some joint may
    /// still break free, drops the quadrature (the integration goes on).
    pub(super) fn settle_creep(&mut self, chain: &Model<'_, R>, cfg: &RolloutConfig, evals: u16) {
        let Some(mut settle) = self.settle.take() else {
            return;
        };
        let n = self.count();
        let mut budget = evals;
        while usize::from(settle.joint) < n {
            let j = usize::from(settle.joint);
            if self.latched[j] {
                settle.joint += 1;
                continue;
            }
            let (Some(joint), Some(&inertia)) = (chain.joints().get(j), settle.inertia.get(j))
            else {
                return;
            };
            let mut run = settle.run.unwrap_or_else(|| {
                CreepRun::new(
                    CreepJoint {
                        from_rad: libm::fabsf(self.x.phi[j]),
                        capture_rad: self.start.capture_rad[j],
                        spring_scale: self.start.spring_scale[j],
                        coulomb_nm: self.start.coulomb_nm[j],
                        viscous_nms: self.start.viscous_nms[j],
                        inertia_kgm2: inertia,
                    },
                    cfg.coulomb_threshold_rad_s,
                    settle.time_left,
                )
            });
            let Some(creep) = run.run(&joint.spring, &mut budget) else {
                // Out of work for this slice: resume here.
                settle.run = Some(run);
                self.settle = Some(settle);
                return;
            };
            let time_left = settle.time_left;
            match creep {
                Creep::Covers(t) if t <= time_left => settle.after[j] = t,
                Creep::Covers(_) | Creep::Stops => {}
                Creep::BreaksFree(t) if t <= time_left => return,
                Creep::BreaksFree(_) => {}
            }
            settle.run = None;
            settle.joint += 1;
        }
        for j in 0..n {
            if !self.latched[j] && settle.after[j].is_finite() {
                self.latched[j] = true;
                self.latch_after_s[j] = self.t_s + settle.after[j];
            }
        }
        self.finish();
    }
}
