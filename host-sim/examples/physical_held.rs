//! How settled each of the two latch criteria is on the physical-latch
//! wings, and what faster settings keep of each: seed 001 T01 with its
//! ball plungers and with its pawls, the identified friction given a 5 %
//! normal dispersion, the crude Monte-Carlo draws of seed 0 (the draws of
//! `examples/physical_ledger.rs`), each deployed the way `reliability`
//! does (`Problem::deploy_tuned`: `Keep::Settled`, one sample at `T`)
//! with the verdict's settings (rtol = atol = 1e-6, the ledger held to
//! 1e-6 of the stored energy: the reference), at the tighter rtol = atol
//! = 1e-7, with the ledger held to 1e-4, and with the ledger booked but
//! not enforced (no step retaken).
//!
//! One run gives both verdicts: `not_latched` (a switch open at `T`) and
//! `not_held` (a latch not holding its joint at `T`: a ball plunger short
//! of its crest, a pawl out of its notch). Per wing and setting: the
//! failures of each, the draws whose verdict differs from the reference's
//! and the deployments per core-second (CPU time of the process,
//! `/proc/self/stat`, every thread). It is a measurement: it exits 0
//! whatever the verdicts (1 on an error).
//!
//! `cargo run --release -p deploywatch-sim --example physical_held -- [DRAWS]`
//! (default 200); `scripts/measured.py run physical-held ...` records it in
//! docs/measured.md.

use deploywatch_sim::deployment::{SimOptions, MAX_LEDGER_DRIFT};
use deploywatch_sim::reliability::{Problem, VERDICT_LEDGER_DRIFT};
use rayon::prelude::*;
use std::process::ExitCode;

#[path = "common/physical_case.rs"]
mod case;
#[path = "common/cpu.rs"]
mod cpu;
use case::WINGS;
use cpu::{cpu_s, load_average};

/// The settings compared, the reference first: rtol = atol, the ledger's
/// tolerance (of the stored energy; infinite: booked, not enforced).
const SETTINGS: [(&str, f64, f64); 4] = [
    ("reference: 1e-6, ledger 1e-6", 1e-6, MAX_LEDGER_DRIFT),
    ("1e-7, ledger 1e-6", 1e-7, MAX_LEDGER_DRIFT),
    ("1e-6, ledger 1e-4", 1e-6, VERDICT_LEDGER_DRIFT),
    ("1e-6, ledger not enforced", 1e-6, f64::INFINITY),
];

/// The criteria, each on its own.
const CRITERIA: [&str; 2] = ["not_latched", "not_held"];

/// Per draw, whether it failed each of [`CRITERIA`] with the settings
/// `(tol, drift)`, and the CPU seconds the draws took.
fn run(
    p: &Problem,
    xs: &[Vec<f64>],
    (tol, drift): (f64, f64),
) -> Result<(Vec<[bool; 2]>, f64), String> {
    let criteria: Vec<_> = CRITERIA
        .iter()
        .map(|c| c.parse().map_err(|e| format!("{e}")))
        .collect::<Result<_, String>>()?;
    let tune = move |o: &mut SimOptions| {
        o.rtol = tol;
        o.atol = tol;
        o.max_drift = drift;
    };
    let t0 = cpu_s();
    let out: Result<Vec<[bool; 2]>, String> = xs
        .par_iter()
        .enumerate()
        .map(|(i, x)| {
            let (o, _) = p
                .deploy_tuned(x, &tune)
                .map_err(|e| format!("draw {i}: {e}"))?;
            Ok([0, 1].map(|k| o.g(std::slice::from_ref(&criteria[k])) <= 0.0))
        })
        .collect();
    Ok((out?, cpu_s() - t0))
}

/// The rows of one wing.
fn wing(name: &str, sd: [f64; 3], draws: usize) -> Result<Vec<String>, String> {
    let (p, xs) = case::problem(name, sd, draws)?;
    let mut rows = Vec::new();
    let mut reference: Option<Vec<[bool; 2]>> = None;
    for (label, tol, drift) in SETTINGS {
        let (failed, cpu) = run(&p, &xs, (tol, drift))?;
        let base = reference.get_or_insert_with(|| failed.clone());
        let cells: Vec<String> = (0..2)
            .map(|k| {
                let count = failed.iter().filter(|f| f[k]).count();
                let flips = base
                    .iter()
                    .zip(&failed)
                    .filter(|(a, b)| a[k] != b[k])
                    .count();
                format!("{count} | {flips}")
            })
            .collect();
        rows.push(format!(
            "| {name} | {label} | {} | {:.1} |",
            cells.join(" | "),
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
    println!(
        "{draws} draws a wing (seed 0), {} threads; load average at the start {}.\n",
        rayon::current_num_threads(),
        load_average()
    );
    println!("| wing | settings | failed `not_latched` | differ from the reference's | failed `not_held` | differ from the reference's | per core-second |");
    println!("|---|---|---|---|---|---|---|");
    for (name, sd) in WINGS {
        match wing(name, sd, draws) {
            Ok(rows) => rows.iter().for_each(|r| println!("{r}")),
            Err(e) => {
                eprintln!("physical_held: {name}: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    ExitCode::SUCCESS
}
