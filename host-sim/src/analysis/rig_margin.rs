//! The hinge friction with the rig taken out, and the margin on orbit
//! beside the margin on the rig (`docs/margin.md`, "The margin in flight").
//!
//! A campaign measured on the zero-g rig (`[rig]`, `physics.md` §11) pays
//! the rails' friction through the wires. An equivalent friction torque
//! (EFT) fitted with the rig's rails taken as frictionless lumps that
//! friction into the hinges (the papers' EFT, which has no rig in its
//! model): `T_lumped,j`. The diagnosis (or the identification) with the
//! rig modelled gives the hinge friction alone, `T_hinge,j` = the
//! mechanism's Coulomb friction plus the `coulomb_friction` found. The
//! difference `T_lumped,j − T_hinge,j` is what the rig's friction accounts
//! for at joint `j`; the margin on the rig (seed 001 Eq. 7 with
//! `T_lumped`) understates the margin on orbit (with `T_hinge`, the rig
//! taken out) by exactly that resistance.

use crate::analysis::campaign_sim::CampaignSim;
use crate::analysis::design_margin::{joint_margin, Standard};
use crate::analysis::fit::{self, FitOptions};
use crate::data::campaign::Campaign;
use crate::model::effect::{Effect, EffectKind};
use crate::model::mechanism::Mechanism;
use crate::report::progress::Progress;

/// Largest lumped EFT excess the fit may take [N·m] (the diagnosis's
/// `coulomb_friction` bound).
const MAX_LUMPED_NM: f64 = 20.0;

/// The lumped EFT stands in for the rails only where its fit leaves the
/// runs within this factor of the RMS with the rig modelled (or of
/// [`LUMPED_RMS_FLOOR_DEG`]): beyond it the rails do something a hinge
/// friction cannot, and the margin on the rig is what a lumped EFT would
/// report, not a property of the hinges.
pub const LUMPED_RMS_RATIO: f64 = 3.0;

/// The RMS below which a fit is taken as explaining the runs whatever the
/// ratio \[deg\]: half an encoder quantum of 14 bits (0.022°), below any
/// sensor noise of a real rig; noise-free synthetic runs are fitted to
/// far less.
pub const LUMPED_RMS_FLOOR_DEG: f64 = 0.011;

/// One hinge: its friction with the rig taken out and lumped with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigJoint {
    /// 1-based joint.
    pub joint: usize,
    /// `T_hinge`: the hinge's Coulomb friction with the rig modelled [N·m].
    pub hinge_nm: f64,
    /// `T_lumped`: the EFT fitted with frictionless rails [N·m].
    pub lumped_nm: f64,
}

impl RigSplit {
    /// True when the lumped fit explains the runs about as well as the rig
    /// modelled does (within [`LUMPED_RMS_RATIO`] of its RMS or of
    /// [`LUMPED_RMS_FLOOR_DEG`]).
    pub fn lumped_explains(&self) -> bool {
        self.lumped_rms_deg <= LUMPED_RMS_RATIO * self.found_rms_deg.max(LUMPED_RMS_FLOOR_DEG)
    }
}

impl RigJoint {
    /// `T_lumped − T_hinge`: what the rig's friction accounts for at the
    /// joint [N·m].
    pub fn rig_share_nm(&self) -> f64 {
        self.lumped_nm - self.hinge_nm
    }
}

/// The torque margins of one mechanism of the campaign.
#[derive(Clone, Debug, PartialEq)]
pub struct MechanismMargins {
    /// The mechanism's name.
    pub mechanism: String,
    /// Per joint, the margin on orbit (with `T_hinge`) [%].
    pub orbit_pct: Vec<f64>,
    /// Per joint, the margin on the rig (with `T_lumped`) [%].
    pub rig_pct: Vec<f64>,
}

/// The hinge friction with the rig taken out, and the margins.
#[derive(Clone, Debug, PartialEq)]
pub struct RigSplit {
    /// Per hinge.
    pub joints: Vec<RigJoint>,
    /// The rig's causes found (`rig_friction`, `wire_length`,
    /// `frame_offset`): rig
    /// findings, not flight ones.
    pub rig_causes: Vec<Effect>,
    /// Per mechanism of the campaign, the margins.
    pub margins: Vec<MechanismMargins>,
    /// RMS of the lumped fit \[deg\] (the rig's friction in the hinges).
    pub lumped_rms_deg: f64,
    /// RMS with what was found, the rig modelled \[deg\].
    pub found_rms_deg: f64,
}

/// Seed 001 Eq. 7 (torque form, no factors) at joint `j` (0-based) of
/// `mech` against the Coulomb friction `friction_nm`; `NaN` for a spring
/// that cannot be built.
pub fn torque_margin_pct(mech: &Mechanism, j: usize, friction_nm: f64) -> f64 {
    let joint = &mech.joints[j];
    match joint.spring.to_spring() {
        Ok(spring) => joint_margin(
            &spring,
            joint.stowed_deg.to_radians(),
            friction_nm,
            Standard::None,
            None,
        )
        .torque_margin_pct(),
        Err(_) => f64::NAN,
    }
}

/// The campaign with every run's rig on frictionless rails, the rig's
/// other causes found (`wire_length`, `frame_offset`) built into it.
fn lumped_campaign(campaign: &Campaign, rig_causes: &[Effect]) -> Campaign {
    let mut c = campaign.clone();
    for r in &mut c.runs {
        if let Some(rig) = r.mechanism.active_rig() {
            r.mechanism.rig = Some(rig.with_effects(rig_causes).frictionless());
        }
    }
    c
}

/// The split of [`RigSplit`] for `campaign` and the effects `found` on it
/// (a diagnosis's, or an identification's `coulomb_friction`); `None`
/// when no run's mechanism has an active rig or a fit fails. The lumped
/// EFT is fitted by Levenberg–Marquardt ([`fit::least_squares`]) on the
/// campaign with frictionless rails, the other effects found kept.
pub fn split(campaign: &Campaign, found: &[Effect], progress: Progress) -> Option<RigSplit> {
    let first = campaign
        .runs
        .iter()
        .find(|r| r.mechanism.active_rig().is_some())?;
    let n = first.mechanism.joint_count();
    let hinge: Vec<f64> = (0..n)
        .map(|j| {
            first.mechanism.joints[j].friction.coulomb_nm
                + found
                    .iter()
                    .filter(|e| e.kind() == EffectKind::CoulombFriction && e.joint == Some(j + 1))
                    .map(|e| e.value())
                    .sum::<f64>()
        })
        .collect();
    let rig_causes: Vec<Effect> = found
        .iter()
        .filter(|e| e.kind().is_rig())
        .copied()
        .collect();
    let kept: Vec<Effect> = found
        .iter()
        .filter(|e| !e.kind().is_rig() && e.kind() != EffectKind::CoulombFriction)
        .copied()
        .collect();
    let lumped = lumped_campaign(campaign, &rig_causes);
    let with = |p: &[f64]| -> Vec<Effect> {
        let mut e = kept.clone();
        e.extend((0..n).map(|j| Effect::joint(EffectKind::CoulombFriction, j + 1, p[j])));
        e
    };
    let model = |p: &[f64]| lumped.residual_vector(&with(p));
    let own: Vec<f64> = (0..n)
        .map(|j| first.mechanism.joints[j].friction.coulomb_nm)
        .collect();
    let p0: Vec<f64> = (0..n).map(|j| hinge[j] - own[j]).collect();
    progress("rig: fitting the EFT that lumps the rails' friction into the hinges");
    let opts = FitOptions {
        upper: vec![MAX_LUMPED_NM; n],
        patience: 40,
        ..FitOptions::new(vec![0.0; n], vec![1e-4; n])
    };
    let fitted = fit::least_squares(&model, &p0, &opts).ok()?;
    let joints: Vec<RigJoint> = (0..n)
        .map(|j| RigJoint {
            joint: j + 1,
            hinge_nm: hinge[j],
            lumped_nm: own[j] + fitted.params[j],
        })
        .collect();
    Some(RigSplit {
        margins: margins(campaign, &joints),
        found_rms_deg: campaign.rms(found).unwrap_or(f64::NAN),
        lumped_rms_deg: fitted.rms(),
        joints,
        rig_causes,
    })
}

/// The margins on orbit and on the rig of every mechanism of the campaign
/// (each once, in the order of the runs).
fn margins(campaign: &Campaign, joints: &[RigJoint]) -> Vec<MechanismMargins> {
    let mut out: Vec<MechanismMargins> = Vec::new();
    for r in &campaign.runs {
        let m = &r.mechanism;
        if out.iter().any(|o| o.mechanism == m.name) {
            continue;
        }
        let per = |t: fn(&RigJoint) -> f64| -> Vec<f64> {
            joints
                .iter()
                .filter(|x| x.joint <= m.joint_count())
                .map(|x| torque_margin_pct(m, x.joint - 1, t(x)))
                .collect()
        };
        out.push(MechanismMargins {
            mechanism: m.name.clone(),
            orbit_pct: per(|x| x.hinge_nm),
            rig_pct: per(|x| x.lumped_nm),
        });
    }
    out
}
