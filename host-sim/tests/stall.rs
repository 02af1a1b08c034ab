//! A joint that stalls with its friction holding it
//! (`docs/spec/physics.md` §4a, "Creep"; `docs/simulator.md`, "Stalls in
//! a verdict"): a verdict's deployment (`reliability`, `margin`'s nominal
//! deployment; `Stall::Hold`) holds it, so its answer does not depend on
//! `duration_s`; `simulate` keeps the contract's smooth law and says which
//! joints it latched only by creeping. `cargo test -p deploywatch-sim
//! --test stall`.
mod common;

use common::{data, deploywatch, s, t01_mechanism, write};
use deploywatch_sim::deployment::{sample_grid, simulate, SimOptions, Stall};
use deploywatch_sim::effect::{Effect, EffectKind};
use deploywatch_sim::latch_deployment::simulate_physical;
use deploywatch_sim::mechanism::Mechanism;
use std::path::{Path, PathBuf};

/// `name` (a bundled mechanism) with `duration_s` set to `seconds`,
/// written to `dir`.
fn with_duration(dir: &Path, name: &str, seconds: f64) -> PathBuf {
    let path = data().join("mechanisms").join(name);
    let text = std::fs::read_to_string(&path).expect("bundled mechanism");
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("duration_s"))
        .expect("a duration_s line");
    let out = text.replace(line, &format!("duration_s = {seconds:?}"));
    write(dir, &format!("{seconds}s_{name}"), out)
}

fn stdout(args: &[&str]) -> String {
    let out = deploywatch(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{args:?}:\n{err}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// One panel on a spring of 1 + 0.5 φ N·m (1.785 N·m at its stowed 90°),
/// 300 s long. With 2.0 N·m of friction it never moves in a verdict; with
/// 1.5 N·m it stalls in mid-stroke and stays, where `simulate` (the
/// contract's law) creeps it onto its latch and says so.
#[test]
fn a_stalled_panel_stays_stalled_in_a_verdict() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mech = with_duration(dir.path(), "reliability_one_panel.toml", 300.0);
    let said = stdout(&["margin", "--mechanism", s(&mech), "--friction", "2.0"]);
    let nominal = said
        .lines()
        .find(|l| l.starts_with("nominal deployment"))
        .expect(&said);
    assert!(nominal.contains("NOT held"), "{nominal}");
    assert!(nominal.contains("ended 90.00°"), "{nominal}");

    let csv = dir.path().join("creep.csv");
    let said = stdout(&[
        "simulate",
        s(&mech),
        "--effect",
        "coulomb_friction:joint=1:value=1.5",
        "--no-noise",
        "-o",
        s(&csv),
    ]);
    assert!(said.contains("joint 1: latched at"), "{said}");
    let line = said
        .lines()
        .find(|l| l.contains("latched only by creeping"))
        .expect(&said);
    // Where it stalls: past the angle where the spring's torque falls to
    // the friction (1 + 0.5 φ = 1.5 at φ = 57.3°), before the latch.
    let stalled: f64 = line
        .split("it stalls ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|v| v.parse().ok())
        .expect(line);
    assert!((1.0..57.3).contains(&stalled), "{line}");

    // The verdict's deployment: held there, the same at 100 s and 300 s.
    let m = Mechanism::load(&mech).expect("mechanism");
    let e = [Effect::joint(EffectKind::CoulombFriction, 1, 1.5)];
    let hold = |end: f64| {
        let opts = SimOptions {
            stall: Stall::Hold,
            duration_s: Some(end),
            ..SimOptions::default()
        };
        simulate(&m, &e, &opts).expect("simulates")
    };
    let (short, long) = (hold(100.0), hold(300.0));
    assert!(!short.deployed() && !long.deployed());
    let end = |t: &deploywatch_sim::deployment::Trajectory| *t.phi_deg[0].last().expect("samples");
    assert_eq!(end(&short), end(&long));
    assert!(
        (end(&long) - stalled).abs() < 0.01,
        "{} vs {stalled}",
        end(&long)
    );
}

/// Seed 001 T01 with its identified friction at 5 % dispersion: the
/// verdicts of the same 2,000 draws are the same with `duration_s` 6 s
/// (the file's) and 30 s, and some fail (joints that stall short of their
/// latch). Under the contract's law alone the 30 s run let most of them
/// creep in.
#[test]
fn reliability_verdicts_do_not_depend_on_the_duration() {
    let dir = tempfile::tempdir().expect("temp dir");
    let long = with_duration(dir.path(), "seed001_T01.toml", 30.0);
    let failed = |mech: &Path| -> String {
        let said = stdout(&[
            "reliability",
            s(mech),
            "--vary",
            "coulomb_friction:joint=1:lognormal(2.63,0.05)",
            "--vary",
            "coulomb_friction:joint=2:lognormal(1.7,0.05)",
            "--vary",
            "coulomb_friction:joint=3:lognormal(0.001,0.05)",
            "--fail",
            "not_latched",
            "--method",
            "mc",
            "--samples",
            "2000",
            "--seed",
            "0",
            "-q",
        ]);
        let line = said.lines().find(|l| l.starts_with("p_fail")).expect(&said);
        line.split(" deployments, ")
            .nth(1)
            .and_then(|r| r.split(' ').next())
            .expect(line)
            .to_string()
    };
    let (six, thirty) = (failed(&t01_mechanism()), failed(&long));
    assert_eq!(six, thirty, "failures in 6 s and in 30 s");
    assert!(six.parse::<usize>().expect("a count") > 0, "{six}");
}

/// With physical latches too: seed 001 T01's plungers, joint 2 with 1.9
/// N·m of friction beside its own 1.7 stalls mid-stroke. Over 30 s the
/// verdict's deployment holds it (the same angle at 10 s and at 30 s, its
/// energy ledger closed), where the contract's law creeps it on. (The
/// runs of 6 s and 30 s are not compared: the ledger's share of a step
/// goes with the duration, and the plungers' rattling of joints 1 and 3
/// makes two runs of other steps part.)
#[test]
fn a_stalled_joint_with_a_physical_latch_stays_in_a_verdict() {
    let m = Mechanism::load(&data().join("mechanisms/seed001_T01_physical_latch.toml"))
        .expect("mechanism");
    let e = [Effect::joint(EffectKind::CoulombFriction, 2, 1.9)];
    let run = |stall: Stall| {
        let opts = SimOptions {
            stall,
            duration_s: Some(30.0),
            ..SimOptions::default()
        };
        let grid = sample_grid(&m, &opts).expect("grid");
        let run = simulate_physical(&m, &e, &opts, grid).expect("simulates, ledger closed");
        let at = |t: f64| {
            let k = run.traj.t_s.iter().position(|&s| s >= t).expect("a sample");
            run.traj.phi_deg[1][k]
        };
        (at(10.0), at(30.0))
    };
    let (ten, thirty) = run(Stall::Hold);
    assert!(ten.abs() > 10.0, "joint 2 stalls short: {ten}");
    assert_eq!(ten, thirty, "held from 10 s to 30 s");
    let (ten, thirty) = run(Stall::Creep);
    assert!(
        thirty.abs() < ten.abs() - 1.0,
        "it creeps: {ten} at 10 s, {thirty} at 30 s"
    );
}

/// Seed 001 T01 with joint 2 seized (40 or 1000 N·m of friction against
/// its spring's 2.92 N·m): held from t = 0 in a verdict, it is kicked off
/// by joint 1's latch (friction's torque is bounded and takes no part in
/// an impulse), slides and is held again, the run's energy ledger closed;
/// the more friction, the less it slides. `reliability` over such draws
/// counts them as failures instead of stopping.
#[test]
fn a_seized_joint_moves_with_a_latch_s_impulse_and_fails_the_verdict() {
    let m = t01_mechanism();
    let mech = Mechanism::load(&m).expect("mechanism");
    let end_of_joint_2 = |nm: f64| {
        let e = [Effect::joint(EffectKind::CoulombFriction, 2, nm)];
        let opts = SimOptions {
            stall: Stall::Hold,
            ..SimOptions::default()
        };
        let run = simulate(&mech, &e, &opts).expect("simulates, ledger closed");
        assert!(run.latch_s[0].is_some() && run.latch_s[1].is_none());
        *run.phi_deg[1].last().expect("samples")
    };
    let (some, much) = (end_of_joint_2(40.0), end_of_joint_2(1000.0));
    let slid = |end: f64| (end - 180.0).abs();
    assert!(slid(much) > 1e-3, "kicked off its stowed 180°: {much}");
    assert!(slid(some) > slid(much), "{some} vs {much}");

    let said = stdout(&[
        "reliability",
        s(&m),
        "--vary",
        "coulomb_friction:joint=2:uniform(10,2000)",
        "--fail",
        "not_latched",
        "--method",
        "mc",
        "--samples",
        "20",
        "--seed",
        "1",
        "-q",
    ]);
    let line = said.lines().find(|l| l.starts_with("p_fail")).expect(&said);
    assert!(line.contains("20 deployments, 20 failed"), "{line}");
}

/// An eight-panel wing whose joints stall for a moment on their way in:
/// `simulate` (the contract's law) says at which instants a verdict's
/// deployment latches them instead, and the last of those is when
/// `margin`'s nominal deployment has every joint held.
#[test]
fn simulate_gives_the_latch_instants_of_a_verdict_where_they_differ() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mech = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/eight_panels.toml");
    let csv = dir.path().join("eight.csv");
    let said = stdout(&["simulate", s(&mech), "--no-noise", "-o", s(&csv)]);
    let line = said
        .lines()
        .find(|l| l.contains("a verdict's deployment"))
        .expect(&said);
    let instants: Vec<f64> = line
        .split(" at ")
        .skip(1)
        .filter_map(|r| r.split(" s").next()?.parse().ok())
        .collect();
    assert!(instants.len() >= 2, "{line}");
    let last = instants.iter().copied().fold(0.0, f64::max);
    let margin = stdout(&["margin", "--mechanism", s(&mech)]);
    let nominal = margin
        .lines()
        .find(|l| l.starts_with("nominal deployment"))
        .expect(&margin);
    assert!(
        nominal.contains(&format!("every joint held by its latch by {last:.3} s")),
        "{nominal} against {line}"
    );
}
