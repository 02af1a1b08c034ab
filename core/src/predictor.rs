//! The latch / stall prediction as a resumable computation: the cycle of
//! rollouts ([`crate::rollout`]) that [`crate::Monitor::predict`] advances
//! slice by slice, at a lower priority than the sample path.
//!
//! The sample path ([`crate::Monitor::update`]) hands the predictor the
//! last settled state ([`Predictor::set_start`]); each slice
//! ([`Predictor::slice`]) advances the rollout in progress by a bounded
//! amount of work and, when it ends, stores its outcome and starts the next
//! rollout of the cycle (nominal, pessimistic, nominal, optimistic:
//! `docs/monitor.md` §6) from that state, with the friction beliefs the
//! monitor gives it then. [`Predictor::prediction`] turns the last finished
//! rollouts into a joint's prediction, confidence and time to the latch.

use crate::chain::{Chain, ChainState};
use crate::margin::MarginResult;
use crate::monitor::Prediction;
use crate::rollout::{
    normal_quantile, Bracket, JointOutcome, Rollout, RolloutConfig, RolloutStart,
};

/// The order of the rollouts: the prediction (nominal) is refreshed most
/// often, the brackets that give its confidence take their turns in
/// between.
pub const CYCLE: [Bracket; 4] = [
    Bracket::Nominal,
    Bracket::Pessimistic,
    Bracket::Nominal,
    Bracket::Optimistic,
];

/// What the monitor believes of one joint's friction and spring when a
/// rollout starts (the friction observer's estimate, `docs/monitor.md`
/// §3.2).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FrictionBelief {
    /// Coulomb torque `T̂_C` [N·m].
    pub coulomb_nm: f32,
    /// Variance of `T̂_C` [N²·m²].
    pub coulomb_var: f32,
    /// Viscous coefficient `f̂` [N·m·s/rad].
    pub viscous_nms: f32,
    /// Variance of `f̂` [N²·m²·s²/rad²].
    pub viscous_var: f32,
    /// Spring-scale error `κ̂` [1] (springs at `1 + κ̂`).
    pub spring_scale_err: f32,
    /// Variance of `κ̂` [1].
    pub spring_scale_var: f32,
    /// Lower bound on `T_C` from the friction torque the observer sees now
    /// [N·m] (used by the optimistic bracket).
    pub coulomb_lower_nm: f32,
}

/// A finished rollout's outcome per joint, with its start time [s].
type Finished<const N: usize> = Option<([JointOutcome; N], f32)>;

/// The rollout cycle of the latch / stall prediction.
#[derive(Clone, Copy, Debug)]
pub struct Predictor<const N: usize> {
    /// The rollout in progress, its bracket and start time [s].
    rollout: Option<(Rollout<N>, Bracket, f32)>,
    /// Position in [`CYCLE`] of the rollout in progress.
    cycle_pos: u8,
    /// Last finished nominal, pessimistic and optimistic outcomes, with
    /// their start times [s].
    nominal: Finished<N>,
    pessimistic: Finished<N>,
    optimistic: Finished<N>,
    /// `z = Φ⁻¹(confidence)`.
    z: f32,
    /// Where the next rollout starts: time [s], state and locked joints
    /// (set by the sample path).
    start: Option<(f32, ChainState<f32, N>, [bool; N])>,
}

impl<const N: usize> Predictor<N> {
    /// A predictor whose brackets are at confidence `confidence` (`Φ(z)`),
    /// with no rollout yet.
    pub fn new(confidence: f32) -> Self {
        Predictor {
            rollout: None,
            cycle_pos: 0,
            nominal: None,
            pessimistic: None,
            optimistic: None,
            z: normal_quantile(confidence),
            start: None,
        }
    }

    /// Where the next rollout starts: time [s], joint state and locked
    /// joints; `None` while no settled state is at hand (a rollout in
    /// progress goes on, a finished one is kept).
    pub fn set_start(&mut self, start: Option<(f32, ChainState<f32, N>, [bool; N])>) {
        self.start = start;
    }

    /// One slice: advances the rollout in progress by at most
    /// `cfg.steps_per_slice` units of work; when it ends, stores its outcome
    /// and starts the next rollout of [`CYCLE`] from the last start handed
    /// over, with `belief(j)` for each joint. `deadline_s` is the absolute
    /// deadline [s]: only the time left to it is simulated. Returns true
    /// when a rollout finished.
    pub fn slice(
        &mut self,
        chain: &Chain<f32, N>,
        cfg: &RolloutConfig,
        deadline_s: f32,
        capture_rad: &[f32; N],
        belief: impl Fn(usize) -> FrictionBelief,
    ) -> bool {
        let mut cfg = *cfg;
        let mut finished = false;
        if let Some((r, bracket, t0)) = self.rollout.as_mut() {
            // Only the time left to the deadline matters.
            cfg.horizon_s = cfg.horizon_s.min(deadline_s - *t0).max(cfg.dt_s);
            r.advance(chain, &cfg);
            if r.is_done() {
                let out = (r.outcome(), *t0);
                match bracket {
                    Bracket::Nominal => self.nominal = Some(out),
                    Bracket::Pessimistic => self.pessimistic = Some(out),
                    Bracket::Optimistic => self.optimistic = Some(out),
                }
                finished = true;
            } else {
                return false;
            }
        }
        let pos = match self.rollout {
            None => 0,
            Some(_) => (usize::from(self.cycle_pos) + 1) % CYCLE.len(),
        };
        let next = CYCLE.get(pos).copied().unwrap_or_default();
        let Some((t, state, locked)) = self.start else {
            // Keep the finished rollout until the estimates have settled.
            return finished;
        };
        let z = self.z;
        let sign = match next {
            Bracket::Nominal => 0.0,
            Bracket::Pessimistic => 1.0,
            Bracket::Optimistic => -1.0,
        };
        let mut coulomb = [0.0f32; N];
        let mut viscous = [0.0f32; N];
        let mut spring = [1.0f32; N];
        for j in 0..N {
            let e = belief(j);
            // More friction goes with weaker springs, and less with stronger.
            let sd_k = crate::real::sqrtf(e.spring_scale_var.max(0.0));
            spring[j] = (1.0 + e.spring_scale_err - sign * z * sd_k).max(0.0);
            let sd_c = crate::real::sqrtf(e.coulomb_var.max(0.0));
            let sd_f = crate::real::sqrtf(e.viscous_var.max(0.0));
            coulomb[j] = (e.coulomb_nm + sign * z * sd_c).max(0.0);
            viscous[j] = (e.viscous_nms + sign * z * sd_f).max(0.0);
            if next == Bracket::Optimistic && !locked[j] {
                // Friction is never below the torque it exerts now.
                let bound = e.coulomb_lower_nm;
                if bound <= e.coulomb_nm + 2.0 * sd_c {
                    coulomb[j] = coulomb[j].max(bound);
                }
            }
        }
        let start = RolloutStart {
            state,
            latched: locked,
            coulomb_nm: coulomb,
            viscous_nms: viscous,
            spring_scale: spring,
            capture_rad: *capture_rad,
        };
        self.rollout = Some((Rollout::new(start), next, t));
        self.cycle_pos = pos as u8;
        finished
    }

    /// The latch / stall prediction of joint `j` at time `t` [s] from the
    /// last finished rollouts and what `query` says of the joint (its
    /// latch, its one-joint energy balance, the deadline): the prediction,
    /// its confidence and the time to the latch [s].
    pub fn prediction(
        &self,
        j: usize,
        t: f32,
        query: &PredictionQuery,
    ) -> (Prediction, f32, Option<f32>) {
        let conf = query.confidence;
        let deadline = query.deadline_s;
        let pick = |o: Finished<N>| {
            o.and_then(|(x, t0)| {
                x.get(j).map(|x| {
                    let mut x = *x;
                    x.latches &= t0 + x.latch_after_s <= deadline;
                    (x, t0)
                })
            })
        };
        let (nom, pess, opt) = (
            pick(self.nominal),
            pick(self.pessimistic),
            pick(self.optimistic),
        );
        let ttl = |o: Option<(JointOutcome, f32)>| {
            o.filter(|(x, _)| x.latches)
                .map(|(x, t0)| (t0 + x.latch_after_s - t).max(0.0))
        };
        let energy = query.energy;
        let energy_stall = energy.is_some_and(|r| r.latch_probability <= 1.0 - conf);
        match nom {
            _ if query.latched => (Prediction::Latch, 1.0, None),
            // Not even the one-joint balance, which counts all the
            // kinetic energy in the joint, gets it to the latch.
            _ if energy_stall => (Prediction::Stall, conf, None),
            // Rollouts switched off: the one-joint balance alone.
            _ if !query.rollouts => match energy {
                Some(r) if r.latch_probability >= conf => {
                    (Prediction::Latch, conf, r.time_to_latch_s)
                }
                _ => (
                    Prediction::Unknown,
                    0.0,
                    energy.and_then(|r| r.time_to_latch_s),
                ),
            },
            None => (Prediction::Unknown, 0.0, None),
            Some((x, _)) if x.latches => {
                let sure = pess.is_some_and(|(p, _)| p.latches);
                (Prediction::Latch, if sure { conf } else { 0.5 }, ttl(nom))
            }
            Some(_) => {
                let sure = opt.is_some_and(|(o, _)| !o.latches);
                (Prediction::Stall, if sure { conf } else { 0.5 }, None)
            }
        }
    }
}

/// What [`Predictor::prediction`] needs to know of one joint besides the
/// rollouts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PredictionQuery {
    /// The joint's latch is declared.
    pub latched: bool,
    /// The one-joint energy balance of the joint, if evaluated.
    pub energy: Option<MarginResult>,
    /// The deployment's deadline, absolute [s]: a latch after it is a stall.
    pub deadline_s: f32,
    /// Confidence level `Φ(z)` [1].
    pub confidence: f32,
    /// False when the rollouts are switched off.
    pub rollouts: bool,
}
