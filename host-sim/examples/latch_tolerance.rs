//! What the integration tolerance does to a latch that rattles: the
//! five-panel wing `tests/data/rattling_five_panels.toml` (its joint 3 ball
//! plunger escapes over its crest several times) deployed nominally at
//! relative tolerances 1e-6 to 1e-10 (absolute a hundredth of it, the
//! energy ledger booked, not enforced), and at the simulator's defaults.
//! For each: every physical latch's escapes and impacts, where joint 3
//! ends, and the CPU time. The counts of a tolerance that has not
//! converged differ from the rest by more than their chaos spreads them;
//! what `diagnose` compares a run's latch events with is simulated at the
//! default accuracy for that reason.
//!
//! `cargo run --release -p deploywatch-sim --example latch_tolerance`

use deploywatch_sim::deployment::{sample_grid, SimOptions};
use deploywatch_sim::latch_deployment::simulate_physical;
use deploywatch_sim::mechanism::Mechanism;
use std::path::Path;

fn main() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/rattling_five_panels.toml");
    let m = Mechanism::load(&path).expect("the bundled test wing");
    let defaults = SimOptions {
        stop_when_deployed: false,
        ..SimOptions::default()
    };
    let at = |rtol: f64| SimOptions {
        rtol,
        atol: rtol * 1e-2,
        max_drift: f64::INFINITY,
        ..defaults
    };
    let rows = [
        ("1e-6, ledger booked", at(1e-6)),
        ("1e-7, ledger booked", at(1e-7)),
        ("1e-8, ledger booked", at(1e-8)),
        ("1e-9, ledger booked", at(1e-9)),
        ("1e-10, ledger booked", at(1e-10)),
        ("defaults (1e-8, ledger held)", defaults),
    ];
    println!("{}, nominal, {} s.\n", m.name, m.duration_s);
    let latched: Vec<usize> = (0..m.joint_count())
        .filter(|&j| m.latch(j).is_some())
        .collect();
    let heads: Vec<String> = latched
        .iter()
        .map(|j| format!("joint {}: escapes / impacts", j + 1))
        .collect();
    println!(
        "| rtol | {} | joint 3 ends [deg] | CPU [s] |",
        heads.join(" | ")
    );
    println!("|---|{}---|---|", "---|".repeat(latched.len()));
    for (name, opts) in rows {
        let grid = sample_grid(&m, &opts).expect("grid");
        let start = std::time::Instant::now();
        let run = match simulate_physical(&m, &[], &opts, grid) {
            Ok(run) => run,
            Err(e) => {
                println!("| {name} | {e} |");
                continue;
            }
        };
        let cpu = start.elapsed().as_secs_f64();
        let counts: Vec<String> = latched
            .iter()
            .map(|&j| {
                let spec = m.latch(j).expect("a physical latch");
                let latch = spec.to_core(m.joints[j].stowed_deg, 1.0, 1.0);
                run.outcome(j + 1, &latch)
                    .map_or("-".into(), |o| format!("{} / {}", o.escapes, o.impacts))
            })
            .collect();
        println!(
            "| {name} | {} | {:.2} | {cpu:.2} |",
            counts.join(" | "),
            run.end_phi_deg[2]
        );
    }
}
