//! Quasi-static creep of one joint over the rest of its stroke, and the
//! snap-through from its capture angle to the latch: how a rollout
//! ([`crate::monitor::rollout`]) ends once every free joint creeps.

use crate::physics::friction::coulomb_shape;
use crate::physics::spring::Branch;

/// Sub-intervals of the creep quadrature.
const CREEP_PANELS: usize = 8;

/// Step of the one-joint snap-through integration \[s\].
const SNAP_DT_S: f32 = 0.002;

/// Longest snap-through from a creep the quadrature integrates \[s\]; a
/// longer one is left to the rollout.
const SNAP_LIMIT_S: f32 = 0.5;

/// What quasi-static creep does over the rest of a joint's stroke.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Creep {
    /// The joint creeps to its capture angle and snaps through to the latch
    /// in this time \[s\] (past the horizon: in no less).
    Covers(f32),
    /// The spring overcomes the Coulomb torque before the capture angle
    /// after this time \[s\] of creep (the joint breaks free and
    /// accelerates), or the snap-through takes longer than
    /// [`SNAP_LIMIT_S`]: the rollout has to go on.
    BreaksFree(f32),
    /// The spring cannot move the joint (no torque inwards).
    Stops,
}

/// One creeping joint, for `creep`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreepJoint {
    /// `|φ|` now \[rad\].
    pub from_rad: f32,
    /// Capture angle \[rad\] (0 without a snap-through).
    pub capture_rad: f32,
    /// Factor on the spring torque \[1\].
    pub spring_scale: f32,
    /// Coulomb torque `T_C` [N·m].
    pub coulomb_nm: f32,
    /// Viscous coefficient `f` [N·m·s/rad].
    pub viscous_nms: f32,
    /// Articulated inertia `1/(M⁻¹)_jj` [kg·m²] (for the snap-through).
    pub inertia_kgm2: f32,
}

/// Quasi-static creep of one joint from `|φ| = from_rad` to its capture
/// angle, then the snap-through to the latch. With inertia negligible the
/// friction balances the spring,
///
/// ```text
/// T_C tanh(ω/ω_c) + f ω = s τ_s(φ)  ⇒  ω ≈ ω_c artanh(s τ_s / T_C)
/// ```
/// (plus one Newton step for `f`), while `s τ_s < T_C`; the time is
/// `∫ dφ / ω(φ)` by the midpoint rule over [`CREEP_PANELS`] panels. The
/// creep rate grows as the spring torque grows along the stroke, so this is
/// where a constant-rate extrapolation would call a stall too early.
///
/// A joint that creeps up to the capture angle does not latch there: it
/// breaks free where the spring's snap-through peak first exceeds `T_C`
/// and accelerates from its creep rate, which with the whole outer chain to
/// move takes a few tenths of a second. That part is integrated for the
/// joint alone, `I φ̈ = s τ_s − T_C tanh(ω/ω_c) − f ω` with `I` its
/// articulated inertia, in steps of [`SNAP_DT_S`] linearly implicit in the
/// friction.
///
/// `horizon_s` is the time that matters \[s\]: the integration stops once it
/// is passed (the joint does not latch within it either way).
#[cfg(test)]
pub fn creep(
    spring: &crate::physics::spring::Spring<f32>,
    joint: &CreepJoint,
    wc: f32,
    horizon_s: f32,
) -> Creep {
    let mut run = CreepRun::new(*joint, wc, horizon_s);
    loop {
        let mut budget = u16::MAX;
        if let Some(out) = run.run(spring, &mut budget) {
            return out;
        }
    }
}

/// `creep` in progress: resumable, a bounded number of spring
/// evaluations at a time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreepRun {
    joint: CreepJoint,
    wc: f32,
    horizon_s: f32,
    stage: CreepStage,
}

/// Where a [`CreepRun`] is.
#[derive(Clone, Copy, Debug, PartialEq)]
enum CreepStage {
    /// Panel `k` of the quadrature next, `t` \[s\] of creep so far.
    Quadrature { k: u8, t: f32 },
    /// The snap-through: creep time `t` \[s\], `|φ|` \[rad\], rate `w`
    /// [rad/s] and time of the snap so far \[s\].
    Snap { t: f32, abs: f32, w: f32, snap: f32 },
}

impl CreepRun {
    /// The creep of `joint` (see `creep`), not yet begun.
    pub fn new(joint: CreepJoint, wc: f32, horizon_s: f32) -> Self {
        CreepRun {
            joint,
            wc,
            horizon_s,
            stage: CreepStage::Quadrature { k: 0, t: 0.0 },
        }
    }

    /// Goes on for at most `budget` spring evaluations (taken off it);
    /// `Some` once the outcome is known, `None` when the budget ran out.
    pub fn run(
        &mut self,
        spring: &crate::physics::spring::Spring<f32>,
        budget: &mut u16,
    ) -> Option<Creep> {
        loop {
            if *budget == 0 {
                return None;
            }
            *budget -= 1;
            let outcome = match self.stage {
                CreepStage::Quadrature { k, t } => self.quadrature(spring, k, t),
                CreepStage::Snap { t, abs, w, snap } => self.snap(spring, t, abs, w, snap),
            };
            if outcome.is_some() {
                return outcome;
            }
        }
    }

    /// Panel `k` of the quadrature after `t` \[s\] of creep, or, past the
    /// last panel, the start of the snap-through from the capture angle at
    /// the creep rate there. `Some` once the outcome is known.
    fn quadrature(
        &mut self,
        spring: &crate::physics::spring::Spring<f32>,
        k: u8,
        mut t: f32,
    ) -> Option<Creep> {
        let joint = self.joint;
        let wc = self.wc;
        let (scale, tc, f) = (joint.spring_scale, joint.coulomb_nm, joint.viscous_nms);
        let to_rad = joint.capture_rad.max(0.0);
        let span = joint.from_rad - to_rad;
        if span > 0.0 && usize::from(k) < CREEP_PANELS {
            let h = span / CREEP_PANELS as f32;
            let abs = joint.from_rad - (f32::from(k) + 0.5) * h;
            let torque = scale * spring.magnitude(abs, Branch::Unfold);
            if !(torque > 0.0) {
                return Some(Creep::Stops);
            }
            if !(torque < tc) {
                return Some(Creep::BreaksFree(t));
            }
            match creep_rate(torque, tc, f, wc) {
                Some(w) => t += h / w,
                None => return Some(Creep::Stops),
            }
            self.stage = CreepStage::Quadrature { k: k + 1, t };
            return None;
        }
        let abs = to_rad.min(joint.from_rad.max(0.0));
        let w = creep_rate(scale * spring.magnitude(abs, Branch::Unfold), tc, f, wc).unwrap_or(0.0);
        if !(joint.inertia_kgm2 > 0.0) {
            return Some(Creep::BreaksFree(t));
        }
        self.stage = CreepStage::Snap {
            t,
            abs,
            w,
            snap: 0.0,
        };
        None
    }

    /// One step of the snap-through after `t` \[s\] of creep, at `|φ|` =
    /// `abs` \[rad\] with rate `w` [rad/s], `snap` \[s\] into it. `Some` once
    /// the outcome is known.
    fn snap(
        &mut self,
        spring: &crate::physics::spring::Spring<f32>,
        t: f32,
        mut abs: f32,
        mut w: f32,
        mut snap: f32,
    ) -> Option<Creep> {
        let joint = self.joint;
        let wc = self.wc;
        let (scale, tc, f) = (joint.spring_scale, joint.coulomb_nm, joint.viscous_nms);
        let inertia = joint.inertia_kgm2;
        if abs > 0.0 {
            if t + snap > self.horizon_s {
                return Some(Creep::Covers(t + snap));
            }
            if snap >= SNAP_LIMIT_S {
                return Some(Creep::BreaksFree(t + snap));
            }
            let th = coulomb_shape(w, wc);
            let torque = scale * spring.magnitude(abs, Branch::Unfold) - tc * th - f * w;
            let damping = tc * (1.0 - th * th) / wc + f;
            let dw = SNAP_DT_S * torque / (inertia + SNAP_DT_S * damping);
            let step = SNAP_DT_S * (w + 0.5 * dw);
            if !step.is_finite() {
                return Some(Creep::Stops);
            }
            if !(step >= abs && step > 0.0) {
                abs -= step;
                w += dw;
                snap += SNAP_DT_S;
                self.stage = CreepStage::Snap { t, abs, w, snap };
                return None;
            }
            snap += SNAP_DT_S * abs / step;
        }
        let total = t + snap;
        Some(if total.is_finite() {
            Creep::Covers(total)
        } else {
            Creep::Stops
        })
    }
}

/// The quasi-static creep rate [rad/s] under a spring torque `torque`
/// below `T_C`: `ω_c artanh(τ/T_C)`, then one Newton step on
/// `T_C tanh(ω/ω_c) + f ω − τ = 0` for the viscous part. `None` when the
/// spring cannot move the joint or overcomes the friction.
fn creep_rate(torque: f32, tc: f32, f: f32, wc: f32) -> Option<f32> {
    if !(torque > 0.0) || !(torque < tc) {
        return None;
    }
    let w0 = wc * libm::atanhf(torque / tc);
    let th = libm::tanhf(w0 / wc);
    let slope = tc * (1.0 - th * th) / wc + f;
    let w = if slope > 0.0 { w0 - f * w0 / slope } else { w0 };
    (w > 0.0 && w.is_finite()).then_some(w)
}
