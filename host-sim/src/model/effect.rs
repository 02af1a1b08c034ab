//! The named effects of `docs/spec/physics.md` section 6: the vocabulary a
//! diagnosis reports, and the extras `deploywatch simulate --effect` adds.

use crate::model::torque_table::{
    self, HostJointEffects, HostTorqueTable, TableError, TablePoints,
};
use deploywatch_core::GlobalEffects;
use std::fmt;
use std::str::FromStr;

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
    pub const EVERY: [EffectKind; 16] = [
        EffectKind::CoulombFriction,
        EffectKind::ViscousDamping,
        EffectKind::SpringSoftening,
        EffectKind::HarnessStiffness,
        EffectKind::LatchDetent,
        EffectKind::AirDrag,
        EffectKind::RigTilt,
        EffectKind::EncoderOffset,
        EffectKind::TorqueTable,
        EffectKind::StribeckFriction,
        EffectKind::QuadraticDamping,
        EffectKind::PlungerWeakening,
        EffectKind::MagnetWeakening,
        EffectKind::RigFriction,
        EffectKind::WireLength,
        EffectKind::FrameOffset,
    ];

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
        !matches!(
            self,
            EffectKind::AirDrag
                | EffectKind::RigTilt
                | EffectKind::RigFriction
                | EffectKind::WireLength
                | EffectKind::FrameOffset
        )
    }

    /// True for effects on the sensor only (the motion is unchanged).
    pub fn is_sensor(self) -> bool {
        matches!(self, EffectKind::EncoderOffset)
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

/// Why an effect was rejected: its `--effect` text, or its joint or value.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EffectError {
    /// Not one of the names of `physics.md` section 6.
    #[error("unknown effect `{name}`: expected one of {}", effect_names())]
    UnknownName {
        /// The name given.
        name: String,
    },
    /// A part of the `--effect` text that is not `key=value`.
    #[error("`{part}` in `{text}`: expected key=value")]
    NotKeyValue {
        /// The part.
        part: String,
        /// The whole text.
        text: String,
    },
    /// A key other than `joint`, `value`, `alpha_deg`.
    #[error("unknown key `{key}` in `{text}`: expected joint, value or alpha_deg")]
    UnknownKey {
        /// The key.
        key: String,
        /// The whole text.
        text: String,
    },
    /// A value that does not parse.
    #[error("`{key}={value}` in `{text}`: expected {expected}")]
    BadNumber {
        /// The key.
        key: String,
        /// The value as written.
        value: String,
        /// The whole text.
        text: String,
        /// What was expected.
        expected: &'static str,
    },
    /// A `torque_table` whose points are not a table.
    #[error("`{text}`: {source}")]
    Table {
        /// The whole text.
        text: String,
        /// What is wrong with the points.
        #[source]
        source: TableError,
    },
    /// Table keys on an effect other than `torque_table`.
    #[error("`{text}`: only torque_table takes angle_deg/torque_nm/rate_deg_s/rate_torque_nm")]
    TableOnNamedEffect {
        /// The whole text.
        text: String,
    },
    /// No `value=V`.
    #[error("`{text}`: missing value=V")]
    MissingValue {
        /// The whole text.
        text: String,
    },
    /// A per-joint effect without `joint=J`.
    #[error("{kind} acts on a joint: give joint=J")]
    NeedsJoint {
        /// The effect.
        kind: EffectKind,
    },
    /// A global effect given a joint.
    #[error("{kind} is global: it takes no joint")]
    GlobalWithJoint {
        /// The effect.
        kind: EffectKind,
    },
    /// A joint the mechanism does not have.
    #[error("{kind}: joint {joint} does not exist (the mechanism has joints 1 to {joints})")]
    NoSuchJoint {
        /// The effect.
        kind: EffectKind,
        /// The joint given.
        joint: usize,
        /// The mechanism's joint count.
        joints: usize,
    },
    /// A value outside [`EffectKind::allowed`].
    #[error("{kind}: value={value}: expected {} [{}]", kind.allowed().describe(), kind.unit())]
    OutOfRange {
        /// The effect.
        kind: EffectKind,
        /// The value given.
        value: f64,
    },
    /// `alpha_deg` not finite.
    #[error("{kind}: alpha_deg={alpha_deg}: expected a finite angle [deg]")]
    BadAlpha {
        /// The effect.
        kind: EffectKind,
        /// The angle given.
        alpha_deg: f64,
    },
}

fn effect_names() -> String {
    let names: Vec<_> = EffectKind::ALL
        .iter()
        .chain(&EffectKind::LATCH)
        .chain(&EffectKind::RIG)
        .map(|k| k.name())
        .collect();
    names.join(", ")
}

impl fmt::Display for EffectKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for EffectKind {
    type Err = EffectError;
    fn from_str(s: &str) -> Result<Self, EffectError> {
        EffectKind::EVERY
            .iter()
            .copied()
            .find(|k| k.name() == s)
            .ok_or_else(|| EffectError::UnknownName {
                name: s.to_string(),
            })
    }
}

/// One effect with its joint and value.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Effect {
    /// Which effect.
    pub kind: EffectKind,
    /// 1-based joint, `None` for global effects.
    pub joint: Option<usize>,
    /// The value, in [`EffectKind::unit`].
    pub value: f64,
    /// `rig_tilt` only: direction of the tilt gravity \[deg\].
    pub alpha_deg: f64,
    /// `stribeck_friction` only: the break-away excess `T_brk − T_C` [N·m].
    pub excess_nm: f64,
    /// `stribeck_friction` only: the Stribeck velocity `ω_st` [rad/s].
    pub stribeck_rad_s: f64,
    /// `torque_table` only: the tables (`value` is then their largest
    /// absolute torque [N·m]).
    pub table: HostTorqueTable,
}

impl Default for EffectKind {
    /// `coulomb_friction`, the first of the vocabulary (for `Default` of
    /// [`Effect`] only).
    fn default() -> Self {
        EffectKind::CoulombFriction
    }
}

impl Effect {
    /// A per-joint effect (`joint` is 1-based).
    pub fn joint(kind: EffectKind, joint: usize, value: f64) -> Self {
        Effect {
            kind,
            joint: Some(joint),
            value,
            ..Effect::default()
        }
    }

    /// A global effect.
    pub fn global(kind: EffectKind, value: f64) -> Self {
        Effect {
            kind,
            joint: None,
            value,
            ..Effect::default()
        }
    }

    /// Checks the joint against a mechanism of `joints` joints and the
    /// value against [`EffectKind::allowed`]: what a user may ask for
    /// (`--effect`).
    pub fn validate(&self, joints: usize) -> Result<(), EffectError> {
        self.validate_joint(joints)?;
        if !self.kind.allowed().contains(self.value) {
            return Err(EffectError::OutOfRange {
                kind: self.kind,
                value: self.value,
            });
        }
        Ok(())
    }

    /// Checks only that the numbers are finite and the joint exists: what
    /// the simulator needs (an identification may try a correction below
    /// the mechanism's own friction, which [`Effect::validate`] refuses).
    pub fn validate_joint(&self, joints: usize) -> Result<(), EffectError> {
        let kind = self.kind;
        if !self.value.is_finite() {
            return Err(EffectError::OutOfRange {
                kind,
                value: self.value,
            });
        }
        if !self.alpha_deg.is_finite() {
            let alpha_deg = self.alpha_deg;
            return Err(EffectError::BadAlpha { kind, alpha_deg });
        }
        match (kind.per_joint(), self.joint) {
            (true, None) => Err(EffectError::NeedsJoint { kind }),
            (true, Some(joint)) if joint == 0 || joint > joints => Err(EffectError::NoSuchJoint {
                kind,
                joint,
                joints,
            }),
            (false, Some(_)) => Err(EffectError::GlobalWithJoint { kind }),
            _ => Ok(()),
        }
    }
}

impl fmt::Display for Effect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.kind)?;
        if let Some(j) = self.joint {
            write!(f, ":joint={j}")?;
        }
        write!(f, ":value={}", self.value)?;
        if self.kind == EffectKind::RigTilt {
            write!(f, ":alpha_deg={}", self.alpha_deg)?;
        }
        if self.kind == EffectKind::StribeckFriction {
            write!(
                f,
                ":excess_nm={}:stribeck_rad_s={}",
                self.excess_nm, self.stribeck_rad_s
            )?;
        }
        if self.kind == EffectKind::TorqueTable {
            f.write_str(&torque_table::to_keys(&self.table))?;
        }
        Ok(())
    }
}

impl FromStr for Effect {
    type Err = EffectError;
    /// Parses `NAME[:joint=J]:value=V[:alpha_deg=A]` (the `--effect` syntax).
    fn from_str(s: &str) -> Result<Self, EffectError> {
        let mut parts = s.split(':');
        let kind: EffectKind = parts.next().unwrap_or("").trim().parse()?;
        let mut joint = None;
        let mut value = None;
        let mut alpha_deg = 0.0;
        let (mut excess_nm, mut stribeck_rad_s) = (None, None);
        let mut points = TablePoints::default();
        let table_error = |source| EffectError::Table {
            text: s.to_string(),
            source,
        };
        for p in parts {
            let (k, v) = p.split_once('=').ok_or_else(|| EffectError::NotKeyValue {
                part: p.to_string(),
                text: s.to_string(),
            })?;
            let bad = |expected| EffectError::BadNumber {
                key: k.to_string(),
                value: v.to_string(),
                text: s.to_string(),
                expected,
            };
            let num = |v: &str| v.trim().parse::<f64>().map_err(|_| bad("a number"));
            match k.trim() {
                "joint" => {
                    joint = Some(
                        v.trim()
                            .parse::<usize>()
                            .map_err(|_| bad("a joint number from 1"))?,
                    )
                }
                "value" => value = Some(num(v)?),
                "alpha_deg" => alpha_deg = num(v)?,
                "excess_nm" if kind == EffectKind::StribeckFriction => {
                    excess_nm = Some(Some(num(v)?).filter(|x| *x >= 0.0).ok_or(bad("≥ 0"))?)
                }
                "stribeck_rad_s" if kind == EffectKind::StribeckFriction => {
                    stribeck_rad_s = Some(Some(num(v)?).filter(|x| *x > 0.0).ok_or(bad("> 0"))?)
                }
                other if points.take(other, v).map_err(table_error)? => {}
                other => {
                    return Err(EffectError::UnknownKey {
                        key: other.to_string(),
                        text: s.to_string(),
                    })
                }
            }
        }
        if kind == EffectKind::TorqueTable {
            let table = points.build().map_err(table_error)?;
            let value = torque_table::max_abs_nm(&table);
            return Ok(Effect {
                kind,
                joint,
                value,
                table,
                ..Effect::default()
            });
        }
        if !points.is_empty() {
            return Err(EffectError::TableOnNamedEffect {
                text: s.to_string(),
            });
        }
        let value = value.ok_or_else(|| EffectError::MissingValue {
            text: s.to_string(),
        })?;
        let (excess_nm, stribeck_rad_s) = stribeck_keys(kind, excess_nm, stribeck_rad_s, s)?;
        Ok(Effect {
            kind,
            joint,
            value,
            alpha_deg,
            excess_nm,
            stribeck_rad_s,
            ..Effect::default()
        })
    }
}

/// `stribeck_friction`'s `excess_nm` and `stribeck_rad_s` (both required
/// there; `(0, 0)` for any other effect).
fn stribeck_keys(
    kind: EffectKind,
    excess_nm: Option<f64>,
    stribeck_rad_s: Option<f64>,
    text: &str,
) -> Result<(f64, f64), EffectError> {
    match (excess_nm, stribeck_rad_s) {
        (Some(e), Some(w)) => Ok((e, w)),
        _ if kind == EffectKind::StribeckFriction => Err(EffectError::UnknownKey {
            key: "(excess_nm and stribeck_rad_s are both required)".into(),
            text: text.to_string(),
        }),
        _ => Ok((0.0, 0.0)),
    }
}

/// The dynamic effects of a list, as the core's per-joint and global tables
/// (sensor effects are left out: see [`encoder_offsets_deg`]).
pub fn to_core(effects: &[Effect], joints: usize) -> (Vec<HostJointEffects>, GlobalEffects<f64>) {
    let mut je = vec![HostJointEffects::default(); joints];
    let mut g = GlobalEffects::default();
    for e in effects {
        let j = e
            .joint
            .and_then(|j| j.checked_sub(1))
            .filter(|&j| j < joints);
        match (e.kind, j) {
            (EffectKind::CoulombFriction, Some(j)) => je[j].coulomb_nm += e.value,
            (EffectKind::ViscousDamping, Some(j)) => je[j].viscous_nms += e.value,
            (EffectKind::QuadraticDamping, Some(j)) => je[j].quadratic_nms2_per_rad2 += e.value,
            (EffectKind::StribeckFriction, Some(j)) => {
                // The kinetic level is Coulomb friction; the excess and its
                // velocity are the law's Stribeck term (the last one given).
                je[j].coulomb_nm += e.value;
                je[j].stribeck_excess_nm += e.excess_nm;
                je[j].stribeck_rad_s = e.stribeck_rad_s;
            }
            (EffectKind::SpringSoftening, Some(j)) => {
                // Two softenings compose: (1 − s1)(1 − s2).
                let s = je[j].spring_softening;
                je[j].spring_softening = 1.0 - (1.0 - s) * (1.0 - e.value);
            }
            (EffectKind::HarnessStiffness, Some(j)) => je[j].harness_nm_per_rad += e.value,
            (EffectKind::LatchDetent, Some(j)) => je[j].detent_nm += e.value,
            (EffectKind::TorqueTable, Some(j)) => je[j].table = e.table,
            (EffectKind::AirDrag, _) => g.air_drag_kg_m2 += e.value,
            (EffectKind::RigTilt, _) => {
                g.tilt_m_s2 = e.value;
                g.tilt_alpha_rad = e.alpha_deg.to_radians();
            }
            _ => {}
        }
    }
    (je, g)
}

/// The `encoder_offset` of each joint \[deg\].
pub fn encoder_offsets_deg(effects: &[Effect], joints: usize) -> Vec<f64> {
    let mut b = vec![0.0; joints];
    for e in effects {
        if let (EffectKind::EncoderOffset, Some(j)) = (e.kind, e.joint) {
            if (1..=joints).contains(&j) {
                b[j - 1] += e.value;
            }
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `EVERY` is the vocabulary: each kind once, and a kind added to the
    /// enum does not compile here until it is listed (the match is
    /// exhaustive) — so every test over `EVERY` covers it.
    #[test]
    fn every_lists_each_kind_once() {
        use EffectKind as K;
        let listed = |k: K| match k {
            K::CoulombFriction
            | K::ViscousDamping
            | K::QuadraticDamping
            | K::StribeckFriction
            | K::SpringSoftening
            | K::HarnessStiffness
            | K::LatchDetent
            | K::AirDrag
            | K::RigTilt
            | K::EncoderOffset
            | K::TorqueTable
            | K::PlungerWeakening
            | K::MagnetWeakening
            | K::RigFriction
            | K::WireLength
            | K::FrameOffset => K::EVERY.iter().filter(|e| **e == k).count(),
        };
        for k in K::EVERY {
            assert_eq!(listed(k), 1, "{k}");
            assert_eq!(k.name().parse::<K>().ok(), Some(k));
        }
    }

    #[test]
    fn parses_the_cli_syntax() {
        let e: Effect = "coulomb_friction:joint=2:value=1.7".parse().unwrap();
        assert_eq!(e, Effect::joint(EffectKind::CoulombFriction, 2, 1.7));
        let e: Effect = "rig_tilt:value=0.05:alpha_deg=30".parse().unwrap();
        assert_eq!(e.kind, EffectKind::RigTilt);
        assert_eq!(e.alpha_deg, 30.0);
        assert!("friction:joint=1:value=1".parse::<Effect>().is_err());
        assert!("air_drag:value=abc".parse::<Effect>().is_err());
        assert!("air_drag".parse::<Effect>().is_err());
        let e: Effect = "air_drag:joint=1:value=0.2".parse().unwrap();
        assert!(e.validate(2).is_err());
        let e: Effect = "harness_stiffness:joint=3:value=0.2".parse().unwrap();
        assert!(e.validate(2).is_err());
        assert!(e.validate(3).is_ok());
        // Values that would turn the effect into another one are refused.
        for bad in [
            "coulomb_friction:joint=1:value=-1",
            "spring_softening:joint=1:value=1",
            "harness_stiffness:joint=1:value=-0.1",
        ] {
            let e: Effect = bad.parse().unwrap();
            assert!(
                matches!(e.validate(2), Err(EffectError::OutOfRange { .. })),
                "{bad}"
            );
        }
        let e: Effect = "spring_softening:joint=1:value=-0.2".parse().unwrap();
        assert!(e.validate(2).is_ok(), "a negative softening stiffens");
    }

    #[test]
    fn parses_and_prints_a_torque_table() {
        let text = "torque_table:joint=2:value=0.3:angle_deg=-90,0:torque_nm=0.3,0:rate_deg_s=0,50:rate_torque_nm=0,-0.1";
        let e: Effect = text.parse().unwrap();
        assert_eq!(e.kind, EffectKind::TorqueTable);
        assert_eq!(e.value, 0.3);
        assert_eq!(e.to_string(), text);
        assert!(e.validate(2).is_ok());
        assert!("torque_table:joint=1:angle_deg=0,1"
            .parse::<Effect>()
            .is_err());
        assert!("air_drag:value=1:angle_deg=0,1:torque_nm=1,1"
            .parse::<Effect>()
            .is_err());
    }

    #[test]
    fn stribeck_and_quadratic_effects_parse_print_and_reach_the_core() {
        let text = "stribeck_friction:joint=2:value=0.3:excess_nm=0.4:stribeck_rad_s=0.05";
        let e: Effect = text.parse().unwrap();
        assert_eq!((e.value, e.excess_nm, e.stribeck_rad_s), (0.3, 0.4, 0.05));
        assert_eq!(e.to_string(), text);
        assert!("stribeck_friction:joint=2:value=0.3"
            .parse::<Effect>()
            .is_err());
        assert!(
            "stribeck_friction:joint=2:value=0.3:excess_nm=0.4:stribeck_rad_s=0"
                .parse::<Effect>()
                .is_err()
        );
        assert!("coulomb_friction:joint=2:value=0.3:excess_nm=0.4"
            .parse::<Effect>()
            .is_err());
        let q: Effect = "quadratic_damping:joint=1:value=0.5".parse().unwrap();
        let (je, _) = to_core(&[e, q], 2);
        assert_eq!(je[1].coulomb_nm, 0.3);
        assert_eq!(
            (je[1].stribeck_excess_nm, je[1].stribeck_rad_s),
            (0.4, 0.05)
        );
        assert_eq!(je[0].quadratic_nms2_per_rad2, 0.5);
        assert!(!EffectKind::ALL.contains(&EffectKind::QuadraticDamping));
        assert!(!EffectKind::ALL.contains(&EffectKind::StribeckFriction));
    }
}
