//! The nominal deployment beside the margins (`docs/margin.md`, "The
//! nominal deployment"): the chain the margins are computed on — its
//! nominal springs, the resistances unfactored — simulated to the
//! mechanism's `duration_s`, and which joints its latches hold at the end.
//! The margins are joint by joint (seed 001 Eq. 7, seed 000 Eq. 21, the
//! stroke, the latch): a joint that passes them all can still be left
//! short by the chain's dynamics (a neighbour's swing, an escape over a
//! ball plunger); the deployment says so.

use crate::analysis::reliability::nominal_outcome;
use crate::analysis::resistances::Resistances;
use crate::model::mechanism::Mechanism;
use crate::simulate::deployment::SimError;

/// The nominal deployment of a margin's chain.
#[derive(Clone, Debug, PartialEq)]
pub struct NominalDeployment {
    /// The time simulated, the mechanism's `duration_s` \[s\].
    pub duration_s: f64,
    /// Per joint, when its latch last came to hold it \[s\], `None` when it
    /// does not hold it at the end (a physical latch by what it does,
    /// whatever its switch reads; `docs/reliability.md`, `not_held`).
    pub held_s: Vec<Option<f64>>,
    /// Per joint, its angle from the latch where the run ended \[deg\]
    /// (0 when held).
    pub end_deg: Vec<f64>,
    /// Whether the deployment was simulated on the mechanism's zero-g rig
    /// (its `[rig]` table; `false` in flight or without one).
    pub on_rig: bool,
}

impl NominalDeployment {
    /// Simulates `mech` with the resistances `r` as they are (unfactored):
    /// each joint's Coulomb friction and viscous damping set to `r`'s, and
    /// `r`'s other effects added.
    pub fn of(mech: &Mechanism, r: &Resistances) -> Result<Self, SimError> {
        let mut m = mech.clone();
        for (j, joint) in m.joints.iter_mut().enumerate() {
            if let Some(&c) = r.coulomb_nm.get(j) {
                joint.friction.coulomb_nm = c;
            }
            if let Some(&v) = r.viscous_nms.get(j) {
                joint.friction.viscous_nms = v;
            }
        }
        let o = nominal_outcome(&m, &r.others)?;
        Ok(NominalDeployment {
            duration_s: m.duration_s,
            end_deg: (0..o.held_s.len())
                .map(|j| match o.held_s[j] {
                    Some(_) => 0.0,
                    None => o.end_deg.get(j).copied().unwrap_or(0.0),
                })
                .collect(),
            held_s: o.held_s,
            on_rig: m.rig.is_some(),
        })
    }

    /// The joints (1-based) its latches do not hold at the end.
    pub fn not_held(&self) -> Vec<usize> {
        (0..self.held_s.len())
            .filter(|&j| self.held_s[j].is_none())
            .map(|j| j + 1)
            .collect()
    }

    /// When the last joint came to be held \[s\], `None` if one is not.
    pub fn all_held_s(&self) -> Option<f64> {
        self.held_s
            .iter()
            .try_fold(0.0_f64, |last, h| h.map(|t| last.max(t)))
    }
}
