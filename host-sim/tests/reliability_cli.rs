//! `deploywatch reliability` as a user runs it: bad input exits 2 with a
//! message naming what is wrong, a deployment that cannot be simulated
//! exits 1 with its parameters, the JSON is the same for the same seed on 1
//! or 2 threads, and `--from` turns an identify result into normal laws.
//!
//! `cargo test -p deploywatch-sim --test reliability_cli`

mod common;

use common::{data, deploywatch, fails, s, write};
use std::process::Command;

fn one_panel() -> String {
    data()
        .join("mechanisms/reliability_one_panel.toml")
        .to_string_lossy()
        .into_owned()
}

#[test]
fn bad_input_exits_2_and_says_what_is_wrong() {
    let m = one_panel();
    let run = |args: &[&str]| {
        let mut all = vec!["reliability", m.as_str()];
        all.extend_from_slice(args);
        deploywatch(&all)
    };
    let v = "coulomb_friction:joint=1:normal(1,0.1)";
    fails(
        &run(&[
            "--vary",
            "coulomb_friction:joint=2:normal(1,0.1)",
            "--fail",
            "not_latched",
        ]),
        2,
        &["joint 2 does not exist"],
    );
    fails(
        &run(&[
            "--vary",
            "coulomb_friction:joint=1:gauss(1,0.1)",
            "--fail",
            "not_latched",
        ]),
        2,
        &["unknown law `gauss`"],
    );
    fails(
        &run(&["--vary", v, "--fail", "time>20"]),
        2,
        &["duration_s (10 s)"],
    );
    // A mechanism parameter is replaced by its draw: two laws for it would
    // leave only the last one counted. Two of an effect add, and stay.
    fails(
        &run(&[
            "--vary",
            "panel_mass:joint=1:normal(3,0.001)",
            "--vary",
            "panel_mass:joint=1:normal(300,0.001)",
            "--fail",
            "not_latched",
        ]),
        2,
        &["--vary panel_mass:joint=1", "varied twice", "one law"],
    );
    fails(
        &run(&["--vary", v, "--fail", "not_latched", "--method", "form"]),
        2,
        &["expected auto, is, subset or mc"],
    );
    fails(
        &run(&["--vary", v, "--fail", "landed"]),
        2,
        &["not_latched, latch_rate>X"],
    );
    fails(
        &run(&[
            "--vary",
            "spring_preload:joint=1:normal(1,0.1)",
            "--fail",
            "not_latched",
            "--json",
            "/no/such/folder/r.json",
        ]),
        2,
        &["does not exist"],
    );
    // Subset's samples per level refused before any deployment, not after
    // `auto`'s importance sampling has run its draws (no progress line).
    let err = fails(
        &run(&["--vary", v, "--fail", "not_latched", "--samples", "10"]),
        2,
        &["subset: 10 samples per level"],
    );
    assert!(!err.contains("is:") && !err.contains("form:"), "{err}");
    // What a valid count would be, in the units of `--samples`.
    fails(
        &run(&["--vary", v, "--fail", "not_latched", "--samples", "15"]),
        2,
        &["N·p0 = 1.5", "a multiple of 10 and at least 20"],
    );
    // A law's number out of range is named, with the value given.
    for (law, said) in [
        ("normal(1,-1)", "sd > 0 and finite, not -1"),
        ("lognormal(0,0.1)", "median > 0 and finite, not 0"),
        ("uniform(2,1)", "lo < hi, not lo = 2 and hi = 1"),
        ("truncnormal(1,0.1,nan,2)", "lo a number, not NaN"),
    ] {
        let vary = format!("coulomb_friction:joint=1:{law}");
        fails(
            &run(&["--vary", &vary, "--fail", "not_latched"]),
            2,
            &[&format!("`{law}`: expected {said}")],
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let not_findings = write(dir.path(), "x.json", "{\"rms\": 1}");
    fails(
        &run(&["--from", s(&not_findings), "--fail", "not_latched"]),
        2,
        &["deploywatch identify", "deploywatch diagnose"],
    );
    // A diagnosis that found nothing: nothing to carry, said so
    // (`docs/reliability.md`, "From a diagnosis").
    let nothing_found = write(dir.path(), "d.json", "{\"effects\": []}");
    fails(
        &run(&["--from", s(&nothing_found), "--fail", "not_latched"]),
        2,
        &["names no effect", "no effect found"],
    );
    // A normal law that reaches a negative mass: refused at the draw (1),
    // the message gives the parameters, the value and the bound.
    fails(
        &run(&[
            "--vary",
            "panel_mass:joint=1:normal(3,2)",
            "--fail",
            "not_latched",
            "--method",
            "mc",
            "--samples",
            "200",
            "-q",
        ]),
        1,
        &[
            "panel_mass:joint=1 = -",
            "panel_mass at joint 1 would be -",
            "expected > 0",
        ],
    );
    // A law whose tail makes friction drive its joint (the mechanism has
    // none of its own): refused at the draw, as `--effect` refuses a
    // negative friction, with the value; kept inside, it runs.
    let mc = [
        "--fail",
        "not_latched",
        "--method",
        "mc",
        "--samples",
        "200",
        "-q",
    ];
    let with = |law: &str| {
        let mut a = vec!["--vary", law];
        a.extend_from_slice(&mc);
        run(&a)
    };
    fails(
        &with("coulomb_friction:joint=1:normal(0.1,1)"),
        1,
        &[
            "coulomb_friction:joint=1 = -",
            "coulomb_friction at joint 1 would be -",
            "expected a finite number ≥ 0",
        ],
    );
    let kept = with("coulomb_friction:joint=1:truncnormal(0.1,1,0,inf)");
    assert!(
        kept.status.success(),
        "{}",
        String::from_utf8_lossy(&kept.stderr)
    );
}

#[test]
fn the_same_seed_gives_the_same_file_on_1_or_2_threads() {
    let dir = tempfile::tempdir().unwrap();
    let out = |threads: &str, name: &str| {
        let json = dir.path().join(name);
        let status = Command::new(env!("CARGO_BIN_EXE_deploywatch"))
            .env("RAYON_NUM_THREADS", threads)
            .args([
                "reliability",
                &one_panel(),
                "--vary",
                "coulomb_friction:joint=1:normal(1.1,0.1)",
                "--vary",
                "panel_inertia:joint=1:truncnormal(0.16,0.02,0.1,0.3)",
                "--fail",
                "not_latched",
                "--fail",
                "latch_rate>100",
                "--samples",
                "500",
                "--seed",
                "5",
                "-q",
                "--json",
                s(&json),
            ])
            .output()
            .unwrap();
        assert!(
            status.status.success(),
            "{}",
            String::from_utf8_lossy(&status.stderr)
        );
        std::fs::read_to_string(json).unwrap()
    };
    let one = out("1", "one.json");
    assert_eq!(one, out("2", "two.json"));
    let v: serde_json::Value = serde_json::from_str(&one).unwrap();
    for key in [
        "p_fail",
        "cov",
        "ci95",
        "simulations",
        "estimates",
        "agree",
        "most_likely_failure",
    ] {
        assert!(v.get(key).is_some(), "{key} missing:\n{one}");
    }
    let p = v["p_fail"].as_f64().unwrap();
    assert!(p > 0.0 && p < 1.0, "{p}");
    // auto: importance sampling around FORM's design points, then subset
    // simulation with one run per mode (criterion x joint).
    assert_eq!(v["method"], "auto");
    assert!(v["estimates"]["is"]["design_points"].is_array(), "{one}");
    assert_eq!(
        v["estimates"]["subset"]["modes"].as_array().unwrap().len(),
        2
    );
}

/// On seed 001 T01 with its pawls, eight crude Monte-Carlo draws fail
/// `not_latched` with a pawl in its notch and its switch open at the end:
/// the command says the verdict is the rattle's phase and names
/// `not_held`, which none of them fails. The ideal-latch wing says nothing
/// of it.
#[test]
fn a_switch_open_over_a_latch_that_holds_is_named() {
    let pawl = data().join("mechanisms/seed001_T01_pawl.toml");
    let ideal = data().join("mechanisms/seed001_T01.toml");
    let dir = tempfile::tempdir().expect("temp dir");
    let json = dir.path().join("r.json");
    // stdout, stderr and the JSON's `warnings`; a 5 % dispersion of the
    // friction seed 001 identified, which the pawl wing has as its own and
    // the ideal wing (none of its own) takes in the laws' means.
    let run = |mech: &std::path::Path, fail: &str| {
        let means = if mech == ideal {
            [2.63, 1.7, 0.001]
        } else {
            [0.0; 3]
        };
        let laws: Vec<String> = [0.1315, 0.085, 0.00005]
            .iter()
            .zip(means)
            .enumerate()
            .map(|(j, (sd, mean))| format!("coulomb_friction:joint={}:normal({mean},{sd})", j + 1))
            .collect();
        let out = deploywatch(&[
            "reliability",
            s(mech),
            "--vary",
            &laws[0],
            "--vary",
            &laws[1],
            "--vary",
            &laws[2],
            "--fail",
            fail,
            "--method",
            "mc",
            "--samples",
            "8",
            "--seed",
            "0",
            "--json",
            s(&json),
            "-q",
        ]);
        let (text, err) = (
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        );
        assert!(out.status.success(), "{text}\n{err}");
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("JSON");
        let warned: Vec<String> = v["warnings"]
            .as_array()
            .expect("a warnings array")
            .iter()
            .map(|w| w.as_str().expect("a string").to_string())
            .collect();
        (text, err, warned)
    };
    let named = "the criterion not_held counts what the latch does";
    let (text, err, warned) = run(&pawl, "not_latched");
    assert!(text.contains("most likely failure seen"), "{text}");
    assert!(err.contains(named), "{err}");
    assert!(err.contains("held by its latch"), "{err}");
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(
        warned[0].contains(named) && err.contains(&warned[0]),
        "{warned:?}\n{err}"
    );
    let (text, err, warned) = run(&pawl, "not_held");
    assert!(text.contains(" 0 failed"), "{text}");
    assert!(!err.contains(named), "{err}");
    assert!(warned.is_empty(), "{warned:?}");
    let (_, err, warned) = run(&ideal, "not_latched");
    assert!(!err.contains(named), "{err}");
    assert!(warned.is_empty(), "{warned:?}");
}

/// The false-bound case: T01 with joint 2's friction `lognormal(1.7,
/// 0.02)` failed at 3.6e-8, where the old subset printed `p_fail <
/// 1.06e-20` as a bound. Now both methods find joint 2's failures, agree,
/// and nothing printed is a bound.
#[test]
fn the_false_bound_of_t01_joint_2_is_gone() {
    let mech = data().join("mechanisms/seed001_T01.toml");
    let out = deploywatch(&[
        "reliability",
        s(&mech),
        "--vary",
        "coulomb_friction:joint=1:normal(2.63,1e-9)",
        "--vary",
        "coulomb_friction:joint=2:lognormal(1.7,0.02)",
        "--vary",
        "coulomb_friction:joint=3:normal(0.001,1e-9)",
        "--fail",
        "not_latched",
        "-q",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(!text.contains("p_fail <"), "{text}");
    assert!(text.contains("auto: is and subset agree"), "{text}");
    let line = text
        .lines()
        .rev()
        .find(|l| l.starts_with("p_fail"))
        .unwrap();
    let p: f64 = line
        .split_whitespace()
        .nth(if line.contains("only") { 5 } else { 2 })
        .unwrap()
        .parse()
        .unwrap();
    // Exact: Φ(−ln(1.89327/1.7)/0.02) = 3.64e-8, plus 0.70e-8 from the
    // window of 1.87771–1.87786 N·m where joint 2 sticks short of its
    // latch (tests/reliability.rs): 4.34e-8.
    assert!((4.34e-8 / 2.0..4.34e-8 * 2.0).contains(&p), "{line}");
}

#[test]
fn from_takes_the_identified_values_and_their_intervals_as_normal_laws() {
    let dir = tempfile::tempdir().unwrap();
    let eft = write(
        dir.path(),
        "eft.json",
        r#"{"method": "direct", "joints": [{"joint": 1, "coulomb_nm": 1.2, "ci95": [1.0, 1.4], "sd_nm": 0.1}]}"#,
    );
    let json = dir.path().join("r.json");
    let out = deploywatch(&[
        "reliability",
        &one_panel(),
        "--from",
        s(&eft),
        "--fail",
        "not_latched",
        "--samples",
        "500",
        "-q",
        "--json",
        s(&json),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let vary = v["vary"][0].as_str().unwrap();
    // sd = (1.4 − 1.0) / (2 · 1.96) = 0.10204 N·m.
    assert!(
        vary.starts_with("coulomb_friction:joint=1:normal(1.2,0.1020"),
        "{vary}"
    );
    // An interval that reaches below zero friction (the mechanism has none
    // of its own): the law is kept where the friction is ≥ 0, and every
    // draw runs.
    let near_zero = write(
        dir.path(),
        "zero.json",
        r#"{"method": "direct", "joints": [{"joint": 1, "coulomb_nm": 2.5e-5, "ci95": [-7e-5, 1.2e-4], "sd_nm": 4.8e-5}]}"#,
    );
    let out = deploywatch(&[
        "reliability",
        &one_panel(),
        "--from",
        s(&near_zero),
        "--fail",
        "not_latched",
        "--method",
        "mc",
        "--samples",
        "200",
        "-q",
        "--json",
        s(&json),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let vary = v["vary"][0].as_str().unwrap();
    // Found on no wing the file names: nothing said of it.
    assert!(!String::from_utf8_lossy(&out.stderr).contains("found on"));
    assert!(
        vary.starts_with("coulomb_friction:joint=1:truncnormal(0.000025,0.0000484")
            && vary.ends_with(",0,inf)"),
        "{vary}"
    );
}

/// The significant digits of a number as printed (`1.40769` → 6, `8e-9`
/// → 1, `0.000123` → 3).
fn significant(number: &str) -> usize {
    let mantissa = number.split(['e', 'E']).next().unwrap_or_default();
    let digits: String = mantissa.chars().filter(|c| c.is_ascii_digit()).collect();
    digits.trim_start_matches('0').len()
}

/// What a reader compares: the laws, the thresholds, the design point and
/// the most likely failure carry their units and at most 7 significant
/// digits (not 17); the JSON keeps every digit.
#[test]
fn thresholds_and_parameters_carry_units_and_few_digits() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("r.json");
    let out = deploywatch(&[
        "reliability",
        &one_panel(),
        "--vary",
        "coulomb_friction:joint=1:normal(0.9321262344584399,0.1)",
        "--vary",
        "spring_stiffness:joint=1:normal(0.5,0.01)",
        "--fail",
        "not_latched",
        "--fail",
        "time>9",
        "--samples",
        "1000",
        "-q",
        "--json",
        s(&json),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("coulomb_friction:joint=1:normal(0.932126,0.1), in N·m"),
        "{text}"
    );
    assert!(
        text.contains("spring_stiffness:joint=1:normal(0.5,0.01), in N·m/rad"),
        "{text}"
    );
    // Every `name = value` of a design point or failure point: a number of
    // at most 7 significant digits, then its unit.
    let mut points = 0;
    for line in text
        .lines()
        .filter(|l| l.contains("most likely failure") || l.contains("form:"))
    {
        for part in line.split(", ").filter(|p| p.contains(" = ")) {
            let value = part.rsplit(" = ").next().unwrap();
            let mut words = value.split_whitespace();
            let number = words.next().unwrap();
            assert!(number.parse::<f64>().is_ok(), "{part} in {line}");
            assert!(significant(number) <= 7, "{part} in {line}");
            let unit = words.next().unwrap_or("");
            assert!(["N·m", "N·m/rad"].contains(&unit), "{part} in {line}");
            points += 1;
        }
    }
    assert!(points >= 4, "{text}");
    // Every subset threshold in seconds, with few digits.
    let thresholds: Vec<&str> = text
        .lines()
        .filter_map(|l| l.split("threshold ").nth(1))
        .collect();
    assert!(thresholds.len() >= 4, "{text}");
    for t in thresholds {
        let mut words = t.split(&[' ', ','][..]);
        let number = words.next().unwrap();
        assert!(significant(number) <= 7, "{t}");
        assert_eq!(words.next(), Some("s"), "{t}");
    }
    // The JSON keeps every digit.
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    let x = v["most_likely_failure"]["parameters"]["coulomb_friction:joint=1"]
        .as_f64()
        .unwrap();
    assert!(significant(&x.to_string()) > 7, "{x}");
}

/// A target c.o.v. that a thousand deployments meet ends crude
/// Monte-Carlo there (the first batch of a run with a target), not after
/// ten thousand; those deployments are the first thousand of the run
/// without a target, so the estimate is theirs.
#[test]
fn a_target_cov_met_early_ends_crude_monte_carlo_early() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mech = data().join("mechanisms/reliability_one_panel.toml");
    let run = |extra: &[&str], name: &str| -> serde_json::Value {
        let json = dir.path().join(name);
        let mut args = vec![
            "reliability",
            s(&mech),
            "--vary",
            "coulomb_friction:joint=1:normal(1.3,0.1)",
            "--fail",
            "not_latched",
            "--method",
            "mc",
            "--json",
            s(&json),
            "-q",
        ];
        args.extend_from_slice(extra);
        let out = deploywatch(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("JSON")
    };
    let target = run(&["--samples", "20000", "--target-cov", "0.1"], "t.json");
    let first = run(&["--samples", "1000"], "f.json");
    let n = |v: &serde_json::Value| v["simulations"].as_u64().expect("simulations");
    assert_eq!(n(&target), 1000, "{target}");
    assert!(target["cov"].as_f64().expect("cov") <= 0.1, "{target}");
    assert_eq!(target["p_fail"], first["p_fail"], "{target}\n{first}");
}

/// A c.o.v. above the one asked is said on stderr and in the JSON's
/// `warnings`, word for word.
#[test]
fn a_target_cov_not_reached_is_a_warning_in_the_json_too() {
    let dir = tempfile::tempdir().expect("temp dir");
    let json = dir.path().join("r.json");
    let mech = data().join("mechanisms/reliability_one_panel.toml");
    let out = deploywatch(&[
        "reliability",
        s(&mech),
        "--vary",
        "coulomb_friction:joint=1:lognormal(0.1,0.1)",
        "--fail",
        "not_latched",
        "--method",
        "mc",
        "--samples",
        "40",
        "--target-cov",
        "0.001",
        "--json",
        s(&json),
        "-q",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("JSON");
    let warned = v["warnings"].as_array().expect("a warnings array");
    assert_eq!(warned.len(), 1, "{warned:?}");
    let w = warned[0].as_str().expect("a string");
    assert!(w.contains("is above the target c.o.v. 0.001"), "{w}");
    assert!(err.contains(w), "stderr says it too:\n{err}");
}

/// `--from` findings made on another wing are applied as they are, and
/// the command says so (as `margin --from` does).
#[test]
fn from_findings_of_another_wing_are_said() {
    let dir = tempfile::tempdir().unwrap();
    let eft = write(
        dir.path(),
        "eft.json",
        r#"{"method": "direct", "joints": [{"joint": 1, "coulomb_nm": 1.2, "ci95": [1.0, 1.4]}],
            "after": {"rms_deg": 0.02, "runs": [{"run": "a.csv", "mechanism": "another-wing", "rms_deg": 0.02}]}}"#,
    );
    let json = dir.path().join("r.json");
    let out = deploywatch(&[
        "reliability",
        &one_panel(),
        "--from",
        s(&eft),
        "--fail",
        "not_latched",
        "--method",
        "mc",
        "--samples",
        "50",
        "--json",
        s(&json),
        "-q",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let said = format!(
        "--from {}: found on another-wing, not on reliability-one-panel: applied as it is",
        eft.display()
    );
    assert!(err.contains(&format!("warning: {said}")), "{err}");
    // The JSON's warnings are every warning said, this one too.
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("JSON");
    assert_eq!(v["warnings"][0], serde_json::json!(said), "{v}");
}

/// A law `--from` gives that the wing refuses is said of the file (not of
/// a `--vary` the user never gave); a pair of parameters given two
/// correlations is refused (not the last one kept); a `truncnormal` whose
/// window lies far in its tail is drawn inside the window, not at its far
/// end.
#[test]
fn from_corr_and_a_far_window_say_and_draw_what_was_given() {
    let dir = tempfile::tempdir().unwrap();
    let three = write(
        dir.path(),
        "eft3.json",
        r#"{"method": "direct", "joints": [{"joint": 3, "coulomb_nm": 0.1, "ci95": [0.0, 0.2]}]}"#,
    );
    let err = fails(
        &deploywatch(&[
            "reliability",
            &one_panel(),
            "--from",
            s(&three),
            "--fail",
            "not_latched",
        ]),
        2,
        &["--from", "eft3.json", "joint 3 does not exist"],
    );
    assert!(!err.contains("--vary"), "{err}");

    let t01 = data().join("mechanisms/seed001_T01.toml");
    let run = |extra: &[&str]| {
        let mut a = vec!["reliability", s(&t01), "--fail", "not_latched"];
        a.extend_from_slice(extra);
        a.extend_from_slice(&["--method", "mc", "--samples", "40", "-q"]);
        deploywatch(&a)
    };
    fails(
        &run(&[
            "--vary",
            "coulomb_friction:joint=1:normal(2.63,0.05)",
            "--vary",
            "coulomb_friction:joint=2:normal(1.7,0.05)",
            "--corr",
            "1,2,0.5",
            "--corr",
            "2,1,-0.5",
        ]),
        2,
        &["--corr 2,1,-0.5", "already correlated by 1,2,0.5"],
    );
    // With joints 1 and 3 at their identified friction, joint 2 fails to
    // latch above about 1.89 N·m. Kept to [1.85, 1.95], 85 deviations
    // above its mean, the law's mass is within 1e-3 N·m of 1.85: no draw
    // fails.
    let out = run(&[
        "--vary",
        "coulomb_friction:joint=1:normal(2.63,1e-9)",
        "--vary",
        "coulomb_friction:joint=3:normal(0.001,1e-9)",
        "--vary",
        "coulomb_friction:joint=2:truncnormal(1.0,0.01,1.85,1.95)",
    ]);
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let line = said.lines().find(|l| l.starts_with("p_fail")).expect(&said);
    assert!(line.contains("40 deployments, 0 failed"), "{line}");
}
