//! What a diagnosis fits of each named effect: its parameters, where they
//! may move ([`ParamBound`]) and the starting points of the coarse scan,
//! one exhaustive `match` each; the effect made of fitted parameters is
//! [`Law::of_params`](super::Law::of_params).

use super::kind::EffectKind;

/// Largest Coulomb torque a fit may take [N·m]: above any hinge spring of
/// the seed mechanisms (2.4–3.6 N·m at the stowed angle), so a wing with it
/// would not deploy; never active on a real cause.
pub const MAX_COULOMB_NM: f64 = 20.0;

/// Largest viscous coefficient [N·m·s/rad]: at 1 rad/s it would stop any
/// seed hinge spring several times over.
pub const MAX_VISCOUS_NMS: f64 = 50.0;
/// Largest quadratic damping a diagnosis fits [N·m·s²/rad²]: a deployment
/// at 1 rad/s with this coefficient meets the viscous bound's torque.
pub const MAX_QUADRATIC_NMS2: f64 = 50.0;

/// The Stribeck velocity's range a diagnosis fits [rad/s]: from 0.3 deg/s
/// (below it the law is a stiff damper at rest, as steep as Coulomb's
/// `ω_coul = 0.01 rad/s` regularisation) to 115 deg/s (beyond it the
/// "break-away" hump is a rate law over the whole deployment).
pub const STRIBECK_RATE_RANGE: [f64; 2] = [0.005, 2.0];

/// Spring softening range \[1\]: from a spring twice as stiff (−1) to one at
/// 1 % of its torque (0.99, not 1: a spring of no torque cannot deploy).
pub const SOFTENING_RANGE: [f64; 2] = [-1.0, 0.99];

/// Largest harness stiffness [N·m/rad]: 20 N·m/rad holds a seed wing well
/// before its latch.
pub const MAX_HARNESS_NM_PER_RAD: f64 = 20.0;

/// Largest detent torque [N·m].
pub const MAX_DETENT_NM: f64 = 50.0;

/// Largest air-drag coefficient [kg/m²] (sea-level air on a flat plate is
/// about 0.6 kg/m²; 20 bounds a rig in any gas).
pub const MAX_AIR_DRAG_KG_M2: f64 = 20.0;

/// Largest rig-tilt component [m/s²]: a rig tilted by 30° has 4.9 m/s².
pub const MAX_TILT_M_S2: f64 = 5.0;

/// Largest encoder offset \[deg\]: beyond it a mounting error is no longer an
/// offset but a wrong mechanism.
pub const MAX_ENCODER_OFFSET_DEG: f64 = 30.0;

/// Largest `rig_friction` excess of the rails' dynamic coefficient \[1\]:
/// ten times the papers' air bearing on rail (0.1, seed 001 §4.2).
pub const MAX_RIG_FRICTION: f64 = 1.0;

/// Largest `wire_length` error \[m\] either way: a third of the seed 001
/// rig's 1.5 m wires.
pub const MAX_WIRE_ERROR_M: f64 = 0.5;

/// Largest `frame_offset` \[m\] either way: the seed 001 rig's `lateral -y`
/// frame stands 80 mm beyond the stowed stack, so a frame 50 mm nearer
/// still leaves the stowed panels clear of it (and a frame 50 mm farther
/// is one no panel of that rig reaches).
pub const MAX_FRAME_OFFSET_M: f64 = 0.05;

/// Where the fit may move one parameter, and how finely it differentiates.
///
/// All three are in the parameter's own unit: [`EffectKind::unit`] of the
/// candidate (N·m for a torque table's node values, m/s² for each rig-tilt
/// component).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamBound {
    /// Smallest value the fit may take.
    pub lower: f64,
    /// Largest value the fit may take.
    pub upper: f64,
    /// Smallest finite-difference step of the Jacobian (the step is
    /// `max(min_step, 1e-4·|p|)`, the fit's `FitOptions::min_step`).
    pub min_step: f64,
}

/// Largest absolute knot torque of a fitted `torque_table` [N·m].
pub const TABLE_BOUND_NM: f64 = 5.0;

impl EffectKind {
    /// Number of parameters a diagnosis fits (rig tilt: its two
    /// components; a Stribeck law: `T_C`, the break-away excess `ΔT` and
    /// the Stribeck velocity `ω_st`). A `torque_table` has its form's knots
    /// (the candidate's table form says how many); without a form, its
    /// value only.
    pub fn fit_params(self) -> usize {
        match self {
            EffectKind::RigTilt => 2,
            EffectKind::StribeckFriction => 3,
            EffectKind::CoulombFriction
            | EffectKind::ViscousDamping
            | EffectKind::QuadraticDamping
            | EffectKind::SpringSoftening
            | EffectKind::HarnessStiffness
            | EffectKind::LatchDetent
            | EffectKind::AirDrag
            | EffectKind::EncoderOffset
            | EffectKind::TorqueTable
            | EffectKind::PlungerWeakening
            | EffectKind::MagnetWeakening
            | EffectKind::RigFriction
            | EffectKind::WireLength
            | EffectKind::FrameOffset => 1,
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => 1,
        }
    }

    /// The fit's bounds and smallest finite-difference step, one per
    /// parameter (`params` of them: [`EffectKind::fit_params`], or a
    /// table form's knot count).
    pub fn bounds(self, params: usize) -> Vec<ParamBound> {
        let b = |lower, upper, min_step| ParamBound {
            lower,
            upper,
            min_step,
        };
        match self {
            EffectKind::CoulombFriction => vec![b(0.0, MAX_COULOMB_NM, 1e-4)],
            EffectKind::ViscousDamping => vec![b(0.0, MAX_VISCOUS_NMS, 1e-4)],
            EffectKind::QuadraticDamping => vec![b(0.0, MAX_QUADRATIC_NMS2, 1e-4)],
            // T_C [N·m], ΔT [N·m], ω_st [rad/s]: entered by the diagnosis's
            // friction-form step, not its stepwise rounds.
            EffectKind::StribeckFriction => vec![
                b(0.0, MAX_COULOMB_NM, 1e-4),
                b(0.0, MAX_COULOMB_NM, 1e-4),
                b(STRIBECK_RATE_RANGE[0], STRIBECK_RATE_RANGE[1], 1e-5),
            ],
            EffectKind::SpringSoftening => {
                vec![b(SOFTENING_RANGE[0], SOFTENING_RANGE[1], 1e-5)]
            }
            EffectKind::HarnessStiffness => vec![b(0.0, MAX_HARNESS_NM_PER_RAD, 1e-4)],
            EffectKind::LatchDetent => vec![b(0.0, MAX_DETENT_NM, 1e-3)],
            EffectKind::AirDrag => vec![b(0.0, MAX_AIR_DRAG_KG_M2, 1e-4)],
            // Cartesian components (g cos α, g sin α): nearly linear in
            // the motion, no wrap-around, no singular direction at g = 0.
            EffectKind::RigTilt => {
                let t = MAX_TILT_M_S2;
                vec![b(-t, t, 1e-5), b(-t, t, 1e-5)]
            }
            EffectKind::EncoderOffset => {
                vec![b(-MAX_ENCODER_OFFSET_DEG, MAX_ENCODER_OFFSET_DEG, 1e-4)]
            }
            EffectKind::TorqueTable => {
                vec![b(-TABLE_BOUND_NM, TABLE_BOUND_NM, 1e-4); params]
            }
            // Physical-latch effects are never candidates (not in
            // `EffectKind::ALL`); bounds for completeness.
            EffectKind::PlungerWeakening | EffectKind::MagnetWeakening => vec![b(0.0, 1.0, 1e-4)],
            EffectKind::RigFriction => vec![b(0.0, MAX_RIG_FRICTION, 1e-5)],
            EffectKind::WireLength => vec![b(-MAX_WIRE_ERROR_M, MAX_WIRE_ERROR_M, 1e-5)],
            // A step of 0.05 mm: the contact's onset resolved by the
            // integrator, not its tolerance.
            EffectKind::FrameOffset => {
                vec![b(-MAX_FRAME_OFFSET_M, MAX_FRAME_OFFSET_M, 5e-5)]
            }
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => vec![b(0.0, MAX_QUADRATIC_NMS2, 1e-4)],
        }
    }

    /// Starting points of the coarse scan (`params` and `snag` describe a
    /// `torque_table`'s form: its knot count, and whether it is a narrow
    /// snag whose middle knot alone is raised).
    pub fn scan(self, params: usize, snag: bool) -> Vec<Vec<f64>> {
        let one = |v: &[f64]| v.iter().map(|&x| vec![x]).collect();
        match self {
            // From 0.01: on a wing of five or six panels, 0.01 N·m at a
            // joint acting after its first latch contact moves the runs by
            // 0.3° (tests/src/after_contact.rs), where a start at 0.03
            // moves them by more than the baseline misses and the screen
            // drops the candidate.
            EffectKind::CoulombFriction => one(&[0.01, 0.03, 0.1, 0.3, 1.0, 3.0]),
            EffectKind::ViscousDamping => one(&[0.01, 0.03, 0.1, 0.3, 1.0, 3.0]),
            EffectKind::QuadraticDamping => one(&[0.03, 0.1, 0.3, 1.0, 3.0]),
            EffectKind::StribeckFriction => {
                let mut v = Vec::new();
                for tc in [0.05, 0.3] {
                    for dt in [0.1, 0.4] {
                        for w in [0.03, 0.2] {
                            v.push(vec![tc, dt, w]);
                        }
                    }
                }
                v
            }
            EffectKind::SpringSoftening => one(&[-0.2, 0.05, 0.2, 0.45]),
            EffectKind::HarnessStiffness => one(&[0.01, 0.03, 0.1, 0.3, 1.0]),
            EffectKind::LatchDetent => one(&[0.3, 1.0, 3.0]),
            EffectKind::AirDrag => one(&[0.05, 0.2, 0.8, 3.0]),
            EffectKind::RigTilt => {
                let mut v = Vec::new();
                for g in [0.01, 0.08] {
                    for k in 0..8 {
                        let a = k as f64 * std::f64::consts::FRAC_PI_4;
                        v.push(vec![g * a.cos(), g * a.sin()]);
                    }
                }
                v
            }
            EffectKind::EncoderOffset => one(&[0.0]),
            // A constant torque of either sign and a few sizes: the scan
            // ranks the joints and forms, the fit shapes the table.
            // A narrow table (the diagnosis's snag candidates): its
            // middle knot raised, either sign, the others at zero.
            EffectKind::TorqueTable if snag => [-0.3, -0.08, 0.08, 0.3]
                .iter()
                .map(|&v| {
                    let mut p = vec![0.0; params];
                    p[2] = v;
                    p
                })
                .collect(),
            EffectKind::TorqueTable => [-0.3, -0.05, 0.0, 0.05, 0.3]
                .iter()
                .map(|&v| vec![v; params])
                .collect(),
            EffectKind::PlungerWeakening | EffectKind::MagnetWeakening => one(&[0.3]),
            EffectKind::RigFriction => one(&[0.02, 0.05, 0.1, 0.2, 0.5]),
            EffectKind::WireLength => one(&[-0.3, -0.1, 0.1, 0.3]),
            // Either way, a few millimetres to centimetres: a frame nearer
            // is met earlier and harder, one farther later or not at all
            // (no contact, a flat objective: no gain, never kept).
            EffectKind::FrameOffset => one(&[-0.02, -0.005, 0.005, 0.02]),
            #[cfg(feature = "demo-effect")]
            EffectKind::DemoDrag => one(&[0.03, 0.1, 0.3, 1.0, 3.0]),
        }
    }
}
