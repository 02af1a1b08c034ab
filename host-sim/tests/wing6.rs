//! A six-panel wing with mixed latches
//! (ideal at joints 1, 3, 4, 6, a pawl at 2, a ball plunger at 5) through
//! every command of the `deploywatch` binary. With a `[rig]` it is refused
//! by each one (exit 2, the rig, the joints and the file named); without
//! the rig, and the ideal-latch wing on its rig, each command works and its
//! output is that of six joints. `replay --target qemu` and `hil` of six
//! joints run in `scripts/firmware.sh test` (they need the firmware).
mod common;

use common::{data, deploywatch, fails, s};
use std::path::{Path, PathBuf};
use std::process::Output;

/// A bundled six-panel mechanism.
fn wing(name: &str) -> PathBuf {
    data().join(format!("mechanisms/{name}.toml"))
}

/// Stdout of a run that must succeed (exit 0, no panic).
fn works(out: &Output, what: &str) -> String {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{what}: panic:\n{err}");
    assert_eq!(out.status.code(), Some(0), "{what}: stderr:\n{err}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Simulates `mech` with the sensor model (seed 1) to `dir/run.csv`:
/// the run's path and the summary.
fn simulate(mech: &Path, dir: &Path) -> (PathBuf, String) {
    let csv = dir.join("run.csv");
    let out = deploywatch(&["simulate", s(mech), "--seed", "1", "--out", s(&csv)]);
    let said = works(&out, "simulate");
    (csv, said)
}

/// The run CSV's header and rows, comment lines skipped.
fn read_run(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).expect("run CSV");
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let split = |l: &str| l.split(',').map(str::to_string).collect::<Vec<_>>();
    let header = split(lines.next().expect("header"));
    (header, lines.map(split).collect())
}

/// The run has six angle and six switch columns; every joint of `latched`
/// is latched in the summary, and each joint's summary agrees with its
/// switch column at the end ("latched at" exactly when the switch is
/// closed). A physical latch's joint may still rattle at the run's end: a
/// chain of stops and plungers pressed by springs bounces on for seconds,
/// and which joint is still off its stop when the run ends changes with
/// every step the integrator takes (run the wing with another
/// `duration_s` to see it).
fn joints_latched(csv: &Path, said: &str, latched: &[usize]) {
    let (header, rows) = read_run(csv);
    let angles: Vec<&String> = header
        .iter()
        .filter(|h| h.starts_with("phi") && h.ends_with("_deg"))
        .collect();
    assert_eq!(angles.len(), 6, "angle columns: {header:?}");
    for j in 1..=6 {
        let line = said
            .lines()
            .find(|l| l.trim_start().starts_with(&format!("joint {j}: ")))
            .unwrap_or_else(|| panic!("no summary line for joint {j}:\n{said}"));
        let says_latched = line.contains("latched at");
        assert!(
            says_latched || !latched.contains(&j),
            "joint {j}: {line}\n{said}"
        );
        assert!(
            says_latched || line.contains("NOT latched by"),
            "joint {j}: {line}\n{said}"
        );
        let col = header
            .iter()
            .position(|h| *h == format!("latch{j}"))
            .expect("latch column");
        let last = rows.last().expect("rows");
        let closed = if says_latched { "1" } else { "0" };
        assert_eq!(last[col], closed, "joint {j}'s switch at the end: {line}");
    }
}

/// Runs `identify`, `diagnose`, `margin`, `reliability` and `replay --target
/// host` of `mech` on `csv`, each required to work; `identify_args` bound
/// the fit (a wing on its rig is slow to fit in full). `simulated` is the
/// summary of the run: the monitor declares latched exactly the joints it
/// says latched.
fn every_command_works(
    mech: &Path,
    csv: &Path,
    dir: &Path,
    identify_args: &[&str],
    simulated: &str,
) {
    let id_json = dir.join("identify.json");
    let mut args = vec![
        "identify",
        "--mechanism",
        s(mech),
        s(csv),
        "--json",
        s(&id_json),
        "-q",
    ];
    args.extend_from_slice(identify_args);
    let said = works(&deploywatch(&args), "identify");
    assert!(id_json.exists(), "identify wrote its JSON:\n{said}");

    let dg_json = dir.join("diagnosis.json");
    let out = deploywatch(&[
        "diagnose",
        "--mechanism",
        s(mech),
        "--json",
        s(&dg_json),
        "--max-seconds",
        "5",
        "--max-effects",
        "1",
        "-q",
        s(csv),
    ]);
    let said = works(&out, "diagnose");
    assert!(dg_json.exists(), "diagnose wrote its JSON:\n{said}");

    let said = works(
        &deploywatch(&["margin", "--mechanism", s(mech), "-q"]),
        "margin",
    );
    let rows: Vec<&str> = said
        .lines()
        .filter(|l| l.trim_end().ends_with("pass") || l.trim_end().ends_with("FAIL"))
        .collect();
    assert_eq!(rows.len(), 6, "one margin row per joint:\n{said}");

    let out = deploywatch(&[
        "reliability",
        s(mech),
        "--fail",
        "not_latched",
        "--method",
        "mc",
        "--samples",
        "20",
        "--vary",
        "coulomb_friction:joint=1:uniform(0,0.2)",
        "-q",
    ]);
    let said = works(&out, "reliability");
    assert!(said.contains("6 failure mode(s)"), "{said}");
    assert!(said.contains("20 deployments"), "{said}");

    let said = works(
        &deploywatch(&["replay", "--mechanism", s(mech), s(csv), "--target", "host"]),
        "replay",
    );
    assert!(said.contains("of 6 joints"), "{said}");
    for j in 1..=6 {
        let latched = simulated.lines().any(|l| {
            l.trim_start()
                .starts_with(&format!("joint {j}: latched at"))
        });
        assert_eq!(
            said.contains(&format!("joint {j}: latched (latched at")),
            latched,
            "the monitor on joint {j} (latched in the run: {latched}):\n{said}"
        );
    }
}

#[test]
fn the_mixed_wing_goes_through_every_command() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mech = wing("wing6_mixed");
    let (csv, said) = simulate(&mech, dir.path());
    // The ideal latches (joints 1, 3, 4, 6) hold where they are reached.
    joints_latched(&csv, &said, &[1, 3, 4, 6]);
    // Each physical latch in its own words: joint 2's pawl is locked in its
    // notch, joint 5's ball plunger holds it past its crest.
    let line = |start: &str| {
        said.lines()
            .find(|l| l.trim_start().starts_with(start))
            .unwrap_or_else(|| panic!("no {start:?} line:\n{said}"))
            .to_string()
    };
    let pawl = line("joint 2 pawl:");
    assert!(
        pawl.contains("ends locked by its pawl in the notch"),
        "{pawl}"
    );
    assert!(!pawl.to_lowercase().contains("plunger"), "{pawl}");
    // Locked at the drop, before the switch's last closing (the latch
    // instant, its switch chattering in the notch after the drop).
    let number = |l: &str, after: &str| -> f64 {
        l.split(after)
            .nth(1)
            .and_then(|r| r.split(' ').next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("no number after {after:?}: {l}"))
    };
    let locked = number(&pawl, "(locked from ");
    let latched = number(&line("joint 2: latched at"), "latched at ");
    assert!(locked <= latched, "{pawl}; latched at {latched}");
    let plunger = line("joint 5 ball plunger:");
    assert!(
        plunger.contains("ends held past its ball plunger's crest"),
        "{plunger}"
    );
    assert!(!plunger.contains("pawl"), "{plunger}");
    every_command_works(&mech, &csv, dir.path(), &[], &said);
}

#[test]
fn the_ideal_wing_on_its_rig_goes_through_every_command() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mech = wing("wing6_ideal_rig");
    let (csv, said) = simulate(&mech, dir.path());
    joints_latched(&csv, &said, &[1, 2, 3, 4, 5, 6]);
    for p in 1..=6 {
        assert!(
            said.contains(&format!("panel {p} tip lateral (y) drift")),
            "the rig's drift of panel {p}:\n{said}"
        );
    }
    // The rig acts: the flight unit (the rig taken out) runs otherwise.
    let flight = dir.path().join("flight.csv");
    let out = deploywatch(&[
        "simulate",
        s(&mech),
        "--seed",
        "1",
        "--flight",
        "--out",
        s(&flight),
        "-q",
    ]);
    works(&out, "simulate --flight");
    let text = |p: &Path| std::fs::read_to_string(p).expect("run CSV");
    assert_ne!(text(&csv), text(&flight), "the rig changes the run");
    every_command_works(
        &mech,
        &csv,
        dir.path(),
        &["--joints", "6", "--start", "0.1"],
        &said,
    );
}

/// `identify` in full (every joint, its own start) on a run of the rig wing
/// with friction the Coulomb EFT cannot match (quadratic damping at joints
/// 1 and 3): on this wing the scan's per-joint best fits worse than its
/// best uniform EFT, and the solver's trials with a negative EFT fling
/// panels the simulator cannot follow. The fit ends on a point it
/// simulated: fewer degrees than the mechanism as given, no EFT below 0,
/// each joint fixed at 0 reported at 0 with an interval of some width,
/// which `reliability --from` draws.
#[test]
fn identify_fits_the_rig_wing_where_its_trials_cannot_be_simulated() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mech = wing("wing6_ideal_rig");
    let csv = dir.path().join("run.csv");
    let out = deploywatch(&[
        "simulate",
        s(&mech),
        "--seed",
        "3",
        "--effect",
        "quadratic_damping:joint=1:value=0.05",
        "--effect",
        "quadratic_damping:joint=3:value=0.02",
        "--out",
        s(&csv),
        "-q",
    ]);
    works(&out, "simulate");
    let json = dir.path().join("identify.json");
    let out = deploywatch(&[
        "identify",
        "--mechanism",
        s(&mech),
        s(&csv),
        "--json",
        s(&json),
        "-q",
    ]);
    works(&out, "identify");
    let found: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("JSON")).expect("JSON");
    let rms = |k: &str| found[k].as_f64().expect(k);
    assert!(rms("rms_deg_after") < rms("rms_deg_before"), "{found:#}");
    let fixed = found["direct"]["fixed_at_zero"].as_array().expect("fixed");
    for j in found["joints"].as_array().expect("joints") {
        let eft = j["coulomb_nm"].as_f64().expect("EFT");
        assert!(eft >= 0.0, "{j}");
        if fixed.contains(&j["joint"]) {
            assert_eq!(eft, 0.0, "{j}");
            // Zero to the precision the runs give it, not [0, 0].
            assert!(j["ci95"][1].as_f64().expect("ci95") > 0.0, "{j}");
        }
    }
    assert!(!fixed.is_empty(), "{found:#}");
    // Its intervals are laws `reliability --from` can draw.
    let out = deploywatch(&[
        "reliability",
        s(&mech),
        "--from",
        s(&json),
        "--fail",
        "not_latched",
        "--method",
        "mc",
        "--samples",
        "20",
        "-q",
    ]);
    works(&out, "reliability --from");
}

/// The mixed wing on the rig of `wing6_ideal_rig.toml`, written to
/// `dir/wing6_mixed_rig.toml` (not bundled: every bundled mechanism loads).
fn mixed_on_a_rig(dir: &Path) -> PathBuf {
    let read = |name: &str| std::fs::read_to_string(wing(name)).expect("bundled wing");
    let on_rig = read("wing6_ideal_rig");
    let rig =
        &on_rig[on_rig.find("\n[rig]").expect("[rig]")..on_rig.find("\n[run]").expect("[run]")];
    let path = dir.join("wing6_mixed_rig.toml");
    std::fs::write(&path, format!("{}\n{rig}\n", read("wing6_mixed"))).expect("write wing");
    path
}

#[test]
fn the_mixed_wing_on_a_rig_is_refused_by_every_command() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mech = mixed_on_a_rig(dir.path());
    let m = s(&mech);
    // A run of six joints (the refusal comes before the run is read).
    let run = data().join("examples/wing6/wing6_ideal.csv");
    let r = s(&run);
    let json = dir.path().join("out.json");
    let j = s(&json);
    let csv = dir.path().join("out.csv");
    let commands: [&[&str]; 8] = [
        &["simulate", m, "--out", s(&csv), "--no-noise"],
        &["identify", "--mechanism", m, r, "--json", j],
        &["diagnose", "--mechanism", m, "--json", j, r],
        &["margin", "--mechanism", m],
        &[
            "reliability",
            m,
            "--fail",
            "not_latched",
            "--method",
            "mc",
            "--samples",
            "20",
            "--vary",
            "coulomb_friction:joint=1:uniform(0,0.2)",
        ],
        &["replay", "--mechanism", m, r, "--target", "host"],
        &["replay", "--mechanism", m, r, "--target", "qemu"],
        &[
            "hil",
            "--mechanism",
            m,
            r,
            "--target",
            "qemu",
            "--duration",
            "1",
        ],
    ];
    for args in commands {
        let out = deploywatch(args);
        let err = fails(
            &out,
            2,
            &[
                "wing6_mixed_rig.toml",
                "[rig]",
                "joint(s) 2, 5",
                "physical latch",
            ],
        );
        assert!(err.starts_with("error: "), "{args:?}: {err}");
    }
    assert!(
        !csv.exists() && !json.exists(),
        "nothing written on a refusal"
    );
}
