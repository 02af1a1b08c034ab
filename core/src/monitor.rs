//! The on-board deployment monitor: one entry point,
//! [`Monitor::update`]`(&Sample) -> Status`.
//!
//! Each sample (time stamp, encoder angles, latch switches) goes through
//!
//! 1. the time checks (NaN, backwards, gaps: [`Fault`] flags, never a panic);
//! 2. a kinematic Kalman filter per joint: angle and rate from the 14-bit
//!    encoder, spikes gated out ([`crate::observer::RateFilter`]);
//! 3. the latch-state estimator per joint, switch fused with encoder
//!    ([`crate::latch`]);
//! 4. the generalised-momentum disturbance observer and RLS friction
//!    estimate per free joint ([`crate::observer::FrictionObserver`]);
//! 5. the energy margin of the remaining stroke and the latch / stall
//!    prediction, one joint per update in turn ([`crate::margin`]).
//!
//! Everything is `f32`, fixed-size and heap-free; `size_of::<Monitor<3>>()`
//! is under 4 KiB. `docs/monitor.md` has the equations and the tuning.

use crate::chain::{Chain, ChainError, ChainState, GlobalEffects, Joint, JointEffects, Panel};
use crate::faults::{Fault, FaultFlags};
use crate::friction::Friction;
use crate::latch::{LatchConfig, LatchInput, LatchState, LatchTracker};
use crate::linalg::{articulated_inertias, solve_spd_masked};
use crate::margin::{self, MarginInput, MarginResult, MarginSettings, UncertaintyFactors};
use crate::observer::{
    momentum_terms, FrictionObserver, FrictionPrior, Fusion, JerkAdaptation, ObserverInput,
    ObserverTuning, RateFilter,
};
use crate::plausibility::{Reading, ReadingCheck, Verdict};
use crate::rollout::{
    normal_quantile, Bracket, JointOutcome, Rollout, RolloutConfig, RolloutStart,
};
use crate::smoother::CentredFit;
use crate::spring::{Branch, Spring};
use serde::{Deserialize, Serialize};

const DEG: f32 = core::f32::consts::PI / 180.0;

/// Largest encoder reading accepted [deg]; beyond it a reading is a fault.
pub const ENCODER_RANGE_DEG: f32 = 720.0;

/// One sample of the sensors.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sample<const N: usize> {
    /// Time stamp [s].
    pub t_s: f32,
    /// Encoder angle of each joint [deg]; NaN for a missing reading.
    #[serde(with = "crate::telemetry::array")]
    pub phi_deg: [f32; N],
    /// Latch switch of each joint (true = closed).
    #[serde(with = "crate::telemetry::array")]
    pub latch: [bool; N],
}

impl<const N: usize> Sample<N> {
    /// A sample.
    pub const fn new(t_s: f32, phi_deg: [f32; N], latch: [bool; N]) -> Self {
        Sample {
            t_s,
            phi_deg,
            latch,
        }
    }
}

/// The latch / stall prediction of a joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Prediction {
    /// Not decided at the configured confidence.
    #[default]
    Unknown,
    /// Will latch (or has latched).
    Latch,
    /// Will stall short of the latch.
    Stall,
}

impl Prediction {
    /// Every prediction.
    pub const ALL: [Prediction; 3] = [Prediction::Unknown, Prediction::Latch, Prediction::Stall];

    /// The name used in telemetry CSV and reports.
    pub const fn as_str(self) -> &'static str {
        match self {
            Prediction::Unknown => "unknown",
            Prediction::Latch => "latch",
            Prediction::Stall => "stall",
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

/// What the monitor knows about one joint.
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JointStatus {
    /// Estimated angle [deg].
    pub phi_deg: f32,
    /// Estimated rate [deg/s].
    pub rate_deg_s: f32,
    /// Estimated Coulomb friction torque `T_C` [N·m].
    pub coulomb_nm: f32,
    /// Standard deviation of `T_C` [N·m].
    pub coulomb_sd_nm: f32,
    /// Estimated viscous coefficient `f` [N·m·s/rad].
    pub viscous_nms: f32,
    /// Standard deviation of `f` [N·m·s/rad].
    pub viscous_sd_nms: f32,
    /// Disturbance-observer friction torque now (filtered) [N·m].
    pub friction_torque_nm: f32,
    /// Latch state.
    pub latch: LatchState,
    /// Torque margin of the remaining stroke, energy form, with the
    /// configured uncertainty factors [%]; `None` once latched or before
    /// the first evaluation.
    pub margin_pct: Option<f32>,
    /// Latch / stall prediction: the outcome of the nominal rollout
    /// (`Unknown` until the first one has finished).
    pub prediction: Prediction,
    /// Confidence level of `prediction` [0, 1]: the configured level when
    /// the bracketing rollout confirms it, 0.5 when it does not (the best
    /// estimate only), 1 once latched, 0 when unknown.
    pub confidence: f32,
    /// Predicted time until the latch [s], from the nominal rollout; `None`
    /// for a stall, once latched, or before the first rollout.
    pub time_to_latch_s: Option<f32>,
    /// Faults raised at this sample.
    pub faults: FaultFlags,
}

/// The monitor's answer to one sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status<const N: usize> {
    /// Time stamp of the last sample used [s].
    pub t_s: f32,
    /// Samples used so far.
    pub samples: u32,
    /// Per joint.
    #[serde(with = "crate::telemetry::array")]
    pub joints: [JointStatus; N],
}

impl<const N: usize> Default for Status<N> {
    fn default() -> Self {
        Status {
            t_s: 0.0,
            samples: 0,
            joints: [JointStatus::default(); N],
        }
    }
}

impl<const N: usize> Status<N> {
    /// True when no joint has a fault flag.
    pub fn is_clean(&self) -> bool {
        self.joints.iter().all(|j| j.faults.is_empty())
    }
}

/// One joint of the monitored mechanism.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointConfig {
    /// Stowed angle [deg]; the latch angle is 0.
    pub stowed_deg: f32,
    /// The hinge spring (all hinges of the joint), as in the mechanism.
    pub spring: Spring<f32>,
    /// Capture angle `x_c` [deg]: below it the spring completes the latch
    /// whatever the friction (a tape spring's θ_B; 0 for a linear spring).
    pub capture_deg: f32,
    /// Prior of the friction parameters.
    pub prior: FrictionPrior,
}

/// The encoder.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorConfig {
    /// White noise before quantisation, σ [deg].
    pub encoder_sd_deg: f32,
    /// Quantisation step [deg] (360/16384 for 14 bits).
    pub encoder_step_deg: f32,
    /// Consecutive identical readings after which the encoder is stuck
    /// (flag `encoder_stuck`, readings not used until they change); 0
    /// switches the check off. With σ = 0.02° of noise against a 0.022°
    /// step a reading repeats with probability ≤ 0.42, so 20 in a row
    /// happen by chance with probability ≈ 6·10⁻⁸.
    pub stuck_samples: u16,
}

impl Default for SensorConfig {
    fn default() -> Self {
        SensorConfig {
            encoder_sd_deg: 0.02,
            encoder_step_deg: crate::encoder::STEP_DEG as f32,
            stuck_samples: 20,
        }
    }
}

/// Tuning of the rate filter and the friction observer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObserverConfig {
    /// Jerk spectral density of the rate filter at the start [rad²/s⁵].
    pub jerk_psd: f32,
    /// Its adaptation to the innovations.
    pub jerk_adaptation: JerkAdaptation,
    /// The same inside the snap zone of a tape spring [rad²/s⁵].
    pub zone_jerk_psd: f32,
    /// `|φ|` below which a free joint is in its snap zone [deg]: the spring
    /// torque is too steep there for the model, so friction learning pauses.
    pub snap_zone_deg: f32,
    /// Innovation gate of the encoder [σ].
    pub gate_sigma: f32,
    /// Disturbance observer and RLS.
    pub tuning: ObserverTuning,
    /// Pause of the friction learning after a snap, latch or gap [s].
    pub settle_s: f32,
    /// Time step above which the samples around it are a gap [s].
    pub max_gap_s: f32,
    /// Smallest time step accepted [s].
    pub min_dt_s: f32,
}

impl Default for ObserverConfig {
    fn default() -> Self {
        ObserverConfig {
            jerk_psd: 1e-3,
            jerk_adaptation: JerkAdaptation {
                q_min: 1e-3,
                q_max: 1e4,
                high: 2.0,
                low: 1.2,
                weight: 0.05,
            },
            zone_jerk_psd: 1.0e7,
            snap_zone_deg: 3.0,
            gate_sigma: 6.0,
            tuning: ObserverTuning {
                bandwidth_per_s: 10.0,
                coulomb_threshold_rad_s: crate::friction::COULOMB_THRESHOLD_RAD_S as f32,
                coulomb_walk: 0.05,
                viscous_walk: 1e-4,
                residual_var_floor: 1e-4,
            },
            settle_s: 0.1,
            max_gap_s: 0.1,
            min_dt_s: 1e-4,
        }
    }
}

/// Settings of the margin and the prediction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarginConfig {
    /// Uncertainty factors of the reported margin.
    pub factors: UncertaintyFactors,
    /// Confidence level of the latch / stall prediction: the rollouts bracket
    /// the friction at `T̂_C ± zσ`, `Φ(z)` = this.
    pub confidence: f32,
    /// The forward simulations of the prediction.
    pub rollout: RolloutConfig,
    /// The deployment's deadline, from the first sample [s]: a joint that
    /// latches later counts as stalled (the mechanism file's `duration_s`).
    pub deadline_s: f32,
    /// Relative standard deviation of the spring torques [1]: how far the
    /// hinges may be from their curves. The prior spread of the friction
    /// observer's spring-scale estimate `κ` (`docs/monitor.md` §3.2).
    pub spring_sd_rel: f32,
    /// Floor of the energy standard deviation [J].
    pub energy_sd_floor_j: f32,
}

impl Default for MarginConfig {
    fn default() -> Self {
        MarginConfig {
            factors: UncertaintyFactors::UNITY,
            confidence: 0.9,
            rollout: RolloutConfig {
                dt_s: 0.01,
                steps_per_slice: 2,
                slices_per_sample: 6,
                horizon_s: 10.0,
                coulomb_threshold_rad_s: crate::friction::COULOMB_THRESHOLD_RAD_S as f32,
            },
            deadline_s: 6.0,
            spring_sd_rel: 0.05,
            energy_sd_floor_j: 0.02,
        }
    }
}

/// Everything the monitor is configured with: the mechanism as fixed-size
/// tables (the host converts it from the mechanism TOML) and the tuning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MonitorConfig<const N: usize> {
    /// Panels, bus outwards.
    pub panels: [Panel<f32>; N],
    /// Joints; joint j drives panel j.
    pub joints: [JointConfig; N],
    /// The encoder.
    pub sensor: SensorConfig,
    /// Rate filter and friction observer.
    pub observer: ObserverConfig,
    /// Latch-state estimator.
    pub latch: LatchConfig,
    /// Margin and prediction.
    pub margin: MarginConfig,
}

impl<const N: usize> MonitorConfig<N> {
    /// A configuration with the default tuning.
    pub fn new(panels: [Panel<f32>; N], joints: [JointConfig; N]) -> Self {
        MonitorConfig {
            panels,
            joints,
            sensor: SensorConfig::default(),
            observer: ObserverConfig::default(),
            latch: LatchConfig::default(),
            margin: MarginConfig::default(),
        }
    }
}

/// Why a configuration was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ConfigError {
    /// The panels do not make a chain.
    Chain(ChainError),
    /// Joint `index` (0-based) has a bad parameter.
    Joint {
        /// 0-based joint index.
        index: usize,
        /// Which parameter.
        what: &'static str,
    },
    /// A tuning parameter is out of range.
    Parameter(&'static str),
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ConfigError::Chain(e) => write!(f, "monitor mechanism: {e}"),
            ConfigError::Joint { index, what } => {
                write!(
                    f,
                    "monitor joint {}: {what} must be a finite number in range",
                    index + 1
                )
            }
            ConfigError::Parameter(what) => write!(f, "monitor tuning: {what} is out of range"),
        }
    }
}

impl core::error::Error for ConfigError {}

fn positive(v: f32) -> bool {
    v.is_finite() && v > 0.0
}

fn non_negative(v: f32) -> bool {
    v.is_finite() && v >= 0.0
}

impl<const N: usize> MonitorConfig<N> {
    /// Checks every parameter.
    pub fn validate(&self) -> Result<(), ConfigError> {
        for (index, j) in self.joints.iter().enumerate() {
            let checks: [(bool, &'static str); 6] = [
                (
                    j.stowed_deg.is_finite() && libm::fabsf(j.stowed_deg) <= ENCODER_RANGE_DEG,
                    "stowed_deg",
                ),
                (non_negative(j.capture_deg), "capture_deg"),
                (j.prior.coulomb_nm.is_finite(), "coulomb prior"),
                (positive(j.prior.coulomb_sd_nm), "coulomb prior sd"),
                (j.prior.viscous_nms.is_finite(), "viscous prior"),
                (positive(j.prior.viscous_sd_nms), "viscous prior sd"),
            ];
            if let Some((_, what)) = checks.iter().find(|(ok, _)| !ok) {
                return Err(ConfigError::Joint { index, what });
            }
        }
        let o = &self.observer;
        let t = &o.tuning;
        let checks: [(bool, &'static str); 18] = [
            (positive(self.sensor.encoder_sd_deg), "encoder_sd_deg"),
            (
                non_negative(self.sensor.encoder_step_deg),
                "encoder_step_deg",
            ),
            (positive(o.jerk_psd), "jerk_psd"),
            (
                positive(o.jerk_adaptation.q_min)
                    && o.jerk_adaptation.q_max >= o.jerk_adaptation.q_min
                    && o.jerk_adaptation.q_max.is_finite()
                    && positive(o.jerk_adaptation.low)
                    && o.jerk_adaptation.high > o.jerk_adaptation.low
                    && o.jerk_adaptation.high.is_finite()
                    && o.jerk_adaptation.weight > 0.0
                    && o.jerk_adaptation.weight <= 1.0,
                "jerk_adaptation",
            ),
            (positive(o.zone_jerk_psd), "zone_jerk_psd"),
            (non_negative(o.snap_zone_deg), "snap_zone_deg"),
            (positive(o.gate_sigma), "gate_sigma"),
            (positive(t.bandwidth_per_s), "bandwidth_per_s"),
            (
                positive(t.coulomb_threshold_rad_s),
                "coulomb_threshold_rad_s",
            ),
            (
                non_negative(t.coulomb_walk) && non_negative(t.viscous_walk),
                "friction walk",
            ),
            (positive(t.residual_var_floor), "residual_var_floor"),
            (non_negative(o.settle_s), "settle_s"),
            (
                positive(o.min_dt_s) && positive(o.max_gap_s) && o.max_gap_s > o.min_dt_s,
                "time step limits",
            ),
            (self.margin.factors.is_valid(), "uncertainty factors"),
            (
                self.margin.confidence > 0.5 && self.margin.confidence < 1.0,
                "confidence",
            ),
            (
                positive(self.margin.rollout.dt_s)
                    && positive(self.margin.rollout.horizon_s)
                    && positive(self.margin.rollout.coulomb_threshold_rad_s),
                "rollout",
            ),
            (positive(self.margin.deadline_s), "deadline_s"),
            (
                non_negative(self.margin.spring_sd_rel) && positive(self.margin.energy_sd_floor_j),
                "margin spread",
            ),
        ];
        if let Some((_, what)) = checks.iter().find(|(ok, _)| !ok) {
            return Err(ConfigError::Parameter(what));
        }
        if !self.latch.is_valid() {
            return Err(ConfigError::Parameter("latch thresholds"));
        }
        Ok(())
    }
}

/// The on-board monitor of an `N`-joint deployment.
#[derive(Clone, Debug)]
pub struct Monitor<const N: usize> {
    chain: Chain<f32, N>,
    stowed_deg: [f32; N],
    capture_rad: [f32; N],
    sensor: SensorConfig,
    observer: ObserverConfig,
    latch_cfg: LatchConfig,
    margin_cfg: MarginConfig,
    kf: [RateFilter; N],
    fo: [FrictionObserver; N],
    lt: [LatchTracker; N],
    margin: [Option<MarginResult>; N],
    /// The rollout in progress, its bracket and start time [s].
    rollout: Option<(Rollout<N>, Bracket, f32)>,
    /// Position in [`CYCLE`] of the rollout in progress.
    cycle_pos: u8,
    /// Last finished nominal, pessimistic and optimistic outcomes, with
    /// their start times [s].
    nominal: Option<([JointOutcome; N], f32)>,
    pessimistic: Option<([JointOutcome; N], f32)>,
    optimistic: Option<([JointOutcome; N], f32)>,
    /// `z = Φ⁻¹(confidence)`.
    z: f32,
    rejects: [u8; N],
    /// Stale and returning-spike checks of each encoder (`plausibility.rs`).
    plausibility: [ReadingCheck; N],
    /// Last in-range reading of each encoder [deg] and how many samples in
    /// a row repeated it exactly.
    last_raw: [f32; N],
    same_run: [u16; N],
    started: bool,
    /// Time stamp of the first sample [s].
    t_start: f32,
    t_prev: f32,
    back_run: u8,
    t_back: f32,
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
    /// Each switch at the previous sample (a closing is an impact).
    switch_prev: [bool; N],
    /// End of the window after a switch closed in which a reading the rate
    /// filter rejects is the impact, not an outlier [s].
    impact_until: f32,
    /// Samples left whose prediction is widened for the impact.
    impact_samples: u8,
    /// Where the next rollout starts: time [s], state and locked joints
    /// (set by `update`, used by `predict`).
    rollout_start: Option<(f32, ChainState<f32, N>, [bool; N])>,
    next_margin: u8,
    status: Status<N>,
}

/// Rate uncertainty at the first sample [rad/s]: a deployment starts from
/// rest (a monitor started mid-motion is caught by the jerk adaptation).
const START_RATE_SD: f32 = 0.01;
/// Acceleration uncertainty at the first sample [rad/s²].
const START_ACC_SD: f32 = 1.0;
/// Variance added to a rate after a latch impulse or a gap [rad²/s²].
const RATE_SHOCK_VAR: f32 = 0.04;
/// Variance added to an acceleration after a latch impulse or a gap [rad²/s⁴].
const ACC_SHOCK_VAR: f32 = 100.0;
/// Consecutive gate rejections after which the rate filter restarts at the
/// measurement.
const MAX_REJECTS: u8 = 3;
/// Time without a centred fit after which a rollout starts from the rate
/// filter instead [s].
const CENTRE_WAIT_S: f32 = 0.5;
/// The order of the rollouts.
const CYCLE: [Bracket; 4] = [
    Bracket::Nominal,
    Bracket::Pessimistic,
    Bracket::Nominal,
    Bracket::Optimistic,
];
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

impl<const N: usize> Monitor<N> {
    /// A monitor for the configured mechanism, waiting for its first sample.
    pub fn new(config: &MonitorConfig<N>) -> Result<Self, ConfigError> {
        config.validate()?;
        let joints: [Joint<f32>; N] = core::array::from_fn(|j| Joint {
            stowed_rad: config.joints[j].stowed_deg * DEG,
            spring: config.joints[j].spring,
            friction: Friction::default(),
            effects: JointEffects::default(),
        });
        let chain = Chain::new(config.panels, joints, GlobalEffects::default())
            .map_err(ConfigError::Chain)?;
        let sd = config.sensor.encoder_sd_deg * DEG;
        Ok(Monitor {
            chain,
            stowed_deg: core::array::from_fn(|j| config.joints[j].stowed_deg),
            capture_rad: core::array::from_fn(|j| config.joints[j].capture_deg * DEG),
            sensor: config.sensor,
            observer: config.observer,
            latch_cfg: config.latch,
            margin_cfg: config.margin,
            kf: core::array::from_fn(|j| {
                let mut f = RateFilter::new(
                    config.joints[j].stowed_deg * DEG,
                    sd,
                    START_RATE_SD,
                    START_ACC_SD,
                );
                f.set_jerk_psd(config.observer.jerk_psd);
                f
            }),
            fo: core::array::from_fn(|j| {
                FrictionObserver::new(config.joints[j].prior, config.margin.spring_sd_rel)
            }),
            lt: [LatchTracker::new(); N],
            margin: [None; N],
            rollout: None,
            cycle_pos: 0,
            nominal: None,
            pessimistic: None,
            optimistic: None,
            z: normal_quantile(config.margin.confidence),
            rejects: [0; N],
            plausibility: [ReadingCheck::new(); N],
            last_raw: [f32::NAN; N],
            same_run: [0; N],
            started: false,
            t_start: 0.0,
            t_prev: 0.0,
            back_run: 0,
            t_back: 0.0,
            blank_until: f32::NEG_INFINITY,
            fit: CentredFit::new(),
            fit_run: false,
            t_centre: f32::NEG_INFINITY,
            rollout_start: None,
            switch_prev: [false; N],
            dt_mean: 0.0,
            impact_until: f32::NEG_INFINITY,
            impact_samples: 0,
            next_margin: 0,
            status: Status::default(),
        })
    }

    /// The status after the last sample.
    pub fn status(&self) -> &Status<N> {
        &self.status
    }

    /// The friction observer of joint `j` (0-based), for diagnostics.
    pub fn observer(&self, j: usize) -> Option<&FrictionObserver> {
        self.fo.get(j)
    }

    /// The rate filter of joint `j` (0-based), for diagnostics.
    pub fn rate_filter(&self, j: usize) -> Option<&RateFilter> {
        self.kf.get(j)
    }

    /// Slices of [`Monitor::predict`] a replay runs after each sample
    /// (`margin.rollout.slices_per_sample`).
    pub fn config_slices_per_sample(&self) -> u8 {
        self.margin_cfg.rollout.slices_per_sample
    }

    /// The chain model the monitor uses (f32).
    pub fn chain(&self) -> &Chain<f32, N> {
        &self.chain
    }

    /// Measurement variance of one encoder reading [rad²].
    fn meas_var(&self) -> f32 {
        let sd = self.sensor.encoder_sd_deg * DEG;
        let q = self.sensor.encoder_step_deg * DEG;
        sd * sd + q * q / 12.0
    }

    /// The previous status with this sample's faults (a sample not used).
    fn hold(&mut self, faults: FaultFlags) -> Status<N> {
        for js in self.status.joints.iter_mut() {
            js.faults = faults;
        }
        self.status
    }

    /// Processes one sample and returns the monitor's status.
    ///
    /// Never panics: a NaN or infinite reading is a missing measurement, a
    /// time stamp that does not increase or is not finite makes the sample
    /// unused, and each raises a [`Fault`] flag in the status.
    // Out of line: the sample-rate path is one function to measure, and its
    // frame is not merged into the caller's.
    #[inline(never)]
    pub fn update(&mut self, sample: &Sample<N>) -> Status<N> {
        let mut global = FaultFlags::EMPTY;
        let t = sample.t_s;
        if !t.is_finite() {
            global.insert(Fault::TimeInvalid);
            return self.hold(global);
        }
        let mut gap = false;
        let mut dt = 0.0f32;
        if self.started {
            let d = t - self.t_prev;
            if !(d >= self.observer.min_dt_s) {
                global.insert(Fault::TimeBackwards);
                let chained = self.back_run > 0 && t - self.t_back >= self.observer.min_dt_s;
                self.back_run = if chained {
                    self.back_run.saturating_add(1)
                } else {
                    1
                };
                self.t_back = t;
                if self.back_run < RESYNC_SAMPLES {
                    return self.hold(global);
                }
                // Adopt the new time base, as after a gap.
                gap = true;
                dt = self.observer.max_gap_s;
            } else if !(d <= self.observer.max_gap_s) {
                gap = true;
                dt = d.min(1.0);
            } else {
                dt = d;
                // Time-stamp jitter: an interval off the running mean.
                if self.dt_mean > 0.0 && libm::fabsf(d - self.dt_mean) > JITTER_TOL * self.dt_mean {
                    global.insert(Fault::TimeJitter);
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
            global.insert(Fault::TimeGap);
        }

        // Encoders.
        // Not across a gap, nor at or after a switch closing (an impact
        // under way: a joint may stop dead): `plausibility.rs`.
        let no_checks = !self.started
            || gap
            || t <= self.impact_until
            || (0..N).any(|j| sample.latch[j] && !self.switch_prev[j]);
        let mut faults = [global; N];
        let mut meas = [None::<f32>; N];
        let mut stuck = [false; N];
        for j in 0..N {
            let z = sample.phi_deg[j];
            if !z.is_finite() {
                faults[j].insert(Fault::EncoderMissing);
            } else if libm::fabsf(z) > ENCODER_RANGE_DEG {
                faults[j].insert(Fault::EncoderRange);
            } else {
                // A reading frozen to the same value for longer than the
                // noise allows is a stuck (or stale) encoder: not used.
                if z == self.last_raw[j] {
                    self.same_run[j] = self.same_run[j].saturating_add(1);
                } else {
                    self.same_run[j] = 0;
                    self.last_raw[j] = z;
                }
                // A latched joint's encoder reads a constant by rights (a
                // noise-free or coarse encoder repeats exactly): the check
                // ends with the latch, whose declaration is final.
                let limit = self.sensor.stuck_samples;
                let latched = self.lt[j].is_latched();
                // Stale while moving (not used) or a spike that returned
                // (flagged): `plausibility.rs`.
                let verdict = self.plausibility[j].check_filter(
                    &Reading {
                        t_s: t,
                        angle: Some(z * DEG),
                        repeats: self.same_run[j],
                        step: self.sensor.encoder_step_deg * DEG,
                        moving_checks: !no_checks && !latched && !sample.latch[j],
                    },
                    &self.kf[j],
                    self.t_prev,
                );
                if let Some(f) = verdict.fault() {
                    faults[j].insert(f);
                }
                let stale = verdict == Verdict::Stale;
                if !latched && limit > 0 && (stale || self.same_run[j].saturating_add(1) >= limit) {
                    faults[j].insert(Fault::EncoderStuck);
                    stuck[j] = true;
                } else {
                    meas[j] = Some(z * DEG);
                }
            }
        }
        // The readings as they came (range-checked): the latch estimator
        // compares them with the switch even when the rate filter gated one
        // out (a joint stopping dead at its latch looks like a spike to it;
        // the switch must agree anyway).
        let raw = meas;
        let r_meas = self.meas_var();
        let sd = crate::real::sqrtf(r_meas);
        if !self.started {
            for j in 0..N {
                let phi0 = meas[j].unwrap_or(self.stowed_deg[j] * DEG);
                self.kf[j] = RateFilter::new(phi0, sd, START_RATE_SD, START_ACC_SD);
                self.kf[j].set_jerk_psd(self.observer.jerk_psd);
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
            if (0..N).any(|j| sample.latch[j] && !self.switch_prev[j]) {
                self.impact_until = t + IMPACT_WINDOW_S;
                self.impact_samples = IMPACT_INFLATE_SAMPLES;
            }
            let impact = t <= self.impact_until;
            let inflate = self.impact_samples > 0;
            self.impact_samples = self.impact_samples.saturating_sub(1);
            let gate2 = self.observer.gate_sigma * self.observer.gate_sigma;
            let zone = self.observer.snap_zone_deg * DEG;
            for j in 0..N {
                let kf = &mut self.kf[j];
                let q_floor = if !self.lt[j].is_latched() && libm::fabsf(kf.angle()) < zone {
                    self.observer.zone_jerk_psd
                } else {
                    0.0
                };
                if inflate && !self.lt[j].is_latched() {
                    kf.inflate(IMPACT_RATE_VAR, ACC_SHOCK_VAR);
                }
                kf.predict(dt, q_floor);
                if gap {
                    kf.inflate(1.0, ACC_SHOCK_VAR);
                }
                if let Some(z) = meas[j] {
                    let r = if gap { r_meas + 1.0 } else { r_meas };
                    // A reading beyond the gate but within
                    // `MANOEUVRE_GATE` gates of the prediction is a
                    // manoeuvre the white-jerk model did not foresee (a
                    // joint that sticks under its friction stops with a
                    // step in acceleration), not a spike.
                    let nu = z - kf.angle();
                    let manoeuvre =
                        nu * nu <= MANOEUVRE_GATE * MANOEUVRE_GATE * gate2 * (kf.angle_var() + r);
                    match kf.update(z, r, gate2, &self.observer.jerk_adaptation) {
                        Fusion::Accepted => self.rejects[j] = 0,
                        Fusion::Rejected if impact || manoeuvre => {
                            let rate = if impact { 0.0 } else { kf.rate() };
                            *kf = RateFilter::new(z, sd, IMPACT_RATE_SD, START_ACC_SD);
                            kf.set_rate(rate, 0.0);
                            kf.set_jerk_psd(self.observer.jerk_psd);
                            self.rejects[j] = 0;
                            if impact {
                                self.blank_until = t + self.observer.settle_s;
                            }
                        }
                        Fusion::Rejected => {
                            faults[j].insert(Fault::EncoderOutlier);
                            self.rejects[j] = self.rejects[j].saturating_add(1);
                            if self.rejects[j] >= MAX_REJECTS {
                                *kf = RateFilter::new(z, sd, 1.0, 10.0);
                                kf.set_jerk_psd(self.observer.jerk_psd);
                                faults[j].insert(Fault::EstimatorReset);
                                self.rejects[j] = 0;
                                self.blank_until = t + self.observer.settle_s;
                            } else {
                                meas[j] = None;
                            }
                        }
                    }
                }
            }
        }
        self.t_prev = t;
        self.switch_prev = sample.latch;

        // Latch states.
        let mut states = [LatchState::Stowed; N];
        let mut newly = [false; N];
        for j in 0..N {
            let out = self.lt[j].step(
                &LatchInput {
                    t_s: t,
                    switch: sample.latch[j],
                    measured_deg: raw[j].map(|z| z / DEG),
                    angle_deg: self.kf[j].angle() / DEG,
                    rate_deg_s: self.kf[j].rate() / DEG,
                    stowed_deg: self.stowed_deg[j],
                    encoder_stuck: stuck[j],
                },
                &self.latch_cfg,
            );
            states[j] = out.state;
            newly[j] = out.newly_latched;
            faults[j] = faults[j].union(out.faults);
        }
        let locked: [bool; N] =
            core::array::from_fn(|j| self.lt[j].is_latched() || self.lt[j].held_at_latch());
        if newly.iter().any(|n| *n) {
            self.apply_latch_impulse(&newly, &locked);
            self.blank_until = t + self.observer.settle_s;
        }

        // Model quantities: latched joints sit at 0.
        let phi_m: [f32; N] =
            core::array::from_fn(|j| if locked[j] { 0.0 } else { self.kf[j].angle() });
        let om_m: [f32; N] =
            core::array::from_fn(|j| if locked[j] { 0.0 } else { self.kf[j].rate() });
        let m = self.chain.mass_matrix(&phi_m);
        let zone = self.observer.snap_zone_deg * DEG;
        let in_zone = (0..N).any(|j| !locked[j] && libm::fabsf(phi_m[j]) < zone);
        if in_zone || gap {
            self.blank_until = t + self.observer.settle_s;
        }
        let quiet = t >= self.blank_until;

        // Friction learning, half a window back, on the centred fit of the
        // readings (no lag, little noise): only samples outside the snap
        // zones and the settling after a snap, latch or gap, with every
        // free joint measured (`smoother.rs`). The observers restart
        // whenever the run of fits breaks.
        self.fit.push(t, &meas, quiet && !gap && dt > 0.0, &locked);
        let centre = self.fit.centre(r_meas);
        match &centre {
            Some(c) => {
                let terms = momentum_terms(&self.chain, &c.phi, &c.rate);
                for j in 0..N {
                    if c.locked[j] {
                        continue;
                    }
                    if !self.fit_run {
                        self.fo[j].restart();
                    }
                    let mut p = 0.0f32;
                    for k in 0..N {
                        p += terms.mass[j][k] * c.rate[k];
                    }
                    let branch = Branch::select(c.phi[j], c.rate[j]);
                    self.fo[j].step(
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
                }
                self.fit_run = true;
            }
            None => self.fit_run = false,
        }
        // Articulated inertia 1/(M⁻¹)_jj over the free joints: the one-joint
        // energy balance counts all of the joint's kinetic energy, the share
        // the outer panels carry included, so it errs on the side of a latch
        // and its stall verdicts are safe ones.
        let free_inertia = articulated_inertias(&m, &locked);
        let inertia: [f32; N] =
            core::array::from_fn(|j| free_inertia[j].unwrap_or_else(|| m[j][j].max(1e-6)));

        // Health: nothing non-finite survives an update.
        for j in 0..N {
            if !self.kf[j].is_healthy() {
                let phi0 = meas[j].unwrap_or(self.stowed_deg[j] * DEG);
                self.kf[j] = RateFilter::new(phi0, sd, 1.0, 10.0);
                self.kf[j].set_jerk_psd(self.observer.jerk_psd);
                faults[j].insert(Fault::EstimatorReset);
            }
            if !self.fo[j].is_healthy() {
                self.fo[j].reset_parameters();
                faults[j].insert(Fault::EstimatorReset);
            }
        }

        // Margin and prediction: one joint per update, in turn.
        let jm = usize::from(self.next_margin) % N.max(1);
        self.next_margin = ((jm + 1) % N.max(1)) as u8;
        // Not inside a snap zone or the settling time after a snap, latch or
        // gap: the rates there are the rate filter's wide-open transient,
        // and the prediction made on entry stands.
        let settled = quiet && libm::fabsf(phi_m.get(jm).copied().unwrap_or(0.0)) >= zone;
        if let (Some(false), true) = (locked.get(jm), settled) {
            if let Some(slot) = self.margin.get_mut(jm) {
                *slot = Some(Self::joint_margin(
                    &self.chain,
                    inertia.get(jm).copied().unwrap_or(1.0),
                    quiet,
                    jm,
                    &self.kf,
                    &self.fo,
                    self.capture_rad.get(jm).copied().unwrap_or(0.0),
                    &self.margin_cfg,
                ));
            }
        }

        if self.margin_cfg.rollout.steps_per_slice > 0 {
            // A rollout starts from the centred fit (rates to a few tenths
            // of a degree per second, half a window back); from the rate
            // filter only when no fit has come for a while (a flaky
            // encoder), since its rates after a latch impact are off by
            // degrees per second (docs/monitor.md §6).
            let start = match &centre {
                Some(c) => Some((
                    c.t_s,
                    ChainState {
                        phi: c.phi,
                        phi_dot: c.rate,
                    },
                    c.locked,
                )),
                None if quiet && t - self.t_centre > CENTRE_WAIT_S => Some((
                    t,
                    ChainState {
                        phi: phi_m,
                        phi_dot: om_m,
                    },
                    locked,
                )),
                None => None,
            };
            if let Some(c) = &centre {
                self.t_centre = c.t_s;
            }
            // Handed to the next slices of `predict`.
            self.rollout_start = start;
        }

        // Status.
        for j in 0..N {
            let est = self.fo[j].estimate();
            let latched = self.lt[j].is_latched();
            let margin_pct = if latched {
                None
            } else {
                self.margin[j].map(|r| r.margin_pct)
            };
            let (prediction, confidence, time_to_latch) = self.prediction(j, t);
            if newly[j] {
                info!("joint {} latched at t = {} s", j + 1, t);
            }
            if !faults[j].is_empty() {
                debug!("joint {} faults {}", j + 1, faults[j].0);
            }
            self.status.joints[j] = JointStatus {
                phi_deg: finite(self.kf[j].angle() / DEG),
                rate_deg_s: finite(self.kf[j].rate() / DEG),
                coulomb_nm: finite(est.coulomb_nm),
                coulomb_sd_nm: finite(crate::real::sqrtf(est.coulomb_var.max(0.0))),
                viscous_nms: finite(est.viscous_nms),
                viscous_sd_nms: finite(crate::real::sqrtf(est.viscous_var.max(0.0))),
                friction_torque_nm: finite(self.fo[j].disturbance_nm()),
                latch: states[j],
                margin_pct: margin_pct.map(finite),
                prediction,
                confidence,
                time_to_latch_s: time_to_latch.filter(|v| v.is_finite()),
                faults: faults[j],
            };
        }
        self.status.t_s = t;
        self.status.samples = self.status.samples.saturating_add(1);
        self.status
    }

    /// The latch / stall prediction of joint `j` at time `t` [s] from the
    /// last finished rollouts and the energy balance: the prediction, its
    /// confidence and the time to the latch [s].
    fn prediction(&self, j: usize, t: f32) -> (Prediction, f32, Option<f32>) {
        let conf = self.margin_cfg.confidence;
        let latched = self.lt.get(j).is_some_and(|l| l.is_latched());
        // A latch after the deadline is a stall.
        let deadline = self.t_start + self.margin_cfg.deadline_s;
        let pick = |o: Option<([JointOutcome; N], f32)>| {
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
        let energy = self.margin.get(j).copied().flatten();
        let energy_stall = energy.is_some_and(|r| r.latch_probability <= 1.0 - conf);
        let rollouts = self.margin_cfg.rollout.steps_per_slice > 0;
        match nom {
            _ if latched => (Prediction::Latch, 1.0, None),
            // Not even the one-joint balance, which counts all the
            // kinetic energy in the joint, gets it to the latch.
            _ if energy_stall => (Prediction::Stall, conf, None),
            // Rollouts switched off: the one-joint balance alone.
            _ if !rollouts => match energy {
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

    /// One slice of the latch / stall prediction: advances the rollout in
    /// progress by up to `margin.rollout.steps_per_slice` steps, starts the
    /// next one when it ends (from the last settled state [`Monitor::update`]
    /// handed over), and refreshes the prediction in [`Monitor::status`].
    ///
    /// The sample-rate path ([`Monitor::update`]) never runs a rollout: the
    /// application calls this at a lower priority (the idle loop, a
    /// low-priority task), as often as it has time for. Its cost is bounded
    /// by the slice (`docs/performance.md`). Returns true when a rollout
    /// finished in this slice.
    #[inline(never)]
    pub fn predict(&mut self) -> bool {
        if self.margin_cfg.rollout.steps_per_slice == 0 || !self.started {
            return false;
        }
        let finished = self.advance_rollouts();
        if finished {
            let t = self.status.t_s;
            for j in 0..N {
                let (prediction, confidence, time_to_latch) = self.prediction(j, t);
                if let Some(js) = self.status.joints.get_mut(j) {
                    js.prediction = prediction;
                    js.confidence = confidence;
                    js.time_to_latch_s = time_to_latch.filter(|v| v.is_finite());
                }
            }
        }
        finished
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

    /// Advances the rollout in progress; when it ends, stores its outcome
    /// and starts the next bracket from [`Monitor::update`]'s last settled
    /// state — time [s], state and locked joints, `None` while no settled
    /// state is at hand (in a snap zone or the settling after a latch the
    /// rate filter is wide open) — with the current friction estimates.
    /// Returns true when a rollout finished.
    fn advance_rollouts(&mut self) -> bool {
        let mut cfg = self.margin_cfg.rollout;
        let mut finished = false;
        if let Some((r, bracket, t0)) = self.rollout.as_mut() {
            // Only the time left to the deadline matters.
            cfg.horizon_s = cfg
                .horizon_s
                .min(self.t_start + self.margin_cfg.deadline_s - *t0)
                .max(cfg.dt_s);
            r.advance(&self.chain, &cfg);
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
        // The prediction is refreshed most often; the brackets that give
        // its confidence take their turns in between (`CYCLE`).
        let pos = match self.rollout {
            None => 0,
            Some(_) => (usize::from(self.cycle_pos) + 1) % CYCLE.len(),
        };
        let next = CYCLE.get(pos).copied().unwrap_or_default();
        let Some((t, state, locked)) = self.rollout_start else {
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
            let e = self.fo[j].estimate();
            // More friction goes with weaker springs, and less with stronger.
            let sd_k = crate::real::sqrtf(e.spring_scale_var.max(0.0));
            spring[j] = (1.0 + e.spring_scale_err - sign * z * sd_k).max(0.0);
            let sd_c = crate::real::sqrtf(e.coulomb_var.max(0.0));
            let sd_f = crate::real::sqrtf(e.viscous_var.max(0.0));
            coulomb[j] = (e.coulomb_nm + sign * z * sd_c).max(0.0);
            viscous[j] = (e.viscous_nms + sign * z * sd_f).max(0.0);
            if next == Bracket::Optimistic && !locked[j] {
                // Friction is never below the torque it exerts now.
                let bound = self.fo[j].coulomb_lower_bound(self.kf[j].rate());
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
            capture_rad: self.capture_rad,
        };
        self.rollout = Some((Rollout::new(start), next, t));
        self.cycle_pos = pos as u8;
        finished
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
                self.kf[j].angle()
            }
        });
        let om: [f32; N] = core::array::from_fn(|j| {
            if locked_before[j] {
                0.0
            } else {
                self.kf[j].rate()
            }
        });
        let m = momentum_terms(&self.chain, &phi, &om).mass;
        let mut p = [0.0f32; N];
        for (pj, row) in p.iter_mut().zip(m.iter()) {
            *pj = row.iter().zip(om.iter()).map(|(a, b)| a * b).sum();
        }
        if let Ok(after) = solve_spd_masked(&m, &p, locked_after) {
            for j in 0..N {
                if newly[j] {
                    let a = self.kf[j].angle();
                    self.kf[j].pin(a);
                } else if !locked_after[j] && after[j].is_finite() {
                    self.kf[j].set_rate(after[j], RATE_SHOCK_VAR);
                    self.kf[j].inflate(0.0, ACC_SHOCK_VAR);
                }
            }
        }
    }

    /// Energy margin and one-joint latch probability of joint `j`, with
    /// `inertia` its articulated inertia `1/(M⁻¹)_jj` [kg·m²].
    #[allow(clippy::too_many_arguments)]
    fn joint_margin(
        chain: &Chain<f32, N>,
        inertia: f32,
        quiet: bool,
        j: usize,
        kf: &[RateFilter; N],
        fo: &[FrictionObserver; N],
        capture_rad: f32,
        cfg: &MarginConfig,
    ) -> MarginResult {
        let (Some(f), Some(o), Some(joint)) = (kf.get(j), fo.get(j), chain.joints().get(j)) else {
            return MarginResult {
                margin_pct: 0.0,
                latch_probability: 0.5,
                time_to_latch_s: None,
            };
        };
        let est = o.estimate();
        let phi = f.angle();
        let rate = f.rate();
        // The friction torque seen now bounds T_C from below, when the
        // observer runs undisturbed and the bound agrees with the estimate
        // (a bound beyond T̂_C + 2σ is a transient of r, not evidence).
        let bound = if quiet {
            o.coulomb_lower_bound(rate)
        } else {
            0.0
        };
        let bound = if bound <= est.coulomb_nm + 2.0 * crate::real::sqrtf(est.coulomb_var.max(0.0))
        {
            bound
        } else {
            0.0
        };
        margin::evaluate(
            &joint.spring,
            &MarginInput {
                angle_abs_rad: libm::fabsf(phi),
                rate_abs_rad_s: libm::fabsf(rate),
                towards_latch: phi * rate < 0.0,
                inertia_kgm2: inertia,
                rate_var: f.rate_var(),
                capture_rad,
                coulomb_nm: est.coulomb_nm,
                viscous_nms: est.viscous_nms,
                coulomb_var: est.coulomb_var,
                coulomb_lower_nm: bound,
                spring_scale: 1.0 + est.spring_scale_err,
                spring_sd_rel: crate::real::sqrtf(est.spring_scale_var.max(0.0)),
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

#[cfg(test)]
mod tests {
    use super::*;

    fn config() -> MonitorConfig<1> {
        MonitorConfig::new(
            [Panel {
                length_m: 0.8,
                mass_kg: 4.0,
                com_m: 0.4,
                inertia_kgm2: 0.3,
            }],
            [JointConfig {
                stowed_deg: 90.0,
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
            }],
        )
    }

    #[test]
    fn bad_time_stamps_are_flagged_and_resynchronised() {
        let mut m = Monitor::new(&config()).unwrap();
        m.update(&Sample::new(0.0, [90.0], [false]));
        m.update(&Sample::new(0.01, [90.0], [false]));
        let st = m.update(&Sample::new(f32::NAN, [90.0], [false]));
        assert!(st.joints[0].faults.contains(Fault::TimeInvalid));
        assert_eq!(st.samples, 2, "a sample with a bad time stamp is not used");
        // A clock that jumps ahead (a gap), then back to where it was: the
        // samples behind the jump are flagged and not used, until three in a
        // row are adopted as the new time base.
        let st = m.update(&Sample::new(5.0, [90.0], [false]));
        assert!(st.joints[0].faults.contains(Fault::TimeGap));
        assert_eq!(st.samples, 3);
        for (k, t) in [0.02f32, 0.03].iter().enumerate() {
            let st = m.update(&Sample::new(*t, [90.0], [false]));
            assert!(st.joints[0].faults.contains(Fault::TimeBackwards), "{k}");
            assert_eq!(st.samples, 3);
        }
        let st = m.update(&Sample::new(0.04, [90.0], [false]));
        assert!(st.joints[0].faults.contains(Fault::TimeBackwards));
        assert!(st.joints[0].faults.contains(Fault::TimeGap));
        assert_eq!(st.samples, 4, "adopted");
        let st = m.update(&Sample::new(0.05, [90.0], [false]));
        assert!(st.joints[0].faults.is_empty(), "{}", st.joints[0].faults);
    }

    #[test]
    fn missing_reading_is_flagged_and_estimates_stay_finite() {
        let mut m = Monitor::new(&config()).unwrap();
        m.update(&Sample::new(0.0, [90.0], [false]));
        let st = m.update(&Sample::new(0.01, [f32::NAN], [false]));
        assert!(st.joints[0].faults.contains(Fault::EncoderMissing));
        let st = m.update(&Sample::new(0.02, [1e30], [false]));
        assert!(st.joints[0].faults.contains(Fault::EncoderRange));
        assert!(st.joints[0].phi_deg.is_finite() && (st.joints[0].phi_deg - 90.0).abs() < 1.0);
    }

    #[test]
    fn config_errors_name_the_parameter() {
        let mut c = config();
        c.joints[0].prior.coulomb_sd_nm = f32::NAN;
        assert_eq!(
            Monitor::new(&c).err(),
            Some(ConfigError::Joint {
                index: 0,
                what: "coulomb prior sd"
            })
        );
        let mut c = config();
        c.margin.confidence = 1.5;
        assert_eq!(
            Monitor::new(&c).err(),
            Some(ConfigError::Parameter("confidence"))
        );
        let mut c = config();
        c.panels[0].mass_kg = 0.0;
        assert!(matches!(Monitor::new(&c), Err(ConfigError::Chain(_))));
    }

    #[test]
    fn prediction_names_round_trip() {
        for p in Prediction::ALL {
            assert_eq!(Prediction::from_name(p.as_str()), Some(p));
        }
    }
}
