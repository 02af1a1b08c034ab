//! The slow path's hand-over to the latch / stall prediction
//! ([`crate::monitor::predictor`]): the state the next rollout starts
//! from, the friction each rollout assumes, and the prediction read back
//! into the status.

use super::joint::{Forecast, JointState};
use super::learning::{Fitted, Learning};
use super::state::Monitor;
use crate::monitor::predictor::{Cycle, FrictionBelief, Prediction, PredictionQuery, UNCONFIRMED};
use crate::monitor::rollout::RolloutConfig;
use crate::monitor::status::JointStatus;
use crate::physics::chain::{ChainRef, ChainState};

/// Time without a centred fit after which a rollout starts from the rate
/// filter instead \[s\].
const CENTRE_WAIT_S: f32 = 0.5;

impl<const N: usize> Monitor<N> {
    /// Hands the state the next rollout starts from to the prediction.
    ///
    /// A rollout starts from the centred fit (rates to a few tenths of a
    /// degree per second, half a window back); from the rate filter only
    /// when no fit has come for a while (a flaky encoder), since its rates
    /// after a latch impact are off by degrees per second
    /// (docs/monitor.md §6).
    ///
    /// `locked`: the sample's locked joints ([`Learning::locked_padded`]).
    pub(super) fn hand_over_to_prediction(
        &mut self,
        sample: &Learning<N>,
        locked: &[bool; N],
        fit: Option<&Fitted<N>>,
    ) {
        if self.tuning.margin.rollout.steps_per_slice == 0 {
            return;
        }
        hand_over(
            self.predictor.cycle_mut(),
            &self.joints,
            fit,
            (sample.t, sample.quiet, locked),
            &mut self.learner.t_centre,
        );
    }

    /// The learned part of every joint's status: friction, margin and the
    /// latch / stall prediction as of time `t` \[s\] ([`refresh`]).
    pub(super) fn refresh_estimates(&mut self, t: f32) {
        let cfg = &self.tuning.margin;
        refresh(
            self.predictor.cycle_mut(),
            &mut self.joints,
            &mut self.status.joints,
            &Horizon {
                deadline_s: self.timeline.t_start + cfg.deadline_s,
                confidence: cfg.confidence,
                rollouts: cfg.rollout.steps_per_slice > 0,
            },
            t,
        );
    }

    /// Advances the rollout in progress; when it ends, the predictor
    /// starts the next bracket from [`Monitor::update`]'s last settled
    /// state with the current friction estimates ([`advance`]). Returns
    /// true when a rollout finished.
    pub(super) fn advance_rollouts(&mut self) -> bool {
        let store = self.chain.coefficients();
        let chain = self.chain.counted_with(&store);
        let cfg = &self.tuning.margin;
        advance(
            self.predictor.cycle_mut(),
            &chain,
            &cfg.rollout,
            self.timeline.t_start + cfg.deadline_s,
            &self.joints,
        )
    }
}

/// [`Monitor::hand_over_to_prediction`] to `cycle`: the fit `fit` when
/// there is one (its time kept in `t_centre` \[s\]), else, once no fit has
/// come for [`CENTRE_WAIT_S`] and the sample (its time \[s\], whether it is
/// quiet, its locked joints) is quiet, the rate filters of `joints` (0 for
/// a locked joint). Not generic over the joint count: one copy in flash
/// for every monitor.
#[inline(never)]
fn hand_over<const R: usize>(
    cycle: &mut Cycle<R>,
    joints: &[JointState],
    fit: Option<&Fitted<R>>,
    (t, quiet, locked): (f32, bool, &[bool; R]),
    t_centre: &mut f32,
) {
    let start = match fit {
        Some(c) => Some((
            c.t_s,
            ChainState {
                phi: c.phi,
                phi_dot: c.rate,
            },
            c.locked,
        )),
        None if quiet && t - *t_centre > CENTRE_WAIT_S => {
            let mut x = ChainState {
                phi: [0.0; R],
                phi_dot: [0.0; R],
            };
            for j in 0..joints.len().min(R) {
                if let (false, Some(js)) = (locked[j], joints.get(j)) {
                    x.phi[j] = js.kf.angle();
                    x.phi_dot[j] = js.kf.rate();
                }
            }
            Some((t, x, *locked))
        }
        None => None,
    };
    if let Some(c) = fit {
        *t_centre = c.t_s;
    }
    // Handed to the next rollout the predictor starts.
    cycle.set_start(start);
}

/// What the prediction of every joint is asked against: the deadline, the
/// confidence and whether the rollouts run.
struct Horizon {
    /// The deployment's deadline, absolute \[s\].
    deadline_s: f32,
    /// Confidence level `Φ(z)` \[1\].
    confidence: f32,
    /// False when the rollouts are switched off.
    rollouts: bool,
}

/// True when every joint of `joints` is latched or at rest short of its
/// latch (stalled, stopped on a ramp): nothing in the chain moves that
/// could free a joint at rest.
fn chain_at_rest(joints: &[JointState]) -> bool {
    joints
        .iter()
        .all(|js| js.lt.is_latched() || js.lt.at_rest())
}

/// The learned part of the status line `out` of each joint of `joints`:
/// friction, margin and the latch / stall prediction of `cycle` as of time
/// `t` \[s\]. Not generic over the joint count: one copy in flash for every
/// monitor.
#[inline(never)]
fn refresh<const R: usize>(
    cycle: &mut Cycle<R>,
    joints: &mut [JointState],
    out: &mut [JointStatus],
    horizon: &Horizon,
    t: f32,
) {
    let still = chain_at_rest(joints);
    for (j, (js, out)) in joints.iter_mut().zip(out.iter_mut()).enumerate() {
        let (prediction, confidence, time_to_latch_s) = forecast(cycle, j, js, horizon, (t, still));
        js.estimates(
            out,
            Forecast {
                prediction,
                confidence,
                time_to_latch_s,
            },
        );
    }
}

/// The latch / stall prediction of joint `j` (its state `js`) at time `t`
/// \[s\] (`still`: every joint latched or at rest, [`chain_at_rest`]) from
/// the last finished rollouts of `cycle` and the energy balance: the
/// prediction, its confidence and the time to the latch \[s\]. What the
/// latch tracker knows of the joint comes first:
///
/// - its lock broke (a pawl out beyond its notch,
///   [`crate::monitor::latch::LatchTracker::lock_broken`]): it will not be
///   latched, a stall as certain as a declared latch;
/// - past a physical latch's crest since it last escaped
///   ([`crate::monitor::latch::LatchTracker::past_crest`]): a stall is a
///   latch at confidence 0.5, the hold ramp and the magnet pulling it onto
///   the stop, which neither the rollouts nor the balance (its margin
///   frozen on the ramp) model; a rebound may still throw it out;
/// - at rest on a physical latch's ramp
///   ([`crate::monitor::latch::LatchState::StoppedShort`]): a stall is a
///   ramp stop;
/// - at rest short of the latch (stalled, or stopped on the ramp): a latch
///   is the rollouts' best estimate only (confidence 0.5), for they start it
///   from rest with the friction estimate, which does not know what holds
///   it (a jam mid-stroke, the ramp), and the readings say it does not
///   move. Once its readings have held still for longer than the rollouts'
///   time to the latch and the stall time besides, in a chain at rest, it
///   is a stall (a ramp stop on the ramp) at confidence 0.5: the rollouts,
///   started from rest each time, keep giving it the same time, and no
///   neighbour's motion is left to free it (on T01 joint 1 waits at its
///   stowed angle while its neighbours unfold, then latches).
fn forecast<const R: usize>(
    cycle: &mut Cycle<R>,
    j: usize,
    js: &JointState,
    horizon: &Horizon,
    (t, still): (f32, bool),
) -> (Prediction, f32, Option<f32>) {
    if js.lt.lock_broken() {
        return (Prediction::Stall, 1.0, None);
    }
    let on_ramp = js.lt.stopped_short();
    let (prediction, confidence, time) = cycle.prediction(
        j,
        t,
        &PredictionQuery {
            latched: js.lt.is_latched(),
            energy: js.margin,
            deadline_s: horizon.deadline_s,
            confidence: horizon.confidence,
            rollouts: horizon.rollouts,
        },
    );
    let stall = if on_ramp {
        Prediction::RampStop
    } else {
        Prediction::Stall
    };
    match prediction {
        Prediction::Stall | Prediction::RampStop if js.lt.past_crest() => {
            (Prediction::Latch, UNCONFIRMED, None)
        }
        Prediction::Stall => (stall, confidence, time),
        Prediction::Latch if js.lt.at_rest() => {
            // Rested for longer than the rollouts from rest give it to
            // reach the latch, and the stall time besides, in a chain at
            // rest: what holds it is not what they start it with, and no
            // neighbour's motion is left to free it.
            let wait = time.map(|ttl| ttl + js.latch_cfg.stall_time_s);
            if still && wait.is_some_and(|w| js.lt.at_rest_for(t, w)) {
                (stall, UNCONFIRMED, None)
            } else {
                (prediction, confidence.min(UNCONFIRMED), time)
            }
        }
        _ => (prediction, confidence, time),
    }
}

/// One slice of `cycle` ([`Cycle::slice`]) on `chain`, the joints'
/// capture angles and friction beliefs taken from `joints`. Not generic
/// over the joint count: one copy in flash for every monitor.
#[inline(never)]
fn advance<const R: usize>(
    cycle: &mut Cycle<R>,
    chain: &ChainRef<'_, f32, R>,
    cfg: &RolloutConfig,
    deadline_s: f32,
    joints: &[JointState],
) -> bool {
    let mut capture_rad = [0.0f32; R];
    for (c, js) in capture_rad.iter_mut().zip(joints.iter()) {
        *c = js.capture_rad;
    }
    cycle.slice(chain, cfg, deadline_s, &capture_rad, &|j| {
        match joints.get(j) {
            Some(js) => {
                // f only as far as the data resolve it (§3.2).
                let e = js.friction().0;
                FrictionBelief {
                    coulomb_nm: e.coulomb_nm,
                    coulomb_var: e.coulomb_var,
                    viscous_nms: e.viscous_nms,
                    viscous_var: e.viscous_var,
                    spring_scale_err: e.spring_scale_err,
                    spring_scale_var: e.spring_scale_var,
                    coulomb_lower_nm: js.fo.coulomb_lower_bound(js.kf.rate(), e.viscous_nms),
                }
            }
            _ => FrictionBelief::default(),
        }
    })
}
