//! Campaigns of an effect that acts after the first latch contact
//! (`docs/diagnosis.md`, "Runs of a physical latch", 4 and 5): wings of
//! [`crate::wing_gen`] with 4–6 joints, no rig, half of the joints (drawn)
//! with a physical latch and at least one with the ideal latch; one named
//! effect hidden at a drawn joint, raised until it moves the runs by
//! [`WHOLE_DEG`] RMS or more, and kept only when, before the first switch
//! closing of any physical latch, it moves them by less than
//! [`BEFORE_DEG`] (twice the reference sensor's noise). Shared by
//! `examples/after_contact.rs` (the measured rows) and
//! `diagnosis_after_contact.rs` (the CI's cases).

use crate::wing_gen::wing_toml;
use crate::SplitMix;
use deploywatch_sim::deployment::{self, SimOptions, Trajectory};
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::mechanism::Mechanism;

/// What the effect must move the runs by over the whole run \[deg\].
pub const WHOLE_DEG: f64 = 0.3;

/// What it may move them by before the first contact \[deg\]: twice the
/// reference sensor's noise.
pub const BEFORE_DEG: f64 = 0.04;

/// The whole run of `m` with `e`, to its end (not stopped when deployed),
/// as `hidden_effect::moves_runs_deg` compares them.
fn whole(m: &Mechanism, e: &[Effect]) -> Option<Trajectory> {
    let opts = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    deployment::simulate(m, e, &opts).ok()
}

/// RMS \[deg\] of `b` less `a` over the first `n` samples (all when
/// `None`), every joint.
fn rms_between(a: &Trajectory, b: &Trajectory, n: Option<usize>) -> f64 {
    let len = a.t_s.len().min(b.t_s.len());
    let n = n.map_or(len, |n| n.min(len));
    let (mut sse, mut k) = (0.0, 0usize);
    for (x, y) in a.phi_deg.iter().zip(&b.phi_deg) {
        for i in 0..n {
            sse += (y[i] - x[i]).powi(2);
            k += 1;
        }
    }
    (sse / k.max(1) as f64).sqrt()
}

/// The first sample where any of the 1-based joints `physical` has its
/// switch closed.
fn first_contact(a: &Trajectory, physical: &[usize]) -> Option<usize> {
    physical
        .iter()
        .filter_map(|&j| a.latched.get(j - 1)?.iter().position(|&l| l))
        .min()
}

/// Each joint's switch closings over the run (a switch closed at the first
/// sample counts as one).
fn closings(t: &Trajectory) -> Vec<usize> {
    t.latched
        .iter()
        .map(|l| {
            l.windows(2).filter(|w| !w[0] && w[1]).count() + usize::from(l.first() == Some(&true))
        })
        .collect()
}

/// One campaign: the wing, its hidden effect, the first contact's share.
pub struct Case {
    /// The wing's seed.
    pub seed: u64,
    /// The wing (drawing and as built: the latches are the drawing's).
    pub wing: Mechanism,
    /// Its joints.
    pub joints: usize,
    /// The 1-based joints with a physical latch.
    pub physical: Vec<usize>,
    /// The effect hidden.
    pub truth: Effect,
    /// What it moves the runs by before the first contact \[deg\].
    pub before_deg: f64,
    /// Each joint's switch closes as often with the effect as without.
    pub same_history: bool,
}

/// The campaign of `seed`, `kind` hidden, or `None` when the wing or the
/// effect does not qualify.
pub fn case(seed: u64, kind: EffectKind) -> Option<Case> {
    let w = wing_toml(seed, 0.5);
    if !(4..=6).contains(&w.joints) || w.rig || w.physical.is_empty() {
        return None;
    }
    if w.physical.len() == w.joints || !w.effects.is_empty() {
        return None;
    }
    let wing = Mechanism::from_toml_str(&w.toml, &format!("random-{seed}")).ok()?;
    let mut r = SplitMix(seed ^ 0xaf7e_c047);
    let joint = 1 + ((r.next_f64() * w.joints as f64) as usize).min(w.joints - 1);
    let without = whole(&wing, &[])?;
    let first = first_contact(&without, &w.physical)?;
    let mut e = Effect::joint(kind, joint, 0.01);
    for _ in 0..40 {
        let with = whole(&wing, &[e])?;
        if rms_between(&without, &with, None) >= WHOLE_DEG {
            let before = rms_between(&without, &with, Some(first));
            return (before < BEFORE_DEG).then(|| Case {
                seed,
                wing,
                joints: w.joints,
                physical: w.physical,
                truth: e,
                before_deg: before,
                same_history: closings(&with) == closings(&without),
            });
        }
        e = e.with_value(e.value() * 1.3);
    }
    None
}
