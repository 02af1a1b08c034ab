//! How settled a physical-latch verdict is, and what a deployment costs in
//! evaluations of the equations of motion (a working measure that the
//! machine's load does not move): the draws of `examples/physical_verdicts.rs`
//! (seed 001 T01 with its ball plungers and with its pawls, friction with a
//! 5 % normal dispersion, `--fail not_latched`, crude Monte-Carlo draws of
//! seed 0), each simulated as `reliability` does (`Keep::Ledger` at its
//! tolerances, 1e-6), with the steps sized by the ledger too
//! (`Keep::Verdict`), and with `Keep::Ledger` at the tighter tolerances
//! 1e-7 and 1e-8. For each: the failures, the draws whose verdict differs
//! from the first's, and the mean steps, retaken or rejected steps and
//! evaluations per deployment.
//!
//! `cargo run --release -p deploywatch-sim --example physical_tolerance -- [DRAWS]`
//! (default 100).

use deploywatch_sim::deployment::SimOptions;
use deploywatch_sim::latch_deployment::{simulate_with, Keep, LatchRun};
use deploywatch_sim::reliability::Problem;
use deploywatch_sim::trajectory::Samples;
use rayon::prelude::*;

#[path = "common/physical_case.rs"]
mod case;
use case::WINGS;

/// The settings compared: how the run keeps and sizes its steps, and its
/// relative and absolute tolerance (`reliability`'s first).
const SETTINGS: [(Keep, f64); 4] = [
    (Keep::Ledger, 1e-6),
    (Keep::Verdict, 1e-6),
    (Keep::Ledger, 1e-7),
    (Keep::Ledger, 1e-8),
];

/// One draw's run at `x` with one setting, as `Problem::deploy` runs it
/// (no output sample but the last).
fn deploy(p: &Problem, x: &[f64], (keep, tol): (Keep, f64)) -> Result<LatchRun, String> {
    let mut mech = p.mech.clone();
    let mut effects = Vec::new();
    for (v, &x) in p.vary.iter().zip(x) {
        v.apply(x, &mut mech, &mut effects);
    }
    let end = [mech.duration_s];
    let opts = SimOptions {
        duration_s: Some(mech.duration_s),
        settle_s: Some(0.0),
        rtol: tol,
        atol: tol,
        ..SimOptions::default()
    };
    simulate_with(&mech, &effects, &opts, Samples::Listed(&end), keep).map_err(|e| e.to_string())
}

/// `not_latched` failed: some joint's switch not closed at the end, or
/// closed last at the end.
fn failed(run: &LatchRun, duration_s: f64) -> bool {
    run.traj
        .latch_s
        .iter()
        .any(|t| t.is_none_or(|t| t >= duration_s))
}

fn main() -> Result<(), String> {
    let draws: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100);
    println!("{draws} draws a wing (seed 0).\n");
    println!("| wing | run | tolerance | failed | verdicts differ from the first | steps | retaken or rejected | evaluations |");
    println!("|---|---|---|---|---|---|---|---|");
    for (name, sd) in WINGS {
        let (p, xs) = case::problem(name, sd, draws as usize)?;
        let duration = p.mech.duration_s;
        let mut first: Option<Vec<bool>> = None;
        for setting in SETTINGS {
            let runs: Vec<LatchRun> = xs
                .par_iter()
                .map(|x| deploy(&p, x, setting))
                .collect::<Result<_, _>>()?;
            let verdicts: Vec<bool> = runs.iter().map(|r| failed(r, duration)).collect();
            let base = first.get_or_insert_with(|| verdicts.clone());
            let flips = base.iter().zip(&verdicts).filter(|(a, b)| a != b).count();
            let mean = |f: &dyn Fn(&LatchRun) -> usize| {
                runs.iter().map(f).sum::<usize>() as f64 / draws as f64
            };
            println!(
                "| {name} | `{:?}` | {:e} | {} | {flips} | {:.0} | {:.0} | {:.0} |",
                setting.0,
                setting.1,
                verdicts.iter().filter(|&&f| f).count(),
                mean(&|r| r.traj.stats.steps),
                mean(&|r| r.traj.stats.rejected),
                mean(&|r| r.traj.stats.evaluations),
            );
        }
    }
    Ok(())
}
