//! What the monitor tracks about one joint from sample to sample, and the
//! joint's lines of the status. The methods are not generic over the joint
//! count: the monitors of 2 and 3 joints share one copy of each in flash.

use crate::monitor::config::{JointConfig, ObserverConfig};
use crate::monitor::faults::FaultFlags;
use crate::monitor::latch::{LatchConfig, LatchState, LatchTracker, PhysicalLatch};
use crate::monitor::latch_margin::Engagement;
use crate::monitor::margin::MarginResult;
use crate::monitor::observer::{FrictionEstimate, FrictionObserver, FrictionPrior};
use crate::monitor::plausibility::ReadingCheck;
use crate::monitor::predictor::Prediction;
use crate::monitor::rate_filter::RateFilter;
use crate::monitor::status::{JointStatus, Observability, VISCOUS_RESOLVED_SD};

/// One degree \[rad\].
pub(super) const DEG: f32 = core::f32::consts::PI / 180.0;

/// Rate uncertainty at the first sample [rad/s]: a deployment starts from
/// rest (a monitor started mid-motion is caught by the jerk adaptation).
pub(super) const START_RATE_SD: f32 = 0.01;
/// Acceleration uncertainty at the first sample [rad/s²].
pub(super) const START_ACC_SD: f32 = 1.0;

/// What the monitor tracks about one joint from sample to sample.
#[derive(Clone, Copy, Debug)]
pub(super) struct JointState {
    /// Stowed angle \[deg\] (the latch is at 0).
    pub(super) stowed_deg: f32,
    /// Capture angle `x_c` \[rad\] (below it the spring completes the latch).
    pub(super) capture_rad: f32,
    /// The physical latch's engagement (the margin's resistance).
    pub(super) engagement: Engagement,
    /// Kinematic Kalman filter of the angle and rate (§2 of
    /// `docs/monitor.md`).
    pub(super) kf: RateFilter,
    /// Momentum disturbance observer and RLS friction estimate (§3).
    pub(super) fo: FrictionObserver,
    /// Latch-state estimator, switch fused with encoder (§4).
    pub(super) lt: LatchTracker,
    /// Its thresholds, with this joint's latch as built (a wing may mix
    /// ideal, plunger and pawl latches).
    pub(super) latch_cfg: LatchConfig,
    /// Last energy margin and one-joint latch probability (§5).
    pub(super) margin: Option<MarginResult>,
    /// Consecutive readings the rate filter's gate rejected.
    pub(super) rejects: u8,
    /// Last in-range reading of the encoder \[deg\].
    pub(super) last_raw: f32,
    /// How many samples in a row repeated `last_raw` exactly.
    pub(super) same_run: u16,
    /// Stale and returning-spike checks of the encoder (`plausibility.rs`).
    pub(super) plausibility: ReadingCheck,
    /// The latch switch at the previous sample (a closing is an impact).
    pub(super) switch_prev: bool,
    /// The status's standard deviations of `T_C` and `f`, with the
    /// variances they are the roots of (they change only when the observer
    /// learns: the square roots are not taken again in between).
    coulomb_sd: CachedSqrt,
    viscous_sd: CachedSqrt,
}

/// What a joint's state starts from: its [`JointConfig`] but the spring
/// (which the chain model holds; a spring is hundreds of bytes, and a
/// placeholder joint is built on the stack).
#[derive(Clone, Copy, Debug)]
pub(super) struct JointStart {
    /// Stowed angle \[deg\].
    pub(super) stowed_deg: f32,
    /// Capture angle \[deg\].
    pub(super) capture_deg: f32,
    /// Prior of the friction parameters.
    pub(super) prior: FrictionPrior,
    /// The physical latch's engagement.
    pub(super) engagement: Engagement,
    /// The joint's own physical latch (`JointConfig::physical`).
    pub(super) physical: Option<PhysicalLatch>,
}

impl JointStart {
    /// The start of a configured joint.
    pub(super) fn of(joint: &JointConfig) -> Self {
        JointStart {
            stowed_deg: joint.stowed_deg,
            capture_deg: joint.capture_deg,
            prior: joint.prior,
            engagement: joint.latch,
            physical: joint.physical,
        }
    }
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

/// A joint's latch / stall prediction, as the status reports it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Forecast {
    pub(super) prediction: Prediction,
    pub(super) confidence: f32,
    /// Time to the latch \[s\].
    pub(super) time_to_latch_s: Option<f32>,
}

impl JointState {
    /// A joint at its stowed angle, waiting for the first sample: `joint`
    /// without its spring (the chain holds it), `sd` the encoder's standard
    /// deviation \[rad\], `latch` the tracker's thresholds (the joint's
    /// own physical latch, if any, replaces theirs).
    #[inline(never)]
    pub(super) fn new(
        joint: &JointStart,
        sd: f32,
        observer: &ObserverConfig,
        latch: &LatchConfig,
        spring_sd_rel: f32,
    ) -> Self {
        let mut kf = RateFilter::new(joint.stowed_deg * DEG, sd, START_RATE_SD, START_ACC_SD);
        kf.set_jerk_psd(observer.jerk_psd);
        JointState {
            stowed_deg: joint.stowed_deg,
            capture_rad: joint.capture_deg * DEG,
            engagement: joint.engagement,
            kf,
            fo: FrictionObserver::new(joint.prior, spring_sd_rel),
            lt: LatchTracker::new(),
            latch_cfg: LatchConfig {
                physical: joint.physical.or(latch.physical),
                ..*latch
            },
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

    /// [`JointState::new`] in place (a joint state of the monitor in
    /// static memory is reconfigured without a second one on the stack).
    #[inline(never)]
    pub(super) fn reset(
        &mut self,
        joint: &JointStart,
        sd: f32,
        observer: &ObserverConfig,
        latch: &LatchConfig,
        spring_sd_rel: f32,
    ) {
        self.kf = RateFilter::new(joint.stowed_deg * DEG, sd, START_RATE_SD, START_ACC_SD);
        self.kf.set_jerk_psd(observer.jerk_psd);
        self.stowed_deg = joint.stowed_deg;
        self.capture_rad = joint.capture_deg * DEG;
        self.engagement = joint.engagement;
        self.fo = FrictionObserver::new(joint.prior, spring_sd_rel);
        self.lt = LatchTracker::new();
        self.latch_cfg = LatchConfig {
            physical: joint.physical.or(latch.physical),
            ..*latch
        };
        self.margin = None;
        self.rejects = 0;
        self.last_raw = f32::NAN;
        self.same_run = 0;
        self.plausibility = ReadingCheck::new();
        self.switch_prev = false;
        self.coulomb_sd = CachedSqrt::EMPTY;
        self.viscous_sd = CachedSqrt::EMPTY;
    }

    /// True when the joint's switch `switch` and reading `z_deg` \[deg\]
    /// announce an impact: its switch closes (with a physical latch: the
    /// first time since the joint came in, not again at each rebound), or
    /// (physical latch) its encoder comes within the plunger's crest of the
    /// stop, where the joint may hit the stop between two samples with its
    /// switch open again at the next.
    #[inline(never)]
    pub(super) fn announces_impact(&self, switch: bool, z_deg: f32) -> bool {
        (switch && !self.switch_prev) || self.lt.enters_stop_zone(z_deg)
    }

    /// True when the joint is latched or held at its latch (the model sits
    /// it at 0).
    pub(super) fn locked(&self) -> bool {
        self.lt.is_latched() || self.lt.held_at_latch()
    }

    /// The sample-rate part of the joint's status line (non-finite values
    /// as 0): angle, rate, the latch `state` and the `faults` of this
    /// sample, the resolution of its readings; no margin once latched.
    #[inline(never)]
    pub(super) fn sample_status(
        &self,
        out: &mut JointStatus,
        faults: FaultFlags,
        state: LatchState,
    ) {
        out.phi_deg = finite(self.kf.angle() / DEG);
        out.rate_deg_s = finite(self.kf.rate() / DEG);
        out.latch = state;
        out.faults = faults;
        out.resolution = self.plausibility.resolution();
        if self.lt.is_latched() {
            out.margin_pct = None;
        }
    }

    /// The friction the prediction and the energy margin use, and whether
    /// the data resolve `f`: the observer's estimate when they do; when
    /// they do not, the estimate conditioned on `f` = its prior mean, whose
    /// Coulomb torque holds the friction seen at the rates observed
    /// (`docs/monitor.md` §3.2, [`FrictionObserver::estimate_given_viscous`]).
    #[inline(never)]
    pub(super) fn friction(&self) -> (FrictionEstimate, Observability) {
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
    /// deviation.
    #[inline(never)]
    pub(super) fn estimates(&mut self, out: &mut JointStatus, forecast: Forecast) {
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

/// `v` if finite, else 0 (the status never carries a NaN or an infinity).
fn finite(v: f32) -> f32 {
    if v.is_finite() {
        v
    } else {
        0.0
    }
}
