//! What looser settings would buy an ideal-latch verdict, and what they
//! move: the draws of `examples/ideal_ledger.rs` (seed 001 T01 with its
//! identified friction at 5 % lognormal dispersion, `--fail not_latched`,
//! crude Monte-Carlo draws of seed 0), each deployed the way `reliability`
//! does (`Problem::deploy_tuned`: one sample at the end, stopped when every
//! joint latched) with the verdict's settings (`verdict_options`: rtol =
//! atol = 1e-6, longest step 0.05 s, the ledger held to
//! `VERDICT_LEDGER_DRIFT`) and with looser ones: rtol = atol up to 1e-3,
//! the longest step up to 0.2 s, the ledger's tolerance scaled with rtol
//! as the verdict's is (`VERDICT_LEDGER_DRIFT · rtol / VERDICT_RTOL`) or
//! not enforced.
//!
//! Per row: the mean accepted steps and evaluations of the equations of
//! motion per deployment, the deployments per core-second (CPU time of the
//! process, `/proc/self/stat`, every thread), the failures, the draws whose
//! verdict (failed or not) differs from the verdict settings' and the
//! largest difference of the system's margin `g` \[s\]. It is a
//! measurement: it exits 0 whatever the verdicts (1 on an error).
//!
//! `cargo run --release -p deploywatch-sim --example ideal_tolerance -- [DRAWS
//! [MECH.toml VARY...]]` (default 20,000 draws of that case; any
//! ideal-latch mechanism with laws in the syntax of `--vary` instead);
//! `scripts/measured.py run ideal-tolerance ...` records it in
//! docs/measured.md.

use deploywatch_sim::deployment::SimOptions;
use deploywatch_sim::reliability::mc::draw;
use deploywatch_sim::reliability::{Problem, VERDICT_LEDGER_DRIFT, VERDICT_RTOL};
use rayon::prelude::*;
use std::process::ExitCode;

#[path = "common/reliability_case.rs"]
mod case;
#[path = "common/cpu.rs"]
mod cpu;
use cpu::{cpu_s, load_average};

/// One row's settings: rtol = atol, the longest step \[s\], whether the
/// ledger is enforced (at the scaled tolerance) or only booked.
#[derive(Clone, Copy)]
struct Settings {
    rtol: f64,
    max_step_s: f64,
    ledger: bool,
}

/// The rows, the verdict's settings first.
const ROWS: [Settings; 6] = [
    Settings {
        rtol: VERDICT_RTOL,
        max_step_s: 0.05,
        ledger: true,
    },
    Settings {
        rtol: 1e-5,
        max_step_s: 0.05,
        ledger: true,
    },
    Settings {
        rtol: 1e-4,
        max_step_s: 0.05,
        ledger: true,
    },
    Settings {
        rtol: 1e-4,
        max_step_s: 0.05,
        ledger: false,
    },
    Settings {
        rtol: 1e-4,
        max_step_s: 0.1,
        ledger: true,
    },
    Settings {
        rtol: 1e-3,
        max_step_s: 0.2,
        ledger: true,
    },
];

/// What a row measured.
struct Row {
    /// The system's margin of each draw \[s\].
    g: Vec<f64>,
    steps: usize,
    evaluations: usize,
    cpu_s: f64,
}

/// Every draw of `problem` at `xs` with the settings `s`.
fn row(problem: &Problem, xs: &[Vec<f64>], s: Settings) -> Result<Row, String> {
    let tune = move |o: &mut SimOptions| {
        o.rtol = s.rtol;
        o.atol = s.rtol;
        o.max_step_s = s.max_step_s;
        o.max_drift = match s.ledger {
            true => VERDICT_LEDGER_DRIFT * s.rtol / VERDICT_RTOL,
            false => f64::INFINITY,
        };
    };
    let t0 = cpu_s();
    let out: Result<Vec<(f64, usize, usize)>, String> = xs
        .par_iter()
        .enumerate()
        .map(|(i, x)| {
            let (o, stats) = problem
                .deploy_tuned(x, &tune)
                .map_err(|e| format!("draw {i}: {e}"))?;
            Ok((o.g(&problem.fail), stats.steps, stats.evaluations))
        })
        .collect();
    let cpu = cpu_s() - t0;
    let out = out?;
    Ok(Row {
        g: out.iter().map(|r| r.0).collect(),
        steps: out.iter().map(|r| r.1).sum(),
        evaluations: out.iter().map(|r| r.2).sum(),
        cpu_s: cpu,
    })
}

fn main() -> ExitCode {
    let (problem, draws, name) = match case::ideal_from_args(20_000) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("ideal_tolerance: {e}");
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
    println!("| rtol = atol | longest step [s] | ledger | steps | evaluations | per core-second | failed | verdicts differ | largest difference of g [s] |");
    println!("|---|---|---|---|---|---|---|---|---|");
    let mut first: Option<Vec<f64>> = None;
    for s in ROWS {
        let r = match row(&problem, &xs, s) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("ideal_tolerance: {e}");
                return ExitCode::FAILURE;
            }
        };
        let g0 = first.get_or_insert_with(|| r.g.clone());
        let differ = g0
            .iter()
            .zip(&r.g)
            .filter(|(a, b)| (**a <= 0.0) != (**b <= 0.0))
            .count();
        let worst = g0
            .iter()
            .zip(&r.g)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let ledger = match s.ledger {
            true => format!("{:.0e}", VERDICT_LEDGER_DRIFT * s.rtol / VERDICT_RTOL),
            false => "booked, not enforced".to_string(),
        };
        let n = draws.max(1) as f64;
        println!(
            "| {:.0e} | {} | {ledger} | {:.0} | {:.0} | {:.0} | {} | {differ} | {worst:.1e} |",
            s.rtol,
            s.max_step_s,
            r.steps as f64 / n,
            r.evaluations as f64 / n,
            n / r.cpu_s.max(1e-9),
            r.g.iter().filter(|g| **g <= 0.0).count(),
        );
    }
    ExitCode::SUCCESS
}
