//! The on-board monitor on truss runs: runs of the seed
//! 000 truss wing (cases 2 and 3, nominal and with the paper's EFT), made
//! by the truss simulator and read by the reference sensor, replayed
//! through the monitor, whose model is the two-panel chain of the same
//! mechanism (the truss is not on board).
//!
//! Asserted: every latch is declared, never before its switch closes, and
//! within 30 ms of it. Measured and printed (`--nocapture`; the table of
//! docs/monitor.md, "Truss runs"): the monitor's Coulomb estimate per hinge
//! against the true EFT, and against the same panels deployed as an open
//! chain with the same EFT (what the reduced model absorbs of the truss).

use deploywatch_core::monitor::LatchState;
use deploywatch_core::monitor::Monitor;
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::identify::residual_check::synthetic_run;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::monitor_config::{monitor_config, replay};
use deploywatch_sim::run::Run;
use deploywatch_tests::data_dir;

const EFT: [f64; 3] = [0.54, 0.472, 0.065];

/// Replays `run` on the monitor of `mech` (the two-panel chain); returns
/// per joint the latch instant the monitor declared, the switch's first
/// closed sample, and the final Coulomb estimate [N·m] with its sd.
fn on_board(mech: &Mechanism, run: &Run) -> Vec<(Option<f32>, Option<f64>, f32, f32)> {
    let cfg = monitor_config::<2>(mech).unwrap();
    let mut monitor = Monitor::new(&cfg).unwrap();
    let statuses = replay(&mut monitor, run).unwrap();
    (0..2)
        .map(|j| {
            let declared = statuses
                .iter()
                .find(|s| s.joints[j].latch == LatchState::Latched)
                .map(|s| s.t_s);
            let switch = run.latch[j].iter().position(|&l| l).map(|i| run.t_s[i]);
            let last = statuses.last().unwrap().joints[j];
            (declared, switch, last.coulomb_nm, last.coulomb_sd_nm)
        })
        .collect()
}

#[test]
fn truss_runs_replay_with_exact_latches_and_the_absorbed_friction_is_measured() {
    println!("| case | run | joint | true EFT [N·m] | monitor Coulomb, truss run [N·m] | same panels as an open chain [N·m] | absorbed (truss − chain) [N·m] | latch declared − switch [ms] |");
    println!("|---|---|---|---|---|---|---|---|");
    for case in ["seed000_case2_truss", "seed000_case3_truss"] {
        let mech = Mechanism::load(&data_dir().join(format!("mechanisms/{case}.toml"))).unwrap();
        let mut chain = mech.clone();
        chain.truss = None;
        for (label, eft) in [("nominal", [0.0; 3]), ("EFT", EFT)] {
            let effects: Vec<Effect> = (0..3)
                .filter(|&j| eft[j] > 0.0)
                .map(|j| Effect::joint(EffectKind::CoulombFriction, j + 1, eft[j]))
                .collect();
            let run = synthetic_run(&mech, &effects, 7).unwrap();
            let chain_effects: Vec<Effect> = effects
                .iter()
                .copied()
                .filter(|e| e.joint <= Some(2))
                .collect();
            let chain_run = synthetic_run(&chain, &chain_effects, 7).unwrap();
            let truss = on_board(&mech, &run);
            let open = on_board(&chain, &chain_run);
            for j in 0..2 {
                let (declared, switch, c, sd) = truss[j];
                let declared = declared.expect("every latch declared") as f64;
                let switch = switch.expect("every switch closes");
                let lag_ms = 1e3 * (declared - switch);
                assert!(
                    (-1e-3..=30.0).contains(&lag_ms),
                    "{case} {label} joint {}: declared {declared} s, switch {switch} s",
                    j + 1
                );
                let (_, _, c_chain, sd_chain) = open[j];
                println!(
                    "| {} | {label} | {} | {:.3} | {c:.3} ± {sd:.3} | {c_chain:.3} ± {sd_chain:.3} | {:+.3} | {lag_ms:.1} |",
                    &case[8..13],
                    ["O", "I"][j],
                    eft[j],
                    c - c_chain
                );
                assert!(c.is_finite() && c_chain.is_finite());
            }
        }
    }
}
