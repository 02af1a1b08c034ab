//! The monitor's configuration: the chain, the sensors, the friction
//! priors, the margin's factors and the prediction's settings, and their
//! checks.

use crate::monitor::latch::{LatchConfig, PhysicalLatch};
use crate::monitor::latch_margin::Engagement;
use crate::monitor::margin::UncertaintyFactors;
use crate::monitor::observer::{FrictionPrior, ObserverTuning};
use crate::monitor::rate_filter::JerkAdaptation;
use crate::monitor::rollout::RolloutConfig;
use crate::physics::chain::{ChainError, Panel};
use crate::physics::spring::Spring;

/// Largest encoder reading accepted \[deg\]; beyond it a reading is a fault.
pub const ENCODER_RANGE_DEG: f32 = 720.0;

/// One joint of the monitored mechanism.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointConfig {
    /// Stowed angle \[deg\]; the latch angle is 0.
    pub stowed_deg: f32,
    /// The hinge spring (all hinges of the joint), as in the mechanism.
    pub spring: Spring<f32>,
    /// Capture angle `x_c` \[deg\]: below it the spring completes the latch
    /// whatever the friction (a tape spring's θ_B; 0 for a linear spring).
    pub capture_deg: f32,
    /// Prior of the friction parameters.
    pub prior: FrictionPrior,
    /// The physical latch's engagement the margin counts
    /// ([`Engagement::IDEAL`] for the ideal latch of `physics.md` §5).
    pub latch: Engagement,
    /// The joint's physical latch as the latch tracker sees it (stop,
    /// plunger or pawl, ramp); `None`: the wing-wide
    /// [`LatchConfig::physical`],
    /// and with none there the ideal latch. A wing with mixed latches gives
    /// each joint its own (`docs/monitor.md` §4.1).
    pub physical: Option<PhysicalLatch>,
}

/// The encoder.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorConfig {
    /// White noise before quantisation, σ \[deg\].
    pub encoder_sd_deg: f32,
    /// Quantisation step \[deg\] (360/16384 for 14 bits).
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
            encoder_step_deg: crate::monitor::encoder::STEP_DEG as f32,
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
    /// `|φ|` below which a free joint is in its snap zone \[deg\]: the spring
    /// torque is too steep there for the model, so friction learning pauses.
    pub snap_zone_deg: f32,
    /// Innovation gate of the encoder \[σ\].
    pub gate_sigma: f32,
    /// Disturbance observer and RLS.
    pub tuning: ObserverTuning,
    /// Pause of the friction learning after a snap, latch or gap \[s\].
    pub settle_s: f32,
    /// Time step above which the samples around it are a gap \[s\].
    pub max_gap_s: f32,
    /// Smallest time step accepted \[s\].
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
                coulomb_threshold_rad_s: crate::physics::friction::COULOMB_THRESHOLD_RAD_S as f32,
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
    /// The deployment's deadline, from the first sample \[s\]: a joint that
    /// latches later counts as stalled (the mechanism file's `duration_s`).
    pub deadline_s: f32,
    /// Relative standard deviation of the spring torques \[1\]: how far the
    /// hinges may be from their curves. The prior spread of the friction
    /// observer's spring-scale estimate `κ` (`docs/monitor.md` §3.2).
    pub spring_sd_rel: f32,
    /// Floor of the energy standard deviation \[J\].
    pub energy_sd_floor_j: f32,
}

impl Default for MarginConfig {
    fn default() -> Self {
        MarginConfig {
            factors: UncertaintyFactors::UNITY,
            confidence: 0.9,
            rollout: RolloutConfig {
                dt_s: 0.02,
                bracket_dt_s: 0.03,
                glide_dt_s: 0.5,
                steps_per_slice: 1,
                slices_per_sample: 17,
                horizon_s: 10.0,
                coulomb_threshold_rad_s: crate::physics::friction::COULOMB_THRESHOLD_RAD_S as f32,
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

/// Why a configuration was rejected: matchable, every parameter a variant.
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
        what: JointParam,
    },
    /// A tuning parameter is out of range.
    Parameter(TuningParam),
    /// The configuration has `found` joints where the monitor has
    /// `expected` (the joint count is the monitor's type, `Monitor<N>`).
    JointCount {
        /// The monitor's joint count `N`.
        expected: usize,
        /// The configuration's.
        found: usize,
    },
}

/// A parameter of one joint ([`JointConfig`]), as [`ConfigError::Joint`]
/// names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum JointParam {
    /// [`JointConfig::stowed_deg`].
    StowedDeg,
    /// [`JointConfig::capture_deg`].
    CaptureDeg,
    /// The Coulomb prior's mean.
    CoulombPrior,
    /// The Coulomb prior's standard deviation.
    CoulombPriorSd,
    /// The viscous prior's mean.
    ViscousPrior,
    /// The viscous prior's standard deviation.
    ViscousPriorSd,
    /// [`JointConfig::latch`], the latch's engagement.
    LatchEngagement,
    /// [`JointConfig::physical`], the joint's physical latch.
    PhysicalLatch,
}

impl JointParam {
    /// The parameter's name.
    pub const fn name(self) -> &'static str {
        match self {
            JointParam::StowedDeg => "stowed_deg",
            JointParam::CaptureDeg => "capture_deg",
            JointParam::CoulombPrior => "coulomb prior",
            JointParam::CoulombPriorSd => "coulomb prior sd",
            JointParam::ViscousPrior => "viscous prior",
            JointParam::ViscousPriorSd => "viscous prior sd",
            JointParam::LatchEngagement => "latch engagement",
            JointParam::PhysicalLatch => "physical latch",
        }
    }
}

/// A tuning parameter of [`MonitorConfig`], as [`ConfigError::Parameter`]
/// names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum TuningParam {
    /// `SensorConfig::encoder_sd_deg`.
    EncoderSdDeg,
    /// `SensorConfig::encoder_step_deg`.
    EncoderStepDeg,
    /// `ObserverConfig::jerk_psd`.
    JerkPsd,
    /// `ObserverConfig::jerk_adaptation`.
    JerkAdaptation,
    /// `ObserverConfig::zone_jerk_psd`.
    ZoneJerkPsd,
    /// `ObserverConfig::snap_zone_deg`.
    SnapZoneDeg,
    /// `ObserverConfig::gate_sigma`.
    GateSigma,
    /// The friction observer's bandwidth.
    BandwidthPerS,
    /// The friction observer's Coulomb threshold.
    CoulombThreshold,
    /// The friction observer's random walks.
    FrictionWalk,
    /// The friction observer's residual variance floor.
    ResidualVarFloor,
    /// `ObserverConfig::settle_s`.
    SettleS,
    /// `ObserverConfig::min_dt_s` and `max_gap_s`.
    TimeStepLimits,
    /// `MarginConfig::factors`.
    UncertaintyFactors,
    /// `MarginConfig::confidence`.
    Confidence,
    /// `MarginConfig::rollout`.
    Rollout,
    /// `MarginConfig::deadline_s`.
    DeadlineS,
    /// `MarginConfig::spring_sd_rel` and `energy_sd_floor_j`.
    MarginSpread,
    /// `LatchConfig`'s thresholds.
    LatchThresholds,
}

impl TuningParam {
    /// The parameter's name.
    pub const fn name(self) -> &'static str {
        match self {
            TuningParam::EncoderSdDeg => "encoder_sd_deg",
            TuningParam::EncoderStepDeg => "encoder_step_deg",
            TuningParam::JerkPsd => "jerk_psd",
            TuningParam::JerkAdaptation => "jerk_adaptation",
            TuningParam::ZoneJerkPsd => "zone_jerk_psd",
            TuningParam::SnapZoneDeg => "snap_zone_deg",
            TuningParam::GateSigma => "gate_sigma",
            TuningParam::BandwidthPerS => "bandwidth_per_s",
            TuningParam::CoulombThreshold => "coulomb_threshold_rad_s",
            TuningParam::FrictionWalk => "friction walk",
            TuningParam::ResidualVarFloor => "residual_var_floor",
            TuningParam::SettleS => "settle_s",
            TuningParam::TimeStepLimits => "time step limits",
            TuningParam::UncertaintyFactors => "uncertainty factors",
            TuningParam::Confidence => "confidence",
            TuningParam::Rollout => "rollout",
            TuningParam::DeadlineS => "deadline_s",
            TuningParam::MarginSpread => "margin spread",
            TuningParam::LatchThresholds => "latch thresholds",
        }
    }
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ConfigError::Chain(e) => write!(f, "monitor mechanism: {e}"),
            ConfigError::Joint { index, what } => {
                write!(
                    f,
                    "monitor joint {}: {} must be a finite number in range",
                    index + 1,
                    what.name()
                )
            }
            ConfigError::Parameter(what) => {
                write!(f, "monitor tuning: {} is out of range", what.name())
            }
            ConfigError::JointCount { expected, found } => write!(
                f,
                "monitor of {expected} joints given a configuration of {found}"
            ),
        }
    }
}

impl core::error::Error for ConfigError {}

// The checks run once, at configuration: out of line, they take a call
// each instead of their comparisons (flash is short).
#[inline(never)]
fn positive(v: f32) -> bool {
    v.is_finite() && v > 0.0
}

#[inline(never)]
fn non_negative(v: f32) -> bool {
    v.is_finite() && v >= 0.0
}

/// `Err(what)` unless `ok`: one check, in a sequence that stops at the
/// first that fails.
fn require<P>(ok: bool, what: P) -> Result<(), P> {
    if ok {
        Ok(())
    } else {
        Err(what)
    }
}

impl JointConfig {
    /// Checks the joint's parameters; `Err` names the first one out of
    /// range.
    fn check(&self) -> Result<(), JointParam> {
        require(
            self.stowed_deg.is_finite() && libm::fabsf(self.stowed_deg) <= ENCODER_RANGE_DEG,
            JointParam::StowedDeg,
        )?;
        require(non_negative(self.capture_deg), JointParam::CaptureDeg)?;
        require(self.prior.coulomb_nm.is_finite(), JointParam::CoulombPrior)?;
        require(
            positive(self.prior.coulomb_sd_nm),
            JointParam::CoulombPriorSd,
        )?;
        require(self.prior.viscous_nms.is_finite(), JointParam::ViscousPrior)?;
        require(
            positive(self.prior.viscous_sd_nms),
            JointParam::ViscousPriorSd,
        )?;
        require(self.latch.is_valid(), JointParam::LatchEngagement)?;
        require(
            self.physical.is_none_or(|p| p.is_valid()),
            JointParam::PhysicalLatch,
        )?;
        Ok(())
    }
}

impl SensorConfig {
    /// Checks the encoder's parameters; `Err` names the first one out of
    /// range.
    fn check(&self) -> Result<(), TuningParam> {
        require(positive(self.encoder_sd_deg), TuningParam::EncoderSdDeg)?;
        require(
            non_negative(self.encoder_step_deg),
            TuningParam::EncoderStepDeg,
        )?;
        Ok(())
    }
}

/// True when the jerk adaptation's bounds are ordered and its weight is in
/// (0, 1].
fn jerk_adaptation_ok(a: &JerkAdaptation) -> bool {
    positive(a.q_min)
        && a.q_max >= a.q_min
        && a.q_max.is_finite()
        && positive(a.low)
        && a.high > a.low
        && a.high.is_finite()
        && a.weight > 0.0
        && a.weight <= 1.0
}

impl ObserverConfig {
    /// Checks the rate filter's and the friction observer's tuning; `Err`
    /// names the first parameter out of range.
    fn check(&self) -> Result<(), TuningParam> {
        let t = &self.tuning;
        require(positive(self.jerk_psd), TuningParam::JerkPsd)?;
        require(
            jerk_adaptation_ok(&self.jerk_adaptation),
            TuningParam::JerkAdaptation,
        )?;
        require(positive(self.zone_jerk_psd), TuningParam::ZoneJerkPsd)?;
        require(non_negative(self.snap_zone_deg), TuningParam::SnapZoneDeg)?;
        require(positive(self.gate_sigma), TuningParam::GateSigma)?;
        require(positive(t.bandwidth_per_s), TuningParam::BandwidthPerS)?;
        require(
            positive(t.coulomb_threshold_rad_s),
            TuningParam::CoulombThreshold,
        )?;
        require(
            non_negative(t.coulomb_walk) && non_negative(t.viscous_walk),
            TuningParam::FrictionWalk,
        )?;
        require(
            positive(t.residual_var_floor),
            TuningParam::ResidualVarFloor,
        )?;
        require(non_negative(self.settle_s), TuningParam::SettleS)?;
        require(
            positive(self.min_dt_s) && positive(self.max_gap_s) && self.max_gap_s > self.min_dt_s,
            TuningParam::TimeStepLimits,
        )?;
        Ok(())
    }
}

impl MarginConfig {
    /// Checks the margin's and the prediction's settings; `Err` names the
    /// first one out of range.
    fn check(&self) -> Result<(), TuningParam> {
        let r = &self.rollout;
        require(self.factors.is_valid(), TuningParam::UncertaintyFactors)?;
        require(
            self.confidence > 0.5 && self.confidence < 1.0,
            TuningParam::Confidence,
        )?;
        require(
            positive(r.dt_s)
                && positive(r.bracket_dt_s)
                && positive(r.glide_dt_s)
                && positive(r.horizon_s)
                && positive(r.coulomb_threshold_rad_s),
            TuningParam::Rollout,
        )?;
        require(positive(self.deadline_s), TuningParam::DeadlineS)?;
        require(
            non_negative(self.spring_sd_rel) && positive(self.energy_sd_floor_j),
            TuningParam::MarginSpread,
        )?;
        Ok(())
    }
}

impl<const N: usize> MonitorConfig<N> {
    /// Checks every parameter: the joints in order, then the sensor, the
    /// observer, the margin and the latch thresholds; the error names the
    /// first one out of range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        ConfigRef::of(self).validate()
    }
}

/// A [`MonitorConfig`] of any joint count, borrowed, its panels and
/// joints as slices: what the configuration's checks and the monitor's
/// construction read, in code compiled once for every joint count (the
/// firmware's flash holds the monitors of 2 and 3 joints).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ConfigRef<'a> {
    /// Panels, bus outwards.
    pub(crate) panels: &'a [Panel<f32>],
    /// Joints, as many as panels.
    pub(crate) joints: &'a [JointConfig],
    /// The encoder.
    pub(crate) sensor: &'a SensorConfig,
    /// Rate filter and friction observer.
    pub(crate) observer: &'a ObserverConfig,
    /// Latch-state estimator.
    pub(crate) latch: &'a LatchConfig,
    /// Margin and prediction.
    pub(crate) margin: &'a MarginConfig,
}

impl<'a> ConfigRef<'a> {
    /// All of `config`.
    pub(crate) fn of<const N: usize>(config: &'a MonitorConfig<N>) -> Self {
        ConfigRef {
            panels: &config.panels,
            joints: &config.joints,
            sensor: &config.sensor,
            observer: &config.observer,
            latch: &config.latch,
            margin: &config.margin,
        }
    }

    /// [`MonitorConfig::validate`]: one copy for every joint count (the
    /// checks are large enough that a copy per joint count would not fit
    /// the firmware's flash budget).
    #[inline(never)]
    pub(crate) fn validate(&self) -> Result<(), ConfigError> {
        for (index, j) in self.joints.iter().enumerate() {
            j.check()
                .map_err(|what| ConfigError::Joint { index, what })?;
        }
        self.sensor
            .check()
            .and_then(|()| self.observer.check())
            .and_then(|()| self.margin.check())
            .map_err(ConfigError::Parameter)?;
        if !self.latch.is_valid() {
            return Err(ConfigError::Parameter(TuningParam::LatchThresholds));
        }
        Ok(())
    }
}
