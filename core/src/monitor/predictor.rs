//! The latch / stall prediction as a resumable computation: the cycle of
//! rollouts ([`crate::monitor::rollout`]) that [`crate::monitor::Monitor::learn_or_predict`] advances
//! slice by slice, at a lower priority than the sample path.
//!
//! The sample path ([`crate::monitor::Monitor::update`]) hands the predictor the
//! last settled state ([`Cycle::set_start`]); each slice
//! ([`Cycle::slice`]) advances the rollout in progress by a bounded
//! amount of work and, when it ends, stores its outcome and starts the next
//! rollout of the cycle from that state, with the friction beliefs the
//! monitor gives it then. [`Cycle::prediction`] turns the last finished
//! rollouts into a joint's prediction, confidence and time to the latch.
//!
//! A cycle — one *full prediction* — is the nominal rollout (the
//! prediction), then the brackets its verdicts need for their confidence
//! (`docs/monitor.md` §6): the pessimistic one when it latches some joint,
//! watching only those joints (it ends once they have latched), and the
//! optimistic one when it stalls some joint, watching only those (it ends
//! early if they all latch). A bracket that would confirm nothing is not
//! run. [`Predictor::refreshes`] counts the completed cycles.

use crate::monitor::margin::MarginResult;
use crate::monitor::rollout::{
    normal_quantile, Bracket, JointOutcome, RolloutConfig, RolloutStart, Stepper,
    ROLLOUT_MAX_JOINTS,
};
use crate::physics::chain::{ChainRef, ChainState};
use serde::{Deserialize, Serialize};
/// The latch / stall prediction of a joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Prediction {
    /// Not decided at the configured confidence.
    #[default]
    Unknown,
    /// Will latch (or has latched).
    Latch,
    /// Will stall short of the latch (or, its lock broken, will not be
    /// held at it).
    Stall,
    /// Will stop on the physical latch's entry ramp, short of its crest
    /// (the energy balance reaches the ramp's foot and runs out before the
    /// crest: [`crate::monitor::latch_margin`]).
    RampStop,
}

impl Prediction {
    /// Every prediction.
    pub const ALL: [Prediction; 4] = [
        Prediction::Unknown,
        Prediction::Latch,
        Prediction::Stall,
        Prediction::RampStop,
    ];

    /// The name used in telemetry CSV and reports.
    pub const fn as_str(self) -> &'static str {
        match self {
            Prediction::Unknown => "unknown",
            Prediction::Latch => "latch",
            Prediction::Stall => "stall",
            Prediction::RampStop => "ramp_stop",
        }
    }

    /// The prediction of a name written by [`Prediction::as_str`].
    pub fn from_name(name: &str) -> Option<Self> {
        Prediction::ALL.iter().copied().find(|p| p.as_str() == name)
    }
}

impl core::fmt::Display for Prediction {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What the monitor believes of one joint's friction and spring when a
/// rollout starts (the friction observer's estimate, `docs/monitor.md`
/// §3.2). The viscous term is in it only as far as the data resolve it:
/// where they do not, `viscous_nms` is the prior mean with `viscous_var` 0
/// and the Coulomb torque is the estimate conditioned on it, which holds
/// the friction seen at the rates observed
/// (`FrictionObserver::estimate_given_viscous`).
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
    /// Spring-scale error `κ̂` \[1\] (springs at `1 + κ̂`).
    pub spring_scale_err: f32,
    /// Variance of `κ̂` \[1\].
    pub spring_scale_var: f32,
    /// Lower bound on `T_C` from the friction torque the observer sees now
    /// [N·m] (used by the optimistic bracket).
    pub coulomb_lower_nm: f32,
}

/// A finished rollout's outcome per joint, with its start time \[s\].
type Finished<const R: usize> = Option<([JointOutcome; R], f32)>;

/// Where the next rollout starts: time \[s\], joint state and locked joints.
pub(crate) type Start<const M: usize> = (f32, ChainState<f32, M>, [bool; M]);

/// The rollout cycle of the latch / stall prediction of an `N`-joint
/// monitor: a shell over the cycle written once for every joint count
/// (`Cycle<N>`, over arrays of capacity `N`).
#[derive(Clone, Copy, Debug)]
pub struct Predictor<const N: usize> {
    cycle: Cycle<N>,
}

/// The rollout cycle over arrays of capacity `R` (at most
/// [`ROLLOUT_MAX_JOINTS`]), the
/// first `n` joints in use: one copy of the code for the monitors of
/// every joint count ([`Predictor`] is its shell).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cycle<const R: usize> {
    /// Joints in use.
    n: u8,
    /// The rollout in progress, its bracket and start time \[s\].
    rollout: Option<(Stepper<R>, Bracket, f32)>,
    /// The next rollout of the cycle and the joints it watches.
    next: (Bracket, [bool; R]),
    /// The nominal rollout's verdicts in this cycle: the joints it latches
    /// by the deadline and those it does not (free at its start).
    verdict: ([bool; R], [bool; R]),
    /// Completed cycles (full predictions).
    refreshes: u32,
    /// Last finished nominal, pessimistic and optimistic outcomes, with
    /// their start times \[s\].
    nominal: Finished<R>,
    pessimistic: Finished<R>,
    optimistic: Finished<R>,
    /// The joints each bracket watched (only those it confirms or not).
    pessimistic_watch: [bool; R],
    optimistic_watch: [bool; R],
    /// Joints the one-joint energy balance has called stalled
    /// (`P ≤ 1 − confidence`), until it gives `P ≥` [`ENERGY_STALL_CLEAR`].
    energy_stall: [bool; R],
    /// `z = Φ⁻¹(confidence)`.
    z: f32,
    /// Where the next rollout starts: time \[s\], state and locked joints
    /// (set by the sample path; the joints past `n` locked).
    start: Option<Start<R>>,
}

impl<const N: usize> Predictor<N> {
    /// A predictor whose brackets are at confidence `confidence` (`Φ(z)`),
    /// with no rollout yet.
    pub fn new(confidence: f32) -> Self {
        const {
            assert!(
                N <= ROLLOUT_MAX_JOINTS,
                "a predictor holds at most 8 joints"
            )
        };
        Predictor {
            cycle: Cycle::new(N, confidence),
        }
    }

    /// Full predictions completed so far: cycles of the nominal rollout and
    /// the brackets its verdicts need.
    pub fn refreshes(&self) -> u32 {
        self.cycle.refreshes
    }

    /// The cycle itself, for the monitor's slow path written once for
    /// every joint count.
    pub(crate) fn cycle_mut(&mut self) -> &mut Cycle<N> {
        &mut self.cycle
    }
}

impl<const R: usize> Cycle<R> {
    /// A cycle of `n` joints (at most [`ROLLOUT_MAX_JOINTS`]) whose
    /// brackets are at confidence `confidence` (`Φ(z)`), with no rollout
    /// yet.
    fn new(n: usize, confidence: f32) -> Self {
        Cycle {
            n: n.min(R) as u8,
            rollout: None,
            next: (Bracket::Nominal, [true; R]),
            verdict: ([false; R], [false; R]),
            refreshes: 0,
            nominal: None,
            pessimistic: None,
            optimistic: None,
            pessimistic_watch: [false; R],
            optimistic_watch: [false; R],
            energy_stall: [false; R],
            z: normal_quantile(confidence),
            start: None,
        }
    }

    /// The joints in use.
    fn count(&self) -> usize {
        usize::from(self.n).min(R)
    }

    /// Where the next rollout starts: time \[s\], joint state and locked
    /// joints, over arrays of capacity [`ROLLOUT_MAX_JOINTS`] (the joints
    /// past the count locked); `None` while no settled state is at hand (a
    /// rollout in progress goes on, a finished one is kept).
    pub(crate) fn set_start(&mut self, start: Option<Start<R>>) {
        self.start = start;
    }

    /// One slice: advances the rollout in progress by a bounded amount of
    /// work (`RolloutConfig::steps_per_slice`), on the chain's equations over the joints in
    /// use, `capture_rad` and `belief` of each of them: one copy for every
    /// joint count.
    #[inline(never)]
    pub(crate) fn slice(
        &mut self,
        chain: &ChainRef<'_, f32, R>,
        cfg: &RolloutConfig,
        deadline_s: f32,
        capture_rad: &[f32; R],
        belief: &dyn Fn(usize) -> FrictionBelief,
    ) -> bool {
        let n = self.count();
        let mut cfg = *cfg;
        let mut finished = false;
        if let Some((r, bracket, t0)) = self.rollout.as_mut() {
            if *bracket != Bracket::Nominal {
                cfg.dt_s = cfg.bracket_dt_s;
            }
            // Only the time left to the deadline matters.
            cfg.horizon_s = cfg.horizon_s.min(deadline_s - *t0).max(cfg.dt_s);
            r.advance(chain, &cfg);
            if !r.is_done() {
                return false;
            }
            let out = (r.outcome(), *t0);
            let bracket = *bracket;
            if bracket == Bracket::Nominal {
                // The cycle's verdicts: which joints, free at the start,
                // latch by the deadline, and which do not.
                let (x, started_latched) = (out.0, r.started_latched());
                for j in 0..n {
                    let free = !started_latched[j];
                    let by_deadline = x[j].latches && out.1 + x[j].latch_after_s <= deadline_s;
                    self.verdict.0[j] = free && by_deadline;
                    self.verdict.1[j] = free && !by_deadline;
                }
            }
            let (latches, stalls) = self.verdict;
            let any = |m: &[bool; R]| m.iter().any(|v| *v);
            let (next, cycle_done) = match bracket {
                Bracket::Nominal => {
                    self.nominal = Some(out);
                    if any(&latches) {
                        ((Bracket::Pessimistic, latches), false)
                    } else if any(&stalls) {
                        ((Bracket::Optimistic, stalls), false)
                    } else {
                        ((Bracket::Nominal, [true; R]), true)
                    }
                }
                Bracket::Pessimistic => {
                    self.pessimistic = Some(out);
                    self.pessimistic_watch = r.watch();
                    if any(&stalls) {
                        ((Bracket::Optimistic, stalls), false)
                    } else {
                        ((Bracket::Nominal, [true; R]), true)
                    }
                }
                Bracket::Optimistic => {
                    self.optimistic = Some(out);
                    self.optimistic_watch = r.watch();
                    ((Bracket::Nominal, [true; R]), true)
                }
            };
            self.next = next;
            if cycle_done {
                self.refreshes = self.refreshes.wrapping_add(1);
            }
            self.rollout = None;
            finished = true;
        }
        let (next, watch) = self.next;
        let Some((t, state, locked)) = self.start else {
            // No settled state yet: the next rollout waits for one.
            return finished;
        };
        let z = self.z;
        let sign = match next {
            Bracket::Nominal => 0.0,
            Bracket::Pessimistic => 1.0,
            Bracket::Optimistic => -1.0,
        };
        let mut coulomb = [0.0f32; R];
        let mut viscous = [0.0f32; R];
        let mut spring = [1.0f32; R];
        for j in 0..n {
            let floor = next == Bracket::Optimistic && !locked[j];
            (coulomb[j], viscous[j], spring[j]) = bracket_joint(&belief(j), sign * z, floor);
        }
        let start = RolloutStart {
            state,
            latched: locked,
            coulomb_nm: coulomb,
            viscous_nms: viscous,
            spring_scale: spring,
            capture_rad: *capture_rad,
        };
        self.rollout = Some((Stepper::new(n, &start).watching(watch), next, t));
        finished
    }

    /// The latch / stall prediction of joint `j` at time `t` \[s\] from the
    /// last finished rollouts and what `query` says of the joint (its
    /// latch, its one-joint energy balance, the deadline): the prediction,
    /// its confidence and the time to the latch \[s\]. A joint whose balance
    /// stops it on a physical latch's entry ramp is predicted to stop there
    /// ([`crate::monitor::latch_margin`]).
    pub(crate) fn prediction(
        &mut self,
        j: usize,
        t: f32,
        query: &PredictionQuery,
    ) -> (Prediction, f32, Option<f32>) {
        let conf = query.confidence;
        let deadline = query.deadline_s;
        let used = j < self.count();
        let pick = |o: Finished<R>| {
            o.filter(|_| used).and_then(|(x, t0)| {
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
        // The balance's call of a stall holds until it clearly lets the
        // joint latch again: its probability flickers about the threshold
        // as the friction estimate and its bound settle, and a stall must
        // not be taken back by an unconfirmed rollout in between.
        let called = if let Some(r) = energy {
            let p = r.latch_probability;
            let held = self.energy_stall.get(j).copied().unwrap_or(false);
            p <= 1.0 - conf || (held && p < ENERGY_STALL_CLEAR)
        } else {
            false
        };
        if let Some(flag) = self.energy_stall.get_mut(j) {
            *flag = called && !query.latched;
        }
        let energy_stall = called;
        let (pess_watch, opt_watch) = (
            self.pessimistic_watch.get(j).copied().unwrap_or(false),
            self.optimistic_watch.get(j).copied().unwrap_or(false),
        );
        let stall = stall_kind(energy);
        match nom {
            _ if query.latched => (Prediction::Latch, 1.0, None),
            // Not even the one-joint balance, which counts all the
            // kinetic energy in the joint, gets it to the latch.
            _ if energy_stall => (stall, conf, None),
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
                let sure = pess_watch && pess.is_some_and(|(p, _)| p.latches);
                (
                    Prediction::Latch,
                    if sure { conf } else { UNCONFIRMED },
                    ttl(nom),
                )
            }
            Some(_) => {
                let sure = opt_watch && opt.is_some_and(|(o, _)| !o.latches);
                (stall, if sure { conf } else { UNCONFIRMED }, None)
            }
        }
    }
}

/// The name of a stall of a joint whose energy balance is `energy`:
/// [`Prediction::RampStop`] when the balance stops it on a physical latch's
/// entry ramp (`MarginResult::stops_on_ramp`,
/// [`crate::monitor::latch_margin`]), else [`Prediction::Stall`]. The
/// rollouts do not model the plunger, so the balance locates the stall.
#[inline]
fn stall_kind(energy: Option<MarginResult>) -> Prediction {
    if energy.is_some_and(|r| r.stops_on_ramp) {
        Prediction::RampStop
    } else {
        Prediction::Stall
    }
}

/// Confidence of a prediction that is the best estimate only: no bracket
/// confirmed it, or the joint's readings contradict it \[1\].
pub const UNCONFIRMED: f32 = 0.5;

/// Latch probability of the one-joint energy balance at which its call of a
/// stall (`P ≤ 1 − confidence`) is lifted \[1\]: the hysteresis of the
/// override (`docs/monitor.md` §6).
pub const ENERGY_STALL_CLEAR: f32 = 0.5;

/// What [`Cycle::prediction`] needs to know of one joint besides the
/// rollouts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PredictionQuery {
    /// The joint's latch is declared.
    pub latched: bool,
    /// The one-joint energy balance of the joint, if evaluated.
    pub energy: Option<MarginResult>,
    /// The deployment's deadline, absolute \[s\]: a latch after it is a stall.
    pub deadline_s: f32,
    /// Confidence level `Φ(z)` \[1\].
    pub confidence: f32,
    /// False when the rollouts are switched off.
    pub rollouts: bool,
}

/// One joint's Coulomb torque [N·m], viscous coefficient [N·m·s/rad] and
/// spring scale \[1\] in a rollout whose friction is `shift` standard
/// deviations above the belief `e` (below for a negative `shift`; more
/// friction goes with weaker springs, and less with stronger); with
/// `floor`, the Coulomb torque is never below the friction torque the joint
/// exerts now. Not generic over the joint count: one copy in flash for
/// every monitor.
#[inline(never)]
fn bracket_joint(e: &FrictionBelief, shift: f32, floor: bool) -> (f32, f32, f32) {
    let sd_k = crate::physics::real::sqrtf(e.spring_scale_var.max(0.0));
    let spring = (1.0 + e.spring_scale_err - shift * sd_k).max(0.0);
    let sd_c = crate::physics::real::sqrtf(e.coulomb_var.max(0.0));
    let sd_f = crate::physics::real::sqrtf(e.viscous_var.max(0.0));
    let mut coulomb = (e.coulomb_nm + shift * sd_c).max(0.0);
    let viscous = (e.viscous_nms + shift * sd_f).max(0.0);
    if floor {
        // Friction is never below the torque it exerts now.
        let bound = e.coulomb_lower_nm;
        if bound <= e.coulomb_nm + 2.0 * sd_c {
            coulomb = coulomb.max(bound);
        }
    }
    (coulomb, viscous, spring)
}
