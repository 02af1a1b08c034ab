//! The named effects of `docs/spec/physics.md` section 6: the vocabulary a
//! diagnosis reports, and the extras `deploywatch simulate --effect` adds.//!
//! One module per responsibility: `kind` (the vocabulary), `error`,
//! `syntax` (the `--effect` text read and written); here, an [`Effect`] with
//! its checks and its translation into the core's tables ([`to_core`]).

mod error;
mod kind;
mod syntax;

pub use error::EffectError;
pub use kind::{EffectKind, ValueRange};

use crate::model::torque_table::{HostJointEffects, HostTorqueTable};
use deploywatch_core::GlobalEffects;

/// One effect with its joint and value.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Effect {
    /// Which effect.
    pub kind: EffectKind,
    /// 1-based joint, `None` for global effects.
    pub joint: Option<usize>,
    /// The value, in [`EffectKind::unit`].
    pub value: f64,
    /// `rig_tilt` only: direction of the tilt gravity \[deg\].
    pub alpha_deg: f64,
    /// `stribeck_friction` only: the break-away excess `T_brk − T_C` [N·m].
    pub excess_nm: f64,
    /// `stribeck_friction` only: the Stribeck velocity `ω_st` [rad/s].
    pub stribeck_rad_s: f64,
    /// `torque_table` only: the tables (`value` is then their largest
    /// absolute torque [N·m]).
    pub table: HostTorqueTable,
}

impl Effect {
    /// A per-joint effect (`joint` is 1-based).
    pub fn joint(kind: EffectKind, joint: usize, value: f64) -> Self {
        Effect {
            kind,
            joint: Some(joint),
            value,
            ..Effect::default()
        }
    }

    /// A global effect.
    pub fn global(kind: EffectKind, value: f64) -> Self {
        Effect {
            kind,
            joint: None,
            value,
            ..Effect::default()
        }
    }

    /// Checks the joint against a mechanism of `joints` joints and the
    /// value against [`EffectKind::allowed`]: what a user may ask for
    /// (`--effect`).
    pub fn validate(&self, joints: usize) -> Result<(), EffectError> {
        self.validate_joint(joints)?;
        if !self.kind.allowed().contains(self.value) {
            return Err(EffectError::OutOfRange {
                kind: self.kind,
                value: self.value,
            });
        }
        Ok(())
    }

    /// Checks only that the numbers are finite and the joint exists: what
    /// the simulator needs (an identification may try a correction below
    /// the mechanism's own friction, which [`Effect::validate`] refuses).
    pub fn validate_joint(&self, joints: usize) -> Result<(), EffectError> {
        let kind = self.kind;
        if !self.value.is_finite() {
            return Err(EffectError::OutOfRange {
                kind,
                value: self.value,
            });
        }
        if !self.alpha_deg.is_finite() {
            let alpha_deg = self.alpha_deg;
            return Err(EffectError::BadAlpha { kind, alpha_deg });
        }
        match (kind.per_joint(), self.joint) {
            (true, None) => Err(EffectError::NeedsJoint { kind }),
            (true, Some(joint)) if joint == 0 || joint > joints => Err(EffectError::NoSuchJoint {
                kind,
                joint,
                joints,
            }),
            (false, Some(_)) => Err(EffectError::GlobalWithJoint { kind }),
            _ => Ok(()),
        }
    }
}

/// The dynamic effects of a list, as the core's per-joint and global tables
/// (sensor effects are left out: see [`encoder_offsets_deg`]).
pub fn to_core(effects: &[Effect], joints: usize) -> (Vec<HostJointEffects>, GlobalEffects<f64>) {
    let mut je = vec![HostJointEffects::default(); joints];
    let mut g = GlobalEffects::default();
    // A joint effect whose joint is missing or out of range acts nowhere
    // ([`Effect::validate_joint`] refuses it before a run): it is written
    // here and dropped.
    let mut nowhere = HostJointEffects::default();
    for e in effects {
        let at = e
            .joint
            .and_then(|j| j.checked_sub(1))
            .and_then(|j| je.get_mut(j))
            .unwrap_or(&mut nowhere);
        match e.kind {
            EffectKind::CoulombFriction => at.coulomb_nm += e.value,
            EffectKind::ViscousDamping => at.viscous_nms += e.value,
            EffectKind::QuadraticDamping => at.quadratic_nms2_per_rad2 += e.value,
            EffectKind::StribeckFriction => {
                // The kinetic level is Coulomb friction; the excess and its
                // velocity are the law's Stribeck term (the last one given).
                at.coulomb_nm += e.value;
                at.stribeck_excess_nm += e.excess_nm;
                at.stribeck_rad_s = e.stribeck_rad_s;
            }
            EffectKind::SpringSoftening => {
                // Two softenings compose: (1 − s1)(1 − s2).
                let s = at.spring_softening;
                at.spring_softening = 1.0 - (1.0 - s) * (1.0 - e.value);
            }
            EffectKind::HarnessStiffness => at.harness_nm_per_rad += e.value,
            EffectKind::LatchDetent => at.detent_nm += e.value,
            EffectKind::TorqueTable => at.table = e.table,
            EffectKind::AirDrag => g.air_drag_kg_m2 += e.value,
            EffectKind::RigTilt => {
                g.tilt_m_s2 = e.value;
                g.tilt_alpha_rad = e.alpha_deg.to_radians();
            }
            // Not the chain's: the sensor's offset ([`encoder_offsets_deg`]),
            // the physical latch's weakenings
            // (`simulate::latch_deployment::setup::weakenings`) and the rig's
            // causes ([`crate::model::rig::Rig::with_effects`]).
            EffectKind::EncoderOffset
            | EffectKind::PlungerWeakening
            | EffectKind::MagnetWeakening
            | EffectKind::RigFriction
            | EffectKind::WireLength
            | EffectKind::FrameOffset => {}
        }
    }
    (je, g)
}

/// The `encoder_offset` of each joint \[deg\].
pub fn encoder_offsets_deg(effects: &[Effect], joints: usize) -> Vec<f64> {
    let mut b = vec![0.0; joints];
    for e in effects {
        if let (EffectKind::EncoderOffset, Some(j)) = (e.kind, e.joint) {
            if (1..=joints).contains(&j) {
                b[j - 1] += e.value;
            }
        }
    }
    b
}

#[cfg(test)]
mod tests;
