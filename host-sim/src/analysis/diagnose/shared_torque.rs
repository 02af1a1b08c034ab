//! A candidate that shares its torque with an effect already in the set.
//!
//! Two named effects at one joint can make nearly the same torque over a
//! stroke (a softened spring and Coulomb friction both resist all the way
//! out; so do viscous damping and friction). When one is taken first it
//! absorbs most of the other, and the other scanned beside it with the
//! first held over-resists: the move looks poor in the coarse scan and is
//! never fitted, where the two would share the torque. When named pairs
//! are tried at one joint (in place of a table,
//! [`super::policy::Move::NamedForTable`], or of the named effects there,
//! [`super::policy::Move::JointPairs`]), the screen therefore also starts
//! such a move on the line that keeps their summed torque over the measured
//! states fixed: the candidate at a share of the value that would replace
//! the base effect entirely, the base effect lowered by what the candidate
//! takes over. Both come from the residual torque's samples
//! ([`crate::analysis::diagnose::residual_torque`]: the measured rates and angles,
//! weighted by the torque's standard errors) and the effects' signatures
//! ([`residual_named::signature`]); where the residual torque separates the
//! two, its regression on both signatures ([`residual_named::fit`]) is a
//! start too.

use super::candidate::Candidate;
use super::outcome::FittedSet;
use super::Engine;
use crate::analysis::diagnose::residual_named::{self, signature};
use crate::analysis::diagnose::residual_shape::thin;
use crate::analysis::diagnose::residual_torque::{residual_torque, TorqueSample};
use crate::data::campaign::Campaign;
use crate::model::effect::EffectKind;

/// Shares of the candidate's value on the line of fixed summed torque at
/// which the screen starts it \[1\] (of the value that would take over the
/// base effect's whole torque).
const LINE_SHARES: [f64; 3] = [0.25, 0.5, 0.75];

/// Two effects share their torque when their signatures' weighted cosine
/// over the measured states is at least this \[1\].
pub const MIN_SHARED_COSINE: f64 = 0.5;

/// `(⟨a, b⟩, ⟨a, a⟩, ⟨b, b⟩)` of two signatures over the samples, weighted
/// by `1/se²`.
fn products(samples: &[TorqueSample], a: EffectKind, b: EffectKind) -> (f64, f64, f64) {
    let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
    for s in samples {
        let w = 1.0 / s.se_nm.max(1e-9).powi(2);
        let (Some(x), Some(y)) = (signature(a, s), signature(b, s)) else {
            // An effect without a signature shares no torque.
            continue;
        };
        ab += w * x * y;
        aa += w * x * x;
        bb += w * y * y;
    }
    (ab, aa, bb)
}

impl Engine<'_> {
    /// Screens `base ∪ {cand}` from the start points where `cand` shares
    /// its torque with an effect of `base` ([`Engine::shared_starts`]): the
    /// best by SSE; `None` when there are none.
    pub(super) fn screen_shared(
        &self,
        c: &Campaign,
        base: &FittedSet,
        cand: Candidate,
    ) -> Option<FittedSet> {
        let points = self.shared_starts(c, base, &cand);
        self.best_point(c, base, cand, points.into_iter())
    }

    /// Start points (all parameters of `base ∪ {cand}`) where a named
    /// joint effect of `base` at `cand`'s joint, whose signature's cosine
    /// with `cand`'s is at least [`MIN_SHARED_COSINE`], is refitted with
    /// `cand`: on the line of fixed summed torque at [`LINE_SHARES`], and
    /// at the residual torque's regression on both when its values are
    /// positive. None when `cand` is not a named joint effect with a torque
    /// signature.
    pub(super) fn shared_starts(
        &self,
        c: &Campaign,
        base: &FittedSet,
        cand: &Candidate,
    ) -> Vec<Vec<f64>> {
        let kinds = residual_named::KINDS;
        let (Some(joint), None) = (cand.joint, cand.table) else {
            return Vec::new();
        };
        if !kinds.contains(&cand.kind) {
            return Vec::new();
        }
        let mut out = Vec::new();
        for (k, member) in base.members.iter().enumerate() {
            let b = &member.candidate;
            let same_joint = b.joint == Some(joint) && b.table.is_none();
            if !same_joint || b.kind == cand.kind || !kinds.contains(&b.kind) {
                continue;
            }
            let reduced = base.without(k);
            let res = residual_torque(c, &reduced.effects());
            let Some(jt) = res.iter().find(|r| r.joint == joint) else {
                continue;
            };
            let samples = thin(&jt.samples);
            let (ab, aa, bb) = products(&samples, b.kind, cand.kind);
            let cosine = ab / (aa * bb).sqrt().max(1e-300);
            let vb = member.params.first().copied().unwrap_or(0.0);
            if !(cosine >= MIN_SHARED_COSINE) || !(vb > 0.0) {
                continue;
            }
            // `cand` at value 1 makes the torque of `b` at `beta`.
            let beta = ab / aa;
            let mut pairs: Vec<[f64; 2]> = LINE_SHARES
                .iter()
                .map(|s| [(1.0 - s) * vb, s * vb / beta])
                .collect();
            pairs.extend(
                residual_named::fit(&samples, &[b.kind, cand.kind]).map(|(v, _)| [v[0], v[1]]),
            );
            for [xb, xc] in pairs {
                let clamp = |x: f64, c: &Candidate| {
                    let r = c.bounds()[0];
                    x.clamp(r.lower, r.upper)
                };
                let mut start = base.clone();
                if let Some(x) = start.members[k].params.first_mut() {
                    *x = clamp(xb, b);
                }
                let mut p = start.params();
                p.push(clamp(xc, cand));
                out.push(p);
            }
        }
        out
    }
}
