//! A stalled joint's verdict against the run's duration: the draws of
//! `examples/ideal_ledger.rs` (seed 001 T01 with its identified friction
//! at 5 % lognormal dispersion, `--fail not_latched`, crude Monte-Carlo
//! draws of seed 0), each deployed the way `reliability` does
//! (`Problem::deploy_tuned`, the verdict's settings) with the mechanism's
//! `duration_s` at 6 s (the file's), 12 s and 30 s, a joint that stalls
//! left to creep on at the friction law's regularisation (`Stall::Creep`,
//! the contract's law) or held (`Stall::Hold`, the verdict's rule,
//! `docs/spec/physics.md` §4a, "Creep").
//!
//! Per row: the failures, the draws whose verdict differs from the held
//! 6 s row's, and the deployments per core-second (CPU time of the
//! process, every thread). It is a measurement: it exits 0 whatever the
//! verdicts (1 on an error).
//!
//! `cargo run --release -p deploywatch-sim --example stall_durations --
//! [DRAWS [MECH.toml VARY...]]` (default 20,000 draws of that case);
//! `scripts/measured.py run stall-durations ...` records it in
//! docs/measured.md.

use deploywatch_sim::deployment::{SimOptions, Stall};
use deploywatch_sim::reliability::mc::draw;
use deploywatch_sim::reliability::Problem;
use rayon::prelude::*;
use std::process::ExitCode;

#[path = "common/reliability_case.rs"]
mod case;
#[path = "common/cpu.rs"]
mod cpu;
use cpu::{cpu_s, load_average};

/// The durations of the rows \[s\].
const DURATIONS: [f64; 3] = [6.0, 12.0, 30.0];

/// Whether each draw failed, with `stall`, to `duration` \[s\], and the
/// CPU time it took \[s\].
fn row(
    problem: &Problem,
    xs: &[Vec<f64>],
    stall: Stall,
    duration: f64,
) -> Result<(Vec<bool>, f64), String> {
    let mut p = problem.clone();
    p.mech.duration_s = duration;
    let tune = move |o: &mut SimOptions| o.stall = stall;
    let t0 = cpu_s();
    let failed: Result<Vec<bool>, String> = xs
        .par_iter()
        .enumerate()
        .map(|(i, x)| {
            let (o, _) = p
                .deploy_tuned(x, &tune)
                .map_err(|e| format!("draw {i}: {e}"))?;
            Ok(o.g(&p.fail) <= 0.0)
        })
        .collect();
    Ok((failed?, cpu_s() - t0))
}

fn main() -> ExitCode {
    let (problem, draws, name) = match case::ideal_from_args(20_000) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("stall_durations: {e}");
            return ExitCode::from(2);
        }
    };
    let xs: Vec<Vec<f64>> = (0..draws as u64)
        .map(|i| problem.x_of(&draw(0, 0, i, problem.vary.len())))
        .collect();
    println!(
        "{name}, {draws} draws (seed 0), {} threads; load average at the start {}.\n",
        rayon::current_num_threads(),
        load_average()
    );
    println!("| a stalled joint | duration_s [s] | failed | p_fail | verdicts differ from held, 6 s | per core-second |");
    println!("|---|---|---|---|---|---|");
    let mut first: Option<Vec<bool>> = None;
    for (stall, words) in [(Stall::Hold, "held"), (Stall::Creep, "creeps on")] {
        for d in DURATIONS {
            let (failed, cpu) = match row(&problem, &xs, stall, d) {
                Ok(r) => r,
                Err(e) => {
                    eprintln!("stall_durations: {e}");
                    return ExitCode::FAILURE;
                }
            };
            let reference = first.get_or_insert_with(|| failed.clone());
            let differ = reference
                .iter()
                .zip(&failed)
                .filter(|(a, b)| a != b)
                .count();
            let n = failed.iter().filter(|f| **f).count();
            println!(
                "| {words} | {d} | {n} | {:.3e} | {differ} | {:.0} |",
                n as f64 / draws.max(1) as f64,
                draws as f64 / cpu.max(1e-9)
            );
        }
    }
    ExitCode::SUCCESS
}
