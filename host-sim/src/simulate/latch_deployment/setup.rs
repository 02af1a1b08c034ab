//! Setting up a physical-latch run: the core latches of a mechanism's
//! joints with the latch effects' weakenings, and the check that latch
//! effects name joints that have a physical latch; the latch's constants
//! a run computes once.

use crate::model::effect::{Acts, Effect, EffectKind, LatchPart};
use crate::model::mechanism::Mechanism;
use crate::simulate::trajectory::SimError;
use deploywatch_core::physics::latch_contact::{PhysicalLatch, PlungerSegment};

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
        // Only the latch's weakenings ([`Acts::Latch`]).
        match e.kind().acts() {
            Acts::Latch(LatchPart::Plunger) => out[j].0 *= 1.0 - e.value(),
            Acts::Latch(LatchPart::Magnet) => out[j].1 *= 1.0 - e.value(),
            Acts::Chain | Acts::Sensor | Acts::Rig(_) => {}
        }
    }
    out
}

/// Refuses latch effects on joints without a physical latch, a magnet's
/// weakening on a latch without a magnet, and a rig cause on a mechanism
/// without an active rig (they would do nothing, silently).
pub fn check_latch_effects(mech: &Mechanism, effects: &[Effect]) -> Result<(), SimError> {
    for e in effects {
        if !EffectKind::LATCH.contains(&e.kind()) {
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
        let magnet = e
            .joint
            .and_then(|j| mech.latch(j.checked_sub(1)?))
            .is_some_and(|l| l.magnet.is_some());
        if e.kind() == EffectKind::MagnetWeakening && !magnet {
            return Err(SimError::Invalid(format!(
                "{e}: the joint's latch has no magnet ([joint.latch.magnet] in the mechanism file)"
            )));
        }
    }
    crate::simulate::rig::check_rig_effects(mech, effects)
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

/// A latch's figures that do not change over a run.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Consts {
    /// The travels of its marks \[rad\] (`PhysicalLatch::marks`).
    pub(super) marks: [f64; 6],
    /// The ramp rates of its plunger segments [mm/rad]
    /// (`PhysicalLatch::ramp_rate_on`, indexed by [`segment_index`]).
    pub(super) ramp: [f64; 3],
    /// The spring's torque at the stop, `T(0⁺)` [N·m], on the unfolding
    /// and the folding branch (`Sim::spring_extension`).
    pub(super) at_stop: [f64; 2],
}

/// The index of a plunger segment in `Sim::consts`' ramp rates.
pub(super) fn segment_index(seg: PlungerSegment) -> usize {
    match seg {
        PlungerSegment::Clear => 0,
        PlungerSegment::Entry => 1,
        PlungerSegment::Hold => 2,
    }
}
