//! The dynamic torque margin of every joint (`docs/margin.md`, "The dynamic
//! margin"): the driving torque against the factored resistances and the
//! torque `T_a = I α` that accelerates the joint's inertia as the
//! requirement asks.
//!
//! The requirement is a deploy time `T` \[s\] (`margin --deploy-time`): the
//! stroke `S` \[rad\] completed from rest at constant acceleration,
//! `α = 2 S / T²` \[rad/s²\]. The inertia `I` \[kg·m²\] is the largest
//! diagonal term `M_jj` of the core chain's mass matrix
//! ([`deploywatch_core::Chain::mass_matrix`], everything outboard moving
//! with the joint) over the stroke, every joint at the same fraction of its
//! stroke from stowed to latched (the deployed chain included): the
//! conservative choice. At each position `θ` of the static margin's stroke
//! ([`crate::analysis::stroke_margin`]), with `D(θ)` the minimum driving
//! torque and `R(θ) = Σ_i FoS_i R_i(θ)` the factored resistances [N·m]:
//!
//! - NASA-STD-5017B Eq. 4-1 (and ECSS-E-ST-33-01C 4.7.5, and no standard
//!   with factor 1): `MoS = D / (R + FoS_a · I α) − 1 ≥ 0`, `FoS_a` the
//!   inertia (acceleration) factor of the data source's row.
//! - AIAA S-114 (via the Mission Assurance Baseline item 4.4.4.5-6):
//!   `MoS = (D − R) / (I α) − 1 ≥ 25 %`, what is left of the driving
//!   torque after the factored resistances against the torque the
//!   acceleration needs; the 25 % is its inertia factor 1.25, not applied
//!   twice.
//!
//! The worst position is the one with the lowest dynamic margin.

use crate::analysis::design_margin::{margin_pct, Factors, Resistance, Standard};
use crate::analysis::joint_margins::Row;
use crate::analysis::stroke_margin::StrokeMargin;
use crate::model::mechanism::{with_joints, Mechanism};
use crate::model::torque_table::HostJointEffects;
use deploywatch_core::GlobalEffects;

/// AIAA S-114's required dynamic torque margin [%].
pub const AIAA_DYNAMIC_PCT: f64 = 25.0;

/// Positions of the synchronised stroke at which `M_jj` is evaluated.
const INERTIA_STEPS: usize = 360;

/// The dynamic margin of one joint at its worst position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DynamicMargin {
    /// `I`: the largest `M_jj` over the stroke \[kg·m²\].
    pub inertia_kgm2: f64,
    /// `α = 2 S / T²` \[rad/s²\].
    pub accel_rad_s2: f64,
    /// The inertia factor applied to `I α` \[1\] (1 for AIAA S-114, whose
    /// reserve is the required 25 %).
    pub inertia_factor: f64,
    /// Required minimum [%].
    pub required_pct: f64,
    /// The worst position, from the latch \[rad\].
    pub from_latch_rad: f64,
    /// `D` there [N·m].
    pub driving_nm: f64,
    /// The factored resistances `R` there [N·m].
    pub resisting_nm: f64,
    /// The dynamic margin there [%].
    pub margin_pct: f64,
}

impl DynamicMargin {
    /// `I α` [N·m].
    pub fn inertia_torque_nm(&self) -> f64 {
        self.inertia_kgm2 * self.accel_rad_s2
    }

    /// True when the margin is at least the required minimum.
    pub fn pass(&self) -> bool {
        self.margin_pct >= self.required_pct
    }
}

/// The clause of `standard`'s dynamic margin, for the output.
pub fn clause(standard: Standard) -> &'static str {
    match standard {
        Standard::None => "no standard: D / (R + I α) − 1 ≥ 0 (this project's form, unfactored)",
        Standard::NasaStd5017 => {
            "NASA-STD-5017B Eq. 4-1: D / (R + FoS_a · I α) − 1 ≥ 0, FoS_a the acceleration factor"
        }
        Standard::EcssEST3301C => {
            "ECSS-E-ST-33-01C 4.7.5: D / (R + FoS_inertia · I α) − 1 ≥ 0 (inertia factor not confirmed from the text)"
        }
        Standard::AiaaS114 => {
            "AIAA S-114 via MAB 4.4.4.5-6: (D − R) / (I α) − 1 ≥ 25 %"
        }
    }
}

/// `α = 2 S / T²` \[rad/s²\]: the stroke `stroke_rad` from rest in
/// `deploy_time_s` at constant acceleration.
pub fn required_accel(stroke_rad: f64, deploy_time_s: f64) -> f64 {
    2.0 * stroke_rad.abs() / (deploy_time_s * deploy_time_s)
}

/// Per joint, the largest `M_jj` \[kg·m²\] of the core chain over the
/// stroke, every joint at the same fraction of its stroke; `None` when the
/// chain cannot be built (more joints than the core takes).
pub fn largest_inertia(mech: &Mechanism) -> Option<Vec<f64>> {
    let n = mech.joint_count();
    with_joints!(n, N => {
        let effects = vec![HostJointEffects::default(); N];
        let chain = mech.chain::<N>(&effects, GlobalEffects::default())?;
        let stowed: [f64; N] =
            core::array::from_fn(|j| mech.joints[j].stowed_deg.to_radians());
        let mut largest = vec![0.0_f64; N];
        for i in 0..=INERTIA_STEPS {
            let u = i as f64 / INERTIA_STEPS as f64;
            let phi: [f64; N] = core::array::from_fn(|j| stowed[j] * (1.0 - u));
            let m = chain.mass_matrix(&phi);
            for (j, l) in largest.iter_mut().enumerate() {
                *l = l.max(m[j][j]);
            }
        }
        Some(largest)
    }, else None)
}

/// The dynamic margin of a joint with inertia `inertia_kgm2` along its
/// static margin `stroke`, required to complete it in `deploy_time_s`,
/// under `standard` with `factors`; `None` when the stroke has no position.
pub fn dynamic(
    stroke: &StrokeMargin,
    inertia_kgm2: f64,
    deploy_time_s: f64,
    standard: Standard,
    factors: &Factors,
) -> Option<DynamicMargin> {
    let accel = required_accel(stroke.stroke_rad, deploy_time_s);
    let ia = inertia_kgm2 * accel;
    let (factor, required_pct) = match standard {
        Standard::AiaaS114 => (1.0, AIAA_DYNAMIC_PCT),
        _ => (factors.get(Resistance::Inertia), stroke.required_pct),
    };
    let at = |d: f64, r: f64| match standard {
        Standard::AiaaS114 => margin_pct(d - r, ia),
        _ => margin_pct(d, r + factor * ia),
    };
    stroke
        .points
        .iter()
        .map(|p| DynamicMargin {
            inertia_kgm2,
            accel_rad_s2: accel,
            inertia_factor: factor,
            required_pct,
            from_latch_rad: p.from_latch_rad,
            driving_nm: p.driving_nm,
            resisting_nm: p.resisting_nm,
            margin_pct: at(p.driving_nm, p.resisting_nm),
        })
        .min_by(|a, b| a.margin_pct.total_cmp(&b.margin_pct))
}

/// The dynamic margins of a mechanism, or why there are none.
#[derive(Clone, Debug, PartialEq)]
pub enum DynamicMargins {
    /// No required deploy time was given: not computed.
    NotComputed,
    /// With the required deploy time `deploy_time_s` \[s\], per joint (in
    /// the order of the rows; `None` for a stroke with no position).
    Computed {
        /// The required deploy time `T` \[s\].
        deploy_time_s: f64,
        /// Per joint.
        joints: Vec<Option<DynamicMargin>>,
    },
}

impl DynamicMargins {
    /// Every joint's dynamic margin with the required `deploy_time_s`
    /// (none: [`DynamicMargins::NotComputed`]); `None` when the core chain
    /// of `mech` cannot be built.
    pub fn of(
        mech: &Mechanism,
        rows: &[Row],
        deploy_time_s: Option<f64>,
        standard: Standard,
        factors: &Factors,
    ) -> Option<DynamicMargins> {
        let Some(t) = deploy_time_s else {
            return Some(DynamicMargins::NotComputed);
        };
        let inertia = largest_inertia(mech)?;
        let joints = rows
            .iter()
            .zip(inertia)
            .map(|(row, i)| dynamic(&row.stroke, i, t, standard, factors))
            .collect();
        Some(DynamicMargins::Computed {
            deploy_time_s: t,
            joints,
        })
    }

    /// Joint `index`'s (0-based) dynamic margin, if computed.
    pub fn joint(&self, index: usize) -> Option<&DynamicMargin> {
        match self {
            DynamicMargins::NotComputed => None,
            DynamicMargins::Computed { joints, .. } => joints.get(index)?.as_ref(),
        }
    }

    /// True unless a computed dynamic margin is below its minimum.
    pub fn pass(&self, index: usize) -> bool {
        self.joint(index).is_none_or(DynamicMargin::pass)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::stroke_margin::{along_stroke, Term};

    #[test]
    fn each_standard_puts_the_inertia_where_its_clause_does() {
        let terms = [Term::constant("friction", Resistance::Friction, 0.1)];
        let mut f = Factors::UNITY;
        f.set(Resistance::Friction, 2.0);
        f.set(Resistance::Inertia, 1.25);
        let s = along_stroke(|t| 1.0 + t, &[], 0.0, 1.0, 1.0, &terms, &f, 0.0);
        // α = 2 · 1 / 2² = 0.5, I α = 0.4 · 0.5 = 0.2; worst at the latch (D = 1).
        let n = dynamic(&s, 0.4, 2.0, Standard::NasaStd5017, &f).unwrap();
        assert!((n.accel_rad_s2 - 0.5).abs() < 1e-12);
        assert_eq!(n.from_latch_rad, 0.0);
        assert!((n.margin_pct - (1.0 / (0.2 + 1.25 * 0.2) - 1.0) * 100.0).abs() < 1e-9);
        let a = dynamic(&s, 0.4, 2.0, Standard::AiaaS114, &f).unwrap();
        assert!((a.margin_pct - ((1.0 - 0.2) / 0.2 - 1.0) * 100.0).abs() < 1e-9);
        assert_eq!(a.required_pct, AIAA_DYNAMIC_PCT);
        assert!(a.pass());
        let slow = dynamic(&s, 0.4, 20.0, Standard::NasaStd5017, &f).unwrap();
        assert!(slow.margin_pct > n.margin_pct);
    }
}
