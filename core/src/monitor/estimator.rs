//! The on-board deployment monitor: two paths, as flight software runs them.
//!
//! [`Monitor::update`]`(&Sample) -> &Status` is the sample-rate path (a
//! timer interrupt): each sample (time stamp, encoder angles, latch
//! switches) goes through
//!
//! 1. the time checks (NaN, backwards, gaps: [`Fault`] flags, never a panic);
//! 2. the encoder checks and a kinematic Kalman filter per joint: angle and
//!    rate from the 14-bit encoder, spikes gated out
//!    ([`crate::monitor::observer::RateFilter`]);
//! 3. the latch-state estimator per joint, switch fused with encoder
//!    ([`crate::monitor::latch`]), and the plastic latch impulse on the rates;
//! 4. the sample queued for the friction learning (a bounded queue).
//!
//! [`Monitor::predict`] is the slow path (the idle loop or a low-priority
//! task), in slices of bounded cost. A slice either learns from one queued
//! sample, oldest first —
//!
//! 5. the generalised-momentum disturbance observer and RLS friction
//!    estimate per free joint on the centred fit
//!    ([`crate::monitor::observer::FrictionObserver`]);
//! 6. the energy margin of the remaining stroke, one joint per learned
//!    sample in turn ([`crate::monitor::margin`]);
//!
//! — or, with the queue empty, advances the latch / stall prediction by one
//! unit of rollout work ([`crate::monitor::predictor`]).
//!
//! Everything is `f32`, fixed-size and heap-free; `size_of::<Monitor<3>>()`
//! is under 4 KiB. `docs/monitor.md` has the equations and the tuning.

pub use crate::monitor::config::{
    ConfigError, JointConfig, MarginConfig, MonitorConfig, ObserverConfig, SensorConfig,
    ENCODER_RANGE_DEG,
};
use crate::monitor::faults::{Fault, FaultFlags};
use crate::monitor::latch::{LatchConfig, LatchInput, LatchState, LatchTracker};
use crate::monitor::margin::{self, MarginInput, MarginResult, MarginSettings};
use crate::monitor::observer::{
    momentum_terms, FrictionEstimate, FrictionObserver, FrictionPrior, Fusion, ObserverInput,
    RateFilter,
};
use crate::monitor::plausibility::{Reading, ReadingCheck, Verdict};
pub use crate::monitor::predictor::Prediction;
use crate::monitor::predictor::{FrictionBelief, PredictionQuery, Predictor};
use crate::monitor::smoother::{Centre, CentredFit};
pub use crate::monitor::status::{
    JointStatus, Observability, Sample, Status, OBSERVED_PRIOR_SHARE, VISCOUS_RESOLVED_SD,
};
use crate::physics::chain::{Chain, ChainState, GlobalEffects, JointEffects};
use crate::physics::friction::Friction;
use crate::physics::linalg::{articulated_inertia, solve_spd_masked};
use crate::physics::spring::{Branch, Spring};
use heapless::Deque;

const DEG: f32 = core::f32::consts::PI / 180.0;

/// The on-board monitor of an `N`-joint deployment.
#[derive(Clone, Debug)]
pub struct Monitor<const N: usize> {
    chain: Chain<f32, N>,
    /// Variance of one encoder reading [rad²] (noise and quantisation).
    meas_var: f32,
    /// Its square root [rad].
    meas_sd: f32,
    sensor: SensorConfig,
    observer: ObserverConfig,
    latch_cfg: LatchConfig,
    margin_cfg: MarginConfig,
    /// Everything the monitor tracks about each joint.
    joints: [JointState; N],
    /// The latch / stall prediction (the rollout cycle), advanced by
    /// [`Monitor::predict`].
    predictor: Predictor<N>,
    started: bool,
    /// Time stamp of the first sample [s].
    t_start: f32,
    /// Time stamp of the last sample used [s].
    t_prev: f32,
    /// Consecutive time stamps that did not increase, and the last of them
    /// [s] (three in a row are adopted as the new time base).
    back_run: u8,
    t_back: f32,
    /// End of the settling after a snap, latch or gap [s]: the friction
    /// learning and the margin wait until then.
    blank_until: f32,
    /// The last readings, for the friction observer's centred rates.
    fit: CentredFit<N>,
    /// Whether the previous sample gave a centred fit (the observers run
    /// on without a restart).
    fit_run: bool,
    /// Time of the last centred fit [s].
    t_centre: f32,
    /// Running mean of the sample intervals [s] (0 before the first).
    dt_mean: f32,
    /// End of the window after a switch closed in which a reading the rate
    /// filter rejects is the impact, not an outlier [s].
    impact_until: f32,
    /// Samples left whose prediction is widened for the impact.
    impact_samples: u8,
    /// The joint whose energy margin is evaluated at the next learned
    /// sample.
    next_margin: u8,
    /// Samples [`Monitor::update`] queued for the friction learning, which
    /// [`Monitor::predict`] takes oldest first.
    learning: Deque<Learning<N>, LEARNING_QUEUE>,
    /// Samples dropped from a full learning queue (the slow path fell
    /// behind by more than [`LEARNING_QUEUE`] samples).
    learning_overruns: u32,
    status: Status<N>,
}

/// Samples the learning queue holds [1]: at 100 Hz, 80 ms of a slow path
/// kept from running (at the replay's schedule it is emptied after every
/// sample).
pub const LEARNING_QUEUE: usize = 4;

/// What the friction learning and the energy margin need of one sample,
/// queued by [`Monitor::update`] for [`Monitor::predict`].
#[derive(Clone, Copy, Debug)]
struct Learning<const N: usize> {
    /// Time stamp [s].
    t: f32,
    /// The sample is fit to learn from: settled (no snap, latch or gap
    /// within `settle_s`), no gap, a positive time step.
    clean: bool,
    /// No snap, latch or gap within `settle_s` (the margin's condition).
    quiet: bool,
    /// Readings the rate filters used [rad], NaN where none (missing,
    /// out of range, stuck or gated out).
    used: [f32; N],
    /// Joints the model sits at 0.
    locked: [bool; N],
    /// Joints declared latched at the sample (logged by the slow path: a
    /// log line costs a thousand instructions over semihosting).
    newly: [bool; N],
}

/// What the monitor tracks about one joint from sample to sample.
#[derive(Clone, Copy, Debug)]
struct JointState {
    /// Stowed angle [deg] (the latch is at 0).
    stowed_deg: f32,
    /// Capture angle `x_c` [rad] (below it the spring completes the latch).
    capture_rad: f32,
    /// Kinematic Kalman filter of the angle and rate (§2 of
    /// `docs/monitor.md`).
    kf: RateFilter,
    /// Momentum disturbance observer and RLS friction estimate (§3).
    fo: FrictionObserver,
    /// Latch-state estimator, switch fused with encoder (§4).
    lt: LatchTracker,
    /// Last energy margin and one-joint latch probability (§5).
    margin: Option<MarginResult>,
    /// Consecutive readings the rate filter's gate rejected.
    rejects: u8,
    /// Last in-range reading of the encoder [deg].
    last_raw: f32,
    /// How many samples in a row repeated `last_raw` exactly.
    same_run: u16,
    /// Stale and returning-spike checks of the encoder (`plausibility.rs`).
    plausibility: ReadingCheck,
    /// The latch switch at the previous sample (a closing is an impact).
    switch_prev: bool,
    /// The status's standard deviations of `T_C` and `f`, with the
    /// variances they are the roots of (they change only when the observer
    /// learns: the square roots are not taken again in between).
    coulomb_sd: CachedSqrt,
    viscous_sd: CachedSqrt,
}

/// `√v` of the last `v` asked for.
#[derive(Clone, Copy, Debug)]
struct CachedSqrt {
    /// The last argument (NaN at first: never equal).
    v: f32,
    /// Its square root.
    root: f32,
}

impl CachedSqrt {
    const EMPTY: CachedSqrt = CachedSqrt {
        v: f32::NAN,
        root: 0.0,
    };

    /// `√max(v, 0)`, computed only when `v` changed.
    fn sqrt(&mut self, v: f32) -> f32 {
        if v != self.v {
            self.v = v;
            self.root = crate::physics::real::sqrtf(v.max(0.0));
        }
        self.root
    }
}

impl JointState {
    /// A joint at its stowed angle, waiting for the first sample; `sd` is
    /// the encoder's standard deviation [rad]. Not generic over the joint
    /// count (one copy in flash).
    #[inline(never)]
    fn new(joint: &JointConfig, sd: f32, observer: &ObserverConfig, spring_sd_rel: f32) -> Self {
        let mut kf = RateFilter::new(joint.stowed_deg * DEG, sd, START_RATE_SD, START_ACC_SD);
        kf.set_jerk_psd(observer.jerk_psd);
        JointState {
            stowed_deg: joint.stowed_deg,
            capture_rad: joint.capture_deg * DEG,
            kf,
            fo: FrictionObserver::new(joint.prior, spring_sd_rel),
            lt: LatchTracker::new(),
            margin: None,
            rejects: 0,
            last_raw: f32::NAN,
            same_run: 0,
            plausibility: ReadingCheck::new(),
            switch_prev: false,
            coulomb_sd: CachedSqrt::EMPTY,
            viscous_sd: CachedSqrt::EMPTY,
        }
    }

    /// True when the joint is latched or held at its latch (the model sits
    /// it at 0).
    fn locked(&self) -> bool {
        self.lt.is_latched() || self.lt.held_at_latch()
    }

    /// The joint's rate filter at one sample: prediction and fusion of its
    /// reading (see [`Monitor::track_rates`]; `docs/monitor.md` §2, §6.2).
    /// Not generic over the joint count, so the monitors of 2 and 3 joints
    /// share one copy in flash.
    #[inline(never)]
    fn track_rate(
        &mut self,
        reading: Option<f32>,
        faults: &mut FaultFlags,
        ctx: &RateContext<'_>,
    ) -> RateOutcome {
        let (r_meas, sd) = (ctx.meas_var, ctx.meas_sd);
        let observer = ctx.observer;
        let gap = ctx.clock.gap;
        let gate2 = observer.gate_sigma * observer.gate_sigma;
        let zone = observer.snap_zone_deg * DEG;
        let latched = self.lt.is_latched();
        let kf = &mut self.kf;
        let q_floor = if !latched && libm::fabsf(kf.angle()) < zone {
            observer.zone_jerk_psd
        } else {
            0.0
        };
        if ctx.inflate && !latched {
            kf.inflate(IMPACT_RATE_VAR, ACC_SHOCK_VAR);
        }
        kf.predict(ctx.clock.dt, q_floor);
        if gap {
            kf.inflate(GAP_RATE_VAR, ACC_SHOCK_VAR);
        }
        let Some(z) = reading else {
            return RateOutcome::Used;
        };
        let r = if gap { r_meas + GAP_MEAS_VAR } else { r_meas };
        // A reading beyond the gate but within `MANOEUVRE_GATE` gates of
        // the prediction is a manoeuvre the white-jerk model did not
        // foresee (a joint that sticks under its friction stops with a
        // step in acceleration), not a spike.
        let nu = z - kf.angle();
        let manoeuvre = nu * nu <= MANOEUVRE_GATE * MANOEUVRE_GATE * gate2 * (kf.angle_var() + r);
        match kf.update(z, r, gate2, &observer.jerk_adaptation) {
            Fusion::Accepted => {
                self.rejects = 0;
                RateOutcome::Used
            }
            Fusion::Rejected if ctx.impact || manoeuvre => {
                let rate = if ctx.impact { 0.0 } else { kf.rate() };
                *kf = RateFilter::new(z, sd, IMPACT_RATE_SD, START_ACC_SD);
                kf.set_rate(rate, 0.0);
                kf.set_jerk_psd(observer.jerk_psd);
                self.rejects = 0;
                if ctx.impact {
                    RateOutcome::Restarted
                } else {
                    RateOutcome::Used
                }
            }
            Fusion::Rejected => {
                faults.insert(Fault::EncoderOutlier);
                self.rejects = self.rejects.saturating_add(1);
                if self.rejects >= MAX_REJECTS {
                    *kf = RateFilter::new(z, sd, RESET_RATE_SD, RESET_ACC_SD);
                    kf.set_jerk_psd(observer.jerk_psd);
                    faults.insert(Fault::EstimatorReset);
                    self.rejects = 0;
                    RateOutcome::Restarted
                } else {
                    RateOutcome::GatedOut
                }
            }
        }
    }

    /// Checks one encoder reading `z` [deg] (the joint's latch switch
    /// `switch`): missing, out of range, stuck or stale readings are flagged
    /// and not used, a spike that returned is flagged (`plausibility.rs`).
    /// Returns the reading to use [rad], the faults and whether the encoder
    /// is frozen. Not generic over the joint count (one copy in flash).
    #[inline(never)]
    fn read_encoder(
        &mut self,
        z: f32,
        switch: bool,
        ctx: &ReadingContext,
    ) -> (Option<f32>, FaultFlags, bool) {
        let mut faults = FaultFlags::EMPTY;
        if !z.is_finite() {
            faults.insert(Fault::EncoderMissing);
            return (None, faults, false);
        }
        if libm::fabsf(z) > ENCODER_RANGE_DEG {
            faults.insert(Fault::EncoderRange);
            return (None, faults, false);
        }
        // A reading frozen to the same value for longer than the noise
        // allows is a stuck (or stale) encoder: not used.
        if z == self.last_raw {
            self.same_run = self.same_run.saturating_add(1);
        } else {
            self.same_run = 0;
            self.last_raw = z;
        }
        // A latched joint's encoder reads a constant by rights (a
        // noise-free or coarse encoder repeats exactly): the check ends
        // with the latch, whose declaration is final.
        let latched = self.lt.is_latched();
        // Stale while moving (not used) or a spike that returned (flagged):
        // `plausibility.rs`. Runs before the rate filter's step, on its
        // prediction from the last sample.
        let verdict = self.plausibility.check_filter(
            &Reading {
                t_s: ctx.t,
                angle: Some(z * DEG),
                repeats: self.same_run,
                step: ctx.step_rad,
                moving_checks: !ctx.no_checks && !latched && !switch,
            },
            &self.kf,
            ctx.t_prev,
        );
        if let Some(f) = verdict.fault() {
            faults.insert(f);
        }
        let stale = verdict == Verdict::Stale;
        let limit = ctx.stuck_limit;
        if !latched && limit > 0 && (stale || self.same_run.saturating_add(1) >= limit) {
            faults.insert(Fault::EncoderStuck);
            (None, faults, true)
        } else {
            (Some(z * DEG), faults, false)
        }
    }

    /// The sample-rate part of the joint's status line (non-finite values
    /// as 0): angle, rate, the latch `state` and the `faults` of this
    /// sample; no margin once latched. Not generic over the joint count
    /// (one copy in flash).
    #[inline(never)]
    fn sample_status(&self, out: &mut JointStatus, faults: FaultFlags, state: LatchState) {
        out.phi_deg = finite(self.kf.angle() / DEG);
        out.rate_deg_s = finite(self.kf.rate() / DEG);
        out.latch = state;
        out.faults = faults;
        if self.lt.is_latched() {
            out.margin_pct = None;
        }
    }

    /// The friction the prediction and the energy margin use, and whether
    /// the data resolve `f`: the observer's estimate when they do; when
    /// they do not, the estimate conditioned on `f` = its prior mean, whose
    /// Coulomb torque holds the friction seen at the rates observed
    /// (`docs/monitor.md` §3.2, [`FrictionObserver::estimate_given_viscous`]).
    /// Not generic over the joint count (one copy in flash).
    #[inline(never)]
    fn friction(&self) -> (FrictionEstimate, Observability) {
        let est = self.fo.estimate();
        let prior = self.fo.prior();
        let sd = prior.viscous_sd_nms;
        match Observability::of(est.viscous_var, sd * sd, VISCOUS_RESOLVED_SD) {
            Observability::Estimated => (est, Observability::Estimated),
            Observability::Unobservable => (
                self.fo.estimate_given_viscous(prior.viscous_nms),
                Observability::Unobservable,
            ),
        }
    }

    /// The learned part of the joint's status line (non-finite values as
    /// 0): friction estimates, margin and the prediction. The Coulomb
    /// torque is the one the prediction uses ([`JointState::friction`]);
    /// the viscous coefficient is the observer's, with its posterior
    /// deviation. Not generic over the joint count (one copy in flash).
    #[inline(never)]
    fn estimates(&mut self, out: &mut JointStatus, forecast: Forecast) {
        let (used, viscous) = self.friction();
        let est = self.fo.estimate();
        let coulomb_sd = self.coulomb_sd.sqrt(used.coulomb_var);
        let viscous_sd = self.viscous_sd.sqrt(est.viscous_var);
        let margin_pct = if self.lt.is_latched() {
            None
        } else {
            self.margin.map(|r| r.margin_pct)
        };
        out.coulomb_nm = finite(used.coulomb_nm);
        out.coulomb_sd_nm = finite(coulomb_sd);
        out.viscous_nms = finite(est.viscous_nms);
        out.viscous_sd_nms = finite(viscous_sd);
        out.viscous = viscous;
        out.friction_torque_nm = finite(self.fo.disturbance_nm());
        out.margin_pct = margin_pct.map(finite);
        out.prediction = forecast.prediction;
        out.confidence = forecast.confidence;
        out.time_to_latch_s = forecast.time_to_latch_s.filter(|v| v.is_finite());
    }
}

/// What the encoder checks of one sample share (see
/// [`JointState::read_encoder`]).
struct ReadingContext {
    /// Time stamp of this sample and of the last one used [s].
    t: f32,
    t_prev: f32,
    /// Encoder quantisation step [rad].
    step_rad: f32,
    /// Repeats of one value that make an encoder stuck (0: never).
    stuck_limit: u16,
    /// The plausibility checks are off (first sample, gap, impact).
    no_checks: bool,
}

/// A joint's latch / stall prediction, as the status reports it.
#[derive(Clone, Copy, Debug)]
struct Forecast {
    prediction: Prediction,
    confidence: f32,
    /// Time to the latch [s].
    time_to_latch_s: Option<f32>,
}

/// What the rate filters of one sample share (see [`JointState::track_rate`]).
struct RateContext<'a> {
    /// The clock's verdict on this sample.
    clock: Clock,
    /// Within the impact window after a switch closed.
    impact: bool,
    /// Widen the rate filter's prediction for the impact.
    inflate: bool,
    /// Variance of one reading [rad²] and its square root [rad].
    meas_var: f32,
    meas_sd: f32,
    /// The observer's tuning.
    observer: &'a ObserverConfig,
}

/// What a joint's rate filter made of its reading.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RateOutcome {
    /// Fused, or none to fuse.
    Used,
    /// Rejected as an outlier; the reading is not used.
    GatedOut,
    /// The filter restarted at the reading (impact or reset): the friction
    /// learning waits for the settling.
    Restarted,
}

/// The clock's verdict on a sample's time stamp.
#[derive(Clone, Copy, Debug)]
struct Clock {
    /// Time stamp [s].
    t: f32,
    /// Time step used by the filters [s] (0 at the first sample).
    dt: f32,
    /// A gap (or a newly adopted time base) before this sample.
    gap: bool,
    /// Time faults, raised on every joint.
    faults: FaultFlags,
}

/// This sample's encoder readings, per joint.
#[derive(Clone, Copy, Debug)]
struct Readings<const N: usize> {
    /// Faults raised so far.
    faults: [FaultFlags; N],
    /// Readings the rate filters used [rad]: `None` when missing, out of
    /// range, stuck or gated out.
    used: [Option<f32>; N],
    /// The readings as they came, range-checked [rad]: the latch estimator
    /// compares them with the switch even when the rate filter gated one
    /// out (a joint stopping dead at its latch looks like a spike to it;
    /// the switch must agree anyway).
    raw: [Option<f32>; N],
    /// Encoders frozen for longer than the noise allows.
    stuck: [bool; N],
}

/// The latch states after this sample.
#[derive(Clone, Copy, Debug)]
struct Latches<const N: usize> {
    /// Each joint's state.
    states: [LatchState; N],
    /// Joints declared latched at this sample.
    newly: [bool; N],
    /// Joints the model sits at 0 (latched or held at the latch).
    locked: [bool; N],
}

/// Rate uncertainty at the first sample [rad/s]: a deployment starts from
/// rest (a monitor started mid-motion is caught by the jerk adaptation).
const START_RATE_SD: f32 = 0.01;
/// Acceleration uncertainty at the first sample [rad/s²].
const START_ACC_SD: f32 = 1.0;
/// Rate uncertainty of a rate filter restarted after repeated rejections or
/// a numerical failure [rad/s]: the joint may be anywhere in its stroke.
const RESET_RATE_SD: f32 = 1.0;
/// Acceleration uncertainty of such a restarted filter [rad/s²].
const RESET_ACC_SD: f32 = 10.0;
/// Variance added to a rate after a latch impulse [rad²/s²].
const RATE_SHOCK_VAR: f32 = 0.04;
/// Variance added to an acceleration after a latch impulse, an impact or a
/// gap [rad²/s⁴].
const ACC_SHOCK_VAR: f32 = 100.0;
/// Variance added to a rate over a gap [rad²/s²] (the joint may have
/// changed its rate by ≈ 1 rad/s while unobserved).
const GAP_RATE_VAR: f32 = 1.0;
/// Variance added to the first reading after a gap [rad²].
const GAP_MEAS_VAR: f32 = 1.0;
/// Longest time step the filters propagate over a gap [s].
const MAX_GAP_STEP_S: f32 = 1.0;
/// Consecutive gate rejections after which the rate filter restarts at the
/// measurement.
const MAX_REJECTS: u8 = 3;
/// Time without a centred fit after which a rollout starts from the rate
/// filter instead [s].
const CENTRE_WAIT_S: f32 = 0.5;
/// Time after a latch switch closes during which a reading the rate filter
/// rejects is the latch impact, not an outlier [s]: the impact is within a
/// sample of the closing at 100 Hz, and a chattering switch (≤ 20 ms)
/// closes again inside it.
const IMPACT_WINDOW_S: f32 = 0.03;
/// Samples, from the one where a switch closes, whose prediction is widened
/// for the impact.
const IMPACT_INFLATE_SAMPLES: u8 = 2;
/// Rate variance added to every free joint at an impact [rad²/s²]: the
/// plastic impulse changes the rates by up to about 2 rad/s.
const IMPACT_RATE_VAR: f32 = 4.0;
/// Relative departure of a sample interval from the running mean beyond
/// which the time stamp is flagged `time_jitter` [1].
const JITTER_TOL: f32 = 0.2;
/// Weight of a new interval in the running mean [1].
const JITTER_WEIGHT: f32 = 0.05;
/// Innovations up to this many gates are a manoeuvre (the filter restarts
/// at the reading, keeping its rate), beyond it a spike (flagged). At
/// σ ≈ 0.03° a gate is 0.17° and this 0.5°: a joint stopping under its
/// friction at 5 rad/s² misses the prediction by ½·a·t² ≈ 0.06° over 20 ms,
/// while a spike is degrees off.
const MANOEUVRE_GATE: f32 = 3.0;
/// Rate uncertainty of a filter restarted at an impact [rad/s].
const IMPACT_RATE_SD: f32 = 1.0;
/// Consecutive non-increasing time stamps after which the monitor adopts them.
const RESYNC_SAMPLES: u8 = 3;
/// Smallest articulated inertia the margin divides by [kg·m²] (a guard;
/// real panels are 10⁻² and more).
const MIN_INERTIA_KGM2: f32 = 1e-6;
/// Standard deviations of `T̂_C` beyond which the friction torque's lower
/// bound on `T_C` is a transient of `r`, not evidence (`docs/monitor.md`
/// §3.2).
const LOWER_BOUND_SIGMAS: f32 = 2.0;
/// The margin of a joint the monitor knows nothing about (a guard for an
/// index out of range, which the callers never pass).
const UNKNOWN_MARGIN: MarginResult = MarginResult {
    margin_pct: 0.0,
    latch_probability: 0.5,
    time_to_latch_s: None,
};

/// [`MonitorConfig::validate`] of one joint, out of line: one copy for
/// every joint count ([`Monitor::reset`]).
#[inline(never)]
fn validate_one(config: &MonitorConfig<1>) -> Result<(), ConfigError> {
    config.validate()
}

impl<const N: usize> Monitor<N> {
    /// A monitor for the configured mechanism, waiting for its first sample
    /// ([`Monitor::reset`] on a vacant monitor: one definition of the
    /// initial state).
    pub fn new(config: &MonitorConfig<N>) -> Result<Self, ConfigError> {
        let mut m = Self::vacant(config);
        m.reset(config)?;
        Ok(m)
    }

    /// Storage for a monitor, every field written with a placeholder (a
    /// chain of zero panels, unconfigured joints, `config`'s tuning) for
    /// [`Monitor::reset`] to overwrite: not a monitor of any mechanism.
    /// Out of line and returned by value, so that a caller moving it into
    /// its final place (a static slot) has it written there directly, not
    /// built on the stack.
    #[inline(never)]
    pub(crate) fn vacant(config: &MonitorConfig<N>) -> Self {
        // A placeholder joint (unsprung, at the latch, any valid prior; an
        // encoder σ of 1 rad, no spring spread): `reset` replaces it.
        let joint = JointConfig {
            stowed_deg: 0.0,
            spring: Spring::None,
            capture_deg: 0.0,
            prior: FrictionPrior {
                coulomb_nm: 0.0,
                coulomb_sd_nm: 1.0,
                viscous_nms: 0.0,
                viscous_sd_nms: 1.0,
            },
        };
        let state = JointState::new(&joint, 1.0, &config.observer, 0.0);
        // The large parts last: each is written in place only if nothing
        // is built after it (LLVM's call-slot forwarding).
        Monitor {
            meas_var: 0.0,
            meas_sd: 0.0,
            sensor: config.sensor,
            observer: config.observer,
            latch_cfg: config.latch,
            margin_cfg: config.margin,
            started: false,
            t_start: 0.0,
            t_prev: 0.0,
            back_run: 0,
            t_back: 0.0,
            blank_until: 0.0,
            fit_run: false,
            t_centre: 0.0,
            dt_mean: 0.0,
            impact_until: 0.0,
            impact_samples: 0,
            next_margin: 0,
            learning: Deque::new(),
            learning_overruns: 0,
            status: Status::default(),
            fit: CentredFit::new(),
            predictor: Predictor::new(MarginConfig::default().confidence),
            joints: [state; N],
            chain: Chain::vacant(),
        }
    }

    /// [`MonitorConfig::validate`] of `config`, with the same errors in
    /// the same order, compiled once for all joint counts: each joint is
    /// checked, with the tuning, as a one-joint configuration (the checks
    /// take 2.8 KiB of the firmware's flash per joint count otherwise).
    fn validate_config(config: &MonitorConfig<N>) -> Result<(), ConfigError> {
        if N == 0 {
            return config.validate();
        }
        let mut tuning = Ok(());
        for (index, (panel, joint)) in config.panels.iter().zip(&config.joints).enumerate() {
            let one = MonitorConfig {
                panels: [*panel],
                joints: [*joint],
                sensor: config.sensor,
                observer: config.observer,
                latch: config.latch,
                margin: config.margin,
            };
            match validate_one(&one) {
                Err(ConfigError::Joint { what, .. }) => {
                    return Err(ConfigError::Joint { index, what })
                }
                other => tuning = other,
            }
        }
        tuning
    }

    /// Makes this monitor the one for `config`, waiting for its first
    /// sample, in place: it validates `config` and writes every field where
    /// it is, so that a monitor in static memory is (re)configured without
    /// a second monitor, or a `Result` of one, on the stack (the firmware's
    /// start-up, `telemetry::replay`). On an error the monitor is unchanged.
    #[inline(never)]
    pub fn reset(&mut self, config: &MonitorConfig<N>) -> Result<(), ConfigError> {
        Self::validate_config(config)?;
        // Every field by name: a field added to `Monitor` must be set here.
        let Monitor {
            chain,
            meas_var,
            meas_sd,
            sensor,
            observer,
            latch_cfg,
            margin_cfg,
            joints,
            predictor,
            started,
            t_start,
            t_prev,
            back_run,
            t_back,
            blank_until,
            fit,
            fit_run,
            t_centre,
            dt_mean,
            impact_until,
            impact_samples,
            next_margin,
            learning,
            learning_overruns,
            status,
        } = self;
        // The only check that can fail after `validate`: before any write.
        chain
            .set_panels(&config.panels)
            .map_err(ConfigError::Chain)?;
        *chain.global_mut() = GlobalEffects::default();
        for (j, c) in config.joints.iter().enumerate() {
            if let Some(joint) = chain.joint_mut(j) {
                joint.stowed_rad = c.stowed_deg * DEG;
                joint.spring = c.spring;
                joint.friction = Friction::default();
                joint.effects = JointEffects::default();
            }
        }
        let sd = config.sensor.encoder_sd_deg * DEG;
        *meas_var = Self::meas_var(&config.sensor);
        *meas_sd = crate::physics::real::sqrtf(*meas_var);
        *sensor = config.sensor;
        *observer = config.observer;
        *latch_cfg = config.latch;
        *margin_cfg = config.margin;
        for (state, c) in joints.iter_mut().zip(config.joints.iter()) {
            *state = JointState::new(c, sd, &config.observer, config.margin.spring_sd_rel);
        }
        *predictor = Predictor::new(config.margin.confidence);
        *started = false;
        *t_start = 0.0;
        *t_prev = 0.0;
        *back_run = 0;
        *t_back = 0.0;
        *blank_until = f32::NEG_INFINITY;
        *fit = CentredFit::new();
        *fit_run = false;
        *t_centre = f32::NEG_INFINITY;
        *dt_mean = 0.0;
        *impact_until = f32::NEG_INFINITY;
        *impact_samples = 0;
        *next_margin = 0;
        learning.clear();
        *learning_overruns = 0;
        *status = Status::default();
        Ok(())
    }

    /// The status after the last sample.
    pub fn status(&self) -> &Status<N> {
        &self.status
    }

    /// The friction observer of joint `j` (0-based), for diagnostics.
    pub fn observer(&self, j: usize) -> Option<&FrictionObserver> {
        self.joints.get(j).map(|s| &s.fo)
    }

    /// The rate filter of joint `j` (0-based), for diagnostics.
    pub fn rate_filter(&self, j: usize) -> Option<&RateFilter> {
        self.joints.get(j).map(|s| &s.kf)
    }

    /// Slices of [`Monitor::predict`] a replay runs after each sample
    /// (`margin.rollout.slices_per_sample`).
    pub fn config_slices_per_sample(&self) -> u8 {
        self.margin_cfg.rollout.slices_per_sample
    }

    /// The latch / stall prediction (its rollout cycle), for diagnostics.
    pub fn predictor(&self) -> &Predictor<N> {
        &self.predictor
    }

    /// The chain model the monitor uses (f32).
    pub fn chain(&self) -> &Chain<f32, N> {
        &self.chain
    }

    /// Measurement variance of one encoder reading [rad²]: noise and
    /// quantisation, `σ² + Δ²/12`.
    fn meas_var(sensor: &SensorConfig) -> f32 {
        let sd = sensor.encoder_sd_deg * DEG;
        let q = sensor.encoder_step_deg * DEG;
        sd * sd + q * q / 12.0
    }

    /// A rate filter started at `phi_rad` [rad] with rate and acceleration
    /// deviations `sd_rate` [rad/s] and `sd_acc` [rad/s²].
    fn fresh_filter(&self, phi_rad: f32, sd: f32, sd_rate: f32, sd_acc: f32) -> RateFilter {
        let mut f = RateFilter::new(phi_rad, sd, sd_rate, sd_acc);
        f.set_jerk_psd(self.observer.jerk_psd);
        f
    }

    /// The previous status with this sample's faults (a sample not used).
    fn hold(&mut self, faults: FaultFlags) -> &Status<N> {
        for js in self.status.joints.iter_mut() {
            js.faults = faults;
        }
        &self.status
    }

    /// Processes one sample and returns the monitor's status.
    ///
    /// Never panics: a NaN or infinite reading is a missing measurement, a
    /// time stamp that does not increase or is not finite makes the sample
    /// unused, and each raises a [`Fault`] flag in the status.
    // Out of line: the sample-rate path is one function to measure, and its
    // frame is not merged into the caller's.
    #[inline(never)]
    pub fn update(&mut self, sample: &Sample<N>) -> &Status<N> {
        let clock = match self.check_clock(sample.t_s) {
            Ok(clock) => clock,
            Err(faults) => return self.hold(faults),
        };
        let mut readings = self.read_encoders(sample, &clock);
        self.track_rates(sample, &clock, &mut readings);
        let latches = self.track_latches(sample, &clock, &mut readings);
        self.check_health(&mut readings);
        self.queue_for_learning(&clock, &readings, &latches);
        self.compose_status(clock.t, &readings, &latches);
        &self.status
    }

    /// Checks the time stamp: the time step and the time faults, or `Err`
    /// with the faults of a sample that is not used (not finite, or
    /// backwards until [`RESYNC_SAMPLES`] in a row adopt the new time base).
    fn check_clock(&mut self, t: f32) -> Result<Clock, FaultFlags> {
        let mut faults = FaultFlags::EMPTY;
        if !t.is_finite() {
            faults.insert(Fault::TimeInvalid);
            return Err(faults);
        }
        let mut gap = false;
        let mut dt = 0.0f32;
        if self.started {
            let d = t - self.t_prev;
            if !(d >= self.observer.min_dt_s) {
                faults.insert(Fault::TimeBackwards);
                let chained = self.back_run > 0 && t - self.t_back >= self.observer.min_dt_s;
                self.back_run = if chained {
                    self.back_run.saturating_add(1)
                } else {
                    1
                };
                self.t_back = t;
                if self.back_run < RESYNC_SAMPLES {
                    return Err(faults);
                }
                // Adopt the new time base, as after a gap.
                gap = true;
                dt = self.observer.max_gap_s;
            } else if !(d <= self.observer.max_gap_s) {
                gap = true;
                dt = d.min(MAX_GAP_STEP_S);
            } else {
                dt = d;
                // Time-stamp jitter: an interval off the running mean.
                if self.dt_mean > 0.0 && libm::fabsf(d - self.dt_mean) > JITTER_TOL * self.dt_mean {
                    faults.insert(Fault::TimeJitter);
                }
                self.dt_mean = if self.dt_mean > 0.0 {
                    self.dt_mean + JITTER_WEIGHT * (d - self.dt_mean)
                } else {
                    d
                };
            }
        }
        self.back_run = 0;
        if gap {
            faults.insert(Fault::TimeGap);
        }
        Ok(Clock { t, dt, gap, faults })
    }

    fn read_encoders(&mut self, sample: &Sample<N>, clock: &Clock) -> Readings<N> {
        // The plausibility checks (`plausibility.rs`) are off across a
        // gap and at or after a switch closing (an impact under way: a
        // joint may stop dead).
        let no_checks = !self.started
            || clock.gap
            || clock.t <= self.impact_until
            || (0..N).any(|j| sample.latch[j] && !self.joints[j].switch_prev);
        let mut faults = [clock.faults; N];
        let mut used = [None::<f32>; N];
        let mut stuck = [false; N];
        let ctx = ReadingContext {
            t: clock.t,
            t_prev: self.t_prev,
            step_rad: self.sensor.encoder_step_deg * DEG,
            stuck_limit: self.sensor.stuck_samples,
            no_checks,
        };
        for (j, js) in self.joints.iter_mut().enumerate() {
            let (z, switch) = (sample.phi_deg[j], sample.latch[j]);
            let (reading, flags, frozen) = js.read_encoder(z, switch, &ctx);
            faults[j] = faults[j].union(flags);
            used[j] = reading;
            stuck[j] = frozen;
        }
        Readings {
            faults,
            used,
            raw: used,
            stuck,
        }
    }

    /// Tracks the angles and rates: each rate filter predicts to the sample
    /// and fuses its reading, with the latch impact expected when a switch
    /// closes (`docs/monitor.md` §6.2); spikes are flagged and gated out.
    fn track_rates(&mut self, sample: &Sample<N>, clock: &Clock, readings: &mut Readings<N>) {
        let t = clock.t;
        let sd = self.meas_sd;
        if !self.started {
            for j in 0..N {
                let phi0 = readings.used[j].unwrap_or(self.joints[j].stowed_deg * DEG);
                self.joints[j].kf = self.fresh_filter(phi0, sd, START_RATE_SD, START_ACC_SD);
            }
            self.started = true;
            self.t_start = t;
        } else {
            // A latch switch closing announces an impact: the latching
            // joint stops within a sample and the plastic impulse changes
            // the other joints' rates (physics.md §5). Over the next
            // `IMPACT_WINDOW_S` the rate filters widen their gates, and a
            // reading they still cannot reconcile restarts the filter at
            // the reading: expected, not an outlier.
            if (0..N).any(|j| sample.latch[j] && !self.joints[j].switch_prev) {
                self.impact_until = t + IMPACT_WINDOW_S;
                self.impact_samples = IMPACT_INFLATE_SAMPLES;
            }
            let impact = t <= self.impact_until;
            let inflate = self.impact_samples > 0;
            self.impact_samples = self.impact_samples.saturating_sub(1);
            let ctx = RateContext {
                clock: *clock,
                impact,
                inflate,
                meas_var: self.meas_var,
                meas_sd: self.meas_sd,
                observer: &self.observer,
            };
            for (j, js) in self.joints.iter_mut().enumerate() {
                let reading = readings.used.get(j).copied().flatten();
                let mut faults = readings.faults.get(j).copied().unwrap_or_default();
                match js.track_rate(reading, &mut faults, &ctx) {
                    RateOutcome::Used => {}
                    RateOutcome::GatedOut => {
                        if let Some(u) = readings.used.get_mut(j) {
                            *u = None;
                        }
                    }
                    RateOutcome::Restarted => {
                        self.blank_until = t + self.observer.settle_s;
                    }
                }
                if let Some(f) = readings.faults.get_mut(j) {
                    *f = faults;
                }
            }
        }
        self.t_prev = t;
        for (js, s) in self.joints.iter_mut().zip(sample.latch.iter()) {
            js.switch_prev = *s;
        }
    }

    /// Tracks the latch states (switch fused with encoder), and applies the
    /// plastic latch impulse to the rates when a joint latches.
    fn track_latches(
        &mut self,
        sample: &Sample<N>,
        clock: &Clock,
        readings: &mut Readings<N>,
    ) -> Latches<N> {
        let t = clock.t;
        let mut states = [LatchState::Stowed; N];
        let mut newly = [false; N];
        for (j, js) in self.joints.iter_mut().enumerate() {
            let out = js.lt.step(
                &LatchInput {
                    t_s: t,
                    switch: sample.latch[j],
                    measured_deg: readings.raw[j].map(|z| z / DEG),
                    angle_deg: js.kf.angle() / DEG,
                    rate_deg_s: js.kf.rate() / DEG,
                    stowed_deg: js.stowed_deg,
                    encoder_stuck: readings.stuck[j],
                },
                &self.latch_cfg,
            );
            states[j] = out.state;
            newly[j] = out.newly_latched;
            readings.faults[j] = readings.faults[j].union(out.faults);
        }
        let locked: [bool; N] = core::array::from_fn(|j| self.joints[j].locked());
        if newly.iter().any(|n| *n) {
            self.apply_latch_impulse(&newly, &locked);
            self.blank_until = t + self.observer.settle_s;
        }
        Latches {
            states,
            newly,
            locked,
        }
    }

    /// Queues the sample for the friction learning of [`Monitor::predict`].
    /// The settling after a snap or a gap starts here, on the sample's own
    /// angles. A full queue drops its oldest sample and breaks the fit's
    /// run there (the observers restart), counted in
    /// [`Monitor::learning_overruns`]: never silently.
    fn queue_for_learning(&mut self, clock: &Clock, readings: &Readings<N>, latches: &Latches<N>) {
        let t = clock.t;
        let zone = self.observer.snap_zone_deg * DEG;
        let in_zone =
            (0..N).any(|j| !latches.locked[j] && libm::fabsf(self.joints[j].kf.angle()) < zone);
        if in_zone || clock.gap {
            self.blank_until = t + self.observer.settle_s;
        }
        let quiet = self.quiet(t);
        let sample = Learning {
            t,
            clean: quiet && !clock.gap && clock.dt > 0.0,
            quiet,
            used: core::array::from_fn(|j| readings.used[j].unwrap_or(f32::NAN)),
            locked: latches.locked,
            newly: latches.newly,
        };
        if self.learning.is_full() {
            let _ = self.learning.pop_front();
            if let Some(next) = self.learning.front_mut() {
                next.clean = false;
            }
            self.learning_overruns = self.learning_overruns.saturating_add(1);
            // Once: a log line costs more than the sample path's budget
            // over semihosting, and a starved slow path must not be
            // starved further; the counter tells the rest.
            if self.learning_overruns == 1 {
                warn!("learning queue full: samples dropped (see learning_overruns)");
            }
        }
        let _ = self.learning.push_back(sample);
    }

    /// True when no snap, latch or gap has happened for `settle_s`: the
    /// estimates have settled.
    fn quiet(&self, t: f32) -> bool {
        t >= self.blank_until
    }

    /// Health of the rate filters: nothing non-finite survives an update.
    /// A failed rate filter restarts at the reading.
    fn check_health(&mut self, readings: &mut Readings<N>) {
        let sd = self.meas_sd;
        for j in 0..N {
            if !self.joints[j].kf.is_healthy() {
                let phi0 = readings.used[j].unwrap_or(self.joints[j].stowed_deg * DEG);
                self.joints[j].kf = self.fresh_filter(phi0, sd, RESET_RATE_SD, RESET_ACC_SD);
                readings.faults[j].insert(Fault::EstimatorReset);
            }
        }
    }

    /// Composes the sample-rate part of every joint's status at time `t`
    /// [s]; the learned part is [`Monitor::refresh_estimates`]'.
    fn compose_status(&mut self, t: f32, readings: &Readings<N>, latches: &Latches<N>) {
        for j in 0..N {
            let (faults, state) = (readings.faults[j], latches.states[j]);
            if !faults.is_empty() {
                debug!("joint {} faults {}", j + 1, faults.0);
            }
            if let (Some(js), Some(out)) = (self.joints.get(j), self.status.joints.get_mut(j)) {
                js.sample_status(out, faults, state);
            }
        }
        self.status.t_s = t;
        self.status.samples = self.status.samples.saturating_add(1);
    }

    /// The slow path's learning from one queued sample: the friction
    /// observers on the centred fit, the energy margin of one joint, the
    /// start of the next rollout, and the status's learned part.
    fn learn(&mut self, sample: &Learning<N>) {
        for (j, newly) in sample.newly.iter().enumerate() {
            if *newly {
                info!("joint {} latched at t = {} s", j + 1, sample.t);
            }
        }
        let centre = self.learn_friction(sample);
        self.evaluate_margin(sample);
        self.hand_over_to_prediction(sample, centre.as_ref());
        self.refresh_estimates(sample.t);
    }

    /// The model's angles [rad] and rates [rad/s]: the rate filters', 0 for
    /// a `locked` joint (latched joints sit at 0).
    fn model_state(&self, locked: &[bool; N]) -> ([f32; N], [f32; N]) {
        let pick = |j: usize, v: f32| if locked[j] { 0.0 } else { v };
        (
            core::array::from_fn(|j| pick(j, self.joints[j].kf.angle())),
            core::array::from_fn(|j| pick(j, self.joints[j].kf.rate())),
        )
    }

    /// Friction learning, half a window back, on the centred fit of the
    /// readings (no lag, little noise): only samples outside the snap
    /// zones and the settling after a snap, latch or gap, with every free
    /// joint measured (`smoother.rs`). The observers restart whenever the
    /// run of fits breaks; an observer that fails restarts at its prior
    /// (`estimator_reset` in the status). Returns the fit, if any.
    fn learn_friction(&mut self, sample: &Learning<N>) -> Option<Centre<N>> {
        self.fit
            .push(sample.t, &sample.used, sample.clean, &sample.locked);
        let centre = self.fit.centre(self.meas_var);
        match &centre {
            Some(c) => {
                let terms = momentum_terms(&self.chain, &c.phi, &c.rate);
                for j in 0..N {
                    if c.locked[j] {
                        continue;
                    }
                    let js = &mut self.joints[j];
                    if !self.fit_run {
                        js.fo.restart();
                    }
                    let mut p = 0.0f32;
                    for k in 0..N {
                        p += terms.mass[j][k] * c.rate[k];
                    }
                    let branch = Branch::select(c.phi[j], c.rate[j]);
                    js.fo.step(
                        &ObserverInput {
                            momentum: p,
                            spring_torque_nm: self.chain.joints()[j]
                                .spring
                                .torque(c.phi[j], branch),
                            beta_nm: terms.beta[j],
                            rate_rad_s: c.rate[j],
                            rate_var: c.rate_var[j],
                            dt_s: c.dt_s,
                            learn: true,
                        },
                        &self.observer.tuning,
                    );
                    // An observer changes only when it steps.
                    if !js.fo.is_healthy() {
                        js.fo.reset_parameters();
                        if let Some(out) = self.status.joints.get_mut(j) {
                            out.faults.insert(Fault::EstimatorReset);
                        }
                    }
                }
                self.fit_run = true;
            }
            None => self.fit_run = false,
        }
        centre
    }

    /// The energy margin of the remaining stroke: one joint per learned
    /// sample, in turn, not inside a snap zone or the settling time after
    /// a snap, latch or gap (the rates there are the rate filter's
    /// wide-open transient, and the margin computed on entry stands).
    fn evaluate_margin(&mut self, sample: &Learning<N>) {
        let zone = self.observer.snap_zone_deg * DEG;
        let jm = usize::from(self.next_margin) % N.max(1);
        self.next_margin = ((jm + 1) % N.max(1)) as u8;
        let (phi, _) = self.model_state(&sample.locked);
        let settled = sample.quiet && libm::fabsf(phi.get(jm).copied().unwrap_or(0.0)) >= zone;
        if let (Some(false), true) = (sample.locked.get(jm), settled) {
            // Articulated inertia 1/(M⁻¹)_jj over the free joints: the
            // one-joint energy balance counts all of the joint's kinetic
            // energy, the share the outer panels carry included, so it errs
            // on the side of a latch and its stall verdicts are safe ones.
            let m = self.chain.mass_matrix(&phi);
            let own = m
                .get(jm)
                .and_then(|row| row.get(jm))
                .copied()
                .unwrap_or(1.0);
            let inertia = articulated_inertia(&m, &sample.locked, jm)
                .unwrap_or_else(|| own.max(MIN_INERTIA_KGM2));
            let result = self.joint_margin(jm, inertia, sample.quiet);
            if let Some(js) = self.joints.get_mut(jm) {
                js.margin = Some(result);
            }
        }
    }

    /// Hands the state the next rollout starts from to the prediction.
    ///
    /// A rollout starts from the centred fit (rates to a few tenths of a
    /// degree per second, half a window back); from the rate filter only
    /// when no fit has come for a while (a flaky encoder), since its rates
    /// after a latch impact are off by degrees per second
    /// (docs/monitor.md §6).
    fn hand_over_to_prediction(&mut self, sample: &Learning<N>, centre: Option<&Centre<N>>) {
        if self.margin_cfg.rollout.steps_per_slice == 0 {
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
            None if sample.quiet && t - self.t_centre > CENTRE_WAIT_S => {
                let (phi, phi_dot) = self.model_state(&sample.locked);
                Some((t, ChainState { phi, phi_dot }, sample.locked))
            }
            None => None,
        };
        if let Some(c) = centre {
            self.t_centre = c.t_s;
        }
        // Handed to the next rollout the predictor starts.
        self.predictor.set_start(start);
    }

    /// The learned part of every joint's status: friction, margin and the
    /// latch / stall prediction as of time `t` [s].
    fn refresh_estimates(&mut self, t: f32) {
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
    /// confidence and the time to the latch [s].
    fn prediction(&mut self, j: usize, t: f32) -> (Prediction, f32, Option<f32>) {
        self.predictor.prediction(
            j,
            t,
            &PredictionQuery {
                latched: self.joints.get(j).is_some_and(|s| s.lt.is_latched()),
                energy: self.joints.get(j).and_then(|s| s.margin),
                deadline_s: self.t_start + self.margin_cfg.deadline_s,
                confidence: self.margin_cfg.confidence,
                rollouts: self.margin_cfg.rollout.steps_per_slice > 0,
            },
        )
    }

    /// One slice of the slow path. With samples queued by
    /// [`Monitor::update`], it learns from the oldest one: the friction
    /// observers, the energy margin of one joint, the start of the next
    /// rollout, and the learned part of [`Monitor::status`] (friction,
    /// margin, prediction). With the queue empty it advances the rollout
    /// in progress by up to `margin.rollout.steps_per_slice` units of work
    /// (a step of the chain, or a bounded piece of the creep quadrature:
    /// [`crate::monitor::rollout::Rollout::advance`]), starts the next one when it
    /// ends, and refreshes the prediction in the status.
    ///
    /// The sample-rate path ([`Monitor::update`]) neither learns nor runs a
    /// rollout: the application calls this at a lower priority (the idle
    /// loop, a low-priority task), as often as it has time for, and at
    /// least once per sample on average, or the queue overflows
    /// ([`Monitor::learning_overruns`]). Its cost is bounded by the slice
    /// (`docs/performance.md`). Returns true when a rollout finished in
    /// this slice.
    #[inline(never)]
    pub fn predict(&mut self) -> bool {
        if !self.started {
            return false;
        }
        if let Some(sample) = self.learning.pop_front() {
            self.learn(&sample);
            return false;
        }
        if self.margin_cfg.rollout.steps_per_slice == 0 {
            return false;
        }
        let finished = self.advance_rollouts();
        if finished {
            self.refresh_estimates(self.status.t_s);
        }
        finished
    }

    /// Samples dropped so far because the learning queue was full (the
    /// slow path, [`Monitor::predict`], fell behind by more than
    /// [`LEARNING_QUEUE`] samples). 0 on the replay schedule.
    pub fn learning_overruns(&self) -> u32 {
        self.learning_overruns
    }

    /// [`Monitor::update`], then `margin.rollout.slices_per_sample` slices
    /// of [`Monitor::predict`]: the schedule of a replay, fixed so that the
    /// host and the MCU compute the same statuses. Returns the status after
    /// the slices.
    pub fn update_and_predict(&mut self, sample: &Sample<N>) -> Status<N> {
        self.update(sample);
        for _ in 0..self.margin_cfg.rollout.slices_per_sample {
            self.predict();
        }
        self.status
    }

    /// Advances the rollout in progress; when it ends, the predictor
    /// starts the next bracket from [`Monitor::update`]'s last settled
    /// state with the current friction estimates. Returns true when a
    /// rollout finished.
    fn advance_rollouts(&mut self) -> bool {
        let joints = &self.joints;
        let capture_rad: [f32; N] = core::array::from_fn(|j| joints[j].capture_rad);
        self.predictor.slice(
            &self.chain,
            &self.margin_cfg.rollout,
            self.t_start + self.margin_cfg.deadline_s,
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

    /// The plastic latch impulse of `physics.md` §5 applied to the rate
    /// estimates: the momentum of every joint that stays free is kept and
    /// the newly latched joints stop.
    fn apply_latch_impulse(&mut self, newly: &[bool; N], locked_after: &[bool; N]) {
        let locked_before: [bool; N] = core::array::from_fn(|j| locked_after[j] && !newly[j]);
        let phi: [f32; N] = core::array::from_fn(|j| {
            if locked_before[j] {
                0.0
            } else {
                self.joints[j].kf.angle()
            }
        });
        let om: [f32; N] = core::array::from_fn(|j| {
            if locked_before[j] {
                0.0
            } else {
                self.joints[j].kf.rate()
            }
        });
        let m = self.chain.mass_matrix(&phi);
        let mut p = [0.0f32; N];
        for (pj, row) in p.iter_mut().zip(m.iter()) {
            *pj = row.iter().zip(om.iter()).map(|(a, b)| a * b).sum();
        }
        if let Ok(after) = solve_spd_masked(&m, &p, locked_after) {
            for j in 0..N {
                if newly[j] {
                    let a = self.joints[j].kf.angle();
                    self.joints[j].kf.pin(a);
                } else if !locked_after[j] && after[j].is_finite() {
                    self.joints[j].kf.set_rate(after[j], RATE_SHOCK_VAR);
                    self.joints[j].kf.inflate(0.0, ACC_SHOCK_VAR);
                }
            }
        }
    }

    /// Energy margin and one-joint latch probability of joint `j`, with
    /// `inertia` its articulated inertia `1/(M⁻¹)_jj` [kg·m²]; `quiet` when
    /// the observer runs undisturbed (its friction torque then bounds `T_C`
    /// from below).
    fn joint_margin(&self, j: usize, inertia: f32, quiet: bool) -> MarginResult {
        let (Some(js), Some(joint)) = (self.joints.get(j), self.chain.joints().get(j)) else {
            return UNKNOWN_MARGIN;
        };
        let (f, o) = (&js.kf, &js.fo);
        // f only as far as the data resolve it (§3.2).
        let est = js.friction().0;
        let phi = f.angle();
        let rate = f.rate();
        // The friction torque seen now bounds T_C from below, when the
        // observer runs undisturbed and the bound agrees with the estimate
        // (a bound beyond T̂_C + 2σ is a transient of r, not evidence).
        let bound = if quiet {
            o.coulomb_lower_bound(rate, est.viscous_nms)
        } else {
            0.0
        };
        let bound = if bound
            <= est.coulomb_nm
                + LOWER_BOUND_SIGMAS * crate::physics::real::sqrtf(est.coulomb_var.max(0.0))
        {
            bound
        } else {
            0.0
        };
        let cfg = &self.margin_cfg;
        margin::evaluate(
            &joint.spring,
            &MarginInput {
                angle_abs_rad: libm::fabsf(phi),
                rate_abs_rad_s: libm::fabsf(rate),
                towards_latch: phi * rate < 0.0,
                inertia_kgm2: inertia,
                rate_var: f.rate_var(),
                capture_rad: js.capture_rad,
                coulomb_nm: est.coulomb_nm,
                viscous_nms: est.viscous_nms,
                coulomb_var: est.coulomb_var,
                coulomb_lower_nm: bound,
                spring_scale: 1.0 + est.spring_scale_err,
                spring_sd_rel: crate::physics::real::sqrtf(est.spring_scale_var.max(0.0)),
                viscous_var: est.viscous_var,
                cov: est.cov,
            },
            &MarginSettings {
                factors: cfg.factors,
                energy_sd_floor_j: cfg.energy_sd_floor_j,
            },
        )
    }
}

/// `v` if finite, else 0 (the status never carries a NaN or an infinity).
fn finite(v: f32) -> f32 {
    if v.is_finite() {
        v
    } else {
        0.0
    }
}

/// A chain of `N` equal panels (0.8 m, 4 kg) on linear springs, stowed at
/// 90°, 100°, …, with the default tuning: the unit tests' mechanism.
#[cfg(test)]
pub(crate) fn example_config<const N: usize>() -> MonitorConfig<N> {
    let panel = crate::physics::chain::Panel {
        length_m: 0.8,
        mass_kg: 4.0,
        com_m: 0.4,
        inertia_kgm2: 0.3,
    };
    MonitorConfig::new(
        [panel; N],
        core::array::from_fn(|j| JointConfig {
            stowed_deg: 90.0 + 10.0 * j as f32,
            spring: Spring::Linear {
                preload_nm: 1.0,
                stiffness_nm_per_rad: 0.5,
                count: 1.0,
            },
            capture_deg: 0.0,
            prior: FrictionPrior {
                coulomb_nm: 0.0,
                coulomb_sd_nm: 2.0,
                viscous_nms: 0.0,
                viscous_sd_nms: 0.05,
            },
        }),
    )
}

#[cfg(test)]
mod tests;
