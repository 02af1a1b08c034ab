//! `margin --from` and `reliability --from` with a diagnosis JSON
//! (`docs/margin.md` and `docs/reliability.md`, "From a diagnosis"; issue
//! 40, item 6): a file `deploywatch diagnose` wrote on a bundled campaign
//! (seed 001 T01 + T02, friction at joint 1 and a harness at joint 2) is
//! taken by both commands, every effect with its interval; the report's
//! next step runs as printed; what they cannot take is refused by name.

mod common;

use common::{data, deploywatch, fails, s, write as file};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Output;

fn mech(name: &str) -> PathBuf {
    data().join(format!("mechanisms/{name}.toml"))
}

/// Exit 0, no panic; stdout.
fn succeeds(out: &Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "panic:\n{err}");
    assert!(out.status.success(), "exit {:?}:\n{err}", out.status);
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// `deploywatch diagnose` on the bundled campaign `c_seed001_friction_harness`
/// into `dir/diagnosis.json`; the JSON's path.
fn diagnose_bundled(dir: &Path) -> PathBuf {
    let json = dir.join("diagnosis.json");
    let runs = data().join("examples/c_seed001_friction_harness");
    succeeds(&deploywatch(&[
        "diagnose",
        "-q",
        "--mechanism",
        s(&mech("seed001_T01")),
        "--mechanism",
        s(&mech("seed001_T02")),
        "--json",
        s(&json),
        s(&runs.join("seed001_T01.csv")),
        s(&runs.join("seed001_T02.csv")),
    ]));
    json
}

fn read_json(p: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(p).expect("written")).expect("JSON")
}

/// `margin` of seed001_T01 (with `--from FILE` when given); its JSON.
fn margins(from: Option<&Path>, dir: &Path) -> Value {
    let out = dir.join("margins.json");
    let t01 = mech("seed001_T01");
    let mut args = vec!["margin", "-q", "--mechanism", s(&t01), "--json", s(&out)];
    if let Some(f) = from {
        args.extend(["--from", s(f)]);
    }
    succeeds(&deploywatch(&args));
    read_json(&out)
}

/// The effect named `name` of a diagnosis JSON.
fn effect<'a>(d: &'a Value, name: &str) -> &'a Value {
    d["effects"]
        .as_array()
        .expect("effects")
        .iter()
        .find(|e| e["name"] == name)
        .unwrap_or_else(|| panic!("the diagnosis names no {name}: {d}"))
}

/// The report's next step, as printed: every `deploywatch` line of its
/// code blocks runs (the margin of each mechanism; the reliability of the
/// first, the others being the same command on another mechanism).
#[test]
fn the_reports_next_step_runs_as_printed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let json = diagnose_bundled(dir.path());
    let md = std::fs::read_to_string(json.with_extension("md")).expect("report");
    let next = &md[md.rfind("## Next step").expect("a next step")..];
    let commands: Vec<&str> = next
        .lines()
        .filter(|l| l.starts_with("deploywatch "))
        .collect();
    let margin: Vec<&&str> = commands.iter().filter(|c| c.contains(" margin ")).collect();
    let reliability: Vec<&&str> = commands
        .iter()
        .filter(|c| c.starts_with("deploywatch reliability "))
        .collect();
    assert_eq!(margin.len(), 2, "one margin per mechanism:\n{next}");
    assert_eq!(
        reliability.len(),
        2,
        "one reliability per mechanism:\n{next}"
    );
    for c in margin.iter().chain(reliability.iter().take(1)) {
        // The temporary paths hold no character a shell reads specially.
        assert!(!c.contains('\''), "{c}");
        let words: Vec<&str> = c.split_whitespace().skip(1).collect();
        assert!(words.contains(&s(&json)), "{c}");
        let out = succeeds(&deploywatch(&words));
        let said = if c.contains(" margin ") {
            format!("resistances from: diagnose ({})", json.display())
        } else {
            "p_fail".to_string()
        };
        assert!(out.contains(&said), "{c}:\n{out}");
    }
}

/// The values found reach the models: the margins at joint 1 take the
/// friction at the upper end of its interval (against the mechanism's own,
/// none), so its torque margin falls; the reliability draws each effect
/// from its interval, and a deployment time between the nominal one and
/// the one with the effects found fails in every deployment drawn.
#[test]
fn the_effects_found_reach_both_models() {
    let dir = tempfile::tempdir().expect("temp dir");
    let json = diagnose_bundled(dir.path());
    let d = read_json(&json);
    let coulomb = effect(&d, "coulomb_friction");
    let harness = effect(&d, "harness_stiffness");
    assert_eq!(coulomb["joint"], 1);
    assert_eq!(harness["joint"], 2);

    let nominal = margins(None, dir.path());
    let found = margins(Some(&json), dir.path());
    assert_eq!(nominal["joints"][0]["coulomb_nm"].as_f64(), Some(0.0));
    assert_eq!(found["joints"][0]["coulomb_nm"], coulomb["ci95"][1]);
    // Without friction the nominal margin is infinite (written `null`).
    let tm = |m: &Value| m["joints"][0]["torque_margin_pct"].as_f64();
    let before = tm(&nominal).unwrap_or(f64::INFINITY);
    let after = tm(&found).expect("a finite margin with the friction found");
    assert!(
        after < before,
        "joint 1's torque margin {before} % (nominal) → {after} % (found)"
    );

    // The deployment time of T01 as given and with the effects found.
    let latch_time = |from: Option<&Path>| {
        let run = dir.path().join("sim.csv");
        let t01 = mech("seed001_T01");
        let mut args = vec!["simulate", s(&t01), "--no-noise", "--out", s(&run)];
        if let Some(f) = from {
            args.extend(["--from", s(f)]);
        }
        let out = succeeds(&deploywatch(&args));
        out.lines()
            .filter_map(|l| l.split("latched at ").nth(1))
            .filter_map(|t| t.trim_end_matches(" s").parse::<f64>().ok())
            .fold(0.0, f64::max)
    };
    let (t_nominal, t_found) = (latch_time(None), latch_time(Some(&json)));
    assert!(t_found > t_nominal + 0.05, "{t_nominal} s → {t_found} s");
    let limit = format!("time>{}", 0.5 * (t_nominal + t_found));
    let rel = dir.path().join("reliability.json");
    let t01 = mech("seed001_T01");
    succeeds(&deploywatch(&[
        "reliability",
        s(&t01),
        "--from",
        s(&json),
        "--fail",
        &limit,
        "--method",
        "mc",
        "--samples",
        "40",
        "--json",
        s(&rel),
        "-q",
    ]));
    let r = read_json(&rel);
    let vary: Vec<&str> = r["vary"]
        .as_array()
        .expect("vary")
        .iter()
        .filter_map(Value::as_str)
        .collect();
    for (e, name) in [
        (coulomb, "coulomb_friction:joint=1"),
        (harness, "harness_stiffness:joint=2"),
    ] {
        let law = vary
            .iter()
            .find(|v| v.starts_with(name))
            .unwrap_or_else(|| panic!("no law for {name}: {vary:?}"));
        let mean = e["value"].as_f64().expect("value");
        let m: f64 = law
            .split("normal(")
            .nth(1)
            .and_then(|t| t.split(',').next())
            .and_then(|t| t.parse().ok())
            .expect("a normal law");
        assert!(
            (m - mean).abs() <= 1e-6 * mean.abs().max(1.0),
            "{law} for {mean}"
        );
    }
    let (n, failed) = (r["simulations"].as_u64(), r["failures"].as_u64());
    assert!(n.is_some_and(|n| n > 0), "{r}");
    assert_eq!(
        n, failed,
        "with the effects found every deployment is slower than {limit}: {r}"
    );
}

/// Both commands with `--from FILE` for seed001_T01.
fn both(from: &Path) -> [Output; 2] {
    let t01 = mech("seed001_T01");
    [
        deploywatch(&["margin", "-q", "--mechanism", s(&t01), "--from", s(from)]),
        deploywatch(&[
            "reliability",
            s(&t01),
            "--from",
            s(from),
            "--fail",
            "not_latched",
            "-q",
        ]),
    ]
}

/// A misspelt effect, a file that is not JSON, and JSON of neither kind:
/// exit 2, naming the file and what was expected.
#[test]
fn what_cannot_be_read_is_refused_naming_file_and_expectation() {
    let dir = tempfile::tempdir().expect("temp dir");
    let unknown = file(
        dir.path(),
        "unknown.json",
        r#"{"effects": [{"name": "coulomb_frictoin", "joint": 1, "value": 0.5, "ci95": [0.4, 0.6]}]}"#,
    );
    for out in both(&unknown) {
        fails(
            &out,
            2,
            &[
                s(&unknown),
                "coulomb_frictoin",
                "expected one of",
                "coulomb_friction",
            ],
        );
    }
    let broken = file(dir.path(), "broken.json", "{\"effects\": [{\"name\": ");
    for out in both(&broken) {
        fails(&out, 2, &[s(&broken), "not JSON"]);
    }
    let neither = file(dir.path(), "neither.json", r#"{"joints": 3}"#);
    for out in both(&neither) {
        fails(
            &out,
            2,
            &[
                s(&neither),
                "expected the JSON of `deploywatch identify`",
                "diagnose",
            ],
        );
    }
}

/// A diagnosis that names no effect: only `unexplained`, both commands
/// exit 2 saying so; nothing found, the margins are the mechanism's own
/// (said so) and the reliability exits 2 (nothing to draw). Beside a named
/// effect, `unexplained` is left out and said to be.
#[test]
fn a_diagnosis_without_a_named_effect_is_said_so() {
    let dir = tempfile::tempdir().expect("temp dir");
    let unexplained = file(
        dir.path(),
        "unexplained.json",
        r#"{"effects": [{"name": "unexplained", "joint": null, "value": null,
            "description": "the residual stays at 0.3 deg RMS"}]}"#,
    );
    for out in both(&unexplained) {
        fails(
            &out,
            2,
            &[
                s(&unexplained),
                "names no effect",
                "unexplained: the residual stays at 0.3 deg RMS",
            ],
        );
    }
    let none = file(dir.path(), "none.json", r#"{"effects": []}"#);
    let [margin, reliability] = both(&none);
    let text = succeeds(&margin);
    assert!(
        text.contains("no effect found") && text.contains("the margins of the mechanism as given"),
        "{text}"
    );
    fails(
        &reliability,
        2,
        &[s(&none), "names no effect", "no effect found"],
    );

    let beside = file(
        dir.path(),
        "beside.json",
        r#"{"effects": [
            {"name": "coulomb_friction", "joint": 1, "value": 0.5, "ci95": [0.49, 0.51]},
            {"name": "unexplained", "joint": null, "value": null, "description": "a ringing at 7 Hz"}]}"#,
    );
    let t01 = mech("seed001_T01");
    let out = deploywatch(&[
        "reliability",
        s(&t01),
        "--from",
        s(&beside),
        "--fail",
        "not_latched",
        "--method",
        "mc",
        "--samples",
        "20",
    ]);
    succeeds(&out);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("left out, not a named effect: unexplained: a ringing at 7 Hz"),
        "{err}"
    );
}

/// The flight unit (`reliability --flight`) draws no effect of the ground
/// rig a diagnosis named (a tilt of the rig here), and says so; without
/// `--flight` the same file draws it.
#[test]
fn the_flight_unit_draws_no_rig_effect_of_a_diagnosis() {
    let dir = tempfile::tempdir().expect("temp dir");
    let json = file(
        dir.path(),
        "rig.json",
        r#"{"effects": [
            {"name": "coulomb_friction", "joint": 1, "value": 0.5, "ci95": [0.4, 0.6]},
            {"name": "rig_tilt", "joint": null, "value": 0.1, "ci95": [0.08, 0.12], "alpha_deg": 0.0}
        ]}"#,
    );
    let t01 = mech("seed001_T01");
    let vary_of = |flight: bool| {
        let out_json = dir.path().join(format!("rel-{flight}.json"));
        let mut args = vec![
            "reliability",
            s(&t01),
            "--from",
            s(&json),
            "--fail",
            "not_latched",
            "--method",
            "mc",
            "--samples",
            "4",
            "--json",
            s(&out_json),
        ];
        if flight {
            args.push("--flight");
        }
        let out = deploywatch(&args);
        succeeds(&out);
        let r = read_json(&out_json);
        let vary: Vec<String> = r["vary"]
            .as_array()
            .expect("vary")
            .iter()
            .filter_map(|v| v.as_str().map(str::to_string))
            .collect();
        (vary, String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let (ground, _) = vary_of(false);
    assert!(
        ground.iter().any(|v| v.starts_with("rig_tilt")),
        "{ground:?}"
    );
    let (flight, said) = vary_of(true);
    assert!(
        flight
            .iter()
            .any(|v| v.starts_with("coulomb_friction:joint=1")),
        "{flight:?}"
    );
    assert!(
        !flight.iter().any(|v| v.starts_with("rig_tilt")),
        "{flight:?}"
    );
    assert!(
        said.contains("left out of the flight unit") && said.contains("rig_tilt"),
        "{said}"
    );
}
