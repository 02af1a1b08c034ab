//! The vocabulary: each named effect's kind with its name, unit, allowed
//! values and where it acts, and the ranges of values an effect may take.

use std::fmt;

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
    /// Simulated, not in [`EffectKind::ALL`]: its three parameters are not
    /// yet a diagnosis candidate's.
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
}

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

    /// Every effect, in the order of `physics.md` section 6.
    pub const ALL: [EffectKind; 8] = [
        EffectKind::CoulombFriction,
        EffectKind::ViscousDamping,
        EffectKind::SpringSoftening,
        EffectKind::HarnessStiffness,
        EffectKind::LatchDetent,
        EffectKind::AirDrag,
        EffectKind::RigTilt,
        EffectKind::EncoderOffset,
    ];

    /// The whole vocabulary: every kind the effect syntax reads (its
    /// `FromStr` searches this list), the ones of [`EffectKind::ALL`], the
    /// friction forms, the latch's and the rig's. A test over the
    /// vocabulary iterates this (`tests/findings_roundtrip.rs`).
    pub const EVERY: [EffectKind; 16] = joined(
        joined::<8, 3, 11>(
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
            EffectKind::AirDrag
            | EffectKind::RigTilt
            | EffectKind::RigFriction
            | EffectKind::WireLength
            | EffectKind::FrameOffset => false,
        }
    }

    /// True for effects on the sensor only (the motion is unchanged).
    pub fn is_sensor(self) -> bool {
        match self {
            EffectKind::EncoderOffset => true,
            EffectKind::CoulombFriction
            | EffectKind::ViscousDamping
            | EffectKind::QuadraticDamping
            | EffectKind::StribeckFriction
            | EffectKind::SpringSoftening
            | EffectKind::HarnessStiffness
            | EffectKind::LatchDetent
            | EffectKind::AirDrag
            | EffectKind::RigTilt
            | EffectKind::TorqueTable
            | EffectKind::PlungerWeakening
            | EffectKind::MagnetWeakening
            | EffectKind::RigFriction
            | EffectKind::WireLength
            | EffectKind::FrameOffset => false,
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
