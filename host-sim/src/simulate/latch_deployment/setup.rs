//! Setting up a physical-latch run: the core latches of a mechanism's
//! joints with the latch effects' weakenings, and the check that latch
//! effects name joints that have a physical latch.

use crate::model::effect::{Effect, EffectKind};
use crate::model::mechanism::Mechanism;
use crate::simulate::trajectory::SimError;
use deploywatch_core::physics::latch_contact::PhysicalLatch;

/// The latch scales `(plunger, magnet)` of each joint from the
/// `plunger_weakening` / `magnet_weakening` effects (`1 − w`, composed).
pub fn weakenings(effects: &[Effect], joints: usize) -> Vec<(f64, f64)> {
    let mut out = vec![(1.0, 1.0); joints];
    for e in effects {
        let Some(j) = e
            .joint
            .and_then(|j| j.checked_sub(1))
            .filter(|&j| j < joints)
        else {
            continue;
        };
        match e.kind {
            EffectKind::PlungerWeakening => out[j].0 *= 1.0 - e.value,
            EffectKind::MagnetWeakening => out[j].1 *= 1.0 - e.value,
            _ => {}
        }
    }
    out
}

/// Refuses latch effects on joints without a physical latch (they would
/// do nothing, silently).
pub fn check_latch_effects(mech: &Mechanism, effects: &[Effect]) -> Result<(), SimError> {
    for e in effects {
        if !EffectKind::LATCH.contains(&e.kind) {
            continue;
        }
        let has = e
            .joint
            .and_then(|j| j.checked_sub(1))
            .is_some_and(|j| mech.latch(j).is_some());
        if !has || mech.truss.is_some() {
            return Err(SimError::Invalid(format!(
                "{e}: the joint has no physical latch ([joint.latch] model = \"physical\" in the mechanism file)"
            )));
        }
    }
    Ok(())
}

/// The core latches of a mechanism's joints with the effects' weakenings.
pub fn latches<const N: usize>(
    mech: &Mechanism,
    effects: &[Effect],
) -> [Option<PhysicalLatch<f64>>; N] {
    let w = weakenings(effects, N);
    core::array::from_fn(|j| {
        let (p, m) = w.get(j).copied().unwrap_or((1.0, 1.0));
        let stowed = mech.joints.get(j).map_or(1.0, |s| s.stowed_deg);
        mech.latch(j).map(|l| l.to_core(stowed, p, m))
    })
}
