//! Where an ideal-latch deployment's work goes: the draws of
//! `examples/ideal_ledger.rs` (seed 001 T01 with its identified friction at
//! 5 % lognormal dispersion, `--fail not_latched`, crude Monte-Carlo draws
//! of seed 0), each simulated with a verdict's settings
//! (`reliability::verdict_options`: rtol = atol = 1e-6, one sample at the
//! end, stopped when every joint latched) on one thread, its energy ledger held to the verdict's
//! tolerance (`VERDICT_LEDGER_DRIFT`, what `reliability` runs), to the
//! reference's (`MAX_LEDGER_DRIFT`) and not enforced (`f64::INFINITY`:
//! booked, never checked, no step retaken).
//!
//! Per deployment it prints the mean accepted steps, the steps rejected by
//! DOPRI5's error or retaken for the ledger, the evaluations of the
//! equations of motion, the events (latches, branch switches; a spring
//! knot ends a step without being one), the draws that did not deploy,
//! the CPU per evaluation and the deployments per core-second (CPU time of
//! the process, `/proc/self/stat`), with the load average. Exits 1 when
//! the draws that do not deploy differ between the rows.
//!
//! `cargo run --release -p deploywatch-sim --example ideal_profile -- [DRAWS
//! [MECH.toml VARY...]]` (default 2,000 draws of that case; any ideal-latch
//! mechanism with laws in the syntax of `--vary` instead).

use deploywatch_sim::deployment::{simulate_at, SimOptions, MAX_LEDGER_DRIFT};
use deploywatch_sim::reliability::mc::draw;
use deploywatch_sim::reliability::{verdict_options, Problem, VERDICT_LEDGER_DRIFT};
use std::process::ExitCode;

#[path = "common/reliability_case.rs"]
mod case;
#[path = "common/cpu.rs"]
mod cpu;
use cpu::cpu_s;

/// The sums over a row's draws.
#[derive(Default)]
struct Sums {
    steps: usize,
    rejected: usize,
    evaluations: usize,
    events: usize,
    /// The draws that did not deploy, by index.
    failed: Vec<usize>,
    cpu_s: f64,
}

/// Every draw of `problem` at `xs` with the ledger held to `max_drift`.
fn row(problem: &Problem, xs: &[Vec<f64>], max_drift: f64) -> Result<Sums, String> {
    let end = problem.run_end_s();
    let opts = SimOptions {
        max_drift,
        ..verdict_options(&problem.mech, end, false)
    };
    let mut s = Sums::default();
    let t0 = cpu_s();
    for (i, x) in xs.iter().enumerate() {
        let mut mech = problem.mech.clone();
        let mut effects = Vec::new();
        for (v, &x) in problem.vary.iter().zip(x) {
            v.apply(x, &mut mech, &mut effects);
        }
        let traj =
            simulate_at(&mech, &effects, &opts, &[end]).map_err(|e| format!("draw {i}: {e}"))?;
        s.steps += traj.stats.steps;
        s.rejected += traj.stats.rejected;
        s.evaluations += traj.stats.evaluations;
        s.events += traj.stats.events;
        if !traj.deployed() {
            s.failed.push(i);
        }
    }
    s.cpu_s = cpu_s() - t0;
    Ok(s)
}

fn main() -> ExitCode {
    let (problem, draws, name) = match case::ideal_from_args(2_000) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("ideal_profile: {e}");
            return ExitCode::from(2);
        }
    };
    let xs: Vec<Vec<f64>> = (0..draws as u64)
        .map(|i| problem.x_of(&draw(0, 0, i, problem.vary.len())))
        .collect();
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let load: Vec<&str> = load.split_whitespace().take(3).collect();
    println!(
        "{name}, {draws} draws (seed 0), one thread; load average at the start {}.\n",
        load.join(", ")
    );
    println!("| ledger | steps | rejected or retaken | evaluations | events | not deployed | CPU per evaluation [µs] | per core-second |");
    println!("|---|---|---|---|---|---|---|---|");
    let rows = [
        ("verdict, 1e-4", VERDICT_LEDGER_DRIFT),
        ("reference, 1e-6", MAX_LEDGER_DRIFT),
        ("none (no step retaken)", f64::INFINITY),
    ];
    let mut first: Option<Vec<usize>> = None;
    let mut differ = false;
    for (name, drift) in rows {
        let s = match row(&problem, &xs, drift) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("ideal_profile: {e}");
                return ExitCode::FAILURE;
            }
        };
        let n = draws.max(1) as f64;
        println!(
            "| {name} | {:.0} | {:.0} | {:.0} | {:.1} | {} | {:.3} | {:.0} |",
            s.steps as f64 / n,
            s.rejected as f64 / n,
            s.evaluations as f64 / n,
            s.events as f64 / n,
            s.failed.len(),
            s.cpu_s / s.evaluations.max(1) as f64 * 1e6,
            n / s.cpu_s.max(1e-9),
        );
        match &first {
            None => first = Some(s.failed),
            Some(f) => differ |= *f != s.failed,
        }
    }
    if differ {
        eprintln!("ideal_profile: the draws that do not deploy differ between the rows");
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
