//! The named effects of `docs/spec/physics.md` section 6: the vocabulary a
//! diagnosis reports, and the extras `deploywatch simulate --effect` adds.
//!
//! Everything a kind of effect has is here, each an exhaustive `match`:
//! `kind` (the vocabulary and the per-kind tables: name, unit, allowed
//! values, where it acts, its margin form, its residual signature, …),
//! `law` (each effect's own parameters, its value, its keys and its arm of
//! [`to_core`]), `fit` (what a diagnosis fits of it), `roles` (the small
//! enums those tables return, which the rest of the crate matches instead
//! of the kind), `syntax` (the `--effect` text read and written), `error`;
//! here, an [`Effect`] with its checks and its translation into the core's
//! tables ([`to_core`]).

mod error;
mod fit;
mod kind;
mod law;
mod roles;
mod syntax;

pub use error::EffectError;
pub use fit::*;
pub use kind::*;
pub use law::{Key, Law};

use crate::model::torque_table::{HostJointEffects, HostTorqueTable};
use deploywatch_core::GlobalEffects;

/// One effect: where it acts and its law with the law's own parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Effect {
    /// 1-based joint, `None` for global effects.
    pub joint: Option<usize>,
    /// The law and its parameters.
    pub law: Law,
}

impl Effect {
    /// A per-joint effect of one value (`joint` is 1-based; see
    /// [`Law::of_value`] for the kinds of more parameters).
    pub fn joint(kind: EffectKind, joint: usize, value: f64) -> Self {
        Effect {
            joint: Some(joint),
            law: Law::of_value(kind, value),
        }
    }

    /// A global effect of one value (see [`Law::of_value`]).
    pub fn global(kind: EffectKind, value: f64) -> Self {
        Effect {
            joint: None,
            law: Law::of_value(kind, value),
        }
    }

    /// Which effect.
    pub fn kind(&self) -> EffectKind {
        self.law.kind()
    }

    /// The value, in [`EffectKind::unit`] ([`Law::value`]).
    pub fn value(&self) -> f64 {
        self.law.value()
    }

    /// The tables of a `torque_table` (`None` for any other law: a
    /// projection, which a new law never needs an arm of).
    pub fn table(&self) -> Option<&HostTorqueTable> {
        if let Law::TorqueTable(t) = &self.law {
            Some(t)
        } else {
            None
        }
    }

    /// The direction of a `rig_tilt` \[deg\] (`None` for any other law: a
    /// projection, as [`Effect::table`]).
    pub fn tilt_alpha_deg(&self) -> Option<f64> {
        if let Law::RigTilt { alpha_deg, .. } = self.law {
            Some(alpha_deg)
        } else {
            None
        }
    }

    /// The effect with its value set to `x`, its joint and other
    /// parameters kept ([`Law::with_value`]).
    pub fn with_value(self, x: f64) -> Self {
        Effect {
            law: self.law.with_value(x),
            ..self
        }
    }

    /// Checks the joint against a mechanism of `joints` joints and the
    /// value against [`EffectKind::allowed`]: what a user may ask for
    /// (`--effect`).
    pub fn validate(&self, joints: usize) -> Result<(), EffectError> {
        self.validate_joint(joints)?;
        if !self.kind().allowed().contains(self.value()) {
            return Err(EffectError::OutOfRange {
                kind: self.kind(),
                value: self.value(),
            });
        }
        Ok(())
    }

    /// Checks only that the numbers are finite and the joint exists: what
    /// the simulator needs (an identification may try a correction below
    /// the mechanism's own friction, which [`Effect::validate`] refuses).
    pub fn validate_joint(&self, joints: usize) -> Result<(), EffectError> {
        let kind = self.kind();
        let value = self.value();
        if !value.is_finite() {
            return Err(EffectError::OutOfRange { kind, value });
        }
        if let Law::RigTilt { alpha_deg, .. } = self.law {
            if !alpha_deg.is_finite() {
                return Err(EffectError::BadAlpha { kind, alpha_deg });
            }
        }
        match (kind.per_joint(), self.joint) {
            (true, None) => Err(EffectError::NeedsJoint { kind }),
            (true, Some(joint)) if joint == 0 || joint > joints => Err(EffectError::NoSuchJoint {
                kind,
                joint,
                joints,
            }),
            (false, Some(_)) => Err(EffectError::GlobalWithJoint { kind }),
            (true, Some(_)) | (false, None) => Ok(()),
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
        e.law.add_to_core(at, &mut g);
    }
    (je, g)
}

/// The `encoder_offset` of each joint \[deg\].
pub fn encoder_offsets_deg(effects: &[Effect], joints: usize) -> Vec<f64> {
    let mut b = vec![0.0; joints];
    for e in effects {
        if let (Law::EncoderOffset(x), Some(j)) = (e.law, e.joint) {
            if (1..=joints).contains(&j) {
                b[j - 1] += x;
            }
        }
    }
    b
}

#[cfg(test)]
mod tests;
