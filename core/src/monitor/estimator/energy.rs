//! The slow path's energy margin of the remaining stroke, one joint per
//! learned sample in turn ([`crate::monitor::margin`] on the joint's rate
//! filter, friction estimate and articulated inertia).

use super::joint::{JointState, DEG};
use super::learning::Learning;
use super::state::Monitor;
use crate::monitor::config::MarginConfig;
use crate::monitor::margin::{self, MarginInput, MarginResult, MarginSettings};
use crate::monitor::rollout::mass_matrix;
use crate::physics::chain::{ChainRef, Coefficients};
use crate::physics::linalg::articulated_inertia_n;
use crate::physics::spring::Spring;

/// Smallest articulated inertia the margin divides by [kg·m²] (a guard;
/// real panels are 10⁻² and more).
const MIN_INERTIA_KGM2: f32 = 1e-6;
/// Standard deviations of `T̂_C` beyond which the friction torque's lower
/// bound on `T_C` is a transient of `r`, not evidence (`docs/monitor.md`
/// §3.2).
const LOWER_BOUND_SIGMAS: f32 = 2.0;

impl<const N: usize> Monitor<N> {
    /// The energy margin of the remaining stroke: one joint per learned
    /// sample, in turn, not inside a snap zone or the settling time after
    /// a snap, latch or gap (the rates there are the rate filter's
    /// wide-open transient, and the margin computed on entry stands).
    /// `store`: the chain's [`crate::physics::chain::Chain::coefficients`];
    /// `locked`: the sample's locked joints ([`Learning::locked_padded`]).
    pub(super) fn evaluate_margin(
        &mut self,
        sample: &Learning<N>,
        store: &Coefficients<f32, N>,
        locked: &[bool; N],
    ) {
        let jm = usize::from(self.learner.next_margin) % N.max(1);
        self.learner.next_margin = ((jm + 1) % N.max(1)) as u8;
        margin_of(
            &self.chain.counted_with(store),
            &mut self.joints,
            jm,
            locked,
            sample.quiet,
            &self.tuning.margin,
            self.tuning.observer.snap_zone_deg * DEG,
        );
    }
}

/// The energy margin of joint `jm` of `joints` (stored in its state) when
/// it is free and settled: not `locked`, `quiet` (no snap, latch or gap
/// within the settling time) and out of its snap zone (`zone_rad` \[rad\]
/// from the latch). The rates there are the rate filter's wide-open
/// transient, and the margin computed on entry stands. Not generic over
/// the joint count: one copy in flash for every monitor.
#[inline(never)]
fn margin_of<const R: usize>(
    chain: &ChainRef<'_, f32, R>,
    joints: &mut [JointState],
    jm: usize,
    locked: &[bool; R],
    quiet: bool,
    cfg: &MarginConfig,
    zone_rad: f32,
) {
    let n = chain.joint_count();
    // The model's angles: the rate filters', 0 for a locked joint
    // (latched joints sit at 0).
    let mut phi = [0.0f32; R];
    for (j, (p, js)) in phi.iter_mut().zip(joints.iter()).enumerate() {
        if !locked[j] {
            *p = js.kf.angle();
        }
    }
    let settled = quiet && libm::fabsf(phi.get(jm).copied().unwrap_or(0.0)) >= zone_rad;
    if let (Some(false), true) = (locked.get(jm), settled) {
        // Articulated inertia 1/(M⁻¹)_jj over the free joints: the
        // one-joint energy balance counts all of the joint's kinetic
        // energy, the share the outer panels carry included, so it errs
        // on the side of a latch and its stall verdicts are safe ones.
        let m = mass_matrix(chain, &phi);
        let own = m
            .get(jm)
            .and_then(|row| row.get(jm))
            .copied()
            .unwrap_or(1.0);
        let inertia =
            articulated_inertia_n(n, &m, locked, jm).unwrap_or_else(|| own.max(MIN_INERTIA_KGM2));
        let spring = chain.joints().get(jm).map(|joint| &joint.spring);
        if let (Some(js), Some(spring)) = (joints.get_mut(jm), spring) {
            js.margin = Some(joint_margin(js, spring, cfg, inertia, quiet));
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
