//! Physical-latch deployments ended once every latch is held for good
//! (`Keep::Settled`, what `reliability` runs) against the same draws run
//! to `T` (`Keep::Ledger`, as `reliability` ran before): seed 001 T01 with
//! its ball plungers and with its pawls, the identified friction of the
//! mechanism files given a 5 % normal dispersion, `--fail not_latched`,
//! the crude Monte-Carlo draws of seed 0, as `examples/physical_verdicts.rs`;
//! and the one-panel pawl wing (`one_panel_pawl.toml`, a linear spring),
//! its friction dispersed the same way.
//!
//! Each draw is run both ways back to back on one thread (so both see the
//! same load); the table gives the failures of each, the draws whose
//! margins differ by a bit (it exits 1 on one), the draws that ended early
//! and their mean end instant, and the deployments per core-second of each
//! (CPU time of the process, `/proc/self/stat`) with the load average at
//! the start and the end.
//!
//! `cargo run --release -p deploywatch-sim --example physical_settled -- [DRAWS]`
//! (default 200); `scripts/measured.py run physical-settled ...` records it
//! in docs/measured.md.

use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::reliability::mc::draw;
use deploywatch_sim::reliability::{Keep, Problem};
use std::path::PathBuf;
use std::process::ExitCode;

/// The wings and the 5 % dispersions of their joints' friction [N·m]
/// (0.05 × the identified 2.63, 1.7 and 0.001 N·m of the T01 files; 0.05 ×
/// the 0.3 N·m of the one-panel pawl, a wing on a linear spring).
const WINGS: [(&str, &[f64]); 3] = [
    ("seed001_T01_physical_latch", &[0.1315, 0.085, 0.00005]),
    ("seed001_T01_pawl", &[0.1315, 0.085, 0.00005]),
    ("one_panel_pawl", &[0.015]),
];

#[path = "common/cpu.rs"]
mod cpu;
use cpu::cpu_s;

/// The load average now, three figures.
fn load() -> String {
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    load.split_whitespace()
        .take(3)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The problem of wing `mech`, its friction dispersed by `sd`.
fn problem(mech: Mechanism, sd: &[f64]) -> Result<Problem, String> {
    Ok(Problem {
        mech,
        vary: sd
            .iter()
            .enumerate()
            .map(|(j, sd)| format!("coulomb_friction:joint={}:normal(0,{sd})", j + 1).parse())
            .collect::<Result<_, _>>()
            .map_err(|e| format!("{e}"))?,
        fail: vec!["not_latched".parse().map_err(|e| format!("{e}"))?],
        corr: Vec::new(),
        fixed: Vec::new(),
    })
}

/// A draw failed: some mode's margin ≤ 0.
fn failed(margins: &[f64]) -> bool {
    margins.iter().any(|&g| g <= 0.0)
}

/// Sums over the draws of one wing.
#[derive(Default)]
struct Tally {
    failed_full: usize,
    failed_settled: usize,
    differ: usize,
    early: usize,
    early_end_s: f64,
    cpu_full: f64,
    cpu_settled: f64,
}

/// Runs the draws of one wing both ways.
fn wing(p: &Problem, draws: u64) -> Result<Tally, String> {
    let modes = p.modes();
    let mut t = Tally::default();
    for i in 0..draws {
        let x = p.x_of(&draw(0, 0, i, p.vary.len()));
        let c0 = cpu_s();
        let full = p
            .deploy_keeping(&x, Keep::Ledger)
            .map_err(|e| e.to_string())?;
        let c1 = cpu_s();
        let settled = p
            .deploy_keeping(&x, Keep::Settled)
            .map_err(|e| e.to_string())?;
        let c2 = cpu_s();
        t.cpu_full += c1 - c0;
        t.cpu_settled += c2 - c1;
        let (a, b) = (full.margins(&modes), settled.margins(&modes));
        t.failed_full += usize::from(failed(&a));
        t.failed_settled += usize::from(failed(&b));
        let bits = |m: &[f64]| m.iter().map(|g| g.to_bits()).collect::<Vec<_>>();
        if bits(&a) != bits(&b) {
            t.differ += 1;
            eprintln!("draw {i}: margins {a:?} (to T) vs {b:?} (held for good)");
        }
        if settled.end_s < full.end_s {
            t.early += 1;
            t.early_end_s += settled.end_s;
        }
    }
    Ok(t)
}

fn main() -> ExitCode {
    let draws: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(200);
    println!(
        "{draws} draws a wing (seed 0), one thread, each run to `T` and ended when held for good, back to back; load average at the start {}.\n",
        load()
    );
    println!("| wing | failed, to `T` | failed, held for good | margins differ by a bit | ended early | their mean end [s] | per core-second, to `T` | per core-second, held for good | ratio |");
    println!("|---|---|---|---|---|---|---|---|---|");
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms");
    let mut same = true;
    for (name, sd) in WINGS {
        let tally = Mechanism::load(&root.join(format!("{name}.toml")))
            .map_err(|e| e.to_string())
            .and_then(|mech| problem(mech, sd))
            .and_then(|p| wing(&p, draws));
        let t = match tally {
            Ok(t) => t,
            Err(e) => {
                eprintln!("{name}: {e}");
                return ExitCode::FAILURE;
            }
        };
        same &= t.differ == 0;
        let n = draws as f64;
        let (full, settled) = (n / t.cpu_full.max(1e-9), n / t.cpu_settled.max(1e-9));
        println!(
            "| {name} | {} | {} | {} | {} | {:.2} | {full:.1} | {settled:.1} | {:.2} |",
            t.failed_full,
            t.failed_settled,
            t.differ,
            t.early,
            t.early_end_s / t.early.max(1) as f64,
            settled / full,
        );
    }
    println!("\nLoad average at the end {}.", load());
    if same {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
