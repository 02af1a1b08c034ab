//! When each joint's latch last came to hold it, for `not_held`
//! ([`Criterion::NotHeld`](super::criteria::Criterion::NotHeld)): where a
//! physical-latch run ended, in the words of its latch
//! ([`LatchRun::outcome`], [`LatchEnd::holds`](crate::simulate::latch_run::LatchEnd::holds):
//! a ball plunger past its crest, a pawl in its notch), whatever the
//! switch reads.

use crate::model::effect::Effect;
use crate::model::mechanism::Mechanism;
use crate::simulate::latch_deployment::weakenings;
use crate::simulate::latch_run::{LatchEventKind, LatchRun};
use deploywatch_core::physics::latch_contact::LatchMark;

/// Per joint of `mech` (its `effects` weakening its latches as the run
/// had them): the instant \[s\] its latch last came to hold it — the last
/// pawl drop or inward pass over the crest, 0 when it held from the start
/// — or `None` when it does not hold it where `run` ended. A joint with
/// an ideal latch: its latch instant.
pub(super) fn held_instants(
    run: &LatchRun,
    mech: &Mechanism,
    effects: &[Effect],
) -> Vec<Option<f64>> {
    let n = mech.joint_count();
    let weak = weakenings(effects, n);
    (0..n)
        .map(|j| {
            let spec = mech.latches.get(j).and_then(Option::as_ref);
            let (Some(spec), Some(joint)) = (spec, mech.joints.get(j)) else {
                return run.traj.latch_s.get(j).copied().flatten();
            };
            let (p, m) = weak.get(j).copied().unwrap_or((1.0, 1.0));
            let latch = spec.to_core(joint.stowed_deg, p, m);
            if !run.outcome(j + 1, &latch)?.end.holds() {
                return None;
            }
            let came = run
                .events
                .iter()
                .rev()
                .filter(|e| e.joint == j + 1)
                .find(|e| {
                    e.kind == LatchEventKind::PawlDrop
                        || (e.kind == LatchEventKind::Mark(LatchMark::Crest) && e.rate_rad_s < 0.0)
                });
            Some(came.map_or(0.0, |e| e.t_s))
        })
        .collect()
}
