//! What a model run of a wing with flexible panels (`physics.md` §12)
//! costs and how accurate it is at the tolerances a fit runs it at: seed
//! 000 case 1 (or a mechanism given) deployed rigid and with its first
//! mode at 5, 10 and 20 Hz (2 % damping), 2.5 s sampled at 100 Hz, the run
//! not stopped when deployed, as a diagnosis simulates it
//! (`campaign_sim::fit_sim_options_for`). Each row: the tolerances, the
//! accepted steps, the evaluations of the equations of motion, the CPU
//! time of one run, and the largest angle difference from the same run
//! at rtol 1e-10, atol 1e-12.
//!
//! `cargo run --release -p deploywatch-sim --example flexible_cost -- [MECH.toml]`

use deploywatch_sim::deployment::{simulate_at, SimOptions};
use deploywatch_sim::flex::PanelFlex;
use deploywatch_sim::mechanism::Mechanism;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[path = "common/cpu.rs"]
mod cpu;
use cpu::cpu_s;

/// Each row runs again until it has taken this much CPU time \[s\]: the
/// process clock ticks in hundredths of a second.
const CPU_S: f64 = 0.5;

fn main() -> ExitCode {
    let path = std::env::args().nth(1).map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms/seed000_case1.toml"),
        PathBuf::from,
    );
    let mut mech = match Mechanism::load(&path) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("flexible_cost: {e}");
            return ExitCode::from(2);
        }
    };
    let times: Vec<f64> = (0..250).map(|i| i as f64 * 0.01).collect();
    let base = SimOptions {
        stop_when_deployed: false,
        max_drift: f64::INFINITY,
        ..SimOptions::default()
    };
    println!("{}, 2.5 s at 100 Hz, one thread.\n", mech.name);
    println!("| first mode | rtol | atol | steps | evaluations | CPU per run [ms] | largest error [deg] |");
    println!("|---|---|---|---|---|---|---|");
    for hz in [0.0, 5.0, 10.0, 20.0] {
        mech.flexible = (hz > 0.0).then_some(PanelFlex {
            first_mode_hz: hz,
            damping_ratio: 0.02,
        });
        let exact = SimOptions {
            rtol: 1e-10,
            atol: 1e-12,
            ..base
        };
        let Ok(reference) = simulate_at(&mech, &[], &exact, &times) else {
            eprintln!("flexible_cost: {hz} Hz does not simulate");
            return ExitCode::FAILURE;
        };
        let tolerances: &[(f64, f64)] = if hz > 0.0 {
            &[(1e-7, 1e-9), (1e-6, 1e-7), (1e-5, 1e-6)]
        } else {
            &[(1e-7, 1e-9)]
        };
        for &(rtol, atol) in tolerances {
            let o = SimOptions { rtol, atol, ..base };
            let t0 = cpu_s();
            let (mut run, mut runs) = (None, 0usize);
            while runs == 0 || cpu_s() - t0 < CPU_S {
                run = simulate_at(&mech, &[], &o, &times).ok();
                runs += 1;
            }
            let cpu = (cpu_s() - t0) / runs as f64;
            let Some(s) = run else {
                eprintln!("flexible_cost: {hz} Hz at rtol {rtol} does not simulate");
                return ExitCode::FAILURE;
            };
            let mut worst: f64 = 0.0;
            for (a, b) in s.phi_deg.iter().zip(&reference.phi_deg) {
                for (x, y) in a.iter().zip(b) {
                    worst = worst.max((x - y).abs());
                }
            }
            let mode = if hz > 0.0 {
                format!("{hz} Hz")
            } else {
                "rigid".to_string()
            };
            println!(
                "| {mode} | {rtol:.0e} | {atol:.0e} | {} | {} | {:.2} | {worst:.1e} |",
                s.stats.steps,
                s.stats.evaluations,
                cpu * 1e3
            );
        }
    }
    ExitCode::SUCCESS
}
