//! The nominal deployment beside the margins (`docs/margin.md`, "The
//! nominal deployment"): the chain the margins are computed on — its
//! nominal springs, the resistances unfactored — simulated to the
//! mechanism's `duration_s`, and which joints its latches hold at the end.
//! The margins are joint by joint (seed 001 Eq. 7, seed 000 Eq. 21, the
//! stroke, the latch): a joint that passes them all can still be left
//! short by the chain's dynamics (a neighbour's swing, an escape over a
//! ball plunger); the deployment says so.

use crate::analysis::reliability::{nominal_outcome, nominal_outcome_at};
use crate::analysis::resistances::Resistances;
use crate::model::mechanism::Mechanism;
use crate::simulate::deployment::SimError;

/// Latch instants of two deployments of one wing closer than this \[s\]
/// are the same latch (each located to 1e-6 s): `simulate`'s and a
/// verdict's.
pub const SAME_LATCH_S: f64 = 1e-3;

/// The tolerances of the second nominal run of a physical-latch wing,
/// relative to the first's (the simulator's defaults).
const CHAOS_CHECK_SCALE: f64 = 0.1;

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
    /// The joints (1-based) held at the end in one of two runs and not in
    /// the other, the second at a tenth of the tolerances: a wing whose
    /// physical latches rattle is chaotic, and its nominal outcome then
    /// is one of several the same wing gives (`docs/margin.md`, "The
    /// nominal deployment"). Empty for ideal latches (not run twice).
    pub unsettled: Vec<usize>,
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
        let unsettled = match m.has_physical_latch() {
            true => nominal_outcome_at(&m, &r.others, CHAOS_CHECK_SCALE)
                .map(|tight| {
                    (0..o.held_s.len())
                        .filter(|&j| {
                            tight.held_s.get(j).map(Option::is_some) != Some(o.held_s[j].is_some())
                        })
                        .map(|j| j + 1)
                        .collect()
                })
                .unwrap_or_default(),
            false => Vec::new(),
        };
        Ok(NominalDeployment {
            unsettled,
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
