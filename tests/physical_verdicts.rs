//! The reliability analysis's physical-latch runs give the same verdicts
//! without the energy ledger as with it: on a fixed sample of
//! crude Monte-Carlo draws (seed 0) of seed 001 T01 with its ball plungers
//! and with its pawls, each mode's margin is the same to the bit whether
//! the run keeps its ledger (`Keep::Ledger`, as `reliability` ran before)
//! or not (`Keep::Trajectory`). With the steps sized by the ledger too
//! (`Keep::Verdict`) the runs close their ledger with fewer evaluations of
//! the equations of motion; their verdicts are not asserted here (another
//! step sequence: `examples/physical_verdicts.rs` and
//! `examples/physical_tolerance.rs` count the verdicts that differ, recorded
//! in docs/measured.md).
//!
//! The runs ended once every latch is held for good (`Keep::Settled`, what
//! `reliability` runs) give every mode the margin of the run to `T`, to the
//! bit, on a larger fixed sample of both wings, and of the one-panel pawl
//! wing, where some of them do end early. The modes are those of both
//! latch criteria, `not_latched` (the switch) and `not_held` (the latch).

use deploywatch_sim::deployment::SimOptions;
use deploywatch_sim::latch_deployment::simulate_with;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::reliability::mc::draw;
use deploywatch_sim::reliability::{Keep, Problem};
use deploywatch_sim::trajectory::Samples;
use std::path::PathBuf;

/// Draws of the fixed sample, per wing.
const DRAWS: u64 = 6;

/// seed 001 T01 `name` with its friction given a 5 % normal dispersion.
fn problem(name: &str) -> Problem {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../data/mechanisms")
        .join(format!("{name}.toml"));
    let sd = [0.1315, 0.085, 0.00005];
    Problem {
        mech: Mechanism::load(&path).expect("bundled mechanism"),
        vary: (0..3)
            .map(|j| {
                format!("coulomb_friction:joint={}:normal(0,{})", j + 1, sd[j])
                    .parse()
                    .expect("vary")
            })
            .collect(),
        fixed: Vec::new(),
        fail: vec![
            "not_latched".parse().expect("criterion"),
            "not_held".parse().expect("criterion"),
        ],
        corr: Vec::new(),
    }
}

fn same_margins(name: &str) {
    let p = problem(name);
    let modes = p.modes();
    for i in 0..DRAWS {
        let x = p.x_of(&draw(0, 0, i, 3));
        let before = p
            .deploy_keeping(&x, Keep::Ledger)
            .expect("run")
            .margins(&modes);
        let now = p.deploy(&x).expect("run").margins(&modes);
        let bits = |m: &[f64]| m.iter().map(|g| g.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&before),
            bits(&now),
            "{name}, draw {i}: {before:?} vs {now:?}"
        );
        assert_eq!(
            before.iter().any(|&g| g <= 0.0),
            now.iter().any(|&g| g <= 0.0),
            "{name}, draw {i}: the verdicts differ"
        );
    }
}

#[test]
fn plunger_verdicts_are_the_same_without_the_ledger() {
    same_margins("seed001_T01_physical_latch");
}

#[test]
fn pawl_verdicts_are_the_same_without_the_ledger() {
    same_margins("seed001_T01_pawl");
}

/// The evaluations of the equations of motion over the fixed sample's runs
/// of `name` kept as `keep`, at the reliability's tolerances (1e-6); each
/// run closes its ledger (an `EnergyDrift` would fail it).
fn evaluations(name: &str, keep: Keep) -> usize {
    let p = problem(name);
    (0..DRAWS)
        .map(|i| {
            let x = p.x_of(&draw(0, 0, i, 3));
            let mut mech = p.mech.clone();
            let mut effects = Vec::new();
            for (v, &x) in p.vary.iter().zip(&x) {
                v.apply(x, &mut mech, &mut effects);
            }
            let end = [mech.duration_s];
            let opts = SimOptions {
                duration_s: Some(mech.duration_s),
                settle_s: Some(0.0),
                rtol: 1e-6,
                atol: 1e-6,
                ..SimOptions::default()
            };
            let run = simulate_with(&mech, &effects, &opts, Samples::Listed(&end), keep)
                .unwrap_or_else(|e| panic!("{name}, draw {i}, {keep:?}: {e}"));
            run.traj.stats.evaluations
        })
        .sum()
}

#[test]
fn ledger_sized_steps_take_fewer_evaluations() {
    for name in ["seed001_T01_physical_latch", "seed001_T01_pawl"] {
        let (ledger, sized) = (
            evaluations(name, Keep::Ledger),
            evaluations(name, Keep::Verdict),
        );
        assert!(
            sized < ledger,
            "{name}: {sized} evaluations with ledger-sized steps, {ledger} without"
        );
    }
}

/// Draws of the fixed sample of the held-for-good check, per wing.
const SETTLED_DRAWS: u64 = 40;

/// The draws of `p` (wing `name`) whose runs `Keep::Settled` ended before
/// `T`; panics on a draw whose margins or latch instants differ by a bit
/// from the run to `T` (`Keep::Ledger`).
fn settled_early(name: &str, p: &Problem) -> usize {
    let modes = p.modes();
    let mut early = 0;
    for i in 0..SETTLED_DRAWS {
        let x = p.x_of(&draw(0, 0, i, p.vary.len()));
        let full = p.deploy_keeping(&x, Keep::Ledger).expect("run to T");
        let settled = p.deploy_keeping(&x, Keep::Settled).expect("run");
        let (a, b) = (full.margins(&modes), settled.margins(&modes));
        let bits = |m: &[f64]| m.iter().map(|g| g.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a), bits(&b), "{name}, draw {i}: {a:?} vs {b:?}");
        assert_eq!(full.latch_s, settled.latch_s, "{name}, draw {i}");
        assert_eq!(full.held_s, settled.held_s, "{name}, draw {i}");
        assert!(settled.end_s <= full.end_s, "{name}, draw {i}");
        early += usize::from(settled.end_s < full.end_s);
    }
    early
}

#[test]
fn plunger_runs_held_for_good_keep_every_margin() {
    let name = "seed001_T01_physical_latch";
    settled_early(name, &problem(name));
}

#[test]
fn pawl_runs_held_for_good_keep_every_margin() {
    let name = "seed001_T01_pawl";
    settled_early(name, &problem(name));
}

/// On a wing whose spring is passive (the one-panel pawl, a linear
/// spring, its 0.3 N·m friction given a 5 % dispersion) the runs that
/// pass do end early, with the same margins.
#[test]
fn passive_pawl_runs_end_early_with_every_margin_kept() {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms/one_panel_pawl.toml");
    let p = Problem {
        mech: Mechanism::load(&path).expect("bundled mechanism"),
        vary: vec!["coulomb_friction:joint=1:normal(0,0.015)"
            .parse()
            .expect("vary")],
        fixed: Vec::new(),
        fail: vec![
            "not_latched".parse().expect("criterion"),
            "not_held".parse().expect("criterion"),
        ],
        corr: Vec::new(),
    };
    let early = settled_early("one_panel_pawl", &p);
    assert!(early > 0, "no run of {SETTLED_DRAWS} ended early");
}
