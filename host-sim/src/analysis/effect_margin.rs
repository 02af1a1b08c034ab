//! Every named effect (`physics.md` section 6) as a term of the torque
//! margins (`docs/margin.md`, "Every diagnosed cause in the margin"): a
//! resistance of one of the standards' kinds, a smaller driving spring, or
//! nothing (a sensor effect moves no joint).
//!
//! | effect | counts as | torque form [N·m] | energy form \[J\] |
//! |---|---|---|---|
//! | `coulomb_friction` `T_C` | friction | `T_C` | `T_C · S` |
//! | `viscous_damping` `f` | friction | 0 (at rest) | `∫ f φ̇² dt` on the deployment |
//! | `spring_softening` `s` | the driving spring × `(1 − s)` | `T_D (1 − s)` | `E_D (1 − s)` |
//! | `harness_stiffness` `k_h` | harness | `k_h S` (at the latch, its largest) | `½ k_h S²` |
//! | `latch_detent` `T_d` | other | `T_d` | `T_d δ / π` (its resisting half) |
//! | `torque_table` `f + g` | other | largest resisting `f(φ) + g(0)` over the stroke | resisting work on the deployment |
//! | `air_drag` `k` | other | 0 (at rest) | resisting work on the deployment |
//! | `rig_tilt` `g_t` | other | resisting generalised force at the stowed state | resisting work on the deployment |
//! | `encoder_offset` `b` | nothing (sensor) | 0 | 0 |
//! | `rig_friction`, `wire_length`, `frame_offset` | other (rig only: `--flight` leaves them out) | 0 (in `analysis::rig_margin`'s rig line) | 0 |
//!
//! `S = |φ_stowed|` \[rad\] the stroke. "Resisting work on the deployment":
//! `∫ max(0, −τ_e,j φ̇_j) dt` along the deployment simulated with every
//! effect found, `τ_e,j` the generalised torque of effect `e` alone on joint
//! `j` (the chain's right-hand side with the effect minus without it, so the
//! chain equations stay the core's): only the power that resists counts; a
//! part that helps is not credited.

use crate::analysis::design_margin::Resistance;
use crate::analysis::stroke_margin::{Profile, Term};
pub use crate::model::effect::WorstEnd;
use crate::model::effect::{self, Effect, EffectKind, Law, MarginForm, ResistanceClass};
use crate::model::mechanism::{with_joints, Mechanism};
use crate::model::torque_table::HostJointEffects;
use crate::simulate::deployment::{self, SimError, SimOptions, Trajectory};
use deploywatch_core::physics::DETENT_ZONE_DEG;
use deploywatch_core::{ChainState, GlobalEffects, Mode};

/// How one effect enters the margins of one joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Counted {
    /// A resistance of `kind` (its factor applies): `torque_nm` in the
    /// torque form, `energy_j` in the energy form.
    Resistance {
        /// The standards' kind, which selects the factor.
        kind: Resistance,
        /// [N·m].
        torque_nm: f64,
        /// \[J\].
        energy_j: f64,
    },
    /// The driving spring scaled by `scale` (`1 − s` of a softening): the
    /// worst-case driving torque `D_min` of the standards, unfactored.
    Driving {
        /// \[1\].
        scale: f64,
    },
    /// A sensor effect: no torque, nothing to count.
    Sensor,
}

/// The kind of resistance each effect counts as (`None`: a driving
/// spring's softening or a sensor effect): the class of its
/// [`EffectKind::margin`] form.
pub fn kind_of(k: EffectKind) -> Option<Resistance> {
    k.margin().class().map(|c| match c {
        ResistanceClass::Friction => Resistance::Friction,
        ResistanceClass::Harness => Resistance::Harness,
        ResistanceClass::Other => Resistance::Other,
    })
}

/// The end of its interval each effect kind counts at in the margins
/// ([`EffectKind::worst_end`]).
pub fn worst_end(k: EffectKind) -> WorstEnd {
    k.worst_end()
}

/// True for the effects that exist only on a ground rig
/// ([`EffectKind::rig_only`]): `--flight` leaves them out.
pub fn rig_only(k: EffectKind) -> bool {
    k.rig_only()
}

/// True when the effect's energy comes from the simulated deployment
/// (rate-dependent or distributed over the panels; [`MarginForm::needs_simulation`]).
pub fn needs_simulation(k: EffectKind) -> bool {
    k.margin().needs_simulation()
}

/// True when effect `e` acts on joint `j` (0-based): a per-joint effect at
/// `j`, or a global one.
fn acts_on(e: &Effect, j: usize) -> bool {
    e.joint.is_none_or(|k| k == j + 1)
}

/// How effect `e` enters joint `j`'s margins (0-based `j`), with
/// `simulated_j` its resisting work on joint `j` along the deployment
/// ([`resisting_work`]; used where [`needs_simulation`]) and `stowed_q` its
/// generalised torque on joint `j` at the stowed state at rest (used by
/// `rig_tilt`). `None` when `e` does not act on `j`.
pub fn counted(
    mech: &Mechanism,
    j: usize,
    e: &Effect,
    simulated_j: f64,
    stowed_q: f64,
) -> Option<Counted> {
    if !acts_on(e, j) {
        return None;
    }
    let stowed = mech.joints.get(j)?.stowed_deg.to_radians();
    let stroke = stowed.abs();
    // The direction of deployment: towards 0 from the stowed side.
    let d = -stowed.signum();
    let res = |torque_nm: f64, energy_j: f64| {
        kind_of(e.kind()).map(|kind| Counted::Resistance {
            kind,
            torque_nm,
            energy_j,
        })
    };
    let v = e.value();
    match e.kind().margin() {
        MarginForm::Coulomb => res(v, v * stroke),
        MarginForm::Viscous | MarginForm::Quadratic | MarginForm::Distributed => {
            res(0.0, simulated_j)
        }
        // Breakaway torque at rest (kinetic level plus the static excess);
        // the work of the whole rate-dependent law along the deployment.
        MarginForm::Breakaway => res(breakaway_nm(e), simulated_j),
        MarginForm::Driving => Some(Counted::Driving { scale: 1.0 - v }),
        MarginForm::Harness => res(v * stroke, 0.5 * v * stroke * stroke),
        MarginForm::Detent => {
            let delta = DETENT_ZONE_DEG.to_radians();
            res(v, v * delta / core::f64::consts::PI)
        }
        MarginForm::Table => res(table_worst_torque(e, stowed, d), simulated_j),
        MarginForm::Tilt => res((-d * stowed_q).max(0.0), simulated_j),
        MarginForm::Sensor => Some(Counted::Sensor),
        // Effects of a physical latch change its plunger or magnet, which
        // the latch's own line counts (`LatchResistance`).
        MarginForm::LatchLine => res(0.0, 0.0),
        // A rig cause acts on the trolleys, not through the chain's
        // equations: its share of each joint's friction is the rig line of
        // `diagnose` and `identify` (`crate::analysis::rig_margin`).
        MarginForm::RigLine => res(0.0, 0.0),
    }
}

/// Effect `e`, counted as a resistance of `kind` with `torque_nm` in the
/// torque form, as a term of the margin along the stroke: a harness
/// relaxed at the stowed angle grows towards the latch, a detent acts in
/// its zone, a quadratic damping at the deployment's peak rate
/// `peak_rate_rad_s`; every other effect with its torque-form value
/// everywhere (a table: its worst value, a Stribeck law: its breakaway).
pub fn stroke_term(e: &Effect, kind: Resistance, torque_nm: f64, peak_rate_rad_s: f64) -> Term {
    let name = e.kind().to_string();
    match e.kind().margin() {
        MarginForm::Harness => Term {
            name,
            kind,
            torque_nm,
            profile: Profile::FromStowed {
                stiffness_nm_per_rad: e.value(),
            },
        },
        MarginForm::Detent => Term {
            name,
            kind,
            torque_nm,
            profile: Profile::Band {
                from_rad: 0.0,
                to_rad: DETENT_ZONE_DEG.to_radians(),
            },
        },
        MarginForm::Quadratic => Term::constant(
            format!("{name} at the run's peak rate {peak_rate_rad_s:.3} rad/s"),
            kind,
            e.value() * peak_rate_rad_s * peak_rate_rad_s,
        ),
        MarginForm::Viscous => Term::constant(
            format!("{name} at the run's peak rate {peak_rate_rad_s:.3} rad/s"),
            kind,
            e.value() * peak_rate_rad_s,
        ),
        MarginForm::Coulomb
        | MarginForm::Breakaway
        | MarginForm::Driving
        | MarginForm::Distributed
        | MarginForm::Tilt
        | MarginForm::Sensor
        | MarginForm::Table
        | MarginForm::LatchLine
        | MarginForm::RigLine => Term::constant(name, kind, torque_nm),
    }
}

/// The break-away torque at rest of a Stribeck law, its kinetic level plus
/// its excess [N·m] (of another law: its value).
fn breakaway_nm(e: &Effect) -> f64 {
    match e.law {
        Law::StribeckFriction {
            kinetic_nm,
            excess_nm,
            ..
        } => kinetic_nm + excess_nm,
        law => law.value(),
    }
}

/// The largest torque a table resists with at rest over the stroke,
/// `max(0, −d (f(φ) + g(0)))` on 1000 points of `[0, φ_stowed]` [N·m]
/// (0 for an effect that is no table).
fn table_worst_torque(e: &Effect, stowed: f64, d: f64) -> f64 {
    let Some(t) = e.table() else { return 0.0 };
    (0..=1000)
        .map(|i| {
            let phi = stowed * f64::from(i) / 1000.0;
            (-d * t.torque(phi, 0.0)).max(0.0)
        })
        .fold(0.0, f64::max)
}

/// The deployment simulated with `effects` (those found, added to the
/// mechanism's own friction).
pub fn deployment(mech: &Mechanism, effects: &[Effect]) -> Result<Trajectory, SimError> {
    deployment::simulate(mech, effects, &SimOptions::default())
}

/// Per effect (rows) and joint (columns) of [`resisting_work`].
#[derive(Clone, Debug, PartialEq, Default)]
pub struct EffectWork {
    /// The work the effect resists the joint with on the deployment \[J\].
    pub work_j: Vec<Vec<f64>>,
    /// Its generalised torque on the joint at the stowed state at rest [N·m].
    pub stowed_torque_nm: Vec<Vec<f64>>,
}

/// Per effect, per joint: the work `∫ max(0, −τ_e,j φ̇_j) dt` \[J\] effect
/// `e` alone resists joint `j` with along `traj` (rectangle rule on its
/// sample grid), and its generalised torque at the stowed state at rest
/// [N·m]. Zero rows for effects that do not [`needs_simulation`].
pub fn resisting_work(mech: &Mechanism, effects: &[Effect], traj: &Trajectory) -> EffectWork {
    let n = mech.joint_count();
    let zero = || EffectWork {
        work_j: vec![vec![0.0; n]; effects.len()],
        stowed_torque_nm: vec![vec![0.0; n]; effects.len()],
    };
    if mech.truss.is_some() || mech.has_physical_latch() {
        // Only the open chain's equations are split here.
        return zero();
    }
    with_joints!(n, N => work::<N>(mech, effects, traj).unwrap_or_else(zero), else zero())
}

/// [`resisting_work`] for a chain of `N` joints.
fn work<const N: usize>(
    mech: &Mechanism,
    effects: &[Effect],
    traj: &Trajectory,
) -> Option<EffectWork> {
    let bare = mech.chain::<N>(&[HostJointEffects::default(); N], GlobalEffects::default())?;
    let mode = Mode::<N>::default();
    let stowed = ChainState {
        phi: core::array::from_fn(|j| mech.joints[j].stowed_deg.to_radians()),
        phi_dot: [0.0; N],
    };
    let mut works = Vec::with_capacity(effects.len());
    let mut stowed_q = Vec::with_capacity(effects.len());
    for e in effects {
        if !needs_simulation(e.kind()) {
            works.push(vec![0.0; N]);
            stowed_q.push(vec![0.0; N]);
            continue;
        }
        let (je, g) = effect::to_core(std::slice::from_ref(e), N);
        let with = mech.chain::<N>(&je, g)?;
        let torque = |x: &ChainState<f64, N>| -> [f64; N] {
            let (_, r1) = with.equations(x, &mode);
            let (_, r0) = bare.equations(x, &mode);
            core::array::from_fn(|j| r1[j] - r0[j])
        };
        let mut w = vec![0.0; N];
        for i in 0..traj.t_s.len().saturating_sub(1) {
            let dt = traj.t_s[i + 1] - traj.t_s[i];
            let x = ChainState {
                phi: core::array::from_fn(|j| traj.phi_deg[j][i].to_radians()),
                phi_dot: core::array::from_fn(|j| traj.rate_deg_s[j][i].to_radians()),
            };
            let tau = torque(&x);
            for j in 0..N {
                w[j] += (-tau[j] * x.phi_dot[j]).max(0.0) * dt;
            }
        }
        works.push(w);
        stowed_q.push(torque(&stowed).to_vec());
    }
    Some(EffectWork {
        work_j: works,
        stowed_torque_nm: stowed_q,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_effect_has_a_place_in_the_margins() {
        for k in EffectKind::ALL
            .into_iter()
            .chain([EffectKind::TorqueTable])
            .chain(EffectKind::LATCH)
        {
            let counted_somehow = kind_of(k).is_some()
                || matches!(k, EffectKind::SpringSoftening | EffectKind::EncoderOffset);
            assert!(counted_somehow, "{k}");
        }
    }
}
