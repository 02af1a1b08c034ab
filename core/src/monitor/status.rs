//! What the monitor takes and gives each sample: the [`Sample`] of the
//! sensors and the [`Status`] of every joint.

use crate::monitor::faults::FaultFlags;
use crate::monitor::latch::LatchState;
use crate::monitor::predictor::Prediction;
use serde::{Deserialize, Serialize};

/// One sample of the sensors.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sample<const N: usize> {
    /// Time stamp \[s\].
    pub t_s: f32,
    /// Encoder angle of each joint \[deg\]; NaN for a missing reading.
    #[serde(with = "crate::monitor::serde_array")]
    pub phi_deg: [f32; N],
    /// Latch switch of each joint (true = closed).
    #[serde(with = "crate::monitor::serde_array")]
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

/// Whether the measurements determine a parameter, or only its prior does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Observability {
    /// The prior still dominates, or the standard deviation is too wide
    /// for the value to mean anything: the reported value and deviation
    /// are the posterior's (an honest interval under an honest prior), and
    /// the prediction does not use the value (`docs/monitor.md` §3.2).
    #[default]
    Unobservable,
    /// The data determine it: the posterior variance is at most
    /// [`OBSERVED_PRIOR_SHARE`] of the prior's and the standard deviation
    /// at most [`VISCOUS_RESOLVED_SD`]; the prediction uses it.
    Estimated,
}

impl Observability {
    /// Every value.
    pub const ALL: [Observability; 2] = [Observability::Unobservable, Observability::Estimated];

    /// The name used in telemetry CSV and reports.
    pub const fn as_str(self) -> &'static str {
        match self {
            Observability::Unobservable => "unobservable",
            Observability::Estimated => "estimated",
        }
    }

    /// The value of a name written by [`Observability::as_str`].
    pub fn from_name(name: &str) -> Option<Self> {
        Observability::ALL
            .iter()
            .copied()
            .find(|p| p.as_str() == name)
    }

    /// The verdict on a parameter of posterior variance `var` and prior
    /// variance `prior_var`, resolved when its deviation is at most
    /// `resolved_sd`.
    pub fn of(var: f32, prior_var: f32, resolved_sd: f32) -> Self {
        if var <= OBSERVED_PRIOR_SHARE * prior_var && var <= resolved_sd * resolved_sd {
            Observability::Estimated
        } else {
            Observability::Unobservable
        }
    }
}

/// Whether the readings resolve a joint's motion at the sampling rate, or
/// it is shaken faster than the samples can follow (`docs/monitor.md`
/// §6.2, "What stays outside what the monitor can observe at 100 Hz").
/// Decided from the readings only (`resolution.rs`): the change of step
/// `z₀ − 2 z₁ + z₂` of three readings in a row of at least
/// [`UNRESOLVED_BEND_DEG`] in both signs within the last
/// [`RESOLUTION_READINGS`] readings makes the joint unresolved; it is
/// resolved again once they no longer reach [`RESOLVED_BEND_DEG`] both
/// ways. Followed on a wing with a physical latch only (on one of ideal
/// latches every joint is resolved).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Resolution {
    /// The readings follow the joint's motion: every reading check applies.
    #[default]
    Resolved,
    /// The joint is shaken (a rattling pawl or a bouncing plunger next to
    /// it) faster than the samples resolve: its readings cannot tell a
    /// spike from its motion, and the checks that would call a reading an
    /// outlier (`encoder_outlier`) are off for it.
    Unresolved,
}

impl Resolution {
    /// Every value.
    pub const ALL: [Resolution; 2] = [Resolution::Resolved, Resolution::Unresolved];

    /// The name used in telemetry CSV and reports.
    pub const fn as_str(self) -> &'static str {
        match self {
            Resolution::Resolved => "resolved",
            Resolution::Unresolved => "unresolved",
        }
    }

    /// The value of a name written by [`Resolution::as_str`].
    pub fn from_name(name: &str) -> Option<Self> {
        Resolution::ALL.iter().copied().find(|p| p.as_str() == name)
    }

    /// `Unresolved` when `unresolved`.
    pub const fn of(unresolved: bool) -> Self {
        if unresolved {
            Resolution::Unresolved
        } else {
            Resolution::Resolved
        }
    }
}

/// Change of step of three readings in a row from which on, in both signs
/// within [`RESOLUTION_READINGS`], a joint is unresolved \[deg\]: a change
/// of rate of 20°/s within one interval at 100 Hz, the returning-spike
/// check's departure (`plausibility.rs`, `DEPART_RAD`); 4 σ of the
/// reference encoder's change of step (σ √6 ≈ 0.05°).
pub const UNRESOLVED_BEND_DEG: f32 = 0.2;

/// Change of step an unresolved joint's readings must still reach both
/// ways within [`RESOLUTION_READINGS`] to stay unresolved \[deg\]
/// (hysteresis; 2 σ of the reference encoder's change of step: a quiet
/// joint is resolved again within a few samples).
pub const RESOLVED_BEND_DEG: f32 = 0.1;

/// Readings (changes of step) the resolution looks back over.
pub const RESOLUTION_READINGS: u32 = 5;

/// Largest share of the prior variance left once the data determine a
/// parameter \[1\]: the data then carry at least three times the prior's
/// information.
pub const OBSERVED_PRIOR_SHARE: f32 = 0.25;

/// Largest standard deviation of a viscous coefficient reported as
/// estimated [N·m·s/rad]: a damping of 0.2 N·m·s/rad is then resolved at
/// 2σ.
pub const VISCOUS_RESOLVED_SD: f32 = 0.1;

/// What the monitor knows about one joint.
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JointStatus {
    /// Estimated angle \[deg\].
    pub phi_deg: f32,
    /// Estimated rate [deg/s].
    pub rate_deg_s: f32,
    /// Estimated Coulomb friction torque `T_C` [N·m]; while `viscous` is
    /// [`Observability::Unobservable`], the one conditioned on `f` = its
    /// prior mean (the friction seen at the rates observed, what the
    /// prediction uses).
    pub coulomb_nm: f32,
    /// Standard deviation of `T_C` [N·m].
    pub coulomb_sd_nm: f32,
    /// Estimated viscous coefficient `f` [N·m·s/rad].
    pub viscous_nms: f32,
    /// Standard deviation of `f` [N·m·s/rad].
    pub viscous_sd_nms: f32,
    /// Whether the data determine `f` ([`Observability::Estimated`]) or
    /// not (`viscous_nms ± viscous_sd_nms` is then the posterior, wide,
    /// and the prediction leaves `f` out).
    pub viscous: Observability,
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
    /// Predicted time until the latch \[s\], from the nominal rollout; `None`
    /// for a stall, once latched, or before the first rollout.
    pub time_to_latch_s: Option<f32>,
    /// Faults raised at this sample.
    pub faults: FaultFlags,
    /// Whether the readings resolve the joint's motion at this sample
    /// ([`Resolution::Unresolved`]: shaken faster than the samples follow;
    /// the outlier checks are off for it, `docs/monitor.md` §6.2).
    pub resolution: Resolution,
}

/// The monitor's answer to one sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status<const N: usize> {
    /// Time stamp of the last sample used \[s\].
    pub t_s: f32,
    /// Samples used so far.
    pub samples: u32,
    /// Per joint.
    #[serde(with = "crate::monitor::serde_array")]
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
