//! Physical-latch wings' verdicts and rates against the energy ledger's
//! tolerance: seed 001 T01 with its ball plungers and with its
//! pawls, the identified friction given a 5 % normal dispersion,
//! `--fail not_latched`, the crude Monte-Carlo draws of seed 0, as
//! `examples/physical_verdicts.rs`; each draw deployed on one thread the
//! way `reliability` does (`Problem::deploy`: `Keep::Settled`, rtol = atol
//! = 1e-6, one sample at `T`) with its ledger held to
//!
//! - `MAX_LEDGER_DRIFT` (1e-6 of the stored energy): what `reliability`
//!   runs on a physical-latch wing, the reference;
//! - `VERDICT_LEDGER_DRIFT` (1e-4): what it runs on an ideal-latch wing;
//! - no tolerance (`f64::INFINITY`): the ledger booked but neither
//!   checked nor retaking any step, the steps sized by DOPRI5's error
//!   alone.
//!
//! The table gives each tolerance's failures (`p_fail` = failed / draws),
//! the draws whose verdict (failed or not) differs from the reference's,
//! and the deployments per core-second (CPU time of the process,
//! `/proc/self/stat`), with the load average at the start and the end. It
//! is a measurement: it exits 0 whatever the verdicts (1 on an error).
//!
//! `cargo run --release -p deploywatch-sim --example physical_ledger -- [DRAWS]`
//! (default 200); `scripts/measured.py run physical-ledger ...` records it
//! in docs/measured.md.

use deploywatch_sim::deployment::MAX_LEDGER_DRIFT;
use deploywatch_sim::reliability::{Problem, VERDICT_LEDGER_DRIFT};
use rayon::prelude::*;
use std::process::ExitCode;

/// The tolerances compared, the reference first.
const TOLERANCES: [(&str, f64); 3] = [
    ("reference, 1e-6", MAX_LEDGER_DRIFT),
    ("the ideal wing's, 1e-4", VERDICT_LEDGER_DRIFT),
    ("none (no step retaken)", f64::INFINITY),
];

#[path = "common/physical_case.rs"]
mod case;
#[path = "common/cpu.rs"]
mod cpu;
use case::WINGS;
use cpu::{cpu_s, load_average as load};

/// Whether each draw failed with the ledger held to `max_drift`, and the
/// CPU seconds they took.
fn run(problem: &Problem, xs: &[Vec<f64>], max_drift: f64) -> Result<(Vec<bool>, f64), String> {
    let fail = &problem.fail;
    let t0 = cpu_s();
    let out: Result<Vec<bool>, String> = xs
        .par_iter()
        .map(|x| {
            let o = problem
                .deploy_held(x, max_drift)
                .map_err(|e| e.to_string())?;
            Ok(o.g(fail) <= 0.0)
        })
        .collect();
    Ok((out?, cpu_s() - t0))
}

/// The rows of one wing.
fn wing(name: &str, sd: [f64; 3], draws: usize) -> Result<Vec<String>, String> {
    let (problem, xs) = case::problem(name, sd, draws)?;
    let mut rows = Vec::new();
    let mut reference: Option<Vec<bool>> = None;
    for (label, tol) in TOLERANCES {
        let (failed, cpu) = run(&problem, &xs, tol)?;
        let base = reference.get_or_insert_with(|| failed.clone());
        let flips = base.iter().zip(&failed).filter(|(a, b)| a != b).count();
        let count = failed.iter().filter(|&&f| f).count();
        rows.push(format!(
            "| {name} | {label} | {count} | {flips} | {:.1} |",
            draws as f64 / cpu.max(1e-9)
        ));
    }
    Ok(rows)
}

fn main() -> ExitCode {
    let draws: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(200);
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("a thread pool: {e}");
            return ExitCode::FAILURE;
        }
    };
    println!(
        "{draws} draws a wing (seed 0), one thread; load average at the start {}.\n",
        load()
    );
    println!("| wing | ledger tolerance | failed | verdicts differ from the reference's | per core-second |");
    println!("|---|---|---|---|---|");
    for (name, sd) in WINGS {
        match pool.install(|| wing(name, sd, draws)) {
            Ok(rows) => rows.iter().for_each(|r| println!("{r}")),
            Err(e) => {
                eprintln!("{name}: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    println!("\nLoad average at the end {}.", load());
    ExitCode::SUCCESS
}
