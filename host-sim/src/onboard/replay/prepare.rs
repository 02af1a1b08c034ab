//! A run made ready to replay: loaded, checked against its mechanism, turned
//! into the firmware's input frames, and run through the host's `f32`
//! monitor.

use std::path::Path;

use deploywatch_core::monitor::{Monitor, MonitorConfig, Sample};

use super::encode::{config_frames, encode_into};
use super::error::ReplayError;
use super::status::StatusRow;
use crate::data::run::Run;
use crate::model::mechanism::{with_joints, Mechanism};
use crate::onboard::monitor_config::{monitor_config, samples};

/// A run ready to replay: the input frames and the host's statuses.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// Joints.
    pub joints: usize,
    /// Samples.
    pub samples: usize,
    /// The firmware's input: configuration frames, then sample frames.
    pub input: Vec<u8>,
    /// The host's `f32` monitor run, as status frames.
    pub host_frames: Vec<u8>,
    /// The same, decoded.
    pub host: Vec<StatusRow>,
}

/// What a replay of a run on a zero-g rig must say: the monitor models the
/// wing as it flies (no rig: `MonitorConfig` has no term of it), so its
/// friction, margin and prediction include the rig's own resistance and
/// gravity offload. `None` for a mechanism without an active rig.
pub fn rig_note(mech: &Mechanism) -> Option<String> {
    mech.active_rig().map(|_| {
        format!(
            "`{}` deploys on a zero-g rig: the monitor models the wing without it, so its \
             friction, margin and time to latch include the rig's own resistance; `deploywatch \
             diagnose` separates the rig from the hinges (docs/margin.md, \"The hinge friction with the rig taken out\")",
            mech.name
        )
    })
}

/// Loads a run for the monitor (missing samples allowed, as `NaN`).
pub fn load_run(path: &Path) -> Result<Run, ReplayError> {
    let opts = crate::data::run::ReadOptions {
        allow_missing: true,
    };
    Run::load_with(path, opts).map_err(|e| ReplayError::Input(e.to_string()))
}

/// The monitor's configuration of `mech` and the samples of `run` for a
/// monitor of `N` joints (what every replay and the serial link start from).
pub(crate) fn config_and_samples<const N: usize>(
    mech: &Mechanism,
    run: &Run,
) -> Result<(MonitorConfig<N>, Vec<Sample<N>>), ReplayError> {
    let config =
        monitor_config::<N>(mech).map_err(|e| ReplayError::Input(format!("{}: {e}", mech.name)))?;
    let n = run.joints();
    let samples = samples::<N>(run)
        .ok_or_else(|| ReplayError::Input(format!("the run has {n} joints, the mechanism {N}")))?;
    Ok((config, samples))
}

fn prepare_n<const N: usize>(mech: &Mechanism, run: &Run) -> Result<Prepared, ReplayError> {
    let (config, samples) = config_and_samples::<N>(mech, run)?;
    let mut input = config_frames::<N>(mech, &config)?;
    for (i, s) in samples.iter().enumerate() {
        encode_into(s, &mut input, &format!("sample {i}"))?;
    }
    let mut monitor =
        Monitor::new(&config).map_err(|e| ReplayError::Input(format!("{}: {e}", mech.name)))?;
    let mut host_frames = Vec::new();
    let mut host = Vec::with_capacity(samples.len());
    for (i, s) in samples.iter().enumerate() {
        let status = monitor.replay_step(s);
        encode_into(&status, &mut host_frames, &format!("status {i}"))?;
        host.push(StatusRow::from(&status));
    }
    Ok(Prepared {
        joints: N,
        samples: samples.len(),
        input,
        host_frames,
        host,
    })
}

/// Checks that `run` is of `mech` (its `mechanism` metadata, when given)
/// and returns the mechanism's joint count.
pub(crate) fn run_of(mech: &Mechanism, run: &Run) -> Result<usize, ReplayError> {
    if let Some(name) = run.mechanism() {
        if name != mech.name {
            return Err(ReplayError::Input(format!(
                "the run is of mechanism `{name}`, the mechanism file is `{}`",
                mech.name
            )));
        }
    }
    Ok(mech.joint_count())
}

/// The input frames of `run` on `mech` and the host's `f32` monitor run.
/// The run must be of the mechanism (its `mechanism` metadata, when given)
/// and have 1 to 4 joints.
pub fn prepare(mech: &Mechanism, run: &Run) -> Result<Prepared, ReplayError> {
    let n = run_of(mech, run)?;
    with_joints!(n, N => prepare_n::<N>(mech, run), else Err(ReplayError::Input(format!(
        "{}: {n} joints; the monitor is built for 1 to 4",
        mech.name
    ))))
}
