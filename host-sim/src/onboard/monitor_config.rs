//! The host side of the on-board monitor: a [`Mechanism`] (as read from its
//! TOML file) converted into the fixed-size, `f32` [`MonitorConfig`] the
//! core's [`Monitor`] is built from, and a replay of a [`Run`] through it.
//!
//! The conversion keeps the mechanism's panels and springs, takes the
//! friction written in the file as the prior mean of the friction estimate
//! (zero for the nominal mechanisms), with the spread of [`PriorSpread`],
//! and the file's `[run] duration_s` as the deadline of the deployment: a
//! joint predicted to latch later is predicted to stall. A joint with a
//! physical latch (`[joint.latch]`) carries the three figures of its plunger
//! the margin needs ([`engagement`]).

use deploywatch_core::monitor::Engagement;
use deploywatch_core::monitor::FrictionPrior;
use deploywatch_core::monitor::{JointConfig, Monitor, MonitorConfig, Sample, Status};
use deploywatch_core::monitor::{LockKind, PhysicalLatch};
use deploywatch_core::CurveError;
use deploywatch_core::{Panel, Spring};

use crate::data::run::Run;
use crate::model::mechanism::{Mechanism, SpringSpec};

/// Standard deviations of the friction prior.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PriorSpread {
    /// Of the Coulomb torque [N·m].
    pub coulomb_sd_nm: f64,
    /// Of the viscous coefficient [N·m·s/rad].
    pub viscous_sd_nms: f64,
}

impl Default for PriorSpread {
    /// [`COULOMB_PRIOR_SD_NM`] and [`VISCOUS_PRIOR_SD_NMS`].
    fn default() -> Self {
        PriorSpread {
            coulomb_sd_nm: COULOMB_PRIOR_SD_NM,
            viscous_sd_nms: VISCOUS_PRIOR_SD_NMS,
        }
    }
}

/// Standard deviation of the Coulomb torque's prior [N·m]: the papers'
/// identified values are 0.001–2.63 N·m, so 2 N·m says only that a hinge's
/// friction is of that order.
pub const COULOMB_PRIOR_SD_NM: f64 = 2.0;

/// Standard deviation of the viscous coefficient's prior [N·m·s/rad]: what
/// is known of a hinge's damping before the deployment. The papers identify
/// none (`physics.md` §4: their friction is Coulomb alone, `f = 0`, up to
/// 2.63 N·m), so the prior says only that a viscous torque `f ω` at the
/// rates of a deployment (≈ 1 rad/s at its fastest on seed001_T01) is not
/// larger than the largest friction torque seen: 2.63 N·m at 1 rad/s is
/// 2.6 σ. Tighter would be a claim the papers do not make (under a prior of
/// 0.05 a true 0.3 reads `0.06 ± 0.04`, a 5 σ miss); the
/// prediction is unharmed by the width because it uses `f` only once the
/// data resolve it (`docs/monitor.md` §3.2).
pub const VISCOUS_PRIOR_SD_NMS: f64 = 1.0;

/// How long the switch of a physical latch must stay closed, the encoder
/// on the stop, for the monitor to declare the latch \[s\]: ten times the
/// millisecond contact of a Hertzian impact, and with one 10 ms sample
/// interval on top within the 50 ms allowed after the last rebound.
pub const BOUNCE_WINDOW_S: f64 = 0.03;

/// The monitor's [`PhysicalLatch`] of joint `j` (0-based) of a mechanism
/// (`docs/monitor.md` §4.1): `None` (the ideal latch of `physics.md` §5)
/// when its `[joint.latch]` is ideal; a wing may mix ideal, plunger and
/// pawl latches, and each joint's tracker gets its own. The switch travel
/// and the crest are the file's; the ramp reaches from the stop to the
/// outer end of the plunger's entry ramp (crest + its width), where a joint
/// that arrives with too little energy comes to rest. A pawl
/// (`physics.md` §10.5) is [`LockKind::Pawl`], its crest the farthest its
/// notch lets the joint back (the notch and the contact's give under the
/// breaking torque).
pub fn joint_physical_latch(mech: &Mechanism, j: usize) -> Option<PhysicalLatch> {
    let spec = mech.latches.get(j)?.as_ref()?;
    let stowed = mech.joints.get(j).map_or(0.0, |jt| jt.stowed_deg);
    let core = spec.to_core::<f64>(stowed, 1.0, 1.0);
    let crest_deg = spec.plunger.crest_deg;
    let lock = match spec.pawl {
        Some(_) => LockKind::Pawl,
        None => LockKind::Detent,
    };
    let back_deg = spec.hold_limit_deg(stowed);
    Some(PhysicalLatch {
        switch_travel_deg: spec.switch_travel_deg as f32,
        crest_deg: back_deg as f32,
        ramp_deg: (crest_deg + core.entry_width_rad().to_degrees()) as f32,
        bounce_window_s: BOUNCE_WINDOW_S as f32,
        lock,
    })
}

/// Why a mechanism cannot be monitored.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MonitorConfigError {
    /// The monitor was instantiated for a different number of joints.
    #[error("the mechanism has {found} joints but the monitor was built for {expected}")]
    JointCount {
        /// `N` of the monitor.
        expected: usize,
        /// Joints in the mechanism.
        found: usize,
    },
    /// A spring curve is not valid in `f32`.
    #[error("joint {joint}: spring curve: {source}")]
    Curve {
        /// 1-based joint.
        joint: usize,
        /// What is wrong.
        source: CurveError,
    },
    /// The core rejected the configuration.
    #[error("{0}")]
    Config(deploywatch_core::monitor::ConfigError),
}

/// The spring of a joint in `f32` ([`SpringSpec::to_spring`]), and its
/// capture angle \[deg\].
///
/// The capture angle is where a tape spring's snap-through takes over:
/// θ_B of its points (seed 001 Table 1), below which the unfolding moment
/// rises to its peak D. For a curve spring it is the first knot after the
/// highest moment within [`CAPTURE_WINDOW_DEG`] of the latch, if that peak
/// is more than [`CAPTURE_PEAK_RATIO`] times the moment there; a linear
/// spring has none (0).
pub fn spring_f32(spec: &SpringSpec) -> Result<(Spring<f32>, f64), CurveError> {
    let capture_deg = match spec {
        SpringSpec::Linear { .. } => 0.0,
        SpringSpec::Tape { points, .. } => points.b.0,
        SpringSpec::Curve { unfold, .. } => curve_capture_deg(unfold),
    };
    Ok((spec.to_spring::<f32>()?, capture_deg))
}

/// How far from the latch a curve spring's snap-through peak is looked for
/// \[deg\]: a tape spring's peak D lies within a few degrees of the latch
/// (seed 001 Table 1: 1.5° to 3°).
pub const CAPTURE_WINDOW_DEG: f64 = 5.0;

/// How much higher than the moment at the next knot a curve spring's peak
/// must be to count as a snap-through (ratio): a tape spring's peak D is
/// several times its moment past B (seed 001 Table 1), a smooth curve's is
/// not.
pub const CAPTURE_PEAK_RATIO: f64 = 3.0;

fn curve_capture_deg(unfold: &[(f64, f64)]) -> f64 {
    let near: Vec<(usize, &(f64, f64))> = unfold
        .iter()
        .enumerate()
        .filter(|(_, p)| p.0 <= CAPTURE_WINDOW_DEG)
        .collect();
    let Some(&(ipk, peak)) = near.iter().max_by(|a, b| {
        a.1 .1
            .partial_cmp(&b.1 .1)
            .unwrap_or(std::cmp::Ordering::Equal)
    }) else {
        return 0.0;
    };
    match unfold.get(ipk + 1) {
        Some(after) if peak.1 > CAPTURE_PEAK_RATIO * after.1.abs() => after.0,
        _ => 0.0,
    }
}

/// The engagement of joint `j`'s physical latch (0-based) as the monitor's
/// margin counts it (`core::monitor::latch_margin`): the engagement energy
/// `P0 h + ½ k_p h²` \[J\], the crest and the entry ramp's width \[rad\]
/// (the entry torque is the host's torque form's), from the core's law
/// in `f64` (`physics.md` §10.3), rounded to `f32`;
/// [`Engagement::IDEAL`] for an ideal latch.
pub fn engagement(mech: &Mechanism, j: usize) -> Engagement {
    let (Some(spec), Some(joint)) = (mech.latch(j), mech.joints.get(j)) else {
        return Engagement::IDEAL;
    };
    let l = spec.to_core::<f64>(joint.stowed_deg, 1.0, 1.0);
    Engagement {
        energy_j: l.engagement_energy() as f32,
        crest_rad: l.plunger.crest_rad as f32,
        ramp_rad: l.entry_width_rad() as f32,
    }
}

/// The monitor configuration of a mechanism with `N` joints and the default
/// tuning (`docs/monitor.md`).
pub fn monitor_config<const N: usize>(
    mech: &Mechanism,
) -> Result<MonitorConfig<N>, MonitorConfigError> {
    monitor_config_with::<N>(mech, &PriorSpread::default())
}

/// [`monitor_config`] with a chosen spread of the friction prior. Each
/// joint's latch tracker gets that joint's [`joint_physical_latch`] (`None`:
/// its ideal latch).
pub fn monitor_config_with<const N: usize>(
    mech: &Mechanism,
    spread: &PriorSpread,
) -> Result<MonitorConfig<N>, MonitorConfigError> {
    if mech.joints.len() != N || mech.panels.len() != N {
        return Err(MonitorConfigError::JointCount {
            expected: N,
            found: mech.joints.len(),
        });
    }
    let panels: [Panel<f32>; N] = std::array::from_fn(|i| {
        let p = &mech.panels[i];
        Panel {
            length_m: p.length_m as f32,
            mass_kg: p.mass_kg as f32,
            com_m: p.com_m as f32,
            inertia_kgm2: p.inertia_kgm2 as f32,
        }
    });
    let mut joints = Vec::with_capacity(N);
    for (i, j) in mech.joints.iter().enumerate() {
        let (spring, capture_deg) =
            spring_f32(&j.spring).map_err(|source| MonitorConfigError::Curve {
                joint: i + 1,
                source,
            })?;
        joints.push(JointConfig {
            stowed_deg: j.stowed_deg as f32,
            spring,
            capture_deg: capture_deg as f32,
            prior: FrictionPrior {
                coulomb_nm: j.friction.coulomb_nm as f32,
                coulomb_sd_nm: spread.coulomb_sd_nm as f32,
                viscous_nms: j.friction.viscous_nms as f32,
                viscous_sd_nms: spread.viscous_sd_nms as f32,
            },
            latch: engagement(mech, i),
            physical: joint_physical_latch(mech, i),
        });
    }
    let joints: [JointConfig; N] =
        joints
            .try_into()
            .map_err(|_| MonitorConfigError::JointCount {
                expected: N,
                found: mech.joints.len(),
            })?;
    let mut cfg = MonitorConfig::new(panels, joints);
    cfg.margin.deadline_s = mech.duration_s as f32;
    cfg.validate().map_err(MonitorConfigError::Config)?;
    Ok(cfg)
}

/// The samples of a run as the monitor receives them (`f32`).
///
/// Returns `None` if the run does not have `N` joints.
pub fn samples<const N: usize>(run: &Run) -> Option<Vec<Sample<N>>> {
    if run.joints() != N || run.latch.len() != N {
        return None;
    }
    Some(
        (0..run.len())
            .map(|i| Sample {
                t_s: run.t_s[i] as f32,
                phi_deg: std::array::from_fn(|j| run.phi_deg[j][i] as f32),
                latch: std::array::from_fn(|j| run.latch[j].get(i).copied().unwrap_or(false)),
            })
            .collect(),
    )
}

/// Feeds every sample of `run` to `monitor` and returns the statuses.
pub fn replay<const N: usize>(monitor: &mut Monitor<N>, run: &Run) -> Option<Vec<Status<N>>> {
    Some(
        samples::<N>(run)?
            .iter()
            .map(|s| monitor.replay_step(s))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed001_converts_with_the_tape_capture_angle() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../data/mechanisms/seed001_T01.toml");
        let mech = Mechanism::load(&root).unwrap();
        let cfg = monitor_config::<3>(&mech).unwrap();
        assert_eq!(cfg.joints[0].capture_deg, 1.10);
        assert_eq!(cfg.joints[1].capture_deg, 1.28);
        assert_eq!(cfg.joints[2].stowed_deg, -180.0);
        assert!(Monitor::new(&cfg).is_ok());
        assert!(matches!(
            monitor_config::<2>(&mech),
            Err(MonitorConfigError::JointCount {
                expected: 2,
                found: 3
            })
        ));
    }

    #[test]
    fn curve_capture_is_after_a_snap_peak() {
        let pts = [(0.0, 0.0), (0.5, 30.0), (1.2, 1.0), (90.0, 1.2)];
        assert_eq!(curve_capture_deg(&pts), 1.2);
        let flat = [(0.0, 1.0), (90.0, 2.0)];
        assert_eq!(curve_capture_deg(&flat), 0.0);
    }
}
