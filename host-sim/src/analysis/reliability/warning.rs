//! What the reader of a `reliability` result must not miss: methods that
//! disagree, modes not reached, a c.o.v. above its target, and a verdict
//! its latches' switches decide while the latches hold
//! (`docs/reliability.md` §8). The CLI prints them on stderr and writes
//! them in its JSON's `warnings`; Python gives them in its result's
//! `warnings` and raises each as a `UserWarning`.

use super::criteria::Criterion;
use super::estimate::Estimate;
use super::{Param, Problem, ReliabilityError};

/// Every warning of `est`, in the order the CLI prints them: methods that
/// disagree beyond their 95 % intervals, modes not reached, a c.o.v. above
/// `target_cov`, then [`switch_open_warning`] — or, when that check cannot
/// run, the words of why (a check after the result never costs the
/// result). `name` says a parameter the way the caller's user writes it
/// (the CLI's option, Python's argument; [`ReliabilityError::words`]).
pub fn warnings(
    problem: &Problem,
    est: &Estimate,
    target_cov: Option<f64>,
    name: &dyn Fn(Param) -> String,
) -> Vec<String> {
    let mut w = Vec::new();
    if est.agree == Some(false) {
        w.push(
            "importance sampling and subset simulation DISAGREE beyond their 95 % intervals: \
             neither is settled; run method mc with enough deployments (docs/reliability.md §8)"
                .to_string(),
        );
    }
    if !est.converged {
        w.push(format!(
            "{}: not every failure mode was reached: p_fail counts the modes reached only and \
             is not a bound; settle it with method mc (or auto, which checks is against \
             subset)",
            est.method
        ));
    }
    if let Some(c) = target_cov.filter(|&c| est.cov > c) {
        w.push(format!(
            "c.o.v. {:.3} is above the target c.o.v. {c}",
            est.cov
        ));
    }
    match switch_open_warning(problem, est) {
        Ok(Some(said)) => w.push(said),
        Ok(None) => {}
        Err(e) => w.push(format!(
            "the latches of the most likely failure seen could not be checked: {}",
            e.words(name)
        )),
    }
    w
}

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
