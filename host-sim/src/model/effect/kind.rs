//! The vocabulary: each named effect's kind with its name, unit, allowed
//! values and where it acts, and the ranges of values an effect may take.

use std::fmt;

pub use super::roles::{
    Acts, LatchPart, MarginForm, ResistanceClass, RigPart, Signature, TrussPart, WorstEnd,
};

/// The name of an effect, as written in files and reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EffectKind {
    /// `coulomb_friction`: `T_C` [N·m] at a joint.
    CoulombFriction,
    /// `viscous_damping`: `f` [N·m·s/rad] at a joint.
    ViscousDamping,
    /// `quadratic_damping`: `c` [N·m·s²/rad²] at a joint, the torque
    /// `−c φ̇|φ̇|` (this project's own, `physics.md` §6). Simulated, not in
    /// [`EffectKind::ALL`]: as a candidate it took the place of air drag and
    /// friction in the bundled `b_seed000_eft_air_drag` diagnosis
    /// (`docs/simulator.md`).
    QuadraticDamping,
    /// `stribeck_friction`: the kinetic `T_C` [N·m] at a joint with a
    /// break-away excess `excess_nm` and Stribeck velocity `stribeck_rad_s`
    /// (the friction law of `physics.md` §4; this project's own effect, §6).
    /// Not in [`EffectKind::ALL`]: the diagnosis enters it in its
    /// friction-form step, where the residual torque has its shape, not in
    /// its stepwise rounds.
    StribeckFriction,
    /// `spring_softening`: `s` \[1\], the spring is scaled by `1 − s`.
    SpringSoftening,
    /// `harness_stiffness`: `k_h` [N·m/rad] about the stowed angle.
    HarnessStiffness,
    /// `latch_detent`: `T_d` [N·m] within 3° of the latch.
    LatchDetent,
    /// `air_drag`: `k` [kg/m²], global.
    AirDrag,
    /// `rig_tilt`: `g_t` [m/s²] in direction `alpha_deg`, global.
    RigTilt,
    /// `encoder_offset`: `b` \[deg\] added to a joint's reading (sensor only).
    EncoderOffset,
    /// `torque_table`: tables `f(φ) + g(φ̇)` [N·m] at a joint; not in
    /// [`EffectKind::ALL`] (it has tables, not one value: a diagnosis fits it
    /// only when no named effect explains the data).
    TorqueTable,
    /// `plunger_weakening`: `w` \[1\], the ball plunger of a joint's physical
    /// latch has its preload and rate scaled by `1 − w` (this project's
    /// own; not in [`EffectKind::ALL`]: only a physical latch has one).
    PlungerWeakening,
    /// `magnet_weakening`: `w` \[1\], the magnet of a joint's physical latch
    /// has its force scaled by `1 − w` (this project's own, not in
    /// [`EffectKind::ALL`]).
    MagnetWeakening,
    /// `rig_friction`: `Δμ` \[1\] added to the dynamic friction coefficient
    /// of every rail of the mechanism's `[rig]` (trolleys and bars), the
    /// static one raised in the drawing's ratio `μ_s/μ_d` (`physics.md`
    /// §11.7, this project's own). A rig cause: never flies.
    RigFriction,
    /// `wire_length`: `ΔL` \[m\] added to every suspension wire of the
    /// `[rig]` (`physics.md` §11.7, this project's own). A rig cause.
    WireLength,
    /// `frame_offset`: `Δd` \[m\] by which every test frame of the `[rig]`
    /// stands nearer the panels along its normal (positive: less
    /// clearance; `physics.md` §11.7, this project's own). A rig cause.
    FrameOffset,
    /// `demo_drag`: `c` [N·m·s²/rad²] at a joint, the torque `−c φ̇|φ̇|`
    /// through the core's quadratic damping: the test-only effect of the
    /// `demo-effect` feature, a diagnosis candidate there
    /// (`host-sim/tests/demo_effect.rs`).
    #[cfg(feature = "demo-effect")]
    DemoDrag,
}

/// Number of diagnosis candidates ([`EffectKind::ALL`]).
#[cfg(not(feature = "demo-effect"))]
const CANDIDATES: usize = 8;
/// Number of diagnosis candidates ([`EffectKind::ALL`]).
#[cfg(feature = "demo-effect")]
const CANDIDATES: usize = 9;

impl EffectKind {
    /// The effects on a joint's physical latch
    /// ([`crate::model::latch_toml`]): parsed and simulated, never a
    /// diagnosis candidate (they are not in [`EffectKind::ALL`]).
    pub const LATCH: [EffectKind; 2] = [EffectKind::PlungerWeakening, EffectKind::MagnetWeakening];

    /// The causes of the zero-g rig (`[rig]`, `physics.md` §11.7): parsed,
    /// simulated by the rig simulator, diagnosis candidates only when the
    /// mechanism has an active rig (they are not in [`EffectKind::ALL`]).
    pub const RIG: [EffectKind; 3] = [
        EffectKind::RigFriction,
        EffectKind::WireLength,
        EffectKind::FrameOffset,
    ];

    /// True for the causes of the rig ([`EffectKind::RIG`]).
    pub fn is_rig(self) -> bool {
        EffectKind::RIG.contains(&self)
    }

    /// Every effect a diagnosis proposes in its stepwise rounds, in the
    /// order of `physics.md` section 6.
    #[cfg(not(feature = "demo-effect"))]
    pub const ALL: [EffectKind; CANDIDATES] = [
        EffectKind::CoulombFriction,
        EffectKind::ViscousDamping,
        EffectKind::SpringSoftening,
        EffectKind::HarnessStiffness,
        EffectKind::LatchDetent,
        EffectKind::AirDrag,
        EffectKind::RigTilt,
        EffectKind::EncoderOffset,
    ];
    /// Every effect a diagnosis proposes in its stepwise rounds, in the
    /// order of `physics.md` section 6, and the test-only `demo_drag`.
    #[cfg(feature = "demo-effect")]
    pub const ALL: [EffectKind; CANDIDATES] = [
        EffectKind::CoulombFriction,
        EffectKind::ViscousDamping,
        EffectKind::SpringSoftening,
        EffectKind::HarnessStiffness,
        EffectKind::LatchDetent,
        EffectKind::AirDrag,
        EffectKind::RigTilt,
        EffectKind::EncoderOffset,
        EffectKind::DemoDrag,
    ];

    /// The whole vocabulary: every kind the effect syntax reads (its
    /// `FromStr` searches this list), the ones of [`EffectKind::ALL`], the
    /// friction forms, the latch's and the rig's. A test over the
    /// vocabulary iterates this (`tests/findings_roundtrip.rs`).
    pub const EVERY: [EffectKind; CANDIDATES + 8] = joined(
        joined::<CANDIDATES, 3, { CANDIDATES + 3 }>(
            EffectKind::ALL,
            [
                EffectKind::TorqueTable,
                EffectKind::StribeckFriction,
                EffectKind::QuadraticDamping,
            ],
        ),
        joined::<2, 3, 5>(EffectKind::LATCH, EffectKind::RIG),
    );

    /// The name used in files and reports.
    pub fn name(self) -> &'static str {
        match self {
            EffectKind::CoulombFriction => "coulomb_friction",
            EffectKind::ViscousDamping => "viscous_damping",
            EffectKind::QuadraticDamping => "quadratic_damping",
            EffectKind::StribeckFriction => "stribeck_friction",
            EffectKind::SpringSoftening => "spring_softening",
            EffectKind::HarnessStiffness => "harness_stiffness",
            EffectKind::LatchDetent => "latch_detent",
            EffectKind::AirDrag => "air_drag",
            EffectKind::RigTilt => "rig_tilt",
            EffectKind::EncoderOffset => "encoder_offset",
            EffectKind::TorqueTable => "torque_table",
            EffectKind::PlungerWeakening => "plunger_weakening",
            EffectKind::MagnetWeakening => "magnet_weakening",
            EffectKind::RigFriction => "rig_friction",
            EffectKind::WireLength => "wire_length",
            EffectKind::FrameOffset => "frame_offset",
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => "demo_drag",
        }
    }

    /// The unit of the effect's value.
    pub fn unit(self) -> &'static str {
        match self {
            EffectKind::CoulombFriction | EffectKind::LatchDetent | EffectKind::TorqueTable => {
                "N·m"
            }
            EffectKind::ViscousDamping => "N·m·s/rad",
            EffectKind::QuadraticDamping => "N·m·s²/rad²",
            EffectKind::StribeckFriction => "N·m",
            EffectKind::SpringSoftening
            | EffectKind::PlungerWeakening
            | EffectKind::MagnetWeakening
            | EffectKind::RigFriction => "1",
            EffectKind::WireLength | EffectKind::FrameOffset => "m",
            EffectKind::HarnessStiffness => "N·m/rad",
            EffectKind::AirDrag => "kg/m²",
            EffectKind::RigTilt => "m/s²",
            EffectKind::EncoderOffset => "deg",
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => "N·m·s²/rad²",
        }
    }

    /// The values the effect may take: what keeps it the effect its name
    /// says (a negative friction or stiffness would drive the joint, a
    /// softening of 1 or more removes or reverses the spring). The mechanism
    /// file's friction keys follow the same rule
    /// ([`crate::model::mechanism_toml`]).
    pub fn allowed(self) -> ValueRange {
        match self {
            EffectKind::CoulombFriction
            | EffectKind::ViscousDamping
            | EffectKind::QuadraticDamping
            | EffectKind::StribeckFriction
            | EffectKind::HarnessStiffness
            | EffectKind::LatchDetent
            | EffectKind::AirDrag
            | EffectKind::TorqueTable
            | EffectKind::RigFriction => ValueRange::NonNegative,
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => ValueRange::NonNegative,
            EffectKind::SpringSoftening => ValueRange::BelowOne,
            EffectKind::PlungerWeakening | EffectKind::MagnetWeakening => ValueRange::Fraction,
            EffectKind::RigTilt
            | EffectKind::EncoderOffset
            | EffectKind::WireLength
            | EffectKind::FrameOffset => ValueRange::Finite,
        }
    }

    /// True for effects that act on one joint (`joint` is required).
    pub fn per_joint(self) -> bool {
        match self {
            EffectKind::CoulombFriction
            | EffectKind::ViscousDamping
            | EffectKind::QuadraticDamping
            | EffectKind::StribeckFriction
            | EffectKind::SpringSoftening
            | EffectKind::HarnessStiffness
            | EffectKind::LatchDetent
            | EffectKind::EncoderOffset
            | EffectKind::TorqueTable
            | EffectKind::PlungerWeakening
            | EffectKind::MagnetWeakening => true,
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => true,
            EffectKind::AirDrag
            | EffectKind::RigTilt
            | EffectKind::RigFriction
            | EffectKind::WireLength
            | EffectKind::FrameOffset => false,
        }
    }

    /// True for effects on the sensor only (the motion is unchanged).
    pub fn is_sensor(self) -> bool {
        self.acts() == Acts::Sensor
    }

    /// Where the effect acts: the chain's equations (its law's arm of
    /// [`super::to_core`]), the sensor, a joint's physical latch or the
    /// zero-g rig.
    pub fn acts(self) -> Acts {
        match self {
            EffectKind::CoulombFriction
            | EffectKind::ViscousDamping
            | EffectKind::QuadraticDamping
            | EffectKind::StribeckFriction
            | EffectKind::SpringSoftening
            | EffectKind::HarnessStiffness
            | EffectKind::LatchDetent
            | EffectKind::AirDrag
            | EffectKind::RigTilt
            | EffectKind::TorqueTable => Acts::Chain,
            EffectKind::EncoderOffset => Acts::Sensor,
            EffectKind::PlungerWeakening => Acts::Latch(LatchPart::Plunger),
            EffectKind::MagnetWeakening => Acts::Latch(LatchPart::Magnet),
            EffectKind::RigFriction => Acts::Rig(RigPart::RailFriction),
            EffectKind::WireLength => Acts::Rig(RigPart::WireLength),
            EffectKind::FrameOffset => Acts::Rig(RigPart::FrameOffset),
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => Acts::Chain,
        }
    }

    /// What the effect changes on a pin of a wing with a truss (the
    /// multibody simulator's), `None` where a truss wing does not model it.
    pub fn on_truss(self) -> Option<TrussPart> {
        match self {
            EffectKind::CoulombFriction => Some(TrussPart::Coulomb),
            EffectKind::ViscousDamping => Some(TrussPart::Viscous),
            EffectKind::SpringSoftening => Some(TrussPart::SpringSoftening),
            EffectKind::EncoderOffset => Some(TrussPart::Sensor),
            EffectKind::QuadraticDamping
            | EffectKind::StribeckFriction
            | EffectKind::HarnessStiffness
            | EffectKind::LatchDetent
            | EffectKind::AirDrag
            | EffectKind::RigTilt
            | EffectKind::TorqueTable
            | EffectKind::PlungerWeakening
            | EffectKind::MagnetWeakening
            | EffectKind::RigFriction
            | EffectKind::WireLength
            | EffectKind::FrameOffset => None,
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => None,
        }
    }

    /// How the effect enters the torque margins (`docs/margin.md`, "Every
    /// diagnosed cause in the margin"): its form and the standards' kind
    /// of resistance it counts as.
    pub fn margin(self) -> MarginForm {
        match self {
            EffectKind::CoulombFriction => MarginForm::Coulomb,
            EffectKind::ViscousDamping => MarginForm::Viscous,
            EffectKind::QuadraticDamping => MarginForm::Quadratic,
            EffectKind::StribeckFriction => MarginForm::Breakaway,
            EffectKind::SpringSoftening => MarginForm::Driving,
            EffectKind::HarnessStiffness => MarginForm::Harness,
            EffectKind::LatchDetent => MarginForm::Detent,
            EffectKind::AirDrag => MarginForm::Distributed,
            EffectKind::RigTilt => MarginForm::Tilt,
            EffectKind::EncoderOffset => MarginForm::Sensor,
            EffectKind::TorqueTable => MarginForm::Table,
            EffectKind::PlungerWeakening | EffectKind::MagnetWeakening => MarginForm::LatchLine,
            EffectKind::RigFriction | EffectKind::WireLength | EffectKind::FrameOffset => {
                MarginForm::RigLine
            }
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => MarginForm::Quadratic,
        }
    }

    /// The end of its 95 % interval a found effect counts at in the
    /// margins (`docs/margin.md`, "Each effect at the worst end of its
    /// interval").
    pub fn worst_end(self) -> WorstEnd {
        match self {
            EffectKind::CoulombFriction
            | EffectKind::ViscousDamping
            | EffectKind::StribeckFriction
            | EffectKind::QuadraticDamping
            | EffectKind::HarnessStiffness
            | EffectKind::LatchDetent
            | EffectKind::AirDrag
            | EffectKind::RigFriction
            | EffectKind::SpringSoftening => WorstEnd::Upper,
            EffectKind::RigTilt => WorstEnd::LargerMagnitude,
            EffectKind::TorqueTable => WorstEnd::Resisting,
            EffectKind::EncoderOffset => WorstEnd::Estimate("a sensor effect moves no joint"),
            EffectKind::PlungerWeakening | EffectKind::MagnetWeakening => WorstEnd::Estimate(
                "the latch's line takes the nominal plunger and magnet, stronger than any weakened one",
            ),
            EffectKind::WireLength | EffectKind::FrameOffset => {
                WorstEnd::Estimate("the rig's geometry, not in the hinges' margins")
            }
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => WorstEnd::Upper,
        }
    }

    /// True for the effects that exist only on a ground rig (air in the
    /// room, a rig that is not level, the rig's rails, wires and frames):
    /// none of them flies, so `--flight` leaves them out.
    pub fn rig_only(self) -> bool {
        match self {
            EffectKind::AirDrag
            | EffectKind::RigTilt
            | EffectKind::RigFriction
            | EffectKind::WireLength
            | EffectKind::FrameOffset => true,
            EffectKind::CoulombFriction
            | EffectKind::ViscousDamping
            | EffectKind::QuadraticDamping
            | EffectKind::StribeckFriction
            | EffectKind::SpringSoftening
            | EffectKind::HarnessStiffness
            | EffectKind::LatchDetent
            | EffectKind::EncoderOffset
            | EffectKind::TorqueTable
            | EffectKind::PlungerWeakening
            | EffectKind::MagnetWeakening => false,
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => false,
        }
    }

    /// The shape of the effect's torque per unit of its value at a joint,
    /// which the diagnosis regresses the residual torque on
    /// (`analysis::diagnose::residual_named`); `None` for an effect without
    /// one of its own there.
    pub fn signature(self) -> Option<Signature> {
        match self {
            EffectKind::CoulombFriction => Some(Signature::Coulomb),
            EffectKind::ViscousDamping => Some(Signature::Viscous),
            EffectKind::SpringSoftening => Some(Signature::Spring),
            EffectKind::HarnessStiffness => Some(Signature::FromStowed),
            EffectKind::QuadraticDamping
            | EffectKind::StribeckFriction
            | EffectKind::LatchDetent
            | EffectKind::AirDrag
            | EffectKind::RigTilt
            | EffectKind::EncoderOffset
            | EffectKind::TorqueTable
            | EffectKind::PlungerWeakening
            | EffectKind::MagnetWeakening
            | EffectKind::RigFriction
            | EffectKind::WireLength
            | EffectKind::FrameOffset => None,
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => None,
        }
    }
}

/// The values an effect (or a mechanism file's friction key) may take.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ValueRange {
    /// Any finite number.
    Finite,
    /// A finite number ≥ 0.
    NonNegative,
    /// A finite number < 1 (`spring_softening`: 1 removes the spring).
    BelowOne,
    /// A fraction from 0 to 1 (a weakening: 1 removes the part).
    Fraction,
}

impl ValueRange {
    /// True when `x` is allowed.
    pub fn contains(self, x: f64) -> bool {
        x.is_finite()
            && match self {
                ValueRange::Finite => true,
                ValueRange::NonNegative => x >= 0.0,
                ValueRange::BelowOne => x < 1.0,
                ValueRange::Fraction => (0.0..=1.0).contains(&x),
            }
    }

    /// The range in words, e.g. "a finite number ≥ 0".
    pub fn describe(self) -> &'static str {
        match self {
            ValueRange::Finite => "a finite number",
            ValueRange::NonNegative => "a finite number ≥ 0",
            ValueRange::BelowOne => "a finite number < 1 (1 removes the spring, more reverses it)",
            ValueRange::Fraction => "a fraction from 0 to 1 (1 removes the part)",
        }
    }
}

/// `a`, then `b` (`K = N + M`, checked when the constant is built).
const fn joined<const N: usize, const M: usize, const K: usize>(
    a: [EffectKind; N],
    b: [EffectKind; M],
) -> [EffectKind; K] {
    assert!(N + M == K, "K must be N + M");
    let mut out = [EffectKind::CoulombFriction; K];
    let mut i = 0;
    while i < K {
        out[i] = if i < N { a[i] } else { b[i - N] };
        i += 1;
    }
    out
}

impl fmt::Display for EffectKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
