//! A deployment of a wing with a truss, as the rest of the host sees a
//! deployment: the [`Trajectory`] of its hinge joints, with effects. The one
//! truss simulator is [`crate::simulate::multibody`]; this module only
//! dispatches to it ([`crate::simulate::deployment::simulate_at`] and
//! [`crate::simulate::deployment::simulate`] call it for a mechanism with a
//! `[truss]`), applies the effects to the pins and converts its output.
//!
//! Effects on a truss wing (`docs/simulator.md`, "Closed loops: effects"):
//! `coulomb_friction` and `viscous_damping` at joint `j ≤ n` act on hinge
//! `j`, at joint `n + k` on every pin of the `k`-th friction node of the
//! truss ([`crate::model::truss::Truss::friction_nodes`]: the paper's EFT3
//! at F is joint 3 of the two-panel wing); `spring_softening` scales hinge
//! `j`'s spring by `1 − s`; `encoder_offset` is the sensor's. The others
//! (harness, detent, torque table, air drag, tilt) are not modelled on the
//! truss wing yet and are refused with [`SimError::Invalid`].

use crate::model::effect::{Effect, EffectKind, TrussPart};
use crate::model::mechanism::Mechanism;
use crate::simulate::multibody::{self, Model, System, WingRun};
use crate::simulate::trajectory::{
    Samples, SimError, SimOptions, Trajectory, MAX_SAMPLES, SAMPLE_TIME_SLACK_S,
};
use deploywatch_core::Spring;

/// True for the effects the truss wing models ([`system_with_effects`],
/// [`EffectKind::on_truss`]).
pub fn models(kind: EffectKind) -> bool {
    kind.on_truss().is_some()
}

/// The multibody system of a truss wing with `effects` on its pins (see the
/// module docs for which effect acts where).
pub fn system_with_effects(mech: &Mechanism, effects: &[Effect]) -> Result<System, SimError> {
    let truss = mech
        .truss
        .as_ref()
        .ok_or_else(|| SimError::Invalid(format!("mechanism `{}` has no [truss]", mech.name)))?;
    let mut sys = crate::simulate::multibody::build::wing_system(truss, mech)
        .map_err(|e| SimError::Invalid(e.to_string()))?;
    let n = mech.joint_count();
    let nodes = truss.friction_nodes();
    let joints = mech.effect_joints();
    for e in effects {
        e.validate_joint(joints)
            .map_err(|m| SimError::Invalid(m.to_string()))?;
        let Some(part) = e.kind().on_truss() else {
            return Err(SimError::Invalid(format!(
                "{}: not modelled on a wing with a truss; expected coulomb_friction, viscous_damping, spring_softening or encoder_offset",
                e.kind()
            )));
        };
        let Some(j) = e.joint else { continue };
        // The pins the effect acts on: hinge j, or every pin at node j − n.
        let pins: Vec<usize> = if j <= n {
            vec![j - 1]
        } else {
            let point = &truss.points[nodes[j - n - 1]].name;
            let prefix = format!("{point}:");
            (0..sys.pins.len())
                .filter(|&p| sys.pins[p].name.starts_with(&prefix))
                .collect()
        };
        for p in pins {
            let pin = &mut sys.pins[p];
            match part {
                TrussPart::Coulomb => {
                    pin.friction.coulomb_nm += e.value();
                    pin.friction.breakaway_nm += e.value();
                }
                TrussPart::Viscous => pin.friction.viscous_nms += e.value(),
                TrussPart::SpringSoftening if j <= n => match &mut pin.spring {
                    Spring::Linear { count, .. } | Spring::Curve { count, .. } => {
                        *count *= 1.0 - e.value()
                    }
                    Spring::None => {}
                },
                TrussPart::SpringSoftening => {
                    return Err(SimError::Invalid(format!(
                        "spring_softening at joint {j}: a truss node has no spring; expected a hinge joint 1 to {n}"
                    )))
                }
                // The sensor's: applied to the readings.
                TrussPart::Sensor => {}
            }
        }
    }
    Ok(sys)
}

/// Simulates a truss wing with `effects` at the given sample times (the
/// dispatch target of [`crate::simulate::deployment`]): the hinge
/// trajectory and the whole multibody run.
///
/// The run ends as the chain's does (`formats.md`): with
/// `opts.stop_when_deployed`, `settle_s` after the first sample at or after
/// the last lock; otherwise at the last time given. Once every lock is
/// closed the wing has no freedom left, so the samples after it hold the
/// final pose (not integrated). `rate_deg_s` is the central difference of
/// the sampled angles (one-sided at the ends; 0 once latched).
pub fn simulate_truss(
    mech: &Mechanism,
    effects: &[Effect],
    opts: &SimOptions,
    times: Samples<'_>,
) -> Result<(Trajectory, WingRun), SimError> {
    let settle_s = opts.settle_s.unwrap_or(mech.settle_s);
    let times: Vec<f64> = match times {
        Samples::Listed(t) => t.to_vec(),
        Samples::Grid { rate_hz, count } => {
            if count > MAX_SAMPLES {
                // The time of the first sample past the limit.
                return Err(SimError::TooManySamples {
                    t_s: MAX_SAMPLES as f64 / rate_hz,
                });
            }
            (0..count).map(|k| k as f64 / rate_hz).collect()
        }
    };
    let sys = system_with_effects(mech, effects)?;
    let model = Model::new(sys).map_err(|e| SimError::Invalid(e.to_string()))?;
    let inner = SimOptions {
        stop_when_deployed: true,
        ..*opts
    };
    let mut run = multibody::run(&model, &times, &inner)?;
    let locked_up = run.mobility.last() == Some(&0);
    if locked_up && run.t_s.len() < times.len() {
        let end = run.t_s.last().copied().unwrap_or(0.0);
        let last = if opts.stop_when_deployed {
            times.partition_point(|&t| t <= end + settle_s + SAMPLE_TIME_SLACK_S)
        } else {
            times.len()
        };
        for &t in &times[run.t_s.len()..last] {
            run.t_s.push(t);
            for p in 0..run.angle_deg.len() {
                let a = run.angle_deg[p].last().copied().unwrap_or(0.0);
                let l = run.locked[p].last().copied().unwrap_or(false);
                run.angle_deg[p].push(a);
                run.locked[p].push(l);
            }
            let (e, c) = (
                run.energy_j.last().copied().unwrap_or(0.0),
                run.constraint_error.last().copied().unwrap_or(0.0),
            );
            run.energy_j.push(e);
            run.constraint_error.push(c);
        }
    }
    let wing = WingRun {
        pins: model.sys.pins.iter().map(|p| p.name.clone()).collect(),
        run,
    };
    Ok((hinge_trajectory(&wing, mech.joint_count()), wing))
}

/// The hinge series of a truss run as a chain [`Trajectory`] (hinge `j` is
/// pin `hinge j`).
pub fn hinge_trajectory(wing: &WingRun, n: usize) -> Trajectory {
    let r = &wing.run;
    let mut traj = Trajectory {
        t_s: r.t_s.clone(),
        end_s: r.end_s,
        stats: r.stats,
        ..Trajectory::default()
    };
    for j in 0..n {
        let name = format!("hinge {}", j + 1);
        let (a, l) = wing.series(&name).unwrap_or((&[], &[]));
        traj.rate_deg_s.push(rates(&r.t_s, a, l));
        traj.phi_deg.push(a.to_vec());
        traj.latched.push(l.to_vec());
        traj.latch_s.push(wing.lock_s(&name));
    }
    traj
}

/// Central differences of `a` over `t` [deg/s], 0 where latched.
fn rates(t: &[f64], a: &[f64], latched: &[bool]) -> Vec<f64> {
    let n = a.len().min(t.len());
    (0..n)
        .map(|i| {
            if latched.get(i).copied().unwrap_or(false) || n < 2 {
                return 0.0;
            }
            let (lo, hi) = (i.saturating_sub(1), (i + 1).min(n - 1));
            (a[hi] - a[lo]) / (t[hi] - t[lo])
        })
        .collect()
}
