//! What a simulation is asked and what it gives, for the chain
//! ([`crate::simulate::deployment`]) and the truss wing
//! ([`crate::simulate::truss_deployment`]) alike: the settings, the
//! sample times, the trajectory, the counters and the errors.

use crate::simulate::stowed::PastStowed;

/// Integration and output settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimOptions {
    /// Relative tolerance of the error control.
    pub rtol: f64,
    /// Absolute tolerance [rad, rad/s].
    pub atol: f64,
    /// Largest step \[s\].
    pub max_step_s: f64,
    /// Simulated time limit \[s\]; the mechanism's `duration_s` when `None`.
    pub duration_s: Option<f64>,
    /// Output rate \[Hz\]; the mechanism's `sample_hz` when `None`.
    pub sample_hz: Option<f64>,
    /// Latch joints at `φ = 0` (the reference). When false, joints swing
    /// through and the simulation runs the whole duration (energy checks).
    pub latching: bool,
    /// End `settle_s` after the first sample at or after the last latch
    /// (formats.md); when false, hold the deployed state to the last sample.
    pub stop_when_deployed: bool,
    /// Recording after the last latch \[s\]; the mechanism's `settle_s` when
    /// `None` (0: end at the first sample at or after the last latch, as
    /// the golden files do).
    pub settle_s: Option<f64>,
    /// The energy ledger's tolerance (`docs/simulator.md`, "Energy ledger
    /// self-check"): the largest drift of the run from the energy stored at
    /// the start, relative to it \[1\]; beyond it the run stops with
    /// [`SimError::EnergyDrift`], and a step whose drift moves by more than
    /// its share of it is taken again shorter. [`MAX_LEDGER_DRIFT`] by
    /// default; a run asked for less accuracy (a reliability verdict) holds
    /// a looser one. `f64::INFINITY` books the ledger but never stops the
    /// run nor retakes a step (the diagnosis's fits,
    /// [`crate::analysis::campaign_sim::fit_sim_options`]).
    pub max_drift: f64,
    /// What a joint that stalls does ([`Stall`]): creep on at the
    /// regularised law's speed (the contract's trajectories, by default),
    /// or stick (a verdict's deployments).
    pub stall: Stall,
}

/// What a joint that stalls with friction holding it does
/// (`docs/spec/physics.md` §4a, "Creep").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Stall {
    /// It creeps on at the speed of the Coulomb law's regularisation
    /// (`T_C tanh(φ̇/ω_coul)`, the contract's law of §4): the trajectories
    /// of `simulate`, `identify` and `diagnose`, as the reference engine
    /// computes them.
    #[default]
    Creep,
    /// It sticks ([`crate::simulate::creep`]): the deployments of a
    /// verdict (`reliability`, `margin`'s nominal deployment), whose
    /// answer must not depend on how long the run is.
    Hold,
}

/// Default relative tolerance of the DOPRI5 error norm ([`SimOptions::rtol`]):
/// the golden trajectories (`tests/golden.rs`, `docs/simulator.md`) hold
/// their bounds with it.
pub const DEFAULT_RTOL: f64 = 1e-8;

/// Default absolute tolerance of the DOPRI5 error norm [rad, rad/s]
/// ([`SimOptions::atol`]): 10⁻¹⁰ rad is far below any sensor's resolution
/// (an AS5047P count is 3.8·10⁻⁴ rad).
pub const DEFAULT_ATOL: f64 = 1e-10;

/// Default longest step \[s\] ([`SimOptions::max_step_s`]): an event is found
/// by a sign change of its function over a step, and a step much shorter
/// than a deployment's swings (seconds) cannot hide a crossing and its
/// return.
pub const DEFAULT_MAX_STEP_S: f64 = 0.05;

/// Slack on a sample time when deciding whether it is at or before a time
/// of the run \[s\]: far below the µs resolution of `t_s` in a run CSV, far
/// above the rounding of sums of seconds.
pub const SAMPLE_TIME_SLACK_S: f64 = 1e-9;

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            rtol: DEFAULT_RTOL,
            atol: DEFAULT_ATOL,
            max_step_s: DEFAULT_MAX_STEP_S,
            duration_s: None,
            sample_hz: None,
            latching: true,
            stop_when_deployed: true,
            settle_s: None,
            max_drift: MAX_LEDGER_DRIFT,
            stall: Stall::Creep,
        }
    }
}

/// Counters of one simulation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SimStats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Evaluations of the equations of motion.
    pub evaluations: usize,
    /// Latch and branch events.
    pub events: usize,
    /// Steps ended on a knot of a spring's curve (the ideal-latch chain's,
    /// `simulate/spring_knots.rs`); not events.
    pub knots: usize,
}

impl SimStats {
    /// An accepted step taken back because the energy ledger moved too
    /// much over it (`docs/simulator.md`, "Energy ledger self-check"):
    /// counted as rejected; the step \[s\] to try next, a quarter of
    /// `taken` ([`crate::simulate::ode::FAILED_STEP_SHRINK`]).
    pub fn retake(&mut self, taken: f64) -> f64 {
        self.steps -= 1;
        self.rejected += 1;
        taken * crate::simulate::ode::FAILED_STEP_SHRINK
    }
}

/// A simulated deployment, sampled at the output rate.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trajectory {
    /// Sample times \[s\].
    pub t_s: Vec<f64>,
    /// `phi_deg[j][i]`: joint j+1 at sample i \[deg\] (true angle, no sensor).
    pub phi_deg: Vec<Vec<f64>>,
    /// `rate_deg_s[j][i]`: joint j+1's rate [deg/s].
    pub rate_deg_s: Vec<Vec<f64>>,
    /// `latched[j][i]`: joint j+1 latched at sample i.
    pub latched: Vec<Vec<bool>>,
    /// Latch instant of each joint \[s\], `None` if it never latched.
    pub latch_s: Vec<Option<f64>>,
    /// Where the simulation stopped \[s\].
    pub end_s: f64,
    /// Work done.
    pub stats: SimStats,
    /// The joints that swung back past their stowed angle by more than
    /// [`crate::simulate::stowed::STOWED_TOLERANCE_DEG`], in joint order
    /// (found on every accepted step, not only at the samples; empty for a
    /// truss wing, whose hinges are not watched).
    pub past_stowed: Vec<PastStowed>,
}

impl Trajectory {
    /// An empty trajectory of `n` joints, to be filled sample by sample.
    pub fn with_joints(n: usize) -> Self {
        Trajectory {
            phi_deg: vec![Vec::new(); n],
            rate_deg_s: vec![Vec::new(); n],
            latched: vec![Vec::new(); n],
            latch_s: vec![None; n],
            ..Trajectory::default()
        }
    }

    /// Number of joints.
    pub fn joints(&self) -> usize {
        self.phi_deg.len()
    }

    /// True when every joint latched.
    pub fn deployed(&self) -> bool {
        self.latch_s.iter().all(Option::is_some)
    }

    /// The hinges of a run of a flexible chain ([`crate::model::flex`]:
    /// hinge `j` is joint `2j`, 0-based, its flex joint `2j + 1`): what the
    /// encoders and switches read, the flex joints left out, the stowed
    /// passages numbered by hinge.
    pub fn hinges_of_flexible(self) -> Trajectory {
        Trajectory {
            phi_deg: hinges(self.phi_deg),
            rate_deg_s: hinges(self.rate_deg_s),
            latched: hinges(self.latched),
            latch_s: hinges(self.latch_s),
            past_stowed: self
                .past_stowed
                .into_iter()
                .filter(|p| p.joint % 2 == 1)
                .map(|p| PastStowed {
                    joint: p.joint.div_ceil(2),
                    ..p
                })
                .collect(),
            ..self
        }
    }
}

/// The even entries of `v`: the hinges of a flexible chain's joints.
fn hinges<T>(v: Vec<T>) -> Vec<T> {
    v.into_iter().step_by(2).collect()
}

/// Largest drift of a run's energy ledger from the energy stored at the
/// start, relative to it, that a run may reach by default
/// ([`SimOptions::max_drift`]) (`docs/simulator.md`,
/// "Energy ledger self-check"); beyond it the run stops with
/// [`SimError::EnergyDrift`].
pub const MAX_LEDGER_DRIFT: f64 = 1e-6;

/// Why a simulation failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// The mechanism or an effect is not valid for simulation.
    #[error("{0}")]
    Invalid(String),
    /// The equations could not be evaluated (singular mass matrix or a state
    /// that is not finite).
    #[error("the equations of motion failed at t = {t_s:.6} s (singular mass matrix or non-finite state)")]
    Singular {
        /// Simulated time \[s\].
        t_s: f64,
    },
    /// The step size fell below 1e-13 s: the model is too stiff or discontinuous.
    #[error("step size underflow at t = {t_s:.6} s: the model is too stiff here")]
    StepUnderflow {
        /// Simulated time \[s\].
        t_s: f64,
    },
    /// The integration took more than [`MAX_STEPS`] steps.
    #[error("more than {MAX_STEPS} steps by t = {t_s:.6} s: the model is too stiff")]
    TooManySteps {
        /// Simulated time \[s\].
        t_s: f64,
    },
    /// The run would hold more than [`MAX_SAMPLES`] samples.
    #[error("the run would hold more than {MAX_SAMPLES} samples by t = {t_s:.3} s; expected a shorter [run] duration_s or a lower sample rate")]
    TooManySamples {
        /// Simulated time \[s\].
        t_s: f64,
    },
    /// The run's energy ledger does not close: its drift from the energy
    /// stored at the start exceeds the run's [`SimOptions::max_drift`]
    /// of it (`docs/simulator.md`, "Energy ledger self-check"). The run is
    /// wrong and is not written.
    #[error(
        "the energy ledger does not close at joint {joint} ({cause}) at t = {t_s:.6} s: \
         drift {drift_j:.3e} J, {:.2e} of the {stored_j:.6} J stored (more than {limit:.0e}); \
         the run is wrong and was not written",
        drift_j / stored_j.abs().max(f64::MIN_POSITIVE)
    )]
    EnergyDrift {
        /// 1-based joint: the one at whose event the drift jumped, or whose
        /// work term was largest over the step where it did.
        joint: usize,
        /// What happened there (an event's kind, or "its work over a step").
        cause: String,
        /// Where the drift first exceeded the tolerance \[s\].
        t_s: f64,
        /// The drift there \[J\].
        drift_j: f64,
        /// The energy stored at the start \[J\].
        stored_j: f64,
        /// The run's tolerance, relative to `stored_j` \[1\]
        /// ([`SimOptions::max_drift`]).
        limit: f64,
    },
    /// A tape-spring joint sticks at `φ̇ = 0` where neither branch is
    /// consistent (the reference reports this as an error too).
    #[error(
        "joint {joint} slides on φ̇ = 0 at t = {t_s:.6} s: neither spring branch is consistent"
    )]
    Sliding {
        /// 1-based joint.
        joint: usize,
        /// Simulated time \[s\].
        t_s: f64,
    },
}

/// Most accepted plus rejected steps of one simulation (a 12 s deployment
/// takes under 2,000).
pub const MAX_STEPS: usize = 1_000_000;

/// Most samples of one simulated run: 10⁶, 2.8 hours at 100 Hz (deployments
/// last seconds; a 3-joint trajectory of 10⁶ samples takes about 60 MB).
/// Memory grows with the samples written, never with the duration asked for.
pub const MAX_SAMPLES: usize = 1_000_000;

/// The output sample times: a measured run's (listed), or a uniform grid
/// from 0 generated as the run goes.
#[derive(Clone, Copy, Debug)]
pub enum Samples<'a> {
    /// Given times, sorted, from 0.
    Listed(&'a [f64]),
    /// `k / rate_hz` for `k = 0 .. count`.
    Grid {
        /// Sample rate \[Hz\].
        rate_hz: f64,
        /// Number of samples.
        count: usize,
    },
}

/// The most samples a uniform grid counts: one more than [`MAX_SAMPLES`].
/// Every longer grid is refused alike, as a run that would hold more than
/// [`MAX_SAMPLES`] samples, so counting further says nothing; the cap also
/// keeps the count of an absurd `duration × rate` (10³⁰⁰ s) a number, not a
/// saturated conversion, and the time of the refusal in range.
pub const GRID_COUNT_CAP: usize = MAX_SAMPLES + 1;

/// Slack on `duration × rate` when counting a grid's samples \[samples\]: a
/// duration that is a whole number of sample periods ends the grid on it
/// although the product rounds above it (1.1 s × 100 Hz =
/// 110.00000000000001).
pub const GRID_ROUNDING_SAMPLES: f64 = 1e-9;

/// Samples `k / rate_hz`, `k = 0, 1, …`, up to the first at or after
/// `duration_s` (`duration_s` itself when it is a whole number of sample
/// periods), capped at [`GRID_COUNT_CAP`]: the one count of a run's
/// uniform sample grid. The grid covers the whole duration, so a joint
/// that latches within `duration_s` latches within the run whatever the
/// rate (a grid ending at the last sample before it lost a latch between
/// the two). `duration_s` and `rate_hz` are positive and finite (checked
/// by callers).
pub fn grid_count(duration_s: f64, rate_hz: f64) -> usize {
    let last_k = (duration_s * rate_hz - GRID_ROUNDING_SAMPLES).ceil();
    if last_k < (GRID_COUNT_CAP - 1) as f64 {
        last_k as usize + 1
    } else {
        GRID_COUNT_CAP
    }
}

impl Samples<'_> {
    /// The uniform grid `k / rate_hz` covering `[0, duration_s]`
    /// ([`grid_count`]).
    pub fn grid(duration_s: f64, rate_hz: f64) -> Samples<'static> {
        Samples::Grid {
            rate_hz,
            count: grid_count(duration_s, rate_hz),
        }
    }

    /// Sample `k` \[s\], `None` past the end.
    pub fn get(&self, k: usize) -> Option<f64> {
        match *self {
            Samples::Listed(t) => t.get(k).copied(),
            Samples::Grid { rate_hz, count } => (k < count).then(|| k as f64 / rate_hz),
        }
    }

    /// The last sample \[s\] (0 for none).
    pub fn last(&self) -> f64 {
        match *self {
            Samples::Listed(t) => t.last().copied().unwrap_or(0.0),
            Samples::Grid { rate_hz, count } => count.saturating_sub(1) as f64 / rate_hz,
        }
    }
}
