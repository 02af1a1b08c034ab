//! Physical-latch verdicts three ways: seed 001 T01 with its ball plungers
//! and with its pawls, the identified friction of the mechanism files given
//! a 5 % normal dispersion (`coulomb_friction:joint=J:normal(0, 0.05 T_J)`
//! added to `T_J`), `--fail not_latched`, the crude Monte-Carlo draws of
//! seed 0. Each draw is simulated the way `reliability` does
//! (`Keep::Ledger`), without the ledger in the output
//! (`Keep::Trajectory`: the same bits, it exits 1 on a draw whose margins
//! differ by one) and with the steps sized by the ledger too
//! (`Keep::Verdict`: another step sequence), on one thread; the table gives
//! the failures of each, the draws whose verdict (failed or not) differs
//! from `Keep::Ledger`'s, and the deployments per core-second of each (CPU
//! time of the process, `/proc/self/stat`).
//!
//! `cargo run --release -p deploywatch-sim --example physical_verdicts -- [DRAWS]`
//! (default 20,000); `scripts/measured.py run physical-verdicts ...` records
//! it in docs/measured.md.

use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::reliability::mc::draw;
use deploywatch_sim::reliability::{Keep, Problem};
use rayon::prelude::*;
use std::path::PathBuf;
use std::process::ExitCode;

/// The wings and the 5 % dispersions of their friction [N·m] (0.05 × the
/// identified 2.63, 1.7 and 0.001 N·m of the mechanism files).
const WINGS: [(&str, [f64; 3]); 2] = [
    ("seed001_T01_physical_latch", [0.1315, 0.085, 0.00005]),
    ("seed001_T01_pawl", [0.1315, 0.085, 0.00005]),
];

#[path = "common/cpu.rs"]
mod cpu;
use cpu::cpu_s;

/// The margins of every draw kept as `keep` says, and the CPU seconds.
fn run(problem: &Problem, xs: &[Vec<f64>], keep: Keep) -> Result<(Vec<Vec<f64>>, f64), String> {
    let modes = problem.modes();
    let t0 = cpu_s();
    let out: Result<Vec<Vec<f64>>, String> = xs
        .par_iter()
        .map(|x| {
            let o = problem.deploy_keeping(x, keep).map_err(|e| e.to_string())?;
            Ok(o.margins(&modes))
        })
        .collect();
    Ok((out?, cpu_s() - t0))
}

/// A draw failed: some mode's margin ≤ 0.
fn failed(margins: &[f64]) -> bool {
    margins.iter().any(|&g| g <= 0.0)
}

/// The reliability problem of wing `mech`, its friction dispersed by `sd`.
fn problem(mech: Mechanism, sd: [f64; 3]) -> Problem {
    Problem {
        mech,
        vary: (0..3)
            .map(|j| {
                let v = format!("coulomb_friction:joint={}:normal(0,{})", j + 1, sd[j]);
                v.parse().expect("vary")
            })
            .collect(),
        fixed: Vec::new(),
        fail: vec!["not_latched".parse().expect("criterion")],
        corr: Vec::new(),
    }
}

fn main() -> ExitCode {
    let draws: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(20_000);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a thread pool");
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "{draws} draws a wing (seed 0), one thread; load average at the start {}.\n",
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(", ")
    );
    println!("| wing | failed, `Ledger` | failed, `Trajectory` | margins differ by a bit | failed, `Verdict` | verdicts differ | per core-second: `Ledger` | `Trajectory` | `Verdict` |");
    println!("|---|---|---|---|---|---|---|---|---|");
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms");
    let mut same = true;
    for (name, sd) in WINGS {
        let mech = Mechanism::load(&root.join(format!("{name}.toml"))).expect("bundled mechanism");
        let problem = problem(mech, sd);
        let xs: Vec<Vec<f64>> = (0..draws as u64)
            .map(|i| problem.x_of(&draw(0, 0, i, 3)))
            .collect();
        let runs = pool.install(|| {
            [Keep::Ledger, Keep::Trajectory, Keep::Verdict]
                .into_iter()
                .map(|keep| run(&problem, &xs, keep))
                .collect::<Result<Vec<_>, String>>()
        });
        let runs = match runs {
            Ok(r) => r,
            Err(e) => {
                eprintln!("{name}: {e}");
                return ExitCode::FAILURE;
            }
        };
        let [(before, cpu_before), (now, cpu_now), (sized, cpu_sized)] = &runs[..] else {
            return ExitCode::FAILURE;
        };
        let differ = before
            .iter()
            .zip(now)
            .filter(|(a, b)| {
                a.iter()
                    .zip(b.iter())
                    .any(|(x, y)| x.to_bits() != y.to_bits())
            })
            .count();
        let flips = before
            .iter()
            .zip(sized)
            .filter(|(a, b)| failed(a) != failed(b))
            .count();
        same &= differ == 0;
        let count = |m: &[Vec<f64>]| m.iter().filter(|r| failed(r)).count();
        let rate = |cpu: f64| draws as f64 / cpu;
        println!(
            "| {name} | {} | {} | {differ} | {} | {flips} | {:.0} | {:.0} | {:.0} |",
            count(before),
            count(now),
            count(sized),
            rate(*cpu_before),
            rate(*cpu_now),
            rate(*cpu_sized)
        );
    }
    if same {
        ExitCode::SUCCESS
    } else {
        eprintln!("the margins with and without the ledger in the output differ");
        ExitCode::FAILURE
    }
}
