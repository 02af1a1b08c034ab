//! `deploywatch margin` sets the nominal deployment beside its margins
//! (`docs/margin.md`, "The nominal deployment"): the run `simulate` makes
//! of the same chain, which joints its latches hold at the end, a warning
//! for a joint that passes every margin and is not held, and `--check`
//! failing on it. `cargo test -p deploywatch-sim --test margin_nominal`.
mod common;

use common::{data, deploywatch, fails, s};
use deploywatch_sim::deployment::{self, SimOptions};
use deploywatch_sim::latch_deployment::simulate_physical;
use deploywatch_sim::mechanism::Mechanism;
use serde_json::Value;

/// `margin --json` of a bundled mechanism: (stderr, the JSON).
fn margin(name: &str, extra: &[&str]) -> (String, Value) {
    let dir = tempfile::tempdir().expect("temp dir");
    let json = dir.path().join("m.json");
    let mech = data().join(format!("mechanisms/{name}.toml"));
    let mut args = vec!["margin", "--mechanism", s(&mech), "--json", s(&json), "-q"];
    args.extend_from_slice(extra);
    let out = deploywatch(&args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(0), "{name}: {err}");
    let v = serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("JSON");
    (err, v)
}

/// The joints (1-based) the simulator's own account of the run leaves
/// unheld: an ideal latch not latched, a physical latch that does not hold
/// its joint where the run ended (`LatchRun::outcome`).
fn unheld_by_the_simulator(name: &str) -> Vec<u64> {
    unheld(&Mechanism::load(&data().join(format!("mechanisms/{name}.toml"))).expect("mechanism"))
}

/// [`unheld_by_the_simulator`] of a mechanism.
fn unheld(mech: &Mechanism) -> Vec<u64> {
    let mech = mech.clone();
    let opts = SimOptions::default();
    if !mech.has_physical_latch() {
        let traj = deployment::simulate(&mech, &[], &opts).expect("run");
        return (0..traj.latch_s.len())
            .filter(|&j| traj.latch_s[j].is_none())
            .map(|j| j as u64 + 1)
            .collect();
    }
    let grid = deployment::sample_grid(&mech, &opts).expect("grid");
    let run = simulate_physical(&mech, &[], &opts, grid).expect("run");
    (0..mech.joint_count())
        .filter(|&j| match mech.latch(j) {
            Some(spec) => {
                let latch = spec.to_core(mech.joints[j].stowed_deg, 1.0, 1.0);
                !run.outcome(j + 1, &latch).expect("outcome").end.holds()
            }
            None => run.traj.latch_s[j].is_none(),
        })
        .map(|j| j as u64 + 1)
        .collect()
}

fn not_held(v: &Value) -> Vec<u64> {
    v["nominal_deployment"]["not_held"]
        .as_array()
        .expect("not_held")
        .iter()
        .map(|j| j.as_u64().expect("a joint"))
        .collect()
}

#[test]
fn the_nominal_deployment_is_the_run_simulate_makes() {
    let mut short = 0;
    for name in [
        "seed001_T01",
        "seed001_T02",
        "seed001_T01_pawl",
        "seed001_T01_physical_latch",
        "wing6_mixed",
        "wing6_plunger",
    ] {
        let (_, v) = margin(name, &[]);
        let d = &v["nominal_deployment"];
        let want = unheld_by_the_simulator(name);
        assert_eq!(not_held(&v), want, "{name}: {d}");
        let held = d["held_s"].as_array().expect("held_s");
        let ends = d["end_deg"].as_array().expect("end_deg");
        for (j, (h, e)) in held.iter().zip(ends).enumerate() {
            let e = e.as_f64().expect("an angle");
            match h.as_f64() {
                Some(t) => assert!(t >= 0.0 && t <= d["duration_s"].as_f64().unwrap() && e == 0.0),
                None => assert!(
                    want.contains(&(j as u64 + 1)) && e != 0.0,
                    "{name} {j}: {d}"
                ),
            }
        }
        short += want.len();
    }
    assert!(short > 0, "some bundled wing leaves a joint unheld");
}

#[test]
fn a_joint_that_passes_every_margin_but_is_not_held_is_named_and_fails_the_check() {
    // The six-panel plunger wing: a ball plunger throws a joint back out
    // of reach while its margins, joint by joint, pass.
    let (err, v) = margin("wing6_plunger", &[]);
    let short = not_held(&v);
    let passing: Vec<u64> = v["joints"]
        .as_array()
        .expect("joints")
        .iter()
        .filter(|j| j["pass"] == true)
        .map(|j| j["joint"].as_u64().expect("joint"))
        .filter(|j| short.contains(j))
        .collect();
    assert!(!passing.is_empty(), "{short:?}");
    let named: Vec<String> = passing.iter().map(|j| j.to_string()).collect();
    assert!(
        err.contains(&format!(
            "joint(s) {} of `wing6-plunger` pass every margin",
            named.join(", ")
        )),
        "{err}"
    );
    let mech = data().join("mechanisms/wing6_plunger.toml");
    let out = deploywatch(&["margin", "--mechanism", s(&mech), "--check", "-q"]);
    fails(
        &out,
        1,
        &["not held by their latch at the end of the nominal deployment"],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("nominal deployment") && text.contains("NOT held"),
        "{text}"
    );
    // Side by side under every standard: the same line, once.
    let out = deploywatch(&["margin", "--mechanism", s(&mech), "--all-standards"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(text.matches("nominal deployment (").count(), 1, "{text}");
    assert!(text.contains("NOT held"), "{text}");
    // Every joint held: no warning, and the check passes on the margins.
    let (err, v) = margin("seed001_T01", &[]);
    assert!(
        not_held(&v).is_empty() && !err.contains("pass every margin"),
        "{err}"
    );
    let t01 = data().join("mechanisms/seed001_T01.toml");
    let out = deploywatch(&["margin", "--mechanism", s(&t01), "--check", "-q"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// On a mechanism with a rig the nominal deployment is the rig's, and its
/// line says so; `--flight` takes the rig out of it as out of the margins.
#[test]
fn the_nominal_deployment_on_a_rig_is_the_rigs_and_says_so() {
    for name in ["seed001_T01_rig", "wing6_ideal_rig", "seed001_T02_rig"] {
        let mech =
            Mechanism::load(&data().join(format!("mechanisms/{name}.toml"))).expect("mechanism");
        assert!(mech.rig.is_some(), "{name} has a rig");
        for (flight, want) in [(false, unheld(&mech)), (true, unheld(&mech.flight()))] {
            let extra: &[&str] = if flight { &["--flight"] } else { &[] };
            let (_, v) = margin(name, extra);
            let d = &v["nominal_deployment"];
            assert_eq!(d["on_rig"], Value::Bool(!flight), "{name} {flight}: {d}");
            assert_eq!(not_held(&v), want, "{name} flight {flight}: {d}");
            let path = data().join(format!("mechanisms/{name}.toml"));
            let mut args = vec!["margin", "--mechanism", s(&path), "-q"];
            args.extend_from_slice(extra);
            let out = String::from_utf8_lossy(&deploywatch(&args).stdout).into_owned();
            let line = out
                .lines()
                .find(|l| l.starts_with("nominal deployment"))
                .unwrap_or_else(|| panic!("{name}: no nominal line in\n{out}"));
            assert_eq!(
                line.starts_with("nominal deployment on the rig ("),
                !flight,
                "{name} flight {flight}: {line}"
            );
        }
    }
}

/// A wing whose plunger at joint 3 rattles (it escapes over its crest
/// several times, a chaotic sequence): its nominal deployment holds joint
/// 3 at the simulator's tolerances and not at a tenth of them. `margin`
/// says so, writes it in the JSON (`unsettled`), and `--check` fails on
/// it; a wing whose latches settle (`wing6_mixed`) has none.
#[test]
fn a_nominal_outcome_that_moves_with_the_tolerance_is_said_and_fails_check() {
    let dir = tempfile::tempdir().expect("temp dir");
    let json = dir.path().join("m.json");
    let mech = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/rattling_five_panels.toml");
    let err = fails(
        &deploywatch(&["margin", "--mechanism", s(&mech), "--json", s(&json), "--check"]),
        1,
        &[
            "joint(s) 3 of `rattling-five-panels` held at the end of the nominal deployment in one of two runs",
            "margin --check: joint(s) 3",
        ],
    );
    assert!(err.contains("in one of its two runs"), "{err}");
    let v: Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("JSON");
    assert_eq!(
        v["nominal_deployment"]["unsettled"],
        serde_json::json!([3]),
        "{v}"
    );
    let (err, v) = margin("wing6_mixed", &[]);
    assert_eq!(
        v["nominal_deployment"]["unsettled"],
        serde_json::json!([]),
        "{v}"
    );
    assert!(!err.contains("two runs"), "{err}");
}
