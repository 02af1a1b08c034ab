//! The probability that a deployment fails, from the uncertainty of its
//! parameters: crude Monte-Carlo ([`mc`]), subset simulation ([`subset`],
//! Au & Beck 2001, "Estimation of small failure probabilities in high
//! dimensions by subset simulation", Probabilistic Engineering Mechanics
//! 16(4)), one run per failure mode, and importance sampling around the
//! design points of FORM ([`form`], [`importance`]); [`auto`] runs the last
//! two and compares them.
//!
//! A [`Problem`] is a mechanism, its uncertain parameters ([`params::Vary`],
//! each mapped from a standard normal `u`), the effects every deployment
//! carries as found ([`params::Fixed`]) and the failure criteria
//! ([`criteria::Criterion`]), each a failure mode per joint with its own
//! margin (failure iff margin ≤ 0, [`criteria::Mode`]). The algorithms draw
//! the points and ask an [`Evaluate`] callback for their margins by
//! batches: locally [`Problem::margins_batch`] (rayon),
//! or any other engine (the Python package sends the batches to a Dask
//! cluster). Every draw comes from its own ChaCha8 stream, numbered by
//! (seed, level, index) ([`stream`]), and every reduction runs in a fixed
//! order, so the same seed gives the same bits on any number of workers.

pub mod auto;
mod chains;
pub mod correlation;
pub mod criteria;
pub mod estimate;
pub mod form;
mod held;
pub mod identified;
pub mod importance;
mod lineage;
pub mod mc;
pub mod normal;
pub mod params;
pub mod subset;
pub mod text;
pub mod warning;

use crate::model::effect::Effect;
use crate::model::mechanism::Mechanism;
use crate::simulate::deployment::{self, SimError, SimOptions, Trajectory};
use crate::simulate::latch_deployment::{self, Keep};
use crate::simulate::trajectory::{Samples, DEFAULT_RTOL, MAX_LEDGER_DRIFT};
use crate::simulate::trajectory::{SimStats, Stall};
use correlation::Correlation;
use criteria::{Criterion, Mode, Outcome};
use params::{Fixed, Target, Vary};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Output rate of the reliability deployments that need the latch rate
/// (`latch_rate>X`) \[Hz\]: it is extrapolated from the last two samples
/// before the latch, 1 ms apart. The others are not sampled at all.
pub const SAMPLE_HZ: f64 = 1000.0;

/// Relative tolerance of the reliability deployments: a verdict needs the
/// latch instants, not 1e-8 of the trajectory. It moves the failure
/// boundaries by less than 3e-6 N·m on the cases of `tests/reliability.rs`
/// (which checks it against the default tolerance) and halves the work
/// (docs/reliability.md §6).
pub const VERDICT_RTOL: f64 = 1e-6;

/// Absolute tolerance of the reliability deployments [rad, rad/s].
pub const VERDICT_ATOL: f64 = 1e-6;

/// The energy ledger's tolerance in the reliability deployments of an
/// ideal-latch wing ([`SimOptions::max_drift`]), relative to the stored
/// energy: the reference's ([`MAX_LEDGER_DRIFT`]) loosened as the state's
/// tolerance is, `MAX_LEDGER_DRIFT · VERDICT_RTOL / DEFAULT_RTOL`. Still
/// checked in every deployment; held to the reference's, the ledger's
/// retakes (steps taken again shorter where the drift moves by more than
/// its share) cost more work than the whole deployment otherwise takes,
/// and no verdict depends on them (docs/reliability.md §6,
/// docs/decisions/0013-verdict-ledger-tolerance.md). A wing with
/// physical latches keeps [`MAX_LEDGER_DRIFT`]: there the retakes size
/// the steps on the stiff contacts and the verdicts move with the
/// tolerance (docs/performance.md, "Physical latches").
pub const VERDICT_LEDGER_DRIFT: f64 = MAX_LEDGER_DRIFT * VERDICT_RTOL / DEFAULT_RTOL;

/// What a reliability analysis is about.
#[derive(Clone, Debug)]
pub struct Problem {
    /// The nominal mechanism.
    pub mech: Mechanism,
    /// The uncertain parameters (at least one).
    pub vary: Vec<Vary>,
    /// The effects every deployment carries as found, next to the drawn
    /// ones (a diagnosis's torque tables, [`identified`]).
    pub fixed: Vec<Fixed>,
    /// The failure criteria (at least one; any one fails).
    pub fail: Vec<Criterion>,
    /// Correlations of the parameters' standard normals ([`correlation`]).
    pub corr: Vec<Correlation>,
}

/// A parameter of a reliability analysis that an error names: a field of
/// [`Problem`] or a method's setting. The library says it by its name
/// ([`Param::name`]); the command line says it as its option and Python as
/// its argument ([`ReliabilityError::words`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Param {
    /// [`Problem::vary`]: the laws of the parameters drawn.
    Vary,
    /// [`Problem::fixed`]: the effects carried from findings.
    Fixed,
    /// [`Problem::fail`]: the failure criteria.
    Fail,
    /// [`Problem::corr`]: the correlations of the parameters drawn.
    Corr,
    /// The number of samples a method draws.
    Samples,
}

impl Param {
    /// Its name in the library (the field of [`Problem`], `samples`).
    pub fn name(self) -> &'static str {
        match self {
            Param::Vary => "vary",
            Param::Fixed => "fixed",
            Param::Fail => "fail",
            Param::Corr => "corr",
            Param::Samples => "samples",
        }
    }
}

/// Why an analysis stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReliabilityError {
    /// The problem or the settings are not usable.
    #[error("{0}")]
    Invalid(String),
    /// A parameter's value is not usable: `PARAM VALUE: WHY`.
    #[error("{}", self.words(&|p| p.name().to_string()))]
    BadParam {
        /// The parameter.
        param: Param,
        /// The value refused, in its own syntax (`None`: the parameter as
        /// a whole).
        value: Option<String>,
        /// What is wrong.
        why: String,
    },
    /// Nothing to draw: no [`Param::Vary`] and no [`Param::Fixed`] effect
    /// with an interval.
    #[error("{}", self.words(&|p| p.name().to_string()))]
    NothingToDraw {
        /// Effects are fixed as found (they are not drawn).
        fixed: bool,
    },
    /// No failure criterion ([`Param::Fail`]).
    #[error("{}", self.words(&|p| p.name().to_string()))]
    NoCriterion,
    /// A deployment could not be simulated.
    #[error("the deployment at {at} failed: {source}")]
    Simulation {
        /// The parameters, `name = value, ...`.
        at: String,
        /// The simulator's error.
        #[source]
        source: SimError,
    },
    /// The batch evaluator (e.g. a remote engine) failed.
    #[error("the evaluation of a batch failed: {0}")]
    Evaluator(String),
}

impl ReliabilityError {
    /// The error in words, each [`Param`] it names said by `name` (the
    /// command line's option, Python's argument); its `Display` says them
    /// by [`Param::name`].
    pub fn words(&self, name: &dyn Fn(Param) -> String) -> String {
        match self {
            ReliabilityError::BadParam { param, value, why } => match value {
                Some(v) => format!("{} {v}: {why}", name(*param)),
                None => format!("{}: {why}", name(*param)),
            },
            ReliabilityError::NothingToDraw { fixed } => format!(
                "expected at least one {}, or a {} effect with an interval{}",
                name(Param::Vary),
                name(Param::Fixed),
                if *fixed {
                    " (the effects fixed as found are not drawn)"
                } else {
                    ""
                }
            ),
            ReliabilityError::NoCriterion => {
                format!("expected at least one {}", name(Param::Fail))
            }
            other => other.to_string(),
        }
    }

    /// True for the user's input: a problem or settings not usable (not a
    /// deployment or an evaluator that failed).
    pub fn is_input(&self) -> bool {
        matches!(
            self,
            ReliabilityError::Invalid(_)
                | ReliabilityError::BadParam { .. }
                | ReliabilityError::NothingToDraw { .. }
                | ReliabilityError::NoCriterion
        )
    }
}

impl From<correlation::CholeskyError> for ReliabilityError {
    fn from(e: correlation::CholeskyError) -> Self {
        let (value, why) = match e {
            correlation::CholeskyError::Beyond { corr, d } => (
                Some(corr.to_string()),
                format!(
                    "there are {d} parameters (1 to {d}, in the order of the laws drawn, then the effects carried from findings)"
                ),
            ),
            correlation::CholeskyError::NotPositiveDefinite => (
                None,
                "the correlation matrix is not positive definite".to_string(),
            ),
            correlation::CholeskyError::Twice { first, second } => (
                Some(second.to_string()),
                format!(
                    "parameters {} and {} are already correlated by {first}: give each pair once",
                    first.i, first.j
                ),
            ),
        };
        ReliabilityError::BadParam {
            param: Param::Corr,
            value,
            why,
        }
    }
}

/// The margins of a batch of parameter points (`xs[i]` has one value per
/// [`Problem::vary`]; the answer's row `i` one margin per
/// [`Problem::modes`]), in order.
pub type Evaluate<'a> = &'a mut dyn FnMut(&[Vec<f64>]) -> Result<Vec<Vec<f64>>, ReliabilityError>;

impl Problem {
    /// Checks the problem: at least one parameter and criterion, targets
    /// that exist, `time>X` below `duration_s`.
    pub fn check(&self) -> Result<(), ReliabilityError> {
        let bad = |m: String| ReliabilityError::Invalid(m);
        if self.vary.is_empty() {
            return Err(ReliabilityError::NothingToDraw {
                fixed: !self.fixed.is_empty(),
            });
        }
        if self.fail.is_empty() {
            return Err(ReliabilityError::NoCriterion);
        }
        for (i, v) in self.vary.iter().enumerate() {
            v.check(&self.mech)
                .map_err(|why| ReliabilityError::BadParam {
                    param: Param::Vary,
                    value: Some(v.label()),
                    why: why.to_string(),
                })?;
            // A mechanism parameter is replaced by its draw: of two laws
            // only the last would count (effects add, each drawn).
            if let Target::Mech(m, j) = v.target {
                if self.vary[..i].iter().any(|w| w.target == v.target) {
                    return Err(ReliabilityError::BadParam {
                        param: Param::Vary,
                        value: Some(v.label()),
                        why: format!(
                            "{} of joint {j} is varied twice; a mechanism parameter is \
                             replaced by its draw, so give it one law",
                            m.name()
                        ),
                    });
                }
            }
        }
        for f in &self.fixed {
            f.effect
                .validate_joint(self.mech.effect_joints())
                .map_err(|e| bad(format!("{} ({}): {e}", f.effect.kind(), f.source)))?;
        }
        correlation::cholesky(&self.corr, self.vary.len())?;
        for c in &self.fail {
            if let Criterion::TimeAbove(x) = c {
                if *x >= self.mech.duration_s {
                    return Err(ReliabilityError::BadParam {
                        param: Param::Fail,
                        value: Some(c.to_string()),
                        why: format!(
                            "X must be below the mechanism's duration_s ({} s); \
                             use not_latched for a deployment that does not finish",
                            self.mech.duration_s
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// The parameter point at the independent standard normal point `u`
    /// (correlated first by [`correlation::correlate`] if there are
    /// correlations).
    pub fn x_of(&self, u: &[f64]) -> Vec<f64> {
        let l = correlation::cholesky(&self.corr, self.vary.len())
            .ok()
            .flatten();
        let z = match &l {
            Some(l) => correlation::correlate(l, u),
            None => u.to_vec(),
        };
        self.vary
            .iter()
            .zip(&z)
            .map(|(v, &z)| v.dist.at(z))
            .collect()
    }

    /// The parameters in words, `name = value, ...`, every digit kept (to
    /// rerun a deployment that failed; the CLI prints its results with
    /// units and fewer digits).
    pub fn describe(&self, x: &[f64]) -> String {
        let parts: Vec<String> = self
            .vary
            .iter()
            .zip(x)
            .map(|(v, x)| format!("{} = {x}", v.label()))
            .collect();
        parts.join(", ")
    }

    /// The failure modes: every criterion at every joint.
    pub fn modes(&self) -> Vec<Mode> {
        criteria::modes(&self.fail, self.mech.joint_count())
    }

    /// How long a deployment must run for the verdict \[s\]: `duration_s`,
    /// or with only `time>X` criteria the largest `X` (decided then).
    pub fn run_end_s(&self) -> f64 {
        let times = self.fail.iter().map(|c| match c {
            Criterion::TimeAbove(x) => Some(*x),
            _ => None,
        });
        times
            .reduce(|a, b| Some(a?.max(b?)))
            .flatten()
            .unwrap_or(self.mech.duration_s)
    }

    /// The mechanism and effects at the parameter point `x` (the fixed
    /// effects, then the drawn ones), simulated: the one call of the simulator in the reliability analysis. Only
    /// what the verdict needs is computed: no output samples (one at the
    /// end) unless a `latch_rate>X` criterion needs the rate before the
    /// latch, and the run stops at [`Problem::run_end_s`] or when every
    /// joint latched.
    ///
    /// A physical-latch run keeps its energy ledger (`docs/simulator.md`)
    /// and ends as soon as every latch is held for good
    /// ([`Keep::Settled`]: the same margins, to the bit, as the run to the
    /// end, `tests/physical_verdicts.rs`).
    pub fn deploy(&self, x: &[f64]) -> Result<Outcome, ReliabilityError> {
        self.deploy_keeping(x, Keep::Settled)
    }

    /// [`Problem::deploy`] keeping what `keep` says of a physical-latch
    /// run: [`Keep::Trajectory`] drops the energy ledger (and so its
    /// check), for the measurement of what the ledger costs and the check
    /// that it changes no verdict (`tests/physical_verdicts.rs`,
    /// `examples/physical_verdicts.rs`).
    pub fn deploy_keeping(&self, x: &[f64], keep: Keep) -> Result<Outcome, ReliabilityError> {
        Ok(self.deploy_with(x, keep, None)?.0)
    }

    /// [`Problem::deploy`] with the run's energy ledger held to `max_drift`
    /// ([`SimOptions::max_drift`]) instead of the verdict's
    /// ([`VERDICT_LEDGER_DRIFT`] with ideal latches): the measurement that
    /// the verdict's tolerance changes no verdict
    /// (`examples/ideal_ledger.rs`, the test beside this).
    pub fn deploy_held(&self, x: &[f64], max_drift: f64) -> Result<Outcome, ReliabilityError> {
        Ok(self.deploy_tuned(x, &|o| o.max_drift = max_drift)?.0)
    }

    /// [`Problem::deploy`] with the verdict's settings ([`verdict_options`])
    /// changed by `tune` (tolerances, longest step, the ledger's drift),
    /// and the run's work (steps, evaluations): the measurement of what
    /// other settings cost and keep (`examples/ideal_tolerance.rs`).
    pub fn deploy_tuned(
        &self,
        x: &[f64],
        tune: &dyn Fn(&mut SimOptions),
    ) -> Result<(Outcome, SimStats), ReliabilityError> {
        self.deploy_with(x, Keep::Settled, Some(tune))
    }

    /// The verdict's deployment at `x`, keeping `keep`, its settings
    /// changed by `tune` when given, and the run's work.
    fn deploy_with(
        &self,
        x: &[f64],
        keep: Keep,
        tune: Option<&dyn Fn(&mut SimOptions)>,
    ) -> Result<(Outcome, SimStats), ReliabilityError> {
        let mut mech = self.mech.clone();
        let mut effects: Vec<Effect> = self.fixed.iter().map(|f| f.effect).collect();
        for (v, &x) in self.vary.iter().zip(x) {
            v.apply(x, &mut mech, &mut effects);
        }
        params::check_drawn(&mech, &effects).map_err(|why| ReliabilityError::Simulation {
            at: self.describe(x),
            source: SimError::Invalid(why),
        })?;
        let end = self.run_end_s();
        let rate = self
            .fail
            .iter()
            .any(|c| matches!(c, Criterion::LatchRateAbove(_)));
        let mut opts = verdict_options(&mech, end, rate);
        if let Some(tune) = tune {
            tune(&mut opts);
        }
        let (traj, held_s) =
            simulate_verdict(&mech, &effects, &opts, (rate, end), keep).map_err(|source| {
                ReliabilityError::Simulation {
                    at: self.describe(x),
                    source,
                }
            })?;
        Ok((outcome(&traj, held_s, &mech, rate), traj.stats))
    }

    /// The joints (1-based) whose switch is open at the end of the
    /// deployment at `x` while their latch holds them (a pawl in its
    /// notch, a ball plunger past its crest): `not_latched` fails them,
    /// `not_held` does not (`docs/reliability.md` §8).
    pub fn held_with_switch_open(&self, x: &[f64]) -> Result<Vec<usize>, ReliabilityError> {
        let o = self.deploy(x)?;
        let both = o.latch_s.iter().zip(&o.held_s).enumerate();
        Ok(both
            .filter(|(_, (latched, held))| latched.is_none() && held.is_some())
            .map(|(j, _)| j + 1)
            .collect())
    }

    /// The margins of the modes at the parameter point `x`.
    pub fn margins(&self, x: &[f64]) -> Result<Vec<f64>, ReliabilityError> {
        Ok(self.deploy(x)?.margins(&self.modes()))
    }

    /// The system's margin `g` (the smallest of the modes') at `x`.
    pub fn g(&self, x: &[f64]) -> Result<f64, ReliabilityError> {
        Ok(self.deploy(x)?.g(&self.fail))
    }

    /// The outcomes of a batch on every core (rayon), in the order of `xs`.
    pub fn deploy_batch(&self, xs: &[Vec<f64>]) -> Result<Vec<Outcome>, ReliabilityError> {
        xs.par_iter().map(|x| self.deploy(x)).collect()
    }

    /// The margins of a batch on every core (rayon; the order of the
    /// output is the order of `xs`, whatever the threads): the local
    /// [`Evaluate`].
    pub fn margins_batch(&self, xs: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, ReliabilityError> {
        let modes = self.modes();
        xs.par_iter()
            .map(|x| Ok(self.deploy(x)?.margins(&modes)))
            .collect()
    }

    /// `g` of a batch on every core (rayon), in the order of `xs`.
    pub fn g_batch(&self, xs: &[Vec<f64>]) -> Result<Vec<f64>, ReliabilityError> {
        xs.par_iter().map(|x| self.g(x)).collect()
    }
}

/// The settings of a verdict's deployment of `mech`: to `end` \[s\] or
/// the last latch, at [`VERDICT_RTOL`], sampled at [`SAMPLE_HZ`] when the
/// latch rate is needed (`rate`); its ledger held to
/// [`VERDICT_LEDGER_DRIFT`] with ideal latches, to [`MAX_LEDGER_DRIFT`]
/// with physical ones.
pub fn verdict_options(mech: &Mechanism, end: f64, rate: bool) -> SimOptions {
    let max_drift = match mech.has_physical_latch() {
        true => MAX_LEDGER_DRIFT,
        false => VERDICT_LEDGER_DRIFT,
    };
    SimOptions {
        duration_s: Some(end),
        settle_s: Some(0.0),
        stop_when_deployed: true,
        rtol: VERDICT_RTOL,
        atol: VERDICT_ATOL,
        max_drift,
        sample_hz: rate.then_some(SAMPLE_HZ),
        stall: Stall::Hold,
        ..SimOptions::default()
    }
}

/// The deployment of `mech` with `effects` as `deploywatch simulate` runs
/// it (its settings, its sample grid, to the mechanism's `duration_s`), as
/// a verdict reads it: its [`Outcome`] — per joint when its latch last
/// came to hold it (`held_s`, `None` if it does not hold it at the end)
/// and where it ended. What `margin` sets beside its margins
/// (`docs/margin.md`, "The nominal deployment").
pub fn nominal_outcome(mech: &Mechanism, effects: &[Effect]) -> Result<Outcome, SimError> {
    nominal_outcome_at(mech, effects, 1.0)
}

/// [`nominal_outcome`] with the simulator's tolerances scaled by `scale`
/// (the chaos check of `margin`'s nominal deployment runs it at 1/10).
pub fn nominal_outcome_at(
    mech: &Mechanism,
    effects: &[Effect],
    scale: f64,
) -> Result<Outcome, SimError> {
    // A verdict: a joint that stalls sticks (`Stall::Hold`), whatever
    // `duration_s` leaves it to creep.
    let defaults = SimOptions::default();
    let opts = SimOptions {
        stall: Stall::Hold,
        rtol: defaults.rtol * scale,
        atol: defaults.atol * scale,
        ..defaults
    };
    let (traj, held_s) =
        simulate_verdict(mech, effects, &opts, (true, mech.duration_s), Keep::Ledger)?;
    Ok(outcome(&traj, held_s, mech, true))
}

/// The one simulation of a verdict: sampled on `opts`' grid (`rate`) or
/// once at `end` \[s\]. A wing with physical latches keeps what `keep`
/// says ([`Keep::Trajectory`]: the same trajectory and events, bit for
/// bit, without the ledger's Gauss–Legendre power sums and energies of
/// every step); every other wing as `deployment` simulates it. With the
/// trajectory, when each joint's latch last came to hold it
/// ([`Outcome::held_s`]).
fn simulate_verdict(
    mech: &Mechanism,
    effects: &[Effect],
    opts: &SimOptions,
    (rate, end): (bool, f64),
    keep: Keep,
) -> Result<(Trajectory, Vec<Option<f64>>), SimError> {
    let end = [end];
    if mech.has_physical_latch() {
        let times = match rate {
            true => deployment::sample_grid(mech, opts)?,
            false => Samples::Listed(&end),
        };
        let run = latch_deployment::simulate_with(mech, effects, opts, times, keep)?;
        let held = held::held_instants(&run, mech, effects);
        return Ok((run.traj, held));
    }
    let traj = match rate {
        true => deployment::simulate(mech, effects, opts),
        false => deployment::simulate_at(mech, effects, opts, &end),
    }?;
    let held = traj.latch_s.clone();
    Ok((traj, held))
}

/// The outcome of a simulated deployment (`rate`: the trajectory is
/// sampled finely enough to give the rate before each latch).
fn outcome(traj: &Trajectory, held_s: Vec<Option<f64>>, mech: &Mechanism, rate: bool) -> Outcome {
    let n = traj.joints();
    let mut rates = vec![None; n];
    for (j, r) in rates.iter_mut().enumerate().filter(|_| rate) {
        let Some(tl) = traj.latch_s[j] else { continue };
        let before: Vec<usize> = (0..traj.t_s.len())
            .filter(|&i| !traj.latched[j][i] && traj.t_s[i] < tl)
            .collect();
        *r = match before[..] {
            [] => Some(0.0),
            [i] => Some(traj.rate_deg_s[j][i]),
            [.., a, b] => {
                let (ra, rb) = (traj.rate_deg_s[j][a], traj.rate_deg_s[j][b]);
                let slope = (rb - ra) / (traj.t_s[b] - traj.t_s[a]);
                Some(rb + slope * (tl - traj.t_s[b]))
            }
        };
    }
    Outcome {
        latch_s: traj.latch_s.clone(),
        held_s,
        latch_rate_deg_s: rates,
        end_deg: traj
            .phi_deg
            .iter()
            .map(|p| p.last().copied().unwrap_or(0.0))
            .collect(),
        stowed_deg: (0..n)
            .map(|j| mech.joints.get(j).map_or(0.0, |jt| jt.stowed_deg))
            .collect(),
        end_s: traj.end_s,
        duration_s: mech.duration_s,
    }
}

/// The random stream of one draw: ChaCha8 seeded with `seed`, stream
/// `level · 2⁴⁰ + index`, so that each draw's numbers depend on nothing
/// but (seed, level, index).
pub fn stream(seed: u64, level: u32, index: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(((level as u64) << 40) | (index & ((1 << 40) - 1)));
    rng
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An ideal-latch wing's verdicts do not move with the ledger's
    /// tolerance: seed 001 T01 with its identified friction at 15 %
    /// lognormal dispersion (three times the benchmark's, so that a share
    /// of the draws fail near the boundary), each draw deployed with the
    /// verdict's [`VERDICT_LEDGER_DRIFT`] and with the reference's
    /// [`MAX_LEDGER_DRIFT`]: the same draws fail, and every margin agrees
    /// to well within what a verdict resolves (`docs/reliability.md` §6;
    /// `examples/ideal_ledger.rs` measures 20,000 draws).
    #[test]
    fn an_ideal_latch_verdict_does_not_move_with_the_ledger_tolerance() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../data/mechanisms/seed001_T01.toml");
        let problem = Problem {
            mech: Mechanism::load(&path).expect("seed 001 T01"),
            vary: [
                "coulomb_friction:joint=1:lognormal(2.63,0.15)",
                "coulomb_friction:joint=2:lognormal(1.7,0.15)",
                "coulomb_friction:joint=3:lognormal(0.001,0.15)",
            ]
            .iter()
            .map(|v| v.parse().expect("vary"))
            .collect(),
            fixed: Vec::new(),
            fail: vec!["not_latched".parse().expect("criterion")],
            corr: Vec::new(),
        };
        let modes = problem.modes();
        let (mut failed, mut worst) = ([0usize; 2], 0.0f64);
        for i in 0..120u64 {
            let x = problem.x_of(&mc::draw(0, 0, i, 3));
            let loose = problem.deploy(&x).expect("verdict");
            let tight = problem
                .deploy_held(&x, MAX_LEDGER_DRIFT)
                .expect("reference");
            let (gl, gt) = (loose.g(&problem.fail), tight.g(&problem.fail));
            failed[0] += usize::from(gl <= 0.0);
            failed[1] += usize::from(gt <= 0.0);
            assert_eq!(gl <= 0.0, gt <= 0.0, "draw {i}: g {gl} against {gt}");
            for (a, b) in loose.margins(&modes).iter().zip(tight.margins(&modes)) {
                worst = worst.max((a - b).abs());
            }
        }
        eprintln!("failed (verdict, reference): {failed:?}; largest margin difference {worst:.3e}");
        assert!(
            failed[0] > 5,
            "too few failures to test the boundary: {failed:?}"
        );
        assert!(worst < 1e-3, "largest margin difference {worst}");
    }

    /// A draw whose joint swings back past its stowed angle is counted by
    /// its criteria like any other, neither a failure nor an error
    /// (`docs/reliability.md` §8): seed 001 T02 without friction, the
    /// contract's own deployment, pushes joint 1 about 9.7° past −90° and
    /// deploys at 7.33 s. The verdict's run, sampled once at its end, still
    /// carries the passage (watched on every step).
    #[test]
    fn a_draw_past_its_stowed_angle_is_counted_by_its_criteria() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../data/mechanisms/seed001_T02.toml");
        let mech = Mechanism::load(&path).expect("seed 001 T02");
        for rate in [false, true] {
            let opts = verdict_options(&mech, mech.duration_s, rate);
            let (traj, held_s) =
                simulate_verdict(&mech, &[], &opts, (rate, mech.duration_s), Keep::Ledger)
                    .expect("the verdict's run");
            let past: Vec<_> = traj.past_stowed.iter().map(|p| p.joint).collect();
            assert_eq!(past, [1], "{:?}", traj.past_stowed);
            assert!(
                traj.past_stowed[0].past_deg() > 9.0,
                "{:?}",
                traj.past_stowed
            );
            let o = outcome(&traj, held_s, &mech, rate);
            let fail = [Criterion::NotLatched, Criterion::TimeAbove(8.0)];
            assert!(o.g(&fail) > 0.0, "{o:?}");
            assert!(o.g(&[Criterion::TimeAbove(7.0)]) < 0.0, "{o:?}");
        }
    }
}
