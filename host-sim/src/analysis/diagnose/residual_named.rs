//! Named effects proposed by the residual torque: at one joint, the torque
//! the model lacks is regressed on the signatures of the named joint
//! effects of `physics.md` section 6,
//!
//! ```text
//! coulomb_friction   −tanh(φ̇ / 0.01)        × T_C
//! viscous_damping    −φ̇                     × f
//! spring_softening   −τ_spring(φ)           × s
//! harness_stiffness  (φ_stowed − φ)         × k_h
//! ```
//!
//! alone and in pairs, by weighted least squares (no simulation), and the
//! best by BIC is proposed. Two causes at one joint (a softened spring with
//! friction, say) show here as a pair that fits the residual torque far
//! better than either alone, where a stepwise search through the simulator
//! may settle on stand-ins.

use crate::analysis::diagnose::residual_shape::{bic, thin};
use crate::analysis::diagnose::residual_torque::{JointTorque, TorqueSample};
use crate::model::effect::{EffectKind, Signature};

/// The named joint effects with a torque signature
/// ([`EffectKind::signature`]; a test checks the list against it).
pub const KINDS: [EffectKind; 4] = [
    EffectKind::CoulombFriction,
    EffectKind::ViscousDamping,
    EffectKind::SpringSoftening,
    EffectKind::HarnessStiffness,
];

/// A pair is proposed when its BIC beats the best single effect's by more
/// than this (Kass & Raftery's "very strong").
pub const MIN_PAIR_GAIN: f64 = 10.0;

/// A named effect's torque per unit of its value at a sample [N·m per
/// unit] ([`EffectKind::signature`]); `None` for an effect without one
/// (not in [`KINDS`]).
pub fn signature(kind: EffectKind, s: &TorqueSample) -> Option<f64> {
    let g = kind.signature()?;
    Some(g.at(s.rate_deg_s.to_radians(), s.spring_nm, s.from_stowed_rad))
}

/// Named effects that explain one joint's residual torque, with their
/// values and the fit's BIC.
#[derive(Clone, Debug, PartialEq)]
pub struct Proposal {
    /// 1-based joint.
    pub joint: usize,
    /// The effects and their values (in each kind's unit).
    pub effects: Vec<(EffectKind, f64)>,
    /// BIC of the fit to the residual torque.
    pub bic: f64,
}

/// Weighted least squares of the samples on the signatures of `kinds`:
/// the values and the weighted RSS. `None` when singular, a value is not
/// positive (every named effect here has a positive value) or a kind has
/// no signature.
pub fn fit(samples: &[TorqueSample], kinds: &[EffectKind]) -> Option<(Vec<f64>, f64)> {
    let sigs: Option<Vec<Signature>> = kinds.iter().map(|k| k.signature()).collect();
    let cols: Vec<Column> = sigs?
        .into_iter()
        .map(|g| {
            Box::new(move |s: &TorqueSample| {
                g.at(s.rate_deg_s.to_radians(), s.spring_nm, s.from_stowed_rad)
            }) as Column
        })
        .collect();
    let refs: Vec<&dyn Fn(&TorqueSample) -> f64> = cols.iter().map(|c| c.as_ref()).collect();
    lsq(samples, &refs)
}

/// A column of [`lsq`]: a sample's torque per unit of value.
type Column = Box<dyn Fn(&TorqueSample) -> f64>;

/// Weighted least squares (weights `1/se²`) of the samples' torque on one
/// or two columns (a column: a sample's torque per unit of value): the
/// values and the weighted RSS; `None` when singular or a value is not
/// positive (every law fitted this way resists).
pub fn lsq(
    samples: &[TorqueSample],
    cols: &[&dyn Fn(&TorqueSample) -> f64],
) -> Option<(Vec<f64>, f64)> {
    let k = cols.len();
    let (mut a, mut b) = ([[0.0; 2]; 2], [0.0; 2]);
    for s in samples {
        let w = 1.0 / s.se_nm.max(1e-9).powi(2);
        let x: Vec<f64> = cols.iter().map(|c| c(s)).collect();
        for i in 0..k {
            b[i] += w * x[i] * s.torque_nm;
            for j in 0..k {
                a[i][j] += w * x[i] * x[j];
            }
        }
    }
    let v = match k {
        1 if a[0][0] > 0.0 => vec![b[0] / a[0][0]],
        2 => {
            let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
            if det.abs() <= 1e-12 * a[0][0] * a[1][1] {
                return None;
            }
            vec![
                (b[0] * a[1][1] - b[1] * a[0][1]) / det,
                (b[1] * a[0][0] - b[0] * a[1][0]) / det,
            ]
        }
        _ => return None,
    };
    if v.iter().any(|x| !(*x > 0.0)) {
        return None;
    }
    let rss = samples
        .iter()
        .map(|s| {
            let m: f64 = cols.iter().zip(&v).map(|(c, x)| x * c(s)).sum();
            ((s.torque_nm - m) / s.se_nm.max(1e-9)).powi(2)
        })
        .sum();
    Some((v, rss))
}

/// The best named pair at a joint with a significant residual torque, when
/// it beats the best single effect by [`MIN_PAIR_GAIN`]; `None` otherwise
/// (a single effect the stepwise search finds itself).
pub fn propose_pair(jt: &JointTorque) -> Option<Proposal> {
    if !jt.significant {
        return None;
    }
    let samples = thin(&jt.samples);
    let score = |kinds: &[EffectKind]| -> Option<Proposal> {
        let (v, rss) = fit(&samples, kinds)?;
        Some(Proposal {
            joint: jt.joint,
            effects: kinds.iter().copied().zip(v).collect(),
            bic: bic(&samples, rss, kinds.len()),
        })
    };
    let best = |it: Vec<Proposal>| it.into_iter().min_by(|a, b| a.bic.total_cmp(&b.bic));
    let single = best(KINDS.iter().filter_map(|&k| score(&[k])).collect());
    let mut pairs = Vec::new();
    for a in 0..KINDS.len() {
        for b in a + 1..KINDS.len() {
            pairs.extend(score(&[KINDS[a], KINDS[b]]));
        }
    }
    let pair = best(pairs)?;
    match single {
        Some(s) if s.bic - pair.bic <= MIN_PAIR_GAIN => None,
        _ => Some(pair),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`KINDS`] is every kind of the vocabulary with a signature, in its
    /// order.
    #[test]
    fn kinds_are_the_vocabulary_with_a_signature() {
        let with: Vec<EffectKind> = EffectKind::EVERY
            .into_iter()
            .filter(|k| k.signature().is_some())
            .collect();
        assert_eq!(with, KINDS.to_vec());
    }
}
