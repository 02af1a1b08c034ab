//! The named effects of `docs/spec/physics.md` section 6: the vocabulary a
//! diagnosis reports, and the extras `deploywatch simulate --effect` adds.

use crate::model::torque_table::{self, TablePoints};
use deploywatch_core::{GlobalEffects, JointEffects, TorqueTable};
use std::fmt;
use std::str::FromStr;

/// The name of an effect, as written in files and reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EffectKind {
    /// `coulomb_friction`: `T_C` [N·m] at a joint.
    CoulombFriction,
    /// `viscous_damping`: `f` [N·m·s/rad] at a joint.
    ViscousDamping,
    /// `spring_softening`: `s` [1], the spring is scaled by `1 − s`.
    SpringSoftening,
    /// `harness_stiffness`: `k_h` [N·m/rad] about the stowed angle.
    HarnessStiffness,
    /// `latch_detent`: `T_d` [N·m] within 3° of the latch.
    LatchDetent,
    /// `air_drag`: `k` [kg/m²], global.
    AirDrag,
    /// `rig_tilt`: `g_t` [m/s²] in direction `alpha_deg`, global.
    RigTilt,
    /// `encoder_offset`: `b` [deg] added to a joint's reading (sensor only).
    EncoderOffset,
    /// `torque_table`: tables `f(φ) + g(φ̇)` [N·m] at a joint; not in
    /// [`EffectKind::ALL`] (it has tables, not one value: a diagnosis fits it
    /// only when no named effect explains the data).
    TorqueTable,
}

impl EffectKind {
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

    /// The name used in files and reports.
    pub fn name(self) -> &'static str {
        match self {
            EffectKind::CoulombFriction => "coulomb_friction",
            EffectKind::ViscousDamping => "viscous_damping",
            EffectKind::SpringSoftening => "spring_softening",
            EffectKind::HarnessStiffness => "harness_stiffness",
            EffectKind::LatchDetent => "latch_detent",
            EffectKind::AirDrag => "air_drag",
            EffectKind::RigTilt => "rig_tilt",
            EffectKind::EncoderOffset => "encoder_offset",
            EffectKind::TorqueTable => "torque_table",
        }
    }

    /// The unit of the effect's value.
    pub fn unit(self) -> &'static str {
        match self {
            EffectKind::CoulombFriction | EffectKind::LatchDetent | EffectKind::TorqueTable => {
                "N·m"
            }
            EffectKind::ViscousDamping => "N·m·s/rad",
            EffectKind::SpringSoftening => "1",
            EffectKind::HarnessStiffness => "N·m/rad",
            EffectKind::AirDrag => "kg/m²",
            EffectKind::RigTilt => "m/s²",
            EffectKind::EncoderOffset => "deg",
        }
    }

    /// True for effects that act on one joint (`joint` is required).
    pub fn per_joint(self) -> bool {
        !matches!(self, EffectKind::AirDrag | EffectKind::RigTilt)
    }

    /// True for effects on the sensor only (the motion is unchanged).
    pub fn is_sensor(self) -> bool {
        matches!(self, EffectKind::EncoderOffset)
    }
}

impl fmt::Display for EffectKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for EffectKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        EffectKind::ALL
            .iter()
            .copied()
            .chain([EffectKind::TorqueTable])
            .find(|k| k.name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = EffectKind::ALL.iter().map(|k| k.name()).collect();
                format!("unknown effect `{s}`: expected one of {}", names.join(", "))
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
    /// `rig_tilt` only: direction of the tilt gravity [deg].
    pub alpha_deg: f64,
    /// `torque_table` only: the tables (`value` is then their largest
    /// absolute torque [N·m]).
    pub table: TorqueTable<f64>,
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

    /// Checks the joint against a mechanism of `joints` joints.
    pub fn validate(&self, joints: usize) -> Result<(), String> {
        if !self.value.is_finite() || !self.alpha_deg.is_finite() {
            return Err(format!("{}: the value must be a finite number", self.kind));
        }
        match (self.kind.per_joint(), self.joint) {
            (true, None) => Err(format!("{} acts on a joint: give joint=J", self.kind)),
            (true, Some(j)) if j == 0 || j > joints => Err(format!(
                "{}: joint {j} does not exist (the mechanism has joints 1 to {joints})",
                self.kind
            )),
            (false, Some(_)) => Err(format!("{} is global: it takes no joint", self.kind)),
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
        if self.kind == EffectKind::TorqueTable {
            f.write_str(&torque_table::to_keys(&self.table))?;
        }
        Ok(())
    }
}

impl FromStr for Effect {
    type Err = String;
    /// Parses `NAME[:joint=J]:value=V[:alpha_deg=A]` (the `--effect` syntax).
    fn from_str(s: &str) -> Result<Self, String> {
        let mut parts = s.split(':');
        let kind: EffectKind = parts.next().unwrap_or("").trim().parse()?;
        let mut joint = None;
        let mut value = None;
        let mut alpha_deg = 0.0;
        let mut points = TablePoints::default();
        for p in parts {
            let (k, v) = p
                .split_once('=')
                .ok_or_else(|| format!("`{p}` in `{s}`: expected key=value"))?;
            let num = |v: &str| -> Result<f64, String> {
                v.trim()
                    .parse::<f64>()
                    .map_err(|_| format!("`{k}={v}` in `{s}`: expected a number"))
            };
            match k.trim() {
                "joint" => {
                    joint = Some(v.trim().parse::<usize>().map_err(|_| {
                        format!("`joint={v}` in `{s}`: expected a joint number from 1")
                    })?)
                }
                "value" => value = Some(num(v)?),
                "alpha_deg" => alpha_deg = num(v)?,
                other if points.take(other, v).map_err(|m| format!("{m} in `{s}`"))? => {}
                other => {
                    return Err(format!(
                        "unknown key `{other}` in `{s}`: expected joint, value or alpha_deg"
                    ))
                }
            }
        }
        if kind == EffectKind::TorqueTable {
            let table = points.build().map_err(|m| format!("`{s}`: {m}"))?;
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
            return Err(format!("`{s}`: only torque_table takes tables"));
        }
        let value = value.ok_or_else(|| format!("`{s}`: missing value=V"))?;
        Ok(Effect {
            kind,
            joint,
            value,
            alpha_deg,
            ..Effect::default()
        })
    }
}

/// The dynamic effects of a list, as the core's per-joint and global tables
/// (sensor effects are left out: see [`encoder_offsets_deg`]).
pub fn to_core(effects: &[Effect], joints: usize) -> (Vec<JointEffects<f64>>, GlobalEffects<f64>) {
    let mut je = vec![JointEffects::default(); joints];
    let mut g = GlobalEffects::default();
    for e in effects {
        let j = e
            .joint
            .and_then(|j| j.checked_sub(1))
            .filter(|&j| j < joints);
        match (e.kind, j) {
            (EffectKind::CoulombFriction, Some(j)) => je[j].coulomb_nm += e.value,
            (EffectKind::ViscousDamping, Some(j)) => je[j].viscous_nms += e.value,
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

/// The `encoder_offset` of each joint [deg].
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
}
