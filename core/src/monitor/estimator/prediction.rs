//! The slow path's hand-over to the latch / stall prediction
//! ([`crate::monitor::predictor`]): the state the next rollout starts
//! from, the friction each rollout assumes, and the prediction read back
//! into the status.

use super::joint::Forecast;
use super::learning::Learning;
use super::state::Monitor;
use crate::monitor::predictor::{FrictionBelief, Prediction, PredictionQuery};
use crate::monitor::smoother::Centre;
use crate::physics::chain::ChainState;

/// Time without a centred fit after which a rollout starts from the rate
/// filter instead [s].
const CENTRE_WAIT_S: f32 = 0.5;

impl<const N: usize> Monitor<N> {
    /// Hands the state the next rollout starts from to the prediction.
    ///
    /// A rollout starts from the centred fit (rates to a few tenths of a
    /// degree per second, half a window back); from the rate filter only
    /// when no fit has come for a while (a flaky encoder), since its rates
    /// after a latch impact are off by degrees per second
    /// (docs/monitor.md §6).
    pub(super) fn hand_over_to_prediction(
        &mut self,
        sample: &Learning<N>,
        centre: Option<&Centre<N>>,
    ) {
        if self.tuning.margin.rollout.steps_per_slice == 0 {
            return;
        }
        let t = sample.t;
        let start = match centre {
            Some(c) => Some((
                c.t_s,
                ChainState {
                    phi: c.phi,
                    phi_dot: c.rate,
                },
                c.locked,
            )),
            None if sample.quiet && t - self.learner.t_centre > CENTRE_WAIT_S => {
                let locked = sample.locked();
                let (phi, phi_dot) = self.model_state(&locked);
                Some((t, ChainState { phi, phi_dot }, locked))
            }
            None => None,
        };
        if let Some(c) = centre {
            self.learner.t_centre = c.t_s;
        }
        // Handed to the next rollout the predictor starts.
        self.predictor.set_start(start);
    }

    /// The learned part of every joint's status: friction, margin and the
    /// latch / stall prediction as of time `t` [s].
    pub(super) fn refresh_estimates(&mut self, t: f32) {
        for j in 0..N {
            let (prediction, confidence, time_to_latch_s) = self.prediction(j, t);
            if let (Some(js), Some(out)) = (self.joints.get_mut(j), self.status.joints.get_mut(j)) {
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
    }

    /// The latch / stall prediction of joint `j` at time `t` [s] from the
    /// last finished rollouts and the energy balance: the prediction, its
    /// confidence and the time to the latch [s]. A stall of a joint the
    /// latch tracker sees at rest on a physical latch's ramp
    /// ([`crate::monitor::latch::LatchState::StoppedShort`]) is a ramp stop.
    fn prediction(&mut self, j: usize, t: f32) -> (Prediction, f32, Option<f32>) {
        let cfg = &self.tuning.margin;
        let on_ramp = self.joints.get(j).is_some_and(|s| s.lt.stopped_short());
        let (prediction, confidence, time) = self.predictor.prediction(
            j,
            t,
            &PredictionQuery {
                latched: self.joints.get(j).is_some_and(|s| s.lt.is_latched()),
                energy: self.joints.get(j).and_then(|s| s.margin),
                deadline_s: self.timeline.t_start + cfg.deadline_s,
                confidence: cfg.confidence,
                rollouts: cfg.rollout.steps_per_slice > 0,
            },
        );
        match prediction {
            Prediction::Stall if on_ramp => (Prediction::RampStop, confidence, time),
            _ => (prediction, confidence, time),
        }
    }

    /// Advances the rollout in progress; when it ends, the predictor
    /// starts the next bracket from [`Monitor::update`]'s last settled
    /// state with the current friction estimates. Returns true when a
    /// rollout finished.
    pub(super) fn advance_rollouts(&mut self) -> bool {
        let joints = &self.joints;
        let capture_rad: [f32; N] = core::array::from_fn(|j| joints[j].capture_rad);
        let cfg = &self.tuning.margin;
        self.predictor.slice(
            &self.chain,
            &cfg.rollout,
            self.timeline.t_start + cfg.deadline_s,
            &capture_rad,
            |j| match joints.get(j) {
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
            },
        )
    }
}
