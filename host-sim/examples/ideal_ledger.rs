//! An ideal-latch wing's verdicts against the energy ledger's tolerance:
//! seed 001 T01 with its identified friction at 5 % lognormal dispersion
//! (the problem of `benches/reliability.rs` and of docs/reliability.md §6),
//! `--fail not_latched`, the crude Monte-Carlo draws of seed 0, each
//! deployed on one thread the way `reliability` does, with its ledger held
//! to the verdict's tolerance (`VERDICT_LEDGER_DRIFT`) and to the
//! reference's (`MAX_LEDGER_DRIFT`, every run's before). The table gives
//! each tolerance's failures, the draws whose verdict (failed or not)
//! differs from the reference's, the largest difference of a margin, and
//! the deployments per core-second (CPU time of the process,
//! `/proc/self/stat`). Exits 1 when a verdict differs.
//!
//! `cargo run --release -p deploywatch-sim --example ideal_ledger -- [DRAWS
//! [MECH.toml VARY...]]` (default 20,000 draws of that case; any
//! ideal-latch mechanism with laws in the syntax of `--vary` instead);
//! `scripts/measured.py run ideal-ledger ...` records it in
//! docs/measured.md.

use deploywatch_sim::deployment::MAX_LEDGER_DRIFT;
use deploywatch_sim::reliability::mc::draw;
use deploywatch_sim::reliability::{Problem, VERDICT_LEDGER_DRIFT};
use rayon::prelude::*;
use std::process::ExitCode;

#[path = "common/reliability_case.rs"]
mod case;
#[path = "common/cpu.rs"]
mod cpu;
use cpu::cpu_s;

/// The margins of every draw with the ledger held to `max_drift`, and the
/// CPU seconds they took.
fn run(problem: &Problem, xs: &[Vec<f64>], max_drift: f64) -> Result<(Vec<Vec<f64>>, f64), String> {
    let modes = problem.modes();
    let t0 = cpu_s();
    let out: Result<Vec<Vec<f64>>, String> = xs
        .par_iter()
        .map(|x| {
            let o = problem
                .deploy_held(x, max_drift)
                .map_err(|e| e.to_string())?;
            Ok(o.margins(&modes))
        })
        .collect();
    Ok((out?, cpu_s() - t0))
}

/// A draw failed: some mode's margin ≤ 0.
fn failed(margins: &[f64]) -> bool {
    margins.iter().any(|&g| g <= 0.0)
}

fn main() -> ExitCode {
    let (problem, draws, name) = match case::ideal_from_args(20_000) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("ideal_ledger: {e}");
            return ExitCode::from(2);
        }
    };
    let xs: Vec<Vec<f64>> = (0..draws as u64)
        .map(|i| problem.x_of(&draw(0, 0, i, problem.vary.len())))
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a thread pool");
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "{name}, {draws} draws (seed 0), one thread; load average at the start {}.\n",
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(", ")
    );
    println!("| ledger tolerance | failed | verdicts differ from the reference's | largest margin difference | per core-second |");
    println!("|---|---|---|---|---|");
    let tolerances = [
        ("reference", MAX_LEDGER_DRIFT),
        ("verdict", VERDICT_LEDGER_DRIFT),
    ];
    let runs = pool.install(|| {
        tolerances
            .iter()
            .map(|&(_, d)| run(&problem, &xs, d))
            .collect::<Result<Vec<_>, String>>()
    });
    let runs = match runs {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{name}: {e}");
            return ExitCode::FAILURE;
        }
    };
    let reference = &runs[0].0;
    let mut flips_total = 0;
    for ((name, drift), (margins, cpu)) in tolerances.iter().zip(&runs) {
        let flips = reference
            .iter()
            .zip(margins)
            .filter(|(a, b)| failed(a) != failed(b))
            .count();
        let worst = reference
            .iter()
            .zip(margins)
            .flat_map(|(a, b)| a.iter().zip(b.iter()).map(|(x, y)| (x - y).abs()))
            .fold(0.0f64, f64::max);
        flips_total += flips;
        println!(
            "| {name}, {drift:.0e} | {} | {flips} | {worst:.1e} | {:.0} |",
            margins.iter().filter(|m| failed(m)).count(),
            draws as f64 / cpu
        );
    }
    if flips_total > 0 {
        eprintln!("{flips_total} verdicts differ from the reference's");
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
