//! `deploywatch reliability`: the probability that a deployment fails, from
//! the uncertainty of its parameters (crude Monte-Carlo, subset simulation,
//! importance sampling around FORM's design points, or the last two
//! compared: docs/reliability.md).

use super::{check_output, outln, CliError, Console};
use crate::analysis::reliability::auto::{estimate, Method};
use crate::analysis::reliability::correlation::Correlation;
use crate::analysis::reliability::criteria::Criterion;
use crate::analysis::reliability::estimate::Estimate;
use crate::analysis::reliability::identified::{self, FromFindings};
use crate::analysis::reliability::params::{Dist, Target, Vary};
use crate::analysis::reliability::text::{quantity, sig};
use crate::analysis::reliability::warning::warnings;
use crate::analysis::reliability::{form, normal};
use crate::analysis::reliability::{Param, Problem, ReliabilityError};
use crate::model::mechanism::Mechanism;
use crate::report::files::Outputs;
use std::path::{Path, PathBuf};
use std::time::Instant;

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
    /// A failure criterion, repeatable (any one fails): `not_latched` (a
    /// physical latch's switch open at the end), `not_held` (a physical
    /// latch not holding its joint at the end, whatever its switch reads),
    /// `latch_rate>X` in deg/s, `time>X` in s.
    #[arg(long = "fail", value_name = "CRITERION", required = true)]
    pub fail: Vec<Criterion>,
    /// A correlation `I,J,RHO` of the standard normals behind parameters I
    /// and J (1-based, in the order of the --vary, then --from; a Gaussian
    /// copula), repeatable.
    #[arg(long = "corr", value_name = "I,J,RHO")]
    pub corr: Vec<Correlation>,
    /// The estimator: auto runs is and subset and compares them.
    #[arg(long, default_value = "auto", value_name = "auto|is|subset|mc")]
    pub method: Method,
    /// mc: most deployments (default 100000); subset: samples per level
    /// (default 2000, a multiple of 10); is: draws (default 8000); auto:
    /// both of the last two.
    #[arg(long)]
    pub samples: Option<usize>,
    /// mc, is: stop once the c.o.v. is at or below C; subset: warn if the
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
    /// What `deploywatch identify --json` or `deploywatch diagnose --json`
    /// found, as normal laws (the value fitted and its 95 % interval), one
    /// `--vary` per effect; a `--vary` of the same effect and joint wins. A
    /// torque table is fixed as found in every deployment, each knot at
    /// the end of its band that resists the deployment.
    #[arg(long, value_name = "FINDINGS.json")]
    pub from: Option<PathBuf>,
    /// No progress and no chatter: the result, errors and warnings only.
    #[arg(long, short)]
    pub quiet: bool,
    /// The flight unit: the mechanism's `[rig]` taken out (only what
    /// flies; `docs/simulator.md`, "Rig").
    #[arg(long)]
    pub flight: bool,
}

/// The laws and fixed effects of `--from` (an identify or a diagnose
/// JSON) on `mech`, leaving out the laws of the effects a `--vary` already
/// names (same effect, same joint); each fixed effect's source names the
/// file.
fn from_file(path: &Path, given: &[Vary], mech: &Mechanism) -> Result<FromFindings, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::input(format!("--from {}: cannot read: {e}", path.display())))?;
    let mut found = identified::from_findings_json(&text, mech)
        .map_err(|m| CliError::input(format!("--from {}: {m}", path.display())))?;
    if let Some(why) = &found.no_effect {
        return Err(CliError::input(format!("--from {}: {why}", path.display())));
    }
    let named = |v: &Vary| match v.target {
        Target::Effect(e) => Some((e.kind(), e.joint)),
        Target::Mech(..) => None,
    };
    found
        .vary
        .retain(|f| given.iter().all(|g| named(g) != named(f)));
    for s in &mut found.stand_ins {
        s.vary
            .retain(|f| given.iter().all(|g| named(g) != named(f)));
    }
    for f in &mut found.fixed {
        f.source = format!("--from {}: {}", path.display(), f.source);
    }
    // Said of the file, not of a --vary the user did not give.
    for v in found
        .vary
        .iter()
        .chain(found.stand_ins.iter().flat_map(|s| &s.vary))
    {
        v.check(mech).map_err(|why| {
            CliError::input(format!("--from {}: {}: {why}", path.display(), v.label()))
        })?;
    }
    Ok(found)
}

/// The problem of the command line, and what `--from` holds that is no
/// effect (in words: in no deployment, said so by [`run`]).
pub fn problem(args: &ReliabilityArgs) -> Result<(Problem, Vec<String>), CliError> {
    let mech = Mechanism::load(&args.mechanism).map_err(|e| CliError::input(e.to_string()))?;
    let (mut fixed, mut left_out) = (Vec::new(), Vec::new());
    if args.flight && mech.rig.is_none() && args.from.is_none() {
        left_out.push(format!(
            "--flight: {} has no [rig] and nothing is read --from findings: the deployments \
             are those of the mechanism as given",
            args.mechanism.display()
        ));
    }
    let mech = if args.flight { mech.flight() } else { mech };
    let mut vary = args.vary.clone();
    if let Some(f) = &args.from {
        let mut found = from_file(f, &args.vary, &mech)?;
        let from = format!("--from {}", f.display());
        let flight = if args.flight {
            found.take_out_the_rig_said(&from, "--flight")
        } else {
            Vec::new()
        };
        left_out.extend(found.notes(&from, &mech.name));
        left_out.extend(flight);
        vary.extend(found.vary);
        fixed = found.fixed;
    }
    let problem = Problem {
        mech,
        vary,
        fixed,
        fail: args.fail.clone(),
        corr: args.corr.clone(),
    };
    problem.check().map_err(|e| CliError::input(words(&e)))?;
    Ok((problem, left_out))
}

/// The option of the command line that sets `p`.
fn option(p: Param) -> &'static str {
    match p {
        Param::Vary => "--vary",
        Param::Fixed => "--from",
        Param::Fail => "--fail",
        Param::Corr => "--corr",
        Param::Samples => "--samples",
    }
}

/// A reliability error in words, each parameter named by its option.
fn words(e: &ReliabilityError) -> String {
    e.words(&|p| option(p).to_string())
}

/// Runs `deploywatch reliability`.
pub fn run(args: &ReliabilityArgs) -> Result<(), CliError> {
    let (problem, left_out) = problem(args)?;
    if let Some(j) = &args.json {
        let inputs: Vec<&Path> = std::iter::once(&args.mechanism)
            .chain(&args.from)
            .map(|p| p.as_path())
            .collect();
        check_output("--json", j, &inputs)?;
    }
    if let Some(c) = args.target_cov {
        if !(c > 0.0 && c.is_finite()) {
            return Err(CliError::input(format!(
                "--target-cov {c}: expected a positive number"
            )));
        }
    }
    let console = Console::new(args.quiet);
    for w in &left_out {
        console.warn(w);
    }
    let start = Instant::now();
    let mut eval = |xs: &[Vec<f64>]| problem.margins_batch(xs);
    let est = estimate(
        &problem,
        args.method,
        args.samples,
        args.target_cov,
        args.seed,
        &mut eval,
        console.progress(),
    )
    .map_err(|e| match e.is_input() {
        true => CliError::input(words(&e)),
        false => CliError::failed(words(&e)),
    })?;
    let wall = start.elapsed().as_secs_f64();
    print_estimate(&problem, &est, wall);
    // The checks after the result never cost it: one that cannot run is
    // itself a warning.
    let said = warnings(&problem, &est, args.target_cov, &|p| option(p).to_string());
    for w in &said {
        console.warn(w);
    }
    if let Some(j) = &args.json {
        let mut json = est.to_json(&problem, args.seed);
        // Every warning said, `--from`'s notes first, as on stderr.
        let all: Vec<&String> = left_out.iter().chain(&said).collect();
        json["warnings"] = serde_json::json!(all);
        let text =
            serde_json::to_string_pretty(&json).map_err(|e| CliError::failed(e.to_string()))?;
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
        "{}: P({}) by {}, {} parameter(s), {} failure mode(s)",
        problem.mech.name,
        fails.join(" or "),
        est.method,
        problem.vary.len(),
        problem.modes().len()
    );
    for v in &problem.vary {
        outln!("  {}", law(v));
    }
    for f in &problem.fixed {
        outln!(
            "  {} fixed as found, in every deployment ({})",
            f.effect,
            f.source
        );
    }
    if est.checks.is_empty() {
        print_detail(problem, est);
    }
    for c in &est.checks {
        print_detail(problem, c);
        outln!("{}: {}", c.method, summary(c));
    }
    match est.agree {
        Some(agree) => outln!(
            "auto: is and subset {} within their 95 % intervals",
            if agree { "agree" } else { "DISAGREE" }
        ),
        None if est.checks.len() > 1 => {
            outln!("auto: neither is nor subset saw a failure: nothing to compare")
        }
        None => {}
    }
    outln!("{}, {wall_s:.2} s wall", summary(est));
    if let Some(f) = &est.most_likely_failure {
        outln!(
            "most likely failure seen (beta {:.3}): {}",
            f.beta(),
            parameters(problem, &f.x)
        );
    }
}

/// `p_fail = … c.o.v. … 95 % […] n deployments, k failed`.
fn summary(est: &Estimate) -> String {
    let head = if est.converged {
        "p_fail ="
    } else {
        "p_fail (modes reached only) ="
    };
    format!(
        "{head} {:.4e}  c.o.v. {:.3}  95 % [{:.4e}, {:.4e}]  {} deployments, {} failed",
        est.p_fail, est.cov, est.ci95.0, est.ci95.1, est.simulations, est.failures
    )
}

/// The design points (is) or the levels of each mode (subset).
fn print_detail(problem: &Problem, est: &Estimate) {
    for d in &est.design_points {
        outln!(
            "  form: {}: beta {:.4} (first order: {:.3e}), {}",
            d.mode,
            d.beta,
            normal::tail(d.beta),
            parameters(problem, &d.x)
        );
    }
    for m in &est.unreached {
        outln!(
            "  form: {m}: not reached (no failure along the steepest descent within beta {}): \
             sampled around the origin too",
            form::BETA_MAX
        );
    }
    for r in &est.modes {
        let unit = r.mode.criterion.margin_unit();
        for (k, l) in r.levels.iter().enumerate() {
            outln!(
                "  subset: {}: level {k}: threshold {}, p = {:.4}, c.o.v. {:.3}, {} deployments",
                r.mode,
                quantity(l.threshold, unit),
                l.p,
                l.cov,
                l.simulations
            );
        }
        let b = quantity(r.levels.last().map_or(f64::NAN, |l| l.threshold), unit);
        if r.converged {
            outln!(
                "  subset: {}: P = {:.4e}, c.o.v. {:.3}, {:.3} of it not failing an earlier mode",
                r.mode,
                r.p,
                r.cov,
                r.counted
            );
        } else {
            let why = match r.stop {
                "negligible" => "its last level is below 1 % of the modes reached",
                "stalled" => "the thresholds stopped falling",
                _ => "the most levels",
            };
            outln!(
                "  subset: {}: not reached ({why}): margin <= {b} has P about {:.3e} \
                 (an estimate of that level, not a bound on the mode: the chains may not \
                 have entered all of its failures)",
                r.mode,
                r.p
            );
        }
    }
}

/// The parameters in words, `name = value unit, ...` ([`quantity`]).
fn parameters(problem: &Problem, x: &[f64]) -> String {
    let labels = crate::analysis::reliability::params::unique_labels(&problem.vary);
    let parts: Vec<String> = problem
        .vary
        .iter()
        .zip(&labels)
        .zip(x)
        .map(|((v, label), &x)| format!("{label} = {}", quantity(x, v.unit())))
        .collect();
    parts.join(", ")
}

/// A parameter and its law, `name:law(a,b), in unit` ([`sig`]).
fn law(v: &Vary) -> String {
    let args: Vec<f64> = match v.dist {
        Dist::Normal { mean, sd } => vec![mean, sd],
        Dist::LogNormal { median, sigma_ln } => vec![median, sigma_ln],
        Dist::Uniform { lo, hi } => vec![lo, hi],
        Dist::TruncNormal { mean, sd, lo, hi } => vec![mean, sd, lo, hi],
    };
    let name = v.dist.to_string();
    let name = name.split('(').next().unwrap_or_default();
    let args: Vec<String> = args.into_iter().map(sig).collect();
    let unit = match v.unit() {
        "1" => String::new(),
        u => format!(", in {u}"),
    };
    format!("{}:{name}({}){unit}", v.label(), args.join(","))
}
