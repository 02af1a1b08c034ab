//! Each named effect's law with its own parameters: [`Law`], one variant per
//! [`EffectKind`], and what depends on the parameters (the value, the
//! `--effect` keys beyond `value`, the core chain's tables).

use super::fit::STRIBECK_RATE_RANGE;
use super::kind::EffectKind;
use crate::model::torque_table::{self, HostJointEffects, HostTorqueTable};
use deploywatch_core::GlobalEffects;

/// A named effect's law and its parameters, in the units of `physics.md`
/// section 6. The variant is the kind ([`Law::kind`]); a law of one value
/// holds it in the kind's [`EffectKind::unit`].
// A table inline, as the core's joint tables hold it: an effect stays
// `Copy`, the size of the effect struct it replaces.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Law {
    /// `coulomb_friction`: `T_C` [N·m].
    CoulombFriction(f64),
    /// `viscous_damping`: `f` [N·m·s/rad].
    ViscousDamping(f64),
    /// `quadratic_damping`: `c` [N·m·s²/rad²].
    QuadraticDamping(f64),
    /// `stribeck_friction`: the friction law of `physics.md` §4 at a joint.
    StribeckFriction {
        /// The kinetic (Coulomb) level `T_C` [N·m].
        kinetic_nm: f64,
        /// The break-away excess `T_brk − T_C` [N·m].
        excess_nm: f64,
        /// The Stribeck velocity `ω_st` [rad/s].
        rate_rad_s: f64,
    },
    /// `spring_softening`: `s` \[1\].
    SpringSoftening(f64),
    /// `harness_stiffness`: `k_h` [N·m/rad].
    HarnessStiffness(f64),
    /// `latch_detent`: `T_d` [N·m].
    LatchDetent(f64),
    /// `air_drag`: `k` [kg/m²].
    AirDrag(f64),
    /// `rig_tilt`: the tilt's gravity.
    RigTilt {
        /// Its magnitude `g_t` [m/s²].
        g_m_s2: f64,
        /// Its direction \[deg\].
        alpha_deg: f64,
    },
    /// `encoder_offset`: `b` \[deg\].
    EncoderOffset(f64),
    /// `torque_table`: the tables `f(φ) + g(φ̇)` [N·m].
    TorqueTable(HostTorqueTable),
    /// `plunger_weakening`: `w` \[1\].
    PlungerWeakening(f64),
    /// `magnet_weakening`: `w` \[1\].
    MagnetWeakening(f64),
    /// `rig_friction`: `Δμ` \[1\].
    RigFriction(f64),
    /// `wire_length`: `ΔL` \[m\].
    WireLength(f64),
    /// `frame_offset`: `Δd` \[m\].
    FrameOffset(f64),
    /// `demo_drag`: `c` [N·m·s²/rad²] (the `demo-effect` feature's).
    #[cfg(feature = "demo-effect")]
    DemoDrag(f64),
}

/// A parameter of a law beyond its value, as the effect syntax
/// (`--effect`) and the findings JSON name it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    /// `rig_tilt`'s direction \[deg\].
    AlphaDeg,
    /// `stribeck_friction`'s break-away excess [N·m].
    ExcessNm,
    /// `stribeck_friction`'s Stribeck velocity [rad/s].
    StribeckRadS,
    /// A `torque_table`'s angle knots \[deg\].
    AngleDeg,
    /// A `torque_table`'s torques at its angle knots [N·m].
    TorqueNm,
    /// A `torque_table`'s rate knots [deg/s].
    RateDegS,
    /// A `torque_table`'s torques at its rate knots [N·m].
    RateTorqueNm,
}

impl Key {
    /// The key as written.
    pub fn name(self) -> &'static str {
        match self {
            Key::AlphaDeg => "alpha_deg",
            Key::ExcessNm => "excess_nm",
            Key::StribeckRadS => "stribeck_rad_s",
            Key::AngleDeg => "angle_deg",
            Key::TorqueNm => "torque_nm",
            Key::RateDegS => "rate_deg_s",
            Key::RateTorqueNm => "rate_torque_nm",
        }
    }
}

impl Law {
    /// The law's parameters beyond its value, in the order the effect
    /// syntax writes them, each with its numbers (one, or a table's knots;
    /// a table's absent part left out).
    pub fn keys(&self) -> Vec<(Key, Vec<f64>)> {
        match self {
            Law::RigTilt { alpha_deg, .. } => vec![(Key::AlphaDeg, vec![*alpha_deg])],
            Law::StribeckFriction {
                excess_nm,
                rate_rad_s,
                ..
            } => vec![
                (Key::ExcessNm, vec![*excess_nm]),
                (Key::StribeckRadS, vec![*rate_rad_s]),
            ],
            Law::TorqueTable(t) => {
                let mut out = Vec::new();
                if let Some(f) = &t.angle {
                    out.push((Key::AngleDeg, f.xs().to_vec()));
                    out.push((Key::TorqueNm, f.ys().to_vec()));
                }
                if let Some(g) = &t.rate {
                    out.push((Key::RateDegS, g.xs().to_vec()));
                    out.push((Key::RateTorqueNm, g.ys().to_vec()));
                }
                out
            }
            // One value: `value` holds it.
            Law::CoulombFriction(_)
            | Law::ViscousDamping(_)
            | Law::QuadraticDamping(_)
            | Law::SpringSoftening(_)
            | Law::HarnessStiffness(_)
            | Law::LatchDetent(_)
            | Law::AirDrag(_)
            | Law::EncoderOffset(_)
            | Law::PlungerWeakening(_)
            | Law::MagnetWeakening(_)
            | Law::RigFriction(_)
            | Law::WireLength(_)
            | Law::FrameOffset(_) => Vec::new(),
            #[cfg(feature = "demo-effect")]
            Law::DemoDrag(_) => Vec::new(),
        }
    }

    /// The law of `kind` with the value `x` (in [`EffectKind::unit`]) and
    /// its other parameters at zero: a `rig_tilt` towards 0°, a
    /// `stribeck_friction` without excess (Coulomb friction), a
    /// `torque_table` with no table (a table has no one value).
    pub fn of_value(kind: EffectKind, x: f64) -> Law {
        match kind {
            EffectKind::CoulombFriction => Law::CoulombFriction(x),
            EffectKind::ViscousDamping => Law::ViscousDamping(x),
            EffectKind::QuadraticDamping => Law::QuadraticDamping(x),
            EffectKind::StribeckFriction => Law::StribeckFriction {
                kinetic_nm: x,
                excess_nm: 0.0,
                rate_rad_s: 0.0,
            },
            EffectKind::SpringSoftening => Law::SpringSoftening(x),
            EffectKind::HarnessStiffness => Law::HarnessStiffness(x),
            EffectKind::LatchDetent => Law::LatchDetent(x),
            EffectKind::AirDrag => Law::AirDrag(x),
            EffectKind::RigTilt => Law::RigTilt {
                g_m_s2: x,
                alpha_deg: 0.0,
            },
            EffectKind::EncoderOffset => Law::EncoderOffset(x),
            EffectKind::TorqueTable => Law::TorqueTable(HostTorqueTable::default()),
            EffectKind::PlungerWeakening => Law::PlungerWeakening(x),
            EffectKind::MagnetWeakening => Law::MagnetWeakening(x),
            EffectKind::RigFriction => Law::RigFriction(x),
            EffectKind::WireLength => Law::WireLength(x),
            EffectKind::FrameOffset => Law::FrameOffset(x),
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => Law::DemoDrag(x),
        }
    }

    /// The law of `kind` made of a diagnosis's fitted parameters `p` (in
    /// the order of [`EffectKind::bounds`]): a tilt from its Cartesian
    /// components, a Stribeck law from `T_C`, `ΔT`, `ω_st`, any other law
    /// from its value (a `torque_table` is made by its table form).
    pub fn of_params(kind: EffectKind, p: &[f64]) -> Law {
        let x = p.first().copied().unwrap_or(0.0);
        match Law::of_value(kind, x) {
            Law::RigTilt { .. } => {
                let y = p.get(1).copied().unwrap_or(0.0);
                Law::RigTilt {
                    g_m_s2: x.hypot(y),
                    alpha_deg: y.atan2(x).to_degrees().rem_euclid(360.0),
                }
            }
            Law::StribeckFriction { kinetic_nm, .. } => Law::StribeckFriction {
                kinetic_nm,
                excess_nm: p.get(1).copied().unwrap_or(0.0),
                rate_rad_s: p.get(2).copied().unwrap_or(STRIBECK_RATE_RANGE[1]),
            },
            law @ (Law::CoulombFriction(_)
            | Law::ViscousDamping(_)
            | Law::QuadraticDamping(_)
            | Law::SpringSoftening(_)
            | Law::HarnessStiffness(_)
            | Law::LatchDetent(_)
            | Law::AirDrag(_)
            | Law::EncoderOffset(_)
            | Law::TorqueTable(_)
            | Law::PlungerWeakening(_)
            | Law::MagnetWeakening(_)
            | Law::RigFriction(_)
            | Law::WireLength(_)
            | Law::FrameOffset(_)) => law,
            #[cfg(feature = "demo-effect")]
            law @ Law::DemoDrag(_) => law,
        }
    }

    /// The law of `kind` as the effect syntax gives it: its value, with
    /// `rig_tilt`'s direction `alpha_deg` \[deg\] and
    /// `stribeck_friction`'s excess [N·m] and velocity [rad/s] (read and
    /// left unused by the other kinds).
    pub(super) fn of_syntax(
        kind: EffectKind,
        value: f64,
        alpha_deg: f64,
        excess_nm: f64,
        rate_rad_s: f64,
    ) -> Law {
        match Law::of_value(kind, value) {
            Law::RigTilt { g_m_s2, .. } => Law::RigTilt { g_m_s2, alpha_deg },
            Law::StribeckFriction { kinetic_nm, .. } => Law::StribeckFriction {
                kinetic_nm,
                excess_nm,
                rate_rad_s,
            },
            law @ (Law::CoulombFriction(_)
            | Law::ViscousDamping(_)
            | Law::QuadraticDamping(_)
            | Law::SpringSoftening(_)
            | Law::HarnessStiffness(_)
            | Law::LatchDetent(_)
            | Law::AirDrag(_)
            | Law::EncoderOffset(_)
            | Law::TorqueTable(_)
            | Law::PlungerWeakening(_)
            | Law::MagnetWeakening(_)
            | Law::RigFriction(_)
            | Law::WireLength(_)
            | Law::FrameOffset(_)) => law,
            #[cfg(feature = "demo-effect")]
            law @ Law::DemoDrag(_) => law,
        }
    }

    /// The law's kind.
    pub fn kind(&self) -> EffectKind {
        match self {
            Law::CoulombFriction(_) => EffectKind::CoulombFriction,
            Law::ViscousDamping(_) => EffectKind::ViscousDamping,
            Law::QuadraticDamping(_) => EffectKind::QuadraticDamping,
            Law::StribeckFriction { .. } => EffectKind::StribeckFriction,
            Law::SpringSoftening(_) => EffectKind::SpringSoftening,
            Law::HarnessStiffness(_) => EffectKind::HarnessStiffness,
            Law::LatchDetent(_) => EffectKind::LatchDetent,
            Law::AirDrag(_) => EffectKind::AirDrag,
            Law::RigTilt { .. } => EffectKind::RigTilt,
            Law::EncoderOffset(_) => EffectKind::EncoderOffset,
            Law::TorqueTable(_) => EffectKind::TorqueTable,
            Law::PlungerWeakening(_) => EffectKind::PlungerWeakening,
            Law::MagnetWeakening(_) => EffectKind::MagnetWeakening,
            Law::RigFriction(_) => EffectKind::RigFriction,
            Law::WireLength(_) => EffectKind::WireLength,
            Law::FrameOffset(_) => EffectKind::FrameOffset,
            #[cfg(feature = "demo-effect")]
            Law::DemoDrag(_) => EffectKind::DemoDrag,
        }
    }

    /// The law's value, in [`EffectKind::unit`]: its one value, a Stribeck
    /// law's kinetic level, a tilt's magnitude, a table's largest absolute
    /// torque [N·m].
    pub fn value(&self) -> f64 {
        match *self {
            Law::CoulombFriction(x)
            | Law::ViscousDamping(x)
            | Law::QuadraticDamping(x)
            | Law::SpringSoftening(x)
            | Law::HarnessStiffness(x)
            | Law::LatchDetent(x)
            | Law::AirDrag(x)
            | Law::EncoderOffset(x)
            | Law::PlungerWeakening(x)
            | Law::MagnetWeakening(x)
            | Law::RigFriction(x)
            | Law::WireLength(x)
            | Law::FrameOffset(x) => x,
            #[cfg(feature = "demo-effect")]
            Law::DemoDrag(x) => x,
            Law::StribeckFriction { kinetic_nm, .. } => kinetic_nm,
            Law::RigTilt { g_m_s2, .. } => g_m_s2,
            Law::TorqueTable(ref t) => torque_table::max_abs_nm(t),
        }
    }

    /// The law with its value [`Law::value`] set to `x`, its other
    /// parameters kept (a table, which has no one value, is kept whole).
    pub fn with_value(self, x: f64) -> Law {
        match self {
            Law::CoulombFriction(_) => Law::CoulombFriction(x),
            Law::ViscousDamping(_) => Law::ViscousDamping(x),
            Law::QuadraticDamping(_) => Law::QuadraticDamping(x),
            Law::StribeckFriction {
                excess_nm,
                rate_rad_s,
                ..
            } => Law::StribeckFriction {
                kinetic_nm: x,
                excess_nm,
                rate_rad_s,
            },
            Law::SpringSoftening(_) => Law::SpringSoftening(x),
            Law::HarnessStiffness(_) => Law::HarnessStiffness(x),
            Law::LatchDetent(_) => Law::LatchDetent(x),
            Law::AirDrag(_) => Law::AirDrag(x),
            Law::RigTilt { alpha_deg, .. } => Law::RigTilt {
                g_m_s2: x,
                alpha_deg,
            },
            Law::EncoderOffset(_) => Law::EncoderOffset(x),
            Law::TorqueTable(t) => Law::TorqueTable(t),
            Law::PlungerWeakening(_) => Law::PlungerWeakening(x),
            Law::MagnetWeakening(_) => Law::MagnetWeakening(x),
            Law::RigFriction(_) => Law::RigFriction(x),
            Law::WireLength(_) => Law::WireLength(x),
            Law::FrameOffset(_) => Law::FrameOffset(x),
            #[cfg(feature = "demo-effect")]
            Law::DemoDrag(_) => Law::DemoDrag(x),
        }
    }

    /// The law added to a joint's core tables `at` and the chain's global
    /// ones `g`. The laws that are not the chain's add nothing: the
    /// sensor's offset ([`super::encoder_offsets_deg`]), the physical
    /// latch's weakenings (`simulate::latch_deployment::setup::weakenings`)
    /// and the rig's causes ([`crate::model::rig::Rig::with_effects`]).
    pub(super) fn add_to_core(&self, at: &mut HostJointEffects, g: &mut GlobalEffects<f64>) {
        match *self {
            Law::CoulombFriction(x) => at.coulomb_nm += x,
            Law::ViscousDamping(x) => at.viscous_nms += x,
            Law::QuadraticDamping(x) => at.quadratic_nms2_per_rad2 += x,
            // The core's quadratic damping: a new law of existing parameters.
            #[cfg(feature = "demo-effect")]
            Law::DemoDrag(x) => at.quadratic_nms2_per_rad2 += x,
            Law::StribeckFriction {
                kinetic_nm,
                excess_nm,
                rate_rad_s,
            } => {
                // The kinetic level is Coulomb friction; the excess and its
                // velocity are the law's Stribeck term (the last one given).
                at.coulomb_nm += kinetic_nm;
                at.stribeck_excess_nm += excess_nm;
                at.stribeck_rad_s = rate_rad_s;
            }
            Law::SpringSoftening(x) => {
                // Two softenings compose: (1 − s1)(1 − s2).
                let s = at.spring_softening;
                at.spring_softening = 1.0 - (1.0 - s) * (1.0 - x);
            }
            Law::HarnessStiffness(x) => at.harness_nm_per_rad += x,
            Law::LatchDetent(x) => at.detent_nm += x,
            Law::TorqueTable(t) => at.table = t,
            Law::AirDrag(x) => g.air_drag_kg_m2 += x,
            Law::RigTilt { g_m_s2, alpha_deg } => {
                g.tilt_m_s2 = g_m_s2;
                g.tilt_alpha_rad = alpha_deg.to_radians();
            }
            Law::EncoderOffset(_)
            | Law::PlungerWeakening(_)
            | Law::MagnetWeakening(_)
            | Law::RigFriction(_)
            | Law::WireLength(_)
            | Law::FrameOffset(_) => {}
        }
    }
}
