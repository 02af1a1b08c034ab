//! The slow path's energy margin of the remaining stroke, one joint per
//! learned sample in turn ([`crate::monitor::margin`] on the joint's rate
//! filter, friction estimate and articulated inertia).

use super::joint::{JointState, DEG};
use super::learning::Learning;
use super::state::Monitor;
use crate::monitor::config::MarginConfig;
use crate::monitor::margin::{self, MarginInput, MarginResult, MarginSettings};
use crate::physics::linalg::articulated_inertia;
use crate::physics::spring::Spring;

/// Smallest articulated inertia the margin divides by [kg·m²] (a guard;
/// real panels are 10⁻² and more).
const MIN_INERTIA_KGM2: f32 = 1e-6;
/// Standard deviations of `T̂_C` beyond which the friction torque's lower
/// bound on `T_C` is a transient of `r`, not evidence (`docs/monitor.md`
/// §3.2).
const LOWER_BOUND_SIGMAS: f32 = 2.0;
/// The margin of a joint the monitor knows nothing about (a guard for an
/// index out of range, which the callers never pass).
const UNKNOWN_MARGIN: MarginResult = MarginResult {
    margin_pct: 0.0,
    latch_probability: 0.5,
    time_to_latch_s: None,
    stops_on_ramp: false,
};

impl<const N: usize> Monitor<N> {
    /// The energy margin of the remaining stroke: one joint per learned
    /// sample, in turn, not inside a snap zone or the settling time after
    /// a snap, latch or gap (the rates there are the rate filter's
    /// wide-open transient, and the margin computed on entry stands).
    pub(super) fn evaluate_margin(&mut self, sample: &Learning<N>) {
        let zone = self.tuning.observer.snap_zone_deg * DEG;
        let jm = usize::from(self.learner.next_margin) % N.max(1);
        self.learner.next_margin = ((jm + 1) % N.max(1)) as u8;
        let locked = sample.locked();
        let (phi, _) = self.model_state(&locked);
        let settled = sample.quiet && libm::fabsf(phi.get(jm).copied().unwrap_or(0.0)) >= zone;
        if let (Some(false), true) = (locked.get(jm), settled) {
            // Articulated inertia 1/(M⁻¹)_jj over the free joints: the
            // one-joint energy balance counts all of the joint's kinetic
            // energy, the share the outer panels carry included, so it errs
            // on the side of a latch and its stall verdicts are safe ones.
            let m = self.chain.mass_matrix(&phi);
            let own = m
                .get(jm)
                .and_then(|row| row.get(jm))
                .copied()
                .unwrap_or(1.0);
            let inertia =
                articulated_inertia(&m, &locked, jm).unwrap_or_else(|| own.max(MIN_INERTIA_KGM2));
            let result = self.joint_margin(jm, inertia, sample.quiet);
            if let Some(js) = self.joints.get_mut(jm) {
                js.margin = Some(result);
            }
        }
    }

    /// The model's angles [rad] and rates [rad/s]: the rate filters', 0 for
    /// a `locked` joint (latched joints sit at 0).
    pub(super) fn model_state(&self, locked: &[bool; N]) -> ([f32; N], [f32; N]) {
        let pick = |j: usize, v: f32| if locked[j] { 0.0 } else { v };
        (
            core::array::from_fn(|j| pick(j, self.joints[j].kf.angle())),
            core::array::from_fn(|j| pick(j, self.joints[j].kf.rate())),
        )
    }

    /// Energy margin and one-joint latch probability of joint `j`, with
    /// `inertia` its articulated inertia `1/(M⁻¹)_jj` [kg·m²]; `quiet` when
    /// the observer runs undisturbed (its friction torque then bounds `T_C`
    /// from below).
    fn joint_margin(&self, j: usize, inertia: f32, quiet: bool) -> MarginResult {
        match (self.joints.get(j), self.chain.joints().get(j)) {
            (Some(js), Some(joint)) => {
                joint_margin(js, &joint.spring, &self.tuning.margin, inertia, quiet)
            }
            _ => UNKNOWN_MARGIN,
        }
    }
}

/// Energy margin and one-joint latch probability of the joint `js` with
/// spring `spring`, `inertia` its articulated inertia `1/(M⁻¹)_jj`
/// [kg·m²]; `quiet` when the observer runs undisturbed (its friction
/// torque then bounds `T_C` from below). Not generic over the joint
/// count: one copy in flash for every monitor.
#[inline(never)]
fn joint_margin(
    js: &JointState,
    spring: &Spring<f32>,
    cfg: &MarginConfig,
    inertia: f32,
    quiet: bool,
) -> MarginResult {
    let (f, o) = (&js.kf, &js.fo);
    // f only as far as the data resolve it (§3.2).
    let est = js.friction().0;
    let phi = f.angle();
    let rate = f.rate();
    // The friction torque seen now bounds T_C from below, when the
    // observer runs undisturbed and the bound agrees with the estimate
    // (a bound beyond T̂_C + 2σ is a transient of r, not evidence).
    let bound = if quiet {
        o.coulomb_lower_bound(rate, est.viscous_nms)
    } else {
        0.0
    };
    let bound = if bound
        <= est.coulomb_nm
            + LOWER_BOUND_SIGMAS * crate::physics::real::sqrtf(est.coulomb_var.max(0.0))
    {
        bound
    } else {
        0.0
    };
    margin::evaluate(
        spring,
        &MarginInput {
            angle_abs_rad: libm::fabsf(phi),
            rate_abs_rad_s: libm::fabsf(rate),
            towards_latch: phi * rate < 0.0,
            inertia_kgm2: inertia,
            rate_var: f.rate_var(),
            capture_rad: js.capture_rad,
            coulomb_nm: est.coulomb_nm,
            viscous_nms: est.viscous_nms,
            coulomb_var: est.coulomb_var,
            coulomb_lower_nm: bound,
            spring_scale: 1.0 + est.spring_scale_err,
            spring_sd_rel: crate::physics::real::sqrtf(est.spring_scale_var.max(0.0)),
            viscous_var: est.viscous_var,
            cov: est.cov,
            latch: js.engagement,
        },
        &MarginSettings {
            factors: cfg.factors,
            energy_sd_floor_j: cfg.energy_sd_floor_j,
        },
    )
}
