//! The firmware's input written from the host: the monitor configuration
//! as frames ([`config_frames`]), each joint's frame ([`joint_frame`]),
//! and the telemetry frame of any value ([`encode_into`]).

use deploywatch_core::monitor::MonitorConfig;
use deploywatch_core::telemetry;
use deploywatch_core::telemetry::config::{
    ConfigHeader, JointFrame, Knots, SpringFrame, TapeFrame, CONFIG_VERSION,
};
use deploywatch_core::Interp;

use super::error::ReplayError;
use crate::model::mechanism::{Mechanism, SpringSpec};
use crate::onboard::monitor_config::spring_f32;

/// The firmware's [`JointFrame`] of joint `j` (0-based) of `mech`: the same
/// `f32` values that
/// [`monitor_config`](crate::onboard::monitor_config::monitor_config)
/// gives the core's constructors.
pub fn joint_frame(mech: &Mechanism, j: usize) -> Result<JointFrame, ReplayError> {
    let (p, joint) = match (mech.panels.get(j), mech.joints.get(j)) {
        (Some(p), Some(joint)) => (p, joint),
        _ => {
            return Err(ReplayError::Input(format!(
                "{}: no joint {}",
                mech.name,
                j + 1
            )))
        }
    };
    let curve_err =
        |e| ReplayError::Input(format!("{}: joint {}: spring curve: {e}", mech.name, j + 1));
    // The capture angle is derived by the host's conversion; take it from there.
    let (_, capture_deg) = spring_f32(&joint.spring).map_err(curve_err)?;
    let knots = |pts: &[(f64, f64)]| {
        let p: Vec<(f32, f32)> = pts.iter().map(|&(x, y)| (x as f32, y as f32)).collect();
        Knots::new(&p).ok_or_else(|| {
            ReplayError::Input(format!(
                "{}: joint {}: too many spring knots",
                mech.name,
                j + 1
            ))
        })
    };
    let spring = match &joint.spring {
        SpringSpec::Linear {
            preload_nm,
            stiffness_nm_per_rad,
            count,
        } => SpringFrame::Linear {
            preload_nm: *preload_nm as f32,
            stiffness_nm_per_rad: *stiffness_nm_per_rad as f32,
            count: *count as f32,
        },
        SpringSpec::Tape { points, count, .. } => SpringFrame::Tape {
            points: TapeFrame {
                a: (points.a.0 as f32, points.a.1 as f32),
                b: (points.b.0 as f32, points.b.1 as f32),
                d: (points.d.0 as f32, points.d.1 as f32),
                m_90: points.m_90 as f32,
                c_180: points.c_180 as f32,
            },
            count: *count as f32,
        },
        SpringSpec::Curve {
            unfold,
            fold,
            interp,
            count,
        } => SpringFrame::Curve {
            akima: *interp == Interp::Akima,
            unfold: knots(unfold)?,
            fold: fold.as_deref().map(knots).transpose()?,
            count: *count as f32,
        },
    };
    let latch = crate::onboard::monitor_config::engagement(mech, j);
    let spread = crate::onboard::monitor_config::PriorSpread::default();
    Ok(JointFrame {
        length_m: p.length_m as f32,
        mass_kg: p.mass_kg as f32,
        com_m: p.com_m as f32,
        inertia_kgm2: p.inertia_kgm2 as f32,
        stowed_deg: joint.stowed_deg as f32,
        spring,
        capture_deg: capture_deg as f32,
        // The default spread of the prior, as `monitor_config` takes it.
        prior: [
            joint.friction.coulomb_nm as f32,
            spread.coulomb_sd_nm as f32,
            joint.friction.viscous_nms as f32,
            spread.viscous_sd_nms as f32,
        ],
        latch_energy_j: latch.energy_j,
        latch_crest_rad: latch.crest_rad,
        latch_ramp_rad: latch.ramp_rad,
        physical: crate::onboard::monitor_config::joint_physical_latch(mech, j),
    })
}

/// Appends the telemetry frame of `value` to `out`; `what` names it in
/// the error.
pub(super) fn encode_into<T: serde::Serialize>(
    value: &T,
    out: &mut Vec<u8>,
    what: &str,
) -> Result<(), ReplayError> {
    let mut buf = [0u8; 2048];
    let frame = telemetry::encode(value, &mut buf)
        .map_err(|e| ReplayError::Input(format!("{what}: {e}")))?;
    out.extend_from_slice(frame);
    Ok(())
}

/// The configuration frames of `mech` for a monitor of `N` joints, after
/// checking that they build the same [`MonitorConfig`] as the host's
/// conversion `config`.
pub fn config_frames<const N: usize>(
    mech: &Mechanism,
    config: &MonitorConfig<N>,
) -> Result<Vec<u8>, ReplayError> {
    let header = ConfigHeader {
        version: CONFIG_VERSION,
        joints: N as u8,
        deadline_s: mech.duration_s as f32,
        latch: config.latch.physical,
    };
    let mut joints = Vec::with_capacity(N);
    for j in 0..N {
        joints.push(joint_frame(mech, j)?);
    }
    let joints: [JointFrame; N] = joints
        .try_into()
        .map_err(|_| ReplayError::Input(format!("{}: not {N} joints", mech.name)))?;
    match header.config(&joints) {
        Some(Ok(c)) if c == *config => {}
        _ => {
            return Err(ReplayError::Input(format!(
                "{}: the configuration frames do not rebuild the host's monitor configuration \
                 (core/src/telemetry/config.rs and host-sim/src/onboard/replay/encode.rs are out \
                 of step with deploywatch_sim::onboard::monitor_config)",
                mech.name
            )))
        }
    }
    let mut out = Vec::new();
    encode_into(&header, &mut out, "configuration header")?;
    for (j, f) in joints.iter().enumerate() {
        encode_into(f, &mut out, &format!("joint {} frame", j + 1))?;
    }
    Ok(out)
}
