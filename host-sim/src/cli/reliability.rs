//! `deploywatch reliability`: the probability that a deployment fails, from
//! the uncertainty of its parameters (crude Monte-Carlo or subset
//! simulation, docs/reliability.md).

use super::{check_output, outln, CliError, Console};
use crate::analysis::reliability::correlation::Correlation;
use crate::analysis::reliability::criteria::Criterion;
use crate::analysis::reliability::identified;
use crate::analysis::reliability::mc::{self, McSettings};
use crate::analysis::reliability::params::{Target, Vary};
use crate::analysis::reliability::subset::{self, SubsetSettings};
use crate::analysis::reliability::{Estimate, Problem, ReliabilityError};
use crate::model::effect::EffectKind;
use crate::model::mechanism::Mechanism;
use crate::report::files::Outputs;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// Crude Monte-Carlo.
    Mc,
    /// Subset simulation (Au & Beck 2001), p0 = 0.1.
    Subset,
}

/// Arguments of `deploywatch reliability`.
#[derive(Debug, clap::Args)]
pub struct ReliabilityArgs {
    /// The mechanism (TOML, see docs/spec/formats.md).
    pub mechanism: PathBuf,
    /// An uncertain parameter, `NAME[:joint=J]:DIST`, repeatable. NAME: a
    /// named effect (as `simulate --effect`, added to the mechanism) or
    /// spring_preload, spring_stiffness (linear springs), panel_mass,
    /// panel_inertia (replaced); DIST: normal(mean,sd),
    /// lognormal(median,sigma_ln), uniform(lo,hi), truncnormal(mean,sd,lo,hi).
    #[arg(long = "vary", value_name = "SPEC")]
    pub vary: Vec<Vary>,
    /// A failure criterion, repeatable (any one fails): `not_latched`,
    /// `latch_rate>X` [deg/s], `time>X` [s].
    #[arg(long = "fail", value_name = "CRITERION", required = true)]
    pub fail: Vec<Criterion>,
    /// A correlation `I,J,RHO` of the standard normals behind parameters I
    /// and J (1-based, in the order of the --vary, then --from; a Gaussian
    /// copula), repeatable.
    #[arg(long = "corr", value_name = "I,J,RHO")]
    pub corr: Vec<Correlation>,
    /// The estimator.
    #[arg(long, value_enum, default_value_t = Method::Subset)]
    pub method: Method,
    /// mc: most deployments (default 100000); subset: samples per level
    /// (default 2000, a multiple of 10).
    #[arg(long)]
    pub samples: Option<usize>,
    /// mc: stop once the c.o.v. is at or below C; subset: warn if the
    /// reported c.o.v. is above C.
    #[arg(long, value_name = "C")]
    pub target_cov: Option<f64>,
    /// Seed of the draws (the same seed gives the same result, on any
    /// number of threads).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Write the result as JSON here.
    #[arg(long, value_name = "OUT.json")]
    pub json: Option<PathBuf>,
    /// The identified friction of `deploywatch identify --json` as normal
    /// laws (mean and the 95 % interval), one `--vary` per joint.
    #[arg(long, value_name = "IDENTIFY.json")]
    pub from: Option<PathBuf>,
    /// No progress and no chatter: the result, errors and warnings only.
    #[arg(long, short)]
    pub quiet: bool,
    /// The flight unit: the mechanism's `[rig]` taken out (only what
    /// flies; `docs/simulator.md`, "Rig").
    #[arg(long)]
    pub flight: bool,
}

/// The laws of `--from` (the identify JSON), skipping the joints whose
/// friction a `--vary` already names.
fn from_file(path: &Path, given: &[Vary]) -> Result<Vec<Vary>, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::input(format!("--from {}: cannot read: {e}", path.display())))?;
    let found = identified::from_identify_json(&text)
        .map_err(|m| CliError::input(format!("--from {}: {m}", path.display())))?;
    let named = |v: &Vary| match v.target {
        Target::Effect {
            kind: EffectKind::CoulombFriction,
            joint,
            ..
        } => joint,
        _ => None,
    };
    Ok(found
        .into_iter()
        .filter(|f| given.iter().all(|g| named(g) != named(f)))
        .collect())
}

/// The problem of the command line.
pub fn problem(args: &ReliabilityArgs) -> Result<Problem, CliError> {
    let mech = Mechanism::load(&args.mechanism).map_err(|e| CliError::input(e.to_string()))?;
    let mech = if args.flight { mech.flight() } else { mech };
    let mut vary = args.vary.clone();
    if let Some(f) = &args.from {
        vary.extend(from_file(f, &args.vary)?);
    }
    let problem = Problem {
        mech,
        vary,
        fail: args.fail.clone(),
        corr: args.corr.clone(),
    };
    problem
        .check()
        .map_err(|e| CliError::input(e.to_string()))?;
    Ok(problem)
}

/// Runs `deploywatch reliability`.
pub fn run(args: &ReliabilityArgs) -> Result<(), CliError> {
    let problem = problem(args)?;
    if let Some(j) = &args.json {
        check_output("--json", j)?;
    }
    if let Some(c) = args.target_cov {
        if !(c > 0.0 && c.is_finite()) {
            return Err(CliError::input(format!(
                "--target-cov {c}: expected a positive number"
            )));
        }
    }
    let console = Console::new(args.quiet);
    let start = Instant::now();
    let mut eval = |xs: &[Vec<f64>]| problem.g_batch(xs);
    let est = match args.method {
        Method::Mc => mc::run(
            &problem,
            &McSettings {
                samples: args.samples.unwrap_or(100_000),
                target_cov: args.target_cov,
                seed: args.seed,
            },
            &mut eval,
            console.progress(),
        ),
        Method::Subset => subset::run(
            &problem,
            &SubsetSettings {
                samples: args.samples.unwrap_or(SubsetSettings::default().samples),
                seed: args.seed,
                ..SubsetSettings::default()
            },
            &mut eval,
            console.progress(),
        ),
    }
    .map_err(|e| match e {
        ReliabilityError::Invalid(m) => CliError::input(m),
        other => CliError::failed(other.to_string()),
    })?;
    let wall = start.elapsed().as_secs_f64();
    print_estimate(&problem, &est, wall);
    if !est.converged {
        console.warn(format_args!(
            "the thresholds did not reach the failure domain in {} levels: p_fail is an upper bound",
            est.levels.len()
        ));
    }
    if let Some(c) = args.target_cov.filter(|&c| est.cov > c) {
        console.warn(format_args!(
            "c.o.v. {:.3} is above --target-cov {c}",
            est.cov
        ));
    }
    if let Some(j) = &args.json {
        let text = serde_json::to_string_pretty(&est.to_json(&problem, args.seed))
            .map_err(|e| CliError::failed(e.to_string()))?;
        let mut outs = Outputs::new();
        outs.write(j, text + "\n")?;
        outs.commit()?;
        console.say(format_args!("  json: {}", j.display()));
    }
    Ok(())
}

/// The result on stdout.
fn print_estimate(problem: &Problem, est: &Estimate, wall_s: f64) {
    let fails: Vec<String> = problem.fail.iter().map(|c| c.to_string()).collect();
    outln!(
        "{}: P({}) by {}, {} parameter(s)",
        problem.mech.name,
        fails.join(" or "),
        est.method,
        problem.vary.len()
    );
    for v in &problem.vary {
        outln!("  {v}");
    }
    for (k, l) in est.levels.iter().enumerate() {
        outln!(
            "  level {k}: threshold {:.6e}, p = {:.4}, c.o.v. {:.3}, {} deployments",
            l.threshold,
            l.p,
            l.cov,
            l.simulations
        );
    }
    if est.converged {
        outln!(
            "p_fail = {:.4e}  c.o.v. {:.3}  95 % [{:.4e}, {:.4e}]  {} deployments, {} failed, {wall_s:.2} s wall",
            est.p_fail, est.cov, est.ci95.0, est.ci95.1, est.simulations, est.failures
        );
    } else {
        outln!(
            "p_fail < {:.4e} (the last threshold, {:.6e}, is still above 0: the probability \
             of reaching it bounds p_fail)  {} deployments, {wall_s:.2} s wall",
            est.p_fail,
            est.levels.last().map_or(f64::NAN, |l| l.threshold),
            est.simulations
        );
    }
    if let Some(f) = &est.most_likely_failure {
        outln!(
            "most likely failure (beta {:.3}): {}",
            f.beta(),
            problem.describe(&f.x)
        );
    }
}
