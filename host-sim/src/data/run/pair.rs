//! Pairing a run with its mechanism, and whether it holds something to
//! analyse.

use super::error::{RunError, RunErrorKind};
use super::record::{Run, MIN_MOTION_DEG};
use crate::model::mechanism::Mechanism;

/// The line of the run's `# mechanism` metadata: metadata lines come
/// first in a run file, one per key, in order (`docs/spec/formats.md`).
fn mechanism_line(run: &Run) -> usize {
    1 + run
        .metadata
        .iter()
        .position(|(k, _)| k == "mechanism")
        .unwrap_or(0)
}

/// The mechanism a run belongs to: the one whose `name` equals the run's
/// `mechanism` metadata. `run_source` names the run in errors.
///
/// Errors: the run has no `mechanism` metadata; no mechanism of that name is
/// given (the message lists the names given); different mechanisms of that
/// name are given; the joint counts differ.
pub fn pair_runs<'a>(
    mechanisms: &'a [Mechanism],
    run: &Run,
    run_source: &str,
) -> Result<&'a Mechanism, RunError> {
    let file = run_source.to_string();
    let Some(name) = run.mechanism() else {
        return Err(RunError::whole(&file, RunErrorKind::NoMechanism));
    };
    let mut same = mechanisms.iter().filter(|m| m.name == name);
    let Some(m) = same.next() else {
        return Err(RunError::at(
            &file,
            mechanism_line(run),
            RunErrorKind::UnknownMechanism {
                name: name.to_string(),
                given: mechanisms.iter().map(|m| m.name.clone()).collect(),
            },
        ));
    };
    let others: Vec<&Mechanism> = same.collect();
    if others.iter().any(|o| *o != m) {
        return Err(RunError::whole(
            &file,
            RunErrorKind::AmbiguousMechanism {
                name: name.to_string(),
                count: 1 + others.len(),
            },
        ));
    }
    if m.joint_count() != run.joints() {
        return Err(RunError::whole(
            &file,
            RunErrorKind::JointCountMismatch {
                mechanism: m.name.clone(),
                run_joints: run.joints(),
                mechanism_joints: m.joint_count(),
            },
        ));
    }
    Ok(m)
}

/// Checks that a run can be of `mechanism`: its `mechanism` metadata, when
/// given, names it, and the joint counts agree. For the commands that take
/// one mechanism file and one run (`replay`); `file` names the run.
pub fn check_run_of(mechanism: &Mechanism, run: &Run, file: &str) -> Result<(), RunError> {
    if let Some(name) = run.mechanism().filter(|&n| n != mechanism.name) {
        return Err(RunError::at(
            file,
            mechanism_line(run),
            RunErrorKind::UnknownMechanism {
                name: name.to_string(),
                given: vec![mechanism.name.clone()],
            },
        ));
    }
    if mechanism.joint_count() != run.joints() {
        return Err(RunError::whole(
            file,
            RunErrorKind::JointCountMismatch {
                mechanism: mechanism.name.clone(),
                run_joints: run.joints(),
                mechanism_joints: mechanism.joint_count(),
            },
        ));
    }
    Ok(())
}
/// Checks that a run, paired with its mechanism, holds something to analyse
/// (identification, diagnosis), beyond what the format requires:
/// - some joint moves by [`MIN_MOTION_DEG`] or more
///   ([`RunErrorKind::NeverMoves`]);
/// - the run goes on until every latch switch reads closed, or to the
///   mechanism's `duration_s` within one and a half sample intervals
///   ([`RunErrorKind::EndsEarly`]: a file truncated at a line end, which the
///   reader cannot tell from a short run).
///
/// `file` names the run in the error. The monitor does not need this: a
/// run that never moves (a failed release) is one it must call a stall.
pub fn check_analysable(run: &Run, mechanism: &Mechanism, file: &str) -> Result<(), RunError> {
    let (Some(&first), Some(&end_s)) = (run.t_s.first(), run.t_s.last()) else {
        return Err(RunError::whole(
            file,
            RunErrorKind::Invalid {
                reason: "no samples; expected at least one".to_string(),
            },
        ));
    };
    let motion_deg = run.motion_deg();
    if motion_deg < MIN_MOTION_DEG {
        return Err(RunError::whole(
            file,
            RunErrorKind::NeverMoves {
                motion_deg,
                duration_s: end_s - first,
            },
        ));
    }
    let unlatched: Vec<usize> = run
        .latch
        .iter()
        .enumerate()
        .filter(|(_, l)| !l.last().copied().unwrap_or(false))
        .map(|(j, _)| j + 1)
        .collect();
    let dt = if run.len() > 1 {
        (end_s - first) / (run.len() - 1) as f64
    } else {
        0.0
    };
    if !unlatched.is_empty() && end_s < mechanism.duration_s - 1.5 * dt {
        return Err(RunError::whole(
            file,
            RunErrorKind::EndsEarly {
                end_s,
                duration_s: mechanism.duration_s,
                unlatched,
            },
        ));
    }
    Ok(())
}
