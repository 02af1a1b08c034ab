//! `deploywatch diagnose`'s options. `--max-seconds`: a limit too short
//! for any fit still reports the mechanisms as given (marked partial, not
//! "cannot be simulated"), and a limit past what the clock holds (`inf`,
//! `1e300`) is no limit, never a panic. `--max-effects`: a diagnosis that
//! names more effects than it says so. `cargo test -p deploywatch-sim
//! --test diagnose_options`.
mod common;

use common::{deploywatch, s, t01_mechanism, t01_run_text, write};
use serde_json::Value;

/// `diagnose` of a seed 001 T01 run (`run`, its CSV text) with
/// `--max-seconds limit`: (exit code, stderr, the JSON when written).
fn diagnose_within(limit: &str, run: &str) -> (Option<i32>, String, Option<Value>) {
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = write(dir.path(), "t01.csv", run);
    let json = dir.path().join("d.json");
    let mech = t01_mechanism();
    let out = deploywatch(&[
        "diagnose",
        "--mechanism",
        s(&mech),
        "--json",
        s(&json),
        "--max-seconds",
        limit,
        "--max-effects",
        "1",
        "-q",
        s(&csv),
    ]);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let v = std::fs::read_to_string(&json)
        .ok()
        .map(|t| serde_json::from_str(&t).expect("JSON"));
    (out.status.code(), err, v)
}

#[test]
fn a_limit_too_short_for_any_fit_reports_the_mechanisms_as_given() {
    let (code, err, v) = diagnose_within("1e-9", &t01_run_text());
    assert_eq!(code, Some(0), "{err}");
    let v = v.expect("the JSON is written");
    let partial = v["partial"].as_str().expect("marked partial");
    assert!(partial.contains("time"), "{partial}");
    assert!(
        v["baseline"]["rms_deg"]
            .as_f64()
            .is_some_and(f64::is_finite),
        "{}",
        v["baseline"]
    );
}

/// On a clean run of T01 (its diagnosis a fraction of a second, and cut
/// short by a limit of 1e-9 s as the bundled run's is), `inf` and `1e300`
/// let it finish.
#[test]
fn a_limit_past_the_clock_is_no_limit() {
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("clean.csv");
    let out = deploywatch(&[
        "simulate",
        s(&t01_mechanism()),
        "-o",
        s(&csv),
        "--seed",
        "4",
        "-q",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let clean = std::fs::read_to_string(&csv).expect("run");
    let (_, err, v) = diagnose_within("1e-9", &clean);
    let v = v.unwrap_or_else(|| panic!("the JSON is written: {err}"));
    assert!(v["partial"].is_string(), "1e-9 s cuts it short: {v}");
    for limit in ["inf", "1e300"] {
        let (code, err, v) = diagnose_within(limit, &clean);
        assert!(!err.contains("panicked"), "{limit}: {err}");
        assert_eq!(code, Some(0), "{limit}: {err}");
        let v = v.expect("the JSON is written");
        assert!(v["partial"].is_null(), "{limit}: {}", v["partial"]);
    }
}

/// Three effects hidden in a seed 001 T01 run, `--max-effects 1`: when the
/// diagnosis names more than one (an alternative that explains the runs
/// better), stderr says so with the count; when it does not, nothing.
#[test]
fn more_named_effects_than_max_effects_are_said() {
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("three.csv");
    let mech = t01_mechanism();
    let out = deploywatch(&[
        "simulate",
        s(&mech),
        "-o",
        s(&csv),
        "--seed",
        "2",
        "-q",
        "--effect",
        "coulomb_friction:joint=2:value=0.3",
        "--effect",
        "viscous_damping:joint=1:value=0.2",
        "--effect",
        "air_drag:value=0.3",
    ]);
    assert!(out.status.success());
    let json = dir.path().join("d.json");
    let out = deploywatch(&[
        "diagnose",
        "--mechanism",
        s(&mech),
        "--json",
        s(&json),
        "--max-effects",
        "1",
        "-q",
        s(&csv),
    ]);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(0), "{err}");
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let named = v["effects"]
        .as_array()
        .expect("effects")
        .iter()
        .filter(|e| !matches!(e["name"].as_str(), Some("torque_table" | "unexplained")))
        .count();
    let said = format!("names {named} effects, more than --max-effects 1");
    assert_eq!(err.contains(&said), named > 1, "{named} named:\n{err}");
    assert!(
        named > 1,
        "this run's diagnosis names its three effects: {}",
        v["effects"]
    );
}
