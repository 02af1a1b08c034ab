//! The [`Monitor`]'s state, grouped by what holds it, and its
//! construction: in place ([`Monitor::reset`]) so that a monitor in static
//! memory is configured without a second one on the stack.

use super::clock::Timeline;
use super::joint::{JointStart, JointState, DEG};
use super::learning::{Learner, LearningQueue};
use crate::monitor::config::{
    ConfigError, ConfigRef, JointConfig, MarginConfig, MonitorConfig, ObserverConfig, SensorConfig,
};
use crate::monitor::latch_margin::Engagement;
use crate::monitor::observer::FrictionPrior;
use crate::monitor::predictor::Predictor;
use crate::monitor::status::Status;
use crate::physics::chain::{Chain, ChainState, GlobalEffects, Joint, JointEffects, Mode, Panel};
use crate::physics::friction::Friction;
use crate::physics::spring::Branch;

/// The on-board monitor of an `N`-joint deployment.
#[derive(Clone, Debug)]
pub struct Monitor<const N: usize> {
    /// The chain model (f32), with the configured panels and springs.
    pub(super) chain: Chain<f32, N>,
    /// The configuration's tuning.
    pub(super) tuning: Tuning,
    /// Everything the monitor tracks about each joint.
    pub(super) joints: [JointState; N],
    /// The time line of the samples used.
    pub(super) timeline: Timeline,
    /// The windows that events open on the time line.
    pub(super) windows: Windows,
    /// Samples [`Monitor::update`] queued for the friction learning, which
    /// [`Monitor::learn_or_predict`] takes oldest first.
    pub(super) queue: LearningQueue<N>,
    /// What the slow path's learning keeps between samples.
    pub(super) learner: Learner<N>,
    /// The latch / stall prediction (the rollout cycle), advanced by
    /// [`Monitor::learn_or_predict`].
    pub(super) predictor: Predictor<N>,
    /// The status after the last sample.
    pub(super) status: Status<N>,
}

/// The configuration's tuning, as the monitor uses it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Tuning {
    /// Variance of one encoder reading \[rad²\] (noise and quantisation).
    pub(super) meas_var: f32,
    /// Its square root \[rad\].
    pub(super) meas_sd: f32,
    pub(super) sensor: SensorConfig,
    pub(super) observer: ObserverConfig,
    pub(super) margin: MarginConfig,
    /// A joint has a physical latch: the joints' resolution is followed
    /// (`resolution.rs`; on a wing of ideal latches every joint is
    /// resolved).
    pub(super) follow_resolution: bool,
}

/// The windows that events open on the time line \[s\].
#[derive(Clone, Copy, Debug)]
pub(super) struct Windows {
    /// End of the settling after a snap, latch or gap \[s\]: the friction
    /// learning and the margin wait until then.
    pub(super) blank_until: f32,
    /// End of the window after a switch closed in which a reading the rate
    /// filter rejects is the impact, not an outlier \[s\].
    pub(super) impact_until: f32,
    /// Samples left whose prediction is widened for the impact.
    pub(super) impact_samples: u8,
    /// The joints that announced an impact at the previous sample, bit `j`
    /// for joint `j` ([`Monitor::impact_announced`]).
    pub(super) impacts_prev: u32,
}

impl Windows {
    /// No window open.
    const CLOSED: Windows = Windows {
        blank_until: f32::NEG_INFINITY,
        impact_until: f32::NEG_INFINITY,
        impact_samples: 0,
        impacts_prev: 0,
    };
}

/// Sets `tuning` to the tuning of `config` and each joint state to its
/// joint of `config` (as many as `states` holds), waiting for the first
/// sample: [`Monitor::reset`]'s part that does not depend on the joint
/// count, one copy for every joint count.
#[inline(never)]
fn reset_tuning_and_joints(tuning: &mut Tuning, states: &mut [JointState], config: ConfigRef<'_>) {
    let meas_var = meas_var(config.sensor);
    *tuning = Tuning {
        meas_var,
        meas_sd: crate::physics::real::sqrtf(meas_var),
        sensor: *config.sensor,
        observer: *config.observer,
        margin: *config.margin,
        follow_resolution: config.latch.physical.is_some()
            || config.joints.iter().any(|j| j.physical.is_some()),
    };
    let sd = config.sensor.encoder_sd_deg * DEG;
    for (state, c) in states.iter_mut().zip(config.joints) {
        state.reset(
            &JointStart::of(c),
            sd,
            config.observer,
            config.latch,
            config.margin.spring_sd_rel,
        );
    }
}

/// Measurement variance of one encoder reading \[rad²\]: noise and
/// quantisation, `σ² + Δ²/12`.
fn meas_var(sensor: &SensorConfig) -> f32 {
    let sd = sensor.encoder_sd_deg * DEG;
    let q = sensor.encoder_step_deg * DEG;
    sd * sd + q * q / 12.0
}

impl<const N: usize> Monitor<N> {
    /// A monitor for the configured mechanism, waiting for its first sample
    /// ([`Monitor::reset`] on a vacant monitor: one definition of the
    /// initial state).
    pub fn new(config: &MonitorConfig<N>) -> Result<Self, ConfigError> {
        let mut m = Self::vacant(ConfigRef::of(config));
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
    pub(crate) fn vacant(config: ConfigRef<'_>) -> Self {
        // A placeholder joint (at the latch, any valid prior; an encoder σ
        // of 1 rad, no spring spread): `reset` replaces it.
        let joint = JointStart {
            stowed_deg: 0.0,
            capture_deg: 0.0,
            prior: FrictionPrior {
                coulomb_nm: 0.0,
                coulomb_sd_nm: 1.0,
                viscous_nms: 0.0,
                viscous_sd_nms: 1.0,
            },
            engagement: Engagement::IDEAL,
            physical: None,
        };
        let state = JointState::new(&joint, 1.0, config.observer, config.latch, 0.0);
        // The large parts last: each is written in place only if nothing
        // is built after it (LLVM's call-slot forwarding).
        Monitor {
            tuning: Tuning {
                meas_var: 0.0,
                meas_sd: 0.0,
                sensor: *config.sensor,
                observer: *config.observer,
                margin: *config.margin,
                follow_resolution: false,
            },
            timeline: Timeline::START,
            windows: Windows::CLOSED,
            queue: LearningQueue::new(),
            status: Status::default(),
            learner: Learner::new(),
            predictor: Predictor::new(MarginConfig::default().confidence),
            joints: [state; N],
            chain: Chain::vacant(),
        }
    }

    /// Makes this monitor the one for `config`, waiting for its first
    /// sample, in place: it validates `config` and writes every field where
    /// it is, so that a monitor in static memory is (re)configured without
    /// a second monitor, or a `Result` of one, on the stack (the firmware's
    /// start-up, `telemetry::replay`). On an error the monitor is unchanged.
    pub fn reset(&mut self, config: &MonitorConfig<N>) -> Result<(), ConfigError> {
        self.reset_from(ConfigRef::of(config))
    }

    /// [`Monitor::reset`] on a configuration borrowed as slices (the
    /// replay's, of a joint count known at run time):
    /// [`ConfigError::JointCount`] unless it has `N` panels and `N`
    /// joints.
    #[inline(never)]
    pub(crate) fn reset_from(&mut self, config: ConfigRef<'_>) -> Result<(), ConfigError> {
        let (Ok(panels), true) = (
            <&[Panel<f32>; N]>::try_from(config.panels),
            config.joints.len() == N,
        ) else {
            return Err(ConfigError::JointCount {
                expected: N,
                found: config.panels.len().max(config.joints.len()),
            });
        };
        config.validate()?;
        // Every field by name: a field added to `Monitor` must be set here.
        let Monitor {
            chain,
            tuning,
            joints,
            timeline,
            windows,
            queue,
            learner,
            predictor,
            status,
        } = self;
        // The only check that can fail after `validate`: before any write.
        configure_chain(chain, panels, config.joints)?;
        reset_tuning_and_joints(tuning, joints, config);
        release_accelerations(chain, joints);
        *timeline = Timeline::START;
        *windows = Windows::CLOSED;
        queue.clear();
        learner.reset();
        *predictor = Predictor::new(config.margin.confidence);
        *status = Status::default();
        Ok(())
    }

    /// The status after the last sample.
    pub fn status(&self) -> &Status<N> {
        &self.status
    }

    /// Slices of [`Monitor::learn_or_predict`] a replay runs after each sample
    /// (`margin.rollout.slices_per_sample`).
    pub fn config_slices_per_sample(&self) -> u8 {
        self.tuning.margin.rollout.slices_per_sample
    }

    /// Full latch / stall predictions completed so far: cycles of the
    /// nominal rollout and the brackets its verdicts need, each of which
    /// refreshed the prediction in [`Monitor::status`]. How often that
    /// happens is the prediction's refresh rate (`tests/monitor/refresh.rs`).
    pub fn prediction_refreshes(&self) -> u32 {
        self.predictor.refreshes()
    }

    /// Samples dropped so far because the learning queue was full (the
    /// slow path, [`Monitor::learn_or_predict`], fell behind by more than
    /// [`crate::monitor::LEARNING_QUEUE`] samples). 0 on the
    /// replay schedule.
    pub fn learning_overruns(&self) -> u32 {
        self.learner.overruns
    }
}

/// Seeds each joint's rate filter with the acceleration the springs give
/// the chain at release (`docs/monitor.md` §2): at its stowed angles, at
/// rest, on the unfolding branch, with no friction, `φ̈ = M⁻¹ τ`
/// (`physics.md` §2, [`Chain::acceleration`]) \[rad/s²\]. The first sample
/// starts the filter from it ([`super::joint::JointState::start_filter`]): a
/// light outer panel on a tape spring reaches hundreds of rad/s² at release
/// and covers degrees in the first sample interval, which a filter started
/// at rest took for a spike. Left at 0 when the chain cannot be solved.
/// Configuration time, not the sample path.
fn release_accelerations<const N: usize>(chain: &Chain<f32, N>, joints: &mut [JointState; N]) {
    let start = ChainState {
        phi: core::array::from_fn(|j| joints[j].stowed_deg * DEG),
        phi_dot: [0.0; N],
    };
    let mode = Mode {
        latched: [false; N],
        branch: [Branch::Unfold; N],
    };
    if let Ok(acc) = chain.acceleration(&start, &mode) {
        for (js, a) in joints.iter_mut().zip(acc) {
            if a.is_finite() {
                js.kf.set_acceleration(a);
            }
        }
    }
}

impl<const N: usize> MonitorConfig<N> {
    /// The chain model a [`Monitor`] of this configuration runs on (`f32`):
    /// the panels, and each joint's stowed angle and spring, with no
    /// friction and no effects (the monitor learns the friction). The same
    /// model [`Monitor::new`] builds; [`ConfigError::Chain`] when the
    /// panels do not make a chain.
    pub fn chain(&self) -> Result<Chain<f32, N>, ConfigError> {
        let joints = core::array::from_fn(|j| {
            let mut joint = Joint {
                stowed_rad: 0.0,
                spring: self.joints[j].spring,
                friction: Friction::default(),
                effects: JointEffects::default(),
            };
            configure_joint(&mut joint, &self.joints[j]);
            joint
        });
        Chain::new(self.panels, joints, GlobalEffects::default()).map_err(ConfigError::Chain)
    }
}

/// Sets `chain` to `panels` and `joints`, with no effects (no tilt,
/// drag, harness or softening) and no friction: the monitor estimates the
/// friction itself.
fn configure_chain<const N: usize>(
    chain: &mut Chain<f32, N>,
    panels: &[Panel<f32>; N],
    joints: &[JointConfig],
) -> Result<(), ConfigError> {
    chain.set_panels(panels).map_err(ConfigError::Chain)?;
    *chain.global_mut() = GlobalEffects::default();
    for (j, c) in joints.iter().enumerate() {
        if let Some(joint) = chain.joint_mut(j) {
            configure_joint(joint, c);
        }
    }
    Ok(())
}

/// Sets the chain's `joint` to `config`'s stowed angle and spring, with no
/// effects and no friction. Out of line: one copy for every joint count.
#[inline(never)]
fn configure_joint(joint: &mut Joint<f32>, config: &JointConfig) {
    joint.stowed_rad = config.stowed_deg * DEG;
    joint.spring = config.spring;
    joint.friction = Friction::default();
    joint.effects = JointEffects::default();
}
