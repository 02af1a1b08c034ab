//! The torque margins of every joint of a mechanism with its resistances
//! (`docs/margin.md`, `physics.md` 9): the spring's driving torque and
//! energy against the friction, the energy a viscous damping dissipates on
//! the simulated deployment, a physical latch's engagement, and every
//! other effect found, each counted by [`effect_margin::counted`].

use crate::analysis::design_margin::{
    joint_margin, Factors, JointMargin, LatchResistance, Resistance, Standard, LATCH_KIND,
};
use crate::analysis::effect_margin::{self, Counted, EffectWork};
use crate::analysis::resistances::Resistances;
use crate::analysis::stroke_margin::{self, Allowance, Profile, StrokeMargin, Term};
use crate::model::effect::Effect;
use crate::model::mechanism::Mechanism;
use crate::simulate::deployment::SimError;
use deploywatch_core::CurveError;
use deploywatch_core::{Branch, Spring};

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
    /// The static torque margin at every position of the stroke.
    pub stroke: StrokeMargin,
    /// The resistances of `stroke`, unfactored.
    pub terms: Vec<Term>,
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
fn simulated(mech: &Mechanism, r: &Resistances) -> Result<Simulated, SimError> {
    let n = mech.joint_count();
    let zero_others = vec![vec![0.0; n]; r.others.len()];
    let needed = r.viscous_nms.iter().any(|f| *f != 0.0)
        || r.others
            .iter()
            .any(|e| effect_margin::needs_simulation(e.kind()));
    if !needed {
        let work = EffectWork {
            work_j: zero_others.clone(),
            stowed_torque_nm: zero_others,
        };
        return Ok(Simulated {
            viscous_j: vec![0.0; n],
            peak_rate_rad_s: vec![0.0; n],
            work,
        });
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
    let peak_rate_rad_s = traj
        .rate_deg_s
        .iter()
        .map(|rate| {
            rate.iter()
                .fold(0.0, |m: f64, w| m.max(w.abs()))
                .to_radians()
        })
        .collect();
    Ok(Simulated {
        viscous_j: viscous,
        peak_rate_rad_s,
        work: effect_margin::resisting_work(mech, &r.others, &traj),
    })
}

/// What the simulated deployment gives the margins (all zero when no
/// simulation is needed).
struct Simulated {
    /// Per joint, the energy its viscous damping dissipates \[J\].
    viscous_j: Vec<f64>,
    /// Per joint, the largest `|φ̇|` the deployment reaches \[rad/s\].
    peak_rate_rad_s: Vec<f64>,
    /// Per effect and joint, its resisting work and stowed torque.
    work: EffectWork,
}

/// The margins of every joint with the resistances `r` and `factors`, the
/// driving springs reduced by `allowance`, along the stroke as well
/// ([`stroke_margin`]).
pub fn margins(
    mech: &Mechanism,
    r: &Resistances,
    standard: Standard,
    factors: &Factors,
    allowance: &Allowance,
) -> Result<Vec<Row>, MarginsError> {
    let sim = simulated(mech, r)?;
    let mut rows = Vec::with_capacity(mech.joint_count());
    for (j, joint) in mech.joints.iter().enumerate() {
        let spring = joint.spring.to_spring();
        let spring = spring.map_err(|source| MarginsError::Spring {
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
        m.resisting_energy_j += sim.viscous_j[j];
        let latch = latch_resistance(mech, j);
        let mut m = m.with_latch(latch);
        let mut terms = base_terms(r, j, sim.peak_rate_rad_s[j], &latch);
        m.scale_driving(allowance.scale(j));
        let mut scale = allowance.scale(j);
        let mut counted = Vec::new();
        for (i, e) in r.others.iter().enumerate() {
            let w = (sim.work.work_j[i][j], sim.work.stowed_torque_nm[i][j]);
            let Some(c) = effect_margin::counted(mech, j, e, w.0, w.1) else {
                continue;
            };
            match c {
                Counted::Resistance {
                    kind,
                    torque_nm,
                    energy_j,
                } => {
                    m.add_resistance(kind, torque_nm, energy_j, factors);
                    terms.push(effect_margin::stroke_term(
                        e,
                        kind,
                        torque_nm,
                        sim.peak_rate_rad_s[j],
                    ));
                }
                Counted::Driving { scale: s } => {
                    m.scale_driving(s);
                    scale *= s;
                }
                Counted::Sensor => {}
            }
            counted.push((*e, c));
        }
        let stroke = stroke_margin::along_stroke(
            |theta| spring.magnitude(theta, Branch::Unfold),
            &unfold_knots_rad(&spring),
            static_from_rad(&spring),
            m.stroke_rad,
            scale,
            &terms,
            factors,
            m.required_pct,
        );
        rows.push(Row {
            joint: j + 1,
            stowed_deg: joint.stowed_deg,
            viscous_nms: r.viscous_nms[j],
            viscous_energy_j: sim.viscous_j[j],
            margin: m,
            counted,
            stroke,
            terms,
        });
    }
    Ok(rows)
}

/// The angles \[rad\] of a tabulated spring's unfolding points (none for a
/// linear spring).
fn unfold_knots_rad(spring: &Spring<f64>) -> Vec<f64> {
    match spring {
        Spring::Curve { unfold, .. } => (0..unfold.len())
            .filter_map(|i| unfold.knot(i))
            .map(|(deg, _)| deg.to_radians())
            .collect(),
        _ => Vec::new(),
    }
}

/// Where the static margin starts \[rad\] from the latch: 0, or for a
/// spring whose unfolding torque is zero at the latch (a tape spring
/// through `(0, 0)`) its first point past the latch, below which the
/// torque falls to zero and the latching margin applies.
fn static_from_rad(spring: &Spring<f64>) -> f64 {
    if spring.magnitude(0.0, Branch::Unfold) > 0.0 {
        return 0.0;
    }
    unfold_knots_rad(spring)
        .into_iter()
        .find(|t| *t > 0.0)
        .unwrap_or(0.0)
}

/// The resistances of joint `j` (0-based) along the stroke besides the
/// effects found: its Coulomb friction, its viscous damping at the
/// deployment's peak rate `peak_rate_rad_s`, and a physical latch's entry
/// ramp over its width.
fn base_terms(
    r: &Resistances,
    j: usize,
    peak_rate_rad_s: f64,
    latch: &LatchResistance,
) -> Vec<Term> {
    let mut terms = vec![Term::constant(
        "coulomb_friction",
        Resistance::Friction,
        r.coulomb_nm[j],
    )];
    if r.viscous_nms[j] != 0.0 {
        terms.push(Term::constant(
            format!("viscous_damping at the run's peak rate {peak_rate_rad_s:.3} rad/s"),
            Resistance::Friction,
            r.viscous_nms[j] * peak_rate_rad_s,
        ));
    }
    if latch.entry_torque_nm != 0.0 {
        terms.push(Term {
            name: "latch entry ramp".into(),
            kind: LATCH_KIND,
            torque_nm: latch.entry_torque_nm,
            profile: Profile::Band {
                from_rad: latch.entry_from_rad,
                to_rad: latch.entry_to_rad,
            },
        });
    }
    terms
}

/// The engagement of joint `j`'s physical latch (0-based) as a resistance,
/// from the core's law in `f64` (`physics.md` §10.3); zero for the ideal
/// latch.
pub fn latch_resistance(mech: &Mechanism, j: usize) -> LatchResistance {
    let (Some(spec), Some(joint)) = (mech.latch(j), mech.joints.get(j)) else {
        return LatchResistance::default();
    };
    let l = spec.to_core::<f64>(joint.stowed_deg, 1.0, 1.0);
    let crest = l.plunger.crest_rad;
    LatchResistance {
        entry_from_rad: crest,
        entry_to_rad: crest + l.entry_width_rad(),
        entry_torque_nm: l.entry_torque(),
        engagement_energy_j: l.engagement_energy(),
    }
}
