//! The torque margins of every joint of a mechanism with its resistances
//! (`docs/margin.md`, `physics.md` 9): the spring's driving torque and
//! energy against the friction, the energy a viscous damping dissipates on
//! the simulated deployment, a physical latch's engagement, and every
//! other effect found, each counted by [`effect_margin::counted`].

use crate::analysis::design_margin::{
    joint_margin, Factors, JointMargin, LatchResistance, Standard,
};
use crate::analysis::effect_margin::{self, Counted, EffectWork};
use crate::analysis::resistances::Resistances;
use crate::model::effect::Effect;
use crate::model::mechanism::Mechanism;
use crate::simulate::deployment::SimError;
use deploywatch_core::spring::CurveError;

/// One joint's margins with what counts in them.
#[derive(Clone, Debug)]
pub struct Row {
    /// 1-based joint.
    pub joint: usize,
    /// Stowed angle \[deg\].
    pub stowed_deg: f64,
    /// Viscous damping [N·m·s/rad].
    pub viscous_nms: f64,
    /// The energy the viscous damping dissipates on the deployment \[J\],
    /// included in `margin.resisting_energy_j`.
    pub viscous_energy_j: f64,
    /// The margins.
    pub margin: JointMargin,
    /// Each other effect found on this joint (or global) and how it is
    /// counted.
    pub counted: Vec<(Effect, Counted)>,
}

/// Why the margins cannot be computed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MarginsError {
    /// The deployment with what was found does not simulate.
    #[error("the deployment with what was found: {0}")]
    Deployment(#[from] SimError),
    /// A joint's spring is not a spring.
    #[error("joint {joint}: bad spring: {source}")]
    Spring {
        /// 1-based joint.
        joint: usize,
        /// Why.
        source: CurveError,
    },
}

/// What the simulated deployment gives the margins: each joint's viscous
/// energy `∫ f · φ̇² dt` \[J\] (rectangle rule on the sample grid, zero where
/// `f = 0`), and per effect of `r.others` its resisting work and its
/// generalised torque at the stowed state
/// ([`effect_margin::resisting_work`]). No simulation when nothing needs it.
fn simulated(mech: &Mechanism, r: &Resistances) -> Result<(Vec<f64>, EffectWork), SimError> {
    let n = mech.joint_count();
    let zero_others = vec![vec![0.0; n]; r.others.len()];
    let needed = r.viscous_nms.iter().any(|f| *f != 0.0)
        || r.others
            .iter()
            .any(|e| effect_margin::needs_simulation(e.kind));
    if !needed {
        let work = EffectWork {
            work_j: zero_others.clone(),
            stowed_torque_nm: zero_others,
        };
        return Ok((vec![0.0; n], work));
    }
    let traj = effect_margin::deployment(mech, &r.found_effects(mech))?;
    let dt = traj.t_s.windows(2).map(|w| w[1] - w[0]);
    let viscous = (0..n)
        .map(|j| {
            let rate = &traj.rate_deg_s[j];
            dt.clone()
                .zip(rate)
                .map(|(dt, w)| r.viscous_nms[j] * w.to_radians().powi(2) * dt)
                .sum()
        })
        .collect();
    Ok((
        viscous,
        effect_margin::resisting_work(mech, &r.others, &traj),
    ))
}

/// The margins of every joint with the resistances `r` and `factors`.
pub fn margins(
    mech: &Mechanism,
    r: &Resistances,
    standard: Standard,
    factors: &Factors,
) -> Result<Vec<Row>, MarginsError> {
    let (viscous, w) = simulated(mech, r)?;
    let mut rows = Vec::with_capacity(mech.joint_count());
    for (j, joint) in mech.joints.iter().enumerate() {
        let spring = joint
            .spring
            .to_spring()
            .map_err(|source| MarginsError::Spring {
                joint: j + 1,
                source,
            })?;
        let mut m = joint_margin(
            &spring,
            joint.stowed_deg.to_radians(),
            r.coulomb_nm[j],
            standard,
            Some(factors),
        );
        m.resisting_energy_j += viscous[j];
        let mut m = m.with_latch(latch_resistance(mech, j));
        let mut counted = Vec::new();
        for (i, e) in r.others.iter().enumerate() {
            let Some(c) =
                effect_margin::counted(mech, j, e, w.work_j[i][j], w.stowed_torque_nm[i][j])
            else {
                continue;
            };
            match c {
                Counted::Resistance {
                    kind,
                    torque_nm,
                    energy_j,
                } => m.add_resistance(kind, torque_nm, energy_j, factors),
                Counted::Driving { scale } => m.scale_driving(scale),
                Counted::Sensor => {}
            }
            counted.push((*e, c));
        }
        rows.push(Row {
            joint: j + 1,
            stowed_deg: joint.stowed_deg,
            viscous_nms: r.viscous_nms[j],
            viscous_energy_j: viscous[j],
            margin: m,
            counted,
        });
    }
    Ok(rows)
}

/// The engagement of joint `j`'s physical latch (0-based) as a resistance,
/// from the core's law in `f64` (`physics.md` §10.3); zero for the ideal
/// latch.
pub fn latch_resistance(mech: &Mechanism, j: usize) -> LatchResistance {
    let (Some(spec), Some(joint)) = (mech.latch(j), mech.joints.get(j)) else {
        return LatchResistance::default();
    };
    let l = spec.to_core::<f64>(joint.stowed_deg, 1.0, 1.0);
    LatchResistance {
        entry_torque_nm: l.entry_torque(),
        engagement_energy_j: l.engagement_energy(),
    }
}
