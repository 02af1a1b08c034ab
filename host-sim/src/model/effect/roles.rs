//! The roles the per-kind tables of [`EffectKind`](super::EffectKind) give
//! an effect: where it acts, what it changes on a truss wing, how it enters
//! the margins, its residual torque signature. Each is a small enum the
//! simulator, the margins and the diagnosis match on, never on the kind.

use deploywatch_core::physics::{coulomb_shape, COULOMB_THRESHOLD_RAD_S};

/// Where an effect acts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Acts {
    /// The chain's equations (the core's joint and global tables).
    Chain,
    /// The sensor only: the motion is unchanged.
    Sensor,
    /// A part of a joint's physical latch.
    Latch(LatchPart),
    /// The zero-g rig (`[rig]`).
    Rig(RigPart),
}

/// The part of a physical latch a weakening scales by `1 − w`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatchPart {
    /// The ball plunger's preload and rate.
    Plunger,
    /// The magnet's force.
    Magnet,
}

/// What a rig cause changes on the rig.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RigPart {
    /// `Δμ` \[1\] added to the rails' dynamic friction coefficient.
    RailFriction,
    /// `ΔL` \[m\] added to every suspension wire.
    WireLength,
    /// `Δd` \[m\] by which every test frame stands nearer the panels.
    FrameOffset,
}

/// What an effect changes on a pin of a wing with a truss.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrussPart {
    /// The pin's Coulomb (and break-away) friction [N·m].
    Coulomb,
    /// The pin's viscous coefficient [N·m·s/rad].
    Viscous,
    /// The hinge's spring scaled by `1 − s` (a hinge pin only).
    SpringSoftening,
    /// Nothing on the pin: the readings (a sensor effect).
    Sensor,
}

/// How an effect enters the torque margins: the torque form at rest and
/// the energy form on the deployment (`analysis::effect_margin` computes
/// each form), and a term along the stroke.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarginForm {
    /// A torque equal to the value at rest, its work over the stroke
    /// (Coulomb friction).
    Coulomb,
    /// No torque at rest, work on the simulated deployment; along the
    /// stroke the value times the peak rate.
    Viscous,
    /// No torque at rest, work on the simulated deployment; along the
    /// stroke the value times the peak rate squared.
    Quadratic,
    /// The break-away torque at rest (kinetic level plus excess), work on
    /// the simulated deployment (a Stribeck law).
    Breakaway,
    /// The driving spring scaled by `1 − value` (a softening).
    Driving,
    /// A stiffness about the stowed angle: `k S` at the latch, `½ k S²`.
    Harness,
    /// A torque within the detent zone of the latch.
    Detent,
    /// Forces over the panels: no torque at rest, work on the simulated
    /// deployment (air drag).
    Distributed,
    /// The resisting generalised force at the stowed state, work on the
    /// simulated deployment (a tilted rig's gravity).
    Tilt,
    /// The largest resisting torque of a table over the stroke, work on
    /// the simulated deployment.
    Table,
    /// Nothing: a sensor effect moves no joint.
    Sensor,
    /// Counted by the physical latch's own line.
    LatchLine,
    /// Counted by the rig's line (`analysis::rig_margin`).
    RigLine,
}

/// The standards' kind of resistance an effect counts as in the margins.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResistanceClass {
    /// Friction and damping.
    Friction,
    /// A harness.
    Harness,
    /// Any other resistance.
    Other,
}

impl MarginForm {
    /// The kind of resistance the form counts as; `None` for a driving
    /// spring's softening and a sensor effect.
    pub fn class(self) -> Option<ResistanceClass> {
        match self {
            MarginForm::Coulomb
            | MarginForm::Viscous
            | MarginForm::Quadratic
            | MarginForm::Breakaway => Some(ResistanceClass::Friction),
            MarginForm::Harness => Some(ResistanceClass::Harness),
            MarginForm::Detent
            | MarginForm::Distributed
            | MarginForm::Tilt
            | MarginForm::Table
            | MarginForm::LatchLine
            | MarginForm::RigLine => Some(ResistanceClass::Other),
            MarginForm::Driving | MarginForm::Sensor => None,
        }
    }

    /// True when the form's energy comes from the simulated deployment
    /// (rate-dependent or distributed over the panels).
    pub fn needs_simulation(self) -> bool {
        match self {
            MarginForm::Viscous
            | MarginForm::Quadratic
            | MarginForm::Breakaway
            | MarginForm::Distributed
            | MarginForm::Tilt
            | MarginForm::Table => true,
            MarginForm::Coulomb
            | MarginForm::Driving
            | MarginForm::Harness
            | MarginForm::Detent
            | MarginForm::Sensor
            | MarginForm::LatchLine
            | MarginForm::RigLine => false,
        }
    }
}

/// Which end of a found effect's 95 % interval the margins take: the end
/// that lowers them (`docs/margin.md`, "Each effect at the worst end of
/// its interval").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WorstEnd {
    /// The upper end: a larger value resists more (or, for a softening,
    /// drives less).
    Upper,
    /// The end of the larger magnitude: the sign says whether it resists
    /// or helps, a larger one does more of what the estimate does.
    LargerMagnitude,
    /// Per knot of a table, the end of its band that resists the
    /// deployment more (the lower end on a joint deploying towards
    /// positive angles, the upper end otherwise).
    Resisting,
    /// The estimate: no end lowers the margins; the reason in words.
    Estimate(&'static str),
}

/// The shape of a named joint effect's torque per unit of its value, at a
/// state of the joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Signature {
    /// Coulomb friction: `−tanh(φ̇/ω_coul)` (the core's [`coulomb_shape`]).
    Coulomb,
    /// Viscous damping: `−φ̇`.
    Viscous,
    /// A softened spring: minus the spring's torque.
    Spring,
    /// A harness: the angle from the stowed angle.
    FromStowed,
}

impl Signature {
    /// The torque per unit of value [N·m per unit] at the joint rate
    /// `rate_rad_s` [rad/s], with the hinge spring's torque `spring_nm`
    /// [N·m] and the angle from the stowed angle `from_stowed_rad` \[rad\].
    pub fn at(self, rate_rad_s: f64, spring_nm: f64, from_stowed_rad: f64) -> f64 {
        match self {
            Signature::Coulomb => -coulomb_shape(rate_rad_s, COULOMB_THRESHOLD_RAD_S),
            Signature::Viscous => -rate_rad_s,
            Signature::Spring => -spring_nm,
            Signature::FromStowed => from_stowed_rad,
        }
    }
}
