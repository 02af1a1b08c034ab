//! What `reliability` says of a verdict its latches' switches decide
//! while the latches hold (`docs/reliability.md` §8): the CLI prints it on
//! stderr, Python raises it as a `UserWarning`.

use super::criteria::Criterion;
use super::estimate::Estimate;
use super::{Problem, ReliabilityError};

/// When `not_latched` is a criterion of a physical-latch wing and the most
/// likely failure seen of `est` fails it at a joint its latch holds (the
/// switch open at the end as the joint rattles at its stop), the words
/// that say the verdict is the rattle's phase and name `not_held`: what
/// `reliability` prints on stderr and Python warns (one more deployment,
/// [`Problem::held_with_switch_open`]). `None` otherwise.
pub fn switch_open_warning(
    problem: &Problem,
    est: &Estimate,
) -> Result<Option<String>, ReliabilityError> {
    let asked = problem.fail.contains(&Criterion::NotLatched) && problem.mech.has_physical_latch();
    let Some(f) = est.most_likely_failure.as_ref().filter(|_| asked) else {
        return Ok(None);
    };
    let joints = problem.held_with_switch_open(&f.x)?;
    if joints.is_empty() {
        return Ok(None);
    }
    let at = match joints.len() {
        1 => "joint",
        _ => "joints",
    };
    let joints: Vec<String> = joints.iter().map(|j| j.to_string()).collect();
    Ok(Some(format!(
        "the most likely failure seen fails not_latched at {at} {}, held by its latch (a pawl \
         in its notch, a ball plunger past its crest) with its switch open at the end as it \
         rattles at its stop: such a verdict is the rattle's phase at the end, which the \
         integration does not settle (docs/reliability.md §8); the criterion not_held counts \
         what the latch does",
        joints.join(", ")
    )))
}
