//! One candidate cause of a diagnosis and where its parameters may move.

use super::table_form::TableForm;
use crate::model::effect::{Effect, EffectKind, Law};
pub use crate::model::effect::{ParamBound, STRIBECK_RATE_RANGE};
use crate::model::rig::Rig;

/// One candidate cause: an effect kind and, for per-joint effects, a joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Candidate {
    /// The effect.
    pub kind: EffectKind,
    /// 1-based joint for per-joint effects.
    pub joint: Option<usize>,
    /// `torque_table` only: the form of the table.
    pub table: Option<TableForm>,
}

impl Candidate {
    /// Every candidate for a campaign of `joints` joints.
    pub fn all(joints: usize) -> Vec<Candidate> {
        let mut out = Vec::new();
        for kind in EffectKind::ALL {
            if kind.per_joint() {
                for j in 1..=joints {
                    out.push(Candidate {
                        kind,
                        joint: Some(j),
                        table: None,
                    });
                }
            } else {
                out.push(Candidate {
                    kind,
                    joint: None,
                    table: None,
                });
            }
        }
        out
    }

    /// The rig's causes ([`EffectKind::RIG`], global): candidates of a
    /// campaign whose mechanisms have an active `[rig]` (`rigs`, one per
    /// run that has one), none otherwise; `frame_offset` only when a rig
    /// has a frame.
    pub fn rig<'a>(rigs: impl IntoIterator<Item = &'a Rig>) -> Vec<Candidate> {
        let rigs: Vec<&Rig> = rigs.into_iter().collect();
        let frames = rigs.iter().any(|r| !r.frames.is_empty());
        EffectKind::RIG
            .into_iter()
            .filter(|&k| !rigs.is_empty() && (k != EffectKind::FrameOffset || frames))
            .map(|kind| Candidate {
                kind,
                joint: None,
                table: None,
            })
            .collect()
    }

    /// Number of parameters: the table form's knots, or the kind's
    /// ([`EffectKind::fit_params`]).
    pub fn params(&self) -> usize {
        match self.table {
            Some(t) => t.params(),
            None => self.kind.fit_params(),
        }
    }

    /// The fit's bounds and smallest finite-difference step, one per
    /// parameter ([`EffectKind::bounds`]).
    pub fn bounds(&self) -> Vec<ParamBound> {
        self.kind.bounds(self.params())
    }

    /// Starting points of the coarse scan ([`EffectKind::scan`]).
    pub fn scan(&self) -> Vec<Vec<f64>> {
        self.kind.scan(self.params(), self.is_snag())
    }

    /// A narrow placed angle table of five knots without a rate table (the
    /// form of [`super::discover::snag_candidates`]).
    pub(super) fn is_snag(&self) -> bool {
        self.table
            .is_some_and(|t| t.placed.is_some() && t.angle_knots == 5 && t.rate_knots == 0)
    }

    /// The effect with parameters `p`.
    pub fn effect(&self, p: &[f64]) -> Effect {
        if let Some(t) = self.table {
            return t.effect(self.joint, p);
        }
        Effect {
            joint: self.joint,
            law: Law::of_params(self.kind, p),
        }
    }

    /// The 95 % interval of the effect's value, and for a rig tilt of its
    /// direction \[deg\], from the intervals of its parameters (first-order
    /// propagation for the tilt's magnitude and angle).
    pub fn value_ci(&self, p: &[f64], ci: &[[f64; 2]]) -> ([f64; 2], Option<[f64; 2]>) {
        let half = |k: usize| ci.get(k).map_or(f64::INFINITY, |c| 0.5 * (c[1] - c[0]));
        if self.table.is_some() {
            // A table's value is its largest knot torque: that knot's interval.
            let k = (0..p.len())
                .max_by(|&a, &b| p[a].abs().total_cmp(&p[b].abs()))
                .unwrap_or(0);
            let (v, h) = (p.get(k).map_or(0.0, |x| x.abs()), half(k));
            return ([v - h, v + h], None);
        }
        if self.kind == EffectKind::RigTilt {
            let (x, y) = (
                p.first().copied().unwrap_or(0.0),
                p.get(1).copied().unwrap_or(0.0),
            );
            let g = x.hypot(y).max(1e-300);
            let (hx, hy) = (half(0), half(1));
            let hg = ((x * hx).powi(2) + (y * hy).powi(2)).sqrt() / g;
            let ha = (((y * hx).powi(2) + (x * hy).powi(2)).sqrt() / (g * g)).to_degrees();
            let a = y.atan2(x).to_degrees().rem_euclid(360.0);
            return ([g - hg, g + hg], Some([a - ha, a + ha]));
        }
        (
            ci.first()
                .copied()
                .unwrap_or([f64::NEG_INFINITY, f64::INFINITY]),
            None,
        )
    }

    /// `name` or `name@joint`, for progress lines and reports.
    pub fn label(&self) -> String {
        if let (Some(t), Some(j)) = (self.table, self.joint) {
            return format!("{} j{j} ({})", self.kind, t.name());
        }
        match self.joint {
            Some(j) => format!("{} j{j}", self.kind),
            None => self.kind.to_string(),
        }
    }

    /// The candidate in words for progress lines: `coulomb_friction at
    /// joint 1`, `torque_table at joint 2 (angle)`, `air_drag`.
    pub fn words(&self) -> String {
        if let (Some(t), Some(j)) = (self.table, self.joint) {
            return format!("{} at joint {j} ({})", self.kind, t.name());
        }
        match self.joint {
            Some(j) => format!("{} at joint {j}", self.kind),
            None => self.kind.to_string(),
        }
    }
}

/// A set of candidates with their parameters, as effects.
pub fn effects_of(set: &[Candidate], p: &[f64]) -> Vec<Effect> {
    let mut out = Vec::with_capacity(set.len());
    let mut k = 0;
    for c in set {
        out.push(c.effect(&p[k..k + c.params()]));
        k += c.params();
    }
    out
}

/// `a, b, c` of a set in words ([`Candidate::words`]); `nothing` for the
/// empty set.
pub fn labels(set: &[Candidate]) -> String {
    if set.is_empty() {
        return "nothing".to_string();
    }
    set.iter().map(|c| c.words()).collect::<Vec<_>>().join(", ")
}
