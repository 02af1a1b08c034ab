//! The static torque margin at every position of the stroke (`docs/margin.md`,
//! "Along the stroke"): the standards ask for the margin "at any position of
//! motion" with the minimum driving torque there (AIAA S-114 via the
//! Aerospace Mission Assurance Baseline item 4.4.4.5-6; NASA-STD-5017B
//! Eq. 4-1; ECSS-E-ST-33-01C 4.7.5), not at the stowed angle alone.
//!
//! At a position `θ` \[rad\] from the latch (`θ = 0` latched, `θ = S` stowed,
//! `S = |φ_stowed|` the stroke):
//!
//! ```text
//! MoS(θ) = s_D · T_D(θ) / Σ_i FoS_i · R_i(θ) − 1
//! ```
//!
//! `T_D(θ)` the spring's torque on its unfolding branch (the branch it
//! deploys on, so a tape spring's hysteresis is in it) [N·m], `s_D` the
//! product of the driving scales (spring tolerance, end of life, a
//! softening found) \[1\], `R_i(θ)` each resistance's torque there [N·m]
//! with its [`Profile`] and `FoS_i` its kind's factor. The worst position
//! is the one with the lowest margin.

use crate::analysis::design_margin::{margin_pct, Factors, Resistance};
use crate::model::mechanism::Mechanism;

/// How a resistance's torque varies along the stroke.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Profile {
    /// The same torque everywhere (friction, damping at the run's peak
    /// rate, a table's worst value).
    Constant,
    /// A harness stiffness `k_h` [N·m/rad] relaxed at the stowed angle:
    /// `k_h · (S − θ)`, largest at the latch. The term's torque is ignored.
    FromStowed {
        /// `k_h` [N·m/rad].
        stiffness_nm_per_rad: f64,
    },
    /// The term's torque within `from_rad ≤ θ ≤ to_rad` of the latch, zero
    /// elsewhere (a detent's zone, a plunger's entry ramp).
    Band {
        /// Nearest the latch \[rad\].
        from_rad: f64,
        /// Farthest from the latch \[rad\].
        to_rad: f64,
    },
}

/// One resistance of the margin along the stroke.
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    /// What it is, in words (`coulomb_friction`, `latch entry ramp`, …).
    pub name: String,
    /// The standards' kind, which selects its factor.
    pub kind: Resistance,
    /// Its torque [N·m] (unused by [`Profile::FromStowed`]).
    pub torque_nm: f64,
    /// How it varies along the stroke.
    pub profile: Profile,
}

impl Term {
    /// A term of `kind` with the same `torque_nm` everywhere.
    pub fn constant(name: impl Into<String>, kind: Resistance, torque_nm: f64) -> Self {
        Term {
            name: name.into(),
            kind,
            torque_nm,
            profile: Profile::Constant,
        }
    }

    /// Its unfactored torque [N·m] at `theta_rad` from the latch on a stroke
    /// of `stroke_rad`.
    pub fn at(&self, theta_rad: f64, stroke_rad: f64) -> f64 {
        match self.profile {
            Profile::Constant => self.torque_nm,
            Profile::FromStowed {
                stiffness_nm_per_rad,
            } => stiffness_nm_per_rad * (stroke_rad - theta_rad).max(0.0),
            Profile::Band { from_rad, to_rad } => {
                if theta_rad >= from_rad && theta_rad <= to_rad {
                    self.torque_nm
                } else {
                    0.0
                }
            }
        }
    }

    /// The positions \[rad\] where its torque steps (a band's edges), so the
    /// grid holds them.
    fn edges(&self) -> [Option<f64>; 2] {
        match self.profile {
            Profile::Band { from_rad, to_rad } => [Some(from_rad), Some(to_rad)],
            _ => [None, None],
        }
    }
}

/// The reductions of the driving springs below the file's nominal: the
/// springs' torque tolerance (each joint's declared `spring_tolerance_pct`
/// or the one given for every joint, the larger) and their loss at end of
/// life (relaxation, creep).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Allowance {
    /// A torque tolerance given for every joint [%] (`--spring-tolerance`).
    pub spring_tolerance_pct: f64,
    /// The loss of torque at end of life [%].
    pub end_of_life_pct: f64,
    /// Each joint's tolerance declared in the mechanism file [%]
    /// (`spring_tolerance_pct` of its `[[joint]]`; a joint past the list:
    /// none).
    pub declared_pct: Vec<f64>,
}

impl Allowance {
    /// The allowance of `mech`'s declared tolerances with a tolerance
    /// `spring_tolerance_pct` given for every joint and a loss at end of
    /// life `end_of_life_pct` [%].
    pub fn of(mech: &Mechanism, spring_tolerance_pct: f64, end_of_life_pct: f64) -> Self {
        Allowance {
            spring_tolerance_pct,
            end_of_life_pct,
            declared_pct: mech.joints.iter().map(|j| j.spring_tolerance_pct).collect(),
        }
    }

    /// Joint `j`'s (0-based) spring tolerance [%]: the larger of its
    /// declared one and the one given for every joint.
    pub fn tolerance_pct(&self, j: usize) -> f64 {
        let declared = self.declared_pct.get(j).copied().unwrap_or(0.0);
        declared.max(self.spring_tolerance_pct)
    }

    /// Joint `j`'s minimum spring over its nominal,
    /// `(1 − tolerance/100) · (1 − end of life/100)` \[1\].
    pub fn scale(&self, j: usize) -> f64 {
        (1.0 - self.tolerance_pct(j) / 100.0) * (1.0 - self.end_of_life_pct / 100.0)
    }
}

/// The margin at one position of the stroke.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PositionMargin {
    /// `θ`: the angle from the latch \[rad\] (0 = latched).
    pub from_latch_rad: f64,
    /// `s_D · T_D(θ)`: the minimum driving torque there [N·m].
    pub driving_nm: f64,
    /// `Σ_i FoS_i · R_i(θ)`: the factored resistance there [N·m].
    pub resisting_nm: f64,
    /// `(driving / resisting − 1) · 100` [%].
    pub margin_pct: f64,
}

/// The margin of one joint along its whole stroke.
#[derive(Clone, Debug, PartialEq)]
pub struct StrokeMargin {
    /// Where the static margin starts \[rad\] from the latch: 0, or for a
    /// spring whose torque falls to zero at the latch (a tape spring) its
    /// first point past it; below it the latching margin applies.
    pub from_rad: f64,
    /// The stroke `S` \[rad\].
    pub stroke_rad: f64,
    /// The positions, from the latch (`θ = 0`) to the stowed angle.
    pub points: Vec<PositionMargin>,
    /// The index in `points` of the lowest margin (the one nearest the
    /// latch among equals).
    pub worst: usize,
    /// The driving scale `s_D` \[1\].
    pub driving_scale: f64,
    /// Required minimum margin [%].
    pub required_pct: f64,
}

impl StrokeMargin {
    /// The worst position.
    pub fn worst_point(&self) -> Option<&PositionMargin> {
        self.points.get(self.worst)
    }

    /// True when the margin is at least the required minimum at every position.
    pub fn pass(&self) -> bool {
        self.points
            .iter()
            .all(|p| p.margin_pct >= self.required_pct)
    }
}

/// Positions evaluated per stroke, besides the terms' edges.
pub const STEPS: usize = 360;

/// The margin along the stroke of a joint whose unfolding-branch driving
/// torque at `θ` \[rad\] from the latch is `driving(θ)` [N·m], scaled by
/// `driving_scale`, against `terms` each multiplied by its kind's factor in
/// `factors`: at [`STEPS`]` + 1` evenly spaced positions from the latch to
/// `stroke_rad`, at the edges of every band and at `knots_rad` (a tabulated
/// spring's points) inside the stroke, those from `from_rad` on (the end of
/// the stroke below it is the latching margin's,
/// [`crate::analysis::design_margin::JointMargin::latching_margin_pct`]).
#[allow(clippy::too_many_arguments)]
pub fn along_stroke(
    driving: impl Fn(f64) -> f64,
    knots_rad: &[f64],
    from_rad: f64,
    stroke_rad: f64,
    driving_scale: f64,
    terms: &[Term],
    factors: &Factors,
    required_pct: f64,
) -> StrokeMargin {
    let stroke = stroke_rad.abs();
    let mut thetas: Vec<f64> = (0..=STEPS)
        .map(|i| stroke * i as f64 / STEPS as f64)
        .chain(
            terms
                .iter()
                .flat_map(Term::edges)
                .flatten()
                .chain(knots_rad.iter().copied())
                .chain([from_rad])
                .filter(|t| *t >= 0.0 && *t <= stroke),
        )
        .collect();
    thetas.retain(|t| *t >= from_rad);
    thetas.sort_by(f64::total_cmp);
    thetas.dedup();
    let points: Vec<PositionMargin> = thetas
        .into_iter()
        .map(|theta| {
            let driving_nm = driving_scale * driving(theta);
            let resisting_nm = terms
                .iter()
                .map(|t| factors.get(t.kind) * t.at(theta, stroke))
                .sum();
            PositionMargin {
                from_latch_rad: theta,
                driving_nm,
                resisting_nm,
                margin_pct: margin_pct(driving_nm, resisting_nm),
            }
        })
        .collect();
    let worst = points
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.margin_pct.total_cmp(&b.1.margin_pct))
        .map_or(0, |(i, _)| i);
    StrokeMargin {
        from_rad,
        stroke_rad: stroke,
        points,
        worst,
        driving_scale,
        required_pct,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_band_and_a_harness_enter_where_they_act() {
        let terms = [
            Term::constant("friction", Resistance::Friction, 0.1),
            Term {
                name: "detent".into(),
                kind: Resistance::Other,
                torque_nm: 0.2,
                profile: Profile::Band {
                    from_rad: 0.0,
                    to_rad: 0.05,
                },
            },
            Term {
                name: "harness".into(),
                kind: Resistance::Harness,
                torque_nm: 0.0,
                profile: Profile::FromStowed {
                    stiffness_nm_per_rad: 0.1,
                },
            },
        ];
        let mut f = Factors::UNITY;
        f.set(Resistance::Other, 2.0);
        let m = along_stroke(|_| 1.0, &[], 0.0, 1.0, 0.9, &terms, &f, 0.0);
        assert!(m.points.iter().any(|p| p.from_latch_rad == 0.05));
        let at = |theta: f64| {
            m.points
                .iter()
                .find(|p| (p.from_latch_rad - theta).abs() < 1e-12)
                .copied()
                .unwrap()
        };
        // At the latch: 0.1 + 2·0.2 + 0.1·1 = 0.6; past the band: 0.1 + 0.1·(1 − θ).
        assert!((at(0.0).resisting_nm - 0.6).abs() < 1e-12);
        assert!((at(0.5).resisting_nm - 0.15).abs() < 1e-12);
        assert!((at(1.0).resisting_nm - 0.1).abs() < 1e-12);
        assert!((at(0.0).margin_pct - (0.9 / 0.6 - 1.0) * 100.0).abs() < 1e-9);
        assert_eq!(m.worst, 0);
        assert!(m.pass());
        let weak = along_stroke(|_| 0.5, &[], 0.0, 1.0, 1.0, &terms, &f, 0.0);
        assert!(!weak.pass());
    }
}
