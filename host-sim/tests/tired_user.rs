//! A tired user's files, checked on the `deploywatch` binary as a black box:
//! the bundled run `data/examples/c_seed001_friction_harness/seed001_T01.csv`
//! saved the ways people save files (angles in radians, time in milliseconds,
//! a spreadsheet's CSV, a mirrored encoder, an encoder zeroed at the stowed
//! pose or counting 0 to 360 deg, a stuck latch column, another mechanism's
//! header) and its mechanism with a mass typed in grams. Each is refused
//! (exit 2) or warned about with the likely cause, the file, line and column
//! named, before any simulation: the refused cases, run without `--quiet`,
//! print the error and nothing else (no progress line of the identification,
//! which comes first when the work starts). The bundled inputs raise no
//! warning about themselves.
//!
//! `cargo test -p deploywatch-sim --test tired_user`

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{data, deploywatch, fails, s, t01_mechanism, write};

use deploywatch_sim::consistency;
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::plausibility;
use deploywatch_sim::run::Run;

/// A bundled run of seed 001's trials (example campaign c).
fn bundled_run() -> PathBuf {
    data().join("examples/c_seed001_friction_harness/seed001_T01.csv")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The bundled run's lines: metadata, header, rows split into fields.
fn run_parts() -> (Vec<String>, String, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(bundled_run()).expect("bundled run");
    let meta: Vec<String> = text
        .lines()
        .filter(|l| l.starts_with('#'))
        .map(String::from)
        .collect();
    let mut body = text.lines().filter(|l| !l.starts_with('#'));
    let header = body.next().expect("header").to_string();
    let rows = body
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (meta, header, rows)
}

/// The bundled run with each row transformed by `f`, comma-separated.
fn transformed(f: impl Fn(&mut Vec<String>)) -> String {
    let (meta, header, rows) = run_parts();
    let mut out = meta.join("\n") + "\n" + &header + "\n";
    for mut r in rows {
        f(&mut r);
        out.push_str(&r.join(","));
        out.push('\n');
    }
    out
}

/// Line of the first data row of the bundled run (after its metadata and header).
fn first_row_line() -> usize {
    run_parts().0.len() + 2
}

/// `deploywatch identify --method direct` of one run on the T01 mechanism
/// (or `mechanism`), without `--quiet`: the progress, if the work starts,
/// is on stderr.
fn identify(run: &Path, mechanism: &Path) -> Output {
    deploywatch(&[
        "identify",
        "--method",
        "direct",
        "--mechanism",
        s(mechanism),
        s(run),
    ])
}

/// Asserts exit 2 with every one of `says`, and that nothing but the error
/// reached stderr: no progress line, so no simulation ran.
fn refused_before_work(out: &Output, says: &[&str]) {
    let err = fails(out, 2, says);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "more than the error on stderr:\n{err}");
    assert!(lines[0].starts_with("error: "), "{err}");
}

/// The warnings of stderr that are about the inputs: `warning: FILE:...`.
fn input_warnings(err: &str, files: &[&Path]) -> Vec<String> {
    err.lines()
        .filter(|l| {
            l.starts_with("warning:") && files.iter().any(|f| l.contains(&*f.to_string_lossy()))
        })
        .map(String::from)
        .collect()
}

#[test]
fn angles_in_radians_are_refused_naming_radians_line_and_column() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = transformed(|r| {
        for f in &mut r[1..4] {
            *f = format!("{:.6}", f.parse::<f64>().unwrap().to_radians());
        }
    });
    let run = write(dir.path(), "radians.csv", text);
    let out = identify(&run, &t01_mechanism());
    let at = format!("radians.csv:{}:", first_row_line());
    refused_before_work(
        &out,
        &[&at, "column `phi1_deg` (column 2)", "radians", "57.3"],
    );
}

#[test]
fn time_in_milliseconds_is_refused_naming_milliseconds() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = transformed(|r| {
        r[0] = format!("{:.0}", r[0].parse::<f64>().unwrap() * 1000.0);
    });
    let run = write(dir.path(), "ms.csv", text);
    let out = identify(&run, &t01_mechanism());
    refused_before_work(
        &out,
        &["ms.csv:", "column `t_s` (column 1)", "milliseconds"],
    );
}

/// Milliseconds against a mechanism whose `duration_s` is long (100 s):
/// the run (2.55 s, 2550 "s") is shorter than a hundred horizons, so only
/// its sample interval, a thousand times the mechanism's, tells. Refused
/// naming the column and the factor.
#[test]
fn time_in_milliseconds_with_a_long_duration_is_refused_naming_the_factor() {
    let dir = tempfile::tempdir().expect("temp dir");
    let toml = std::fs::read_to_string(t01_mechanism()).unwrap();
    assert!(
        toml.contains("duration_s = 6.0"),
        "the bundled mechanism changed"
    );
    let mech = write(
        dir.path(),
        "long.toml",
        toml.replace("duration_s = 6.0", "duration_s = 100.0"),
    );
    let text = transformed(|r| {
        r[0] = format!("{:.0}", r[0].parse::<f64>().unwrap() * 1000.0);
    });
    let run = write(dir.path(), "ms.csv", text);
    let out = identify(&run, &mech);
    refused_before_work(
        &out,
        &[
            "ms.csv:",
            "column `t_s` (column 1)",
            "1000 times",
            "milliseconds",
            "divide t_s by 1000",
        ],
    );
    let replay = deploywatch(&["replay", s(&run), "--mechanism", s(&mech)]);
    fails(&replay, 2, &["column `t_s` (column 1)", "milliseconds"]);
}

#[test]
fn a_mirrored_encoder_is_refused_naming_the_sign() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = transformed(|r| {
        for f in &mut r[1..4] {
            *f = format!("{:.4}", -f.parse::<f64>().unwrap());
        }
    });
    let run = write(dir.path(), "mirrored.csv", text);
    let out = identify(&run, &t01_mechanism());
    let at = format!("mirrored.csv:{}:", first_row_line());
    refused_before_work(&out, &[&at, "column `phi1_deg`", "mirrored"]);
}

#[test]
fn angles_counted_from_the_stowed_pose_are_refused_naming_the_zero() {
    let dir = tempfile::tempdir().expect("temp dir");
    // seed 001 T01 is stowed at -90, 180 and -180 deg: an encoder zeroed at
    // power-up reads the angle travelled from there.
    let stowed = [-90.0, 180.0, -180.0];
    let text = transformed(|r| {
        for (f, s) in r[1..4].iter_mut().zip(stowed) {
            *f = format!("{:.4}", f.parse::<f64>().unwrap() - s);
        }
    });
    let run = write(dir.path(), "zeroed.csv", text);
    let out = identify(&run, &t01_mechanism());
    let at = format!("zeroed.csv:{}:", first_row_line());
    refused_before_work(
        &out,
        &[&at, "column `phi1_deg`", "counted from the stowed pose"],
    );
}

#[test]
fn angles_a_whole_turn_off_are_refused_naming_the_turn() {
    let dir = tempfile::tempdir().expect("temp dir");
    // An encoder counting 0 to 360 deg reads -90 deg as 270 deg.
    let text = transformed(|r| {
        let phi = r[1].parse::<f64>().unwrap();
        r[1] = format!("{:.4}", phi.rem_euclid(360.0));
    });
    let run = write(dir.path(), "turn.csv", text);
    let out = identify(&run, &t01_mechanism());
    refused_before_work(
        &out,
        &["turn.csv:", "column `phi1_deg`", "whole turn", "0 to 360"],
    );
}

#[test]
fn times_of_a_logger_clock_are_refused_naming_the_offset() {
    let dir = tempfile::tempdir().expect("temp dir");
    // A logger's time since power-up: the release at t = 1234.5 s.
    let text = transformed(|r| {
        r[0] = format!("{:.3}", r[0].parse::<f64>().unwrap() + 1234.5);
    });
    let run = write(dir.path(), "clock.csv", text);
    let out = identify(&run, &t01_mechanism());
    let at = format!("clock.csv:{}:", first_row_line());
    refused_before_work(&out, &[&at, "column `t_s`", "1234.5", "subtract"]);
}

/// The bundled run as a spreadsheet saves it: BOM, `;`, decimal commas,
/// CRLF; the metadata cells quoted when `quote` (as some spreadsheets do).
fn spreadsheet_text(quote: bool) -> String {
    let (meta, header, rows) = run_parts();
    let mut out = String::from("\u{feff}");
    for m in meta {
        if quote {
            out.push_str(&format!("\"{}\";;;;;;\r\n", m.replace('"', "\"\"")));
        } else {
            out.push_str(&format!("{m}\r\n"));
        }
    }
    out.push_str(&header.replace(',', ";"));
    out.push_str("\r\n");
    for r in rows {
        let fields: Vec<String> = r.iter().map(|f| f.replace('.', ",")).collect();
        out.push_str(&fields.join(";"));
        out.push_str("\r\n");
    }
    out
}

#[test]
fn a_spreadsheet_csv_is_read_as_the_comma_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let comma = identify(&bundled_run(), &t01_mechanism());
    assert_eq!(comma.status.code(), Some(0), "{}", stderr(&comma));
    // The report but its cost line (a wall time).
    let table = |out: &Output| {
        stdout(out)
            .lines()
            .filter(|l| !l.starts_with("cost:"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    for quote in [false, true] {
        // Named as the bundled run, for the report names the file.
        let run = write(dir.path(), "seed001_T01.csv", spreadsheet_text(quote));
        let out = identify(&run, &t01_mechanism());
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        assert_eq!(table(&out), table(&comma), "quoted metadata: {quote}");
        let parsed = Run::load(&run).expect("read");
        let original = Run::load(&bundled_run()).expect("read");
        assert_eq!(parsed, original, "quoted metadata: {quote}");
    }
}

#[test]
fn decimal_commas_in_a_comma_file_are_refused_naming_decimal_commas() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (meta, header, rows) = run_parts();
    let mut text = meta.join("\n") + "\n" + &header + "\n";
    for r in rows {
        text.push_str(&r.join(",").replace('.', ","));
        text.push('\n');
    }
    let run = write(dir.path(), "decimal.csv", text);
    let out = identify(&run, &t01_mechanism());
    let at = format!("decimal.csv:{}:", first_row_line());
    refused_before_work(&out, &[&at, "decimal commas", "`;`"]);
}

#[test]
fn a_tab_separated_file_is_refused_naming_the_separator() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (meta, header, rows) = run_parts();
    let mut text = meta.join("\n") + "\n" + &header.replace(',', "\t") + "\n";
    for r in rows {
        text.push_str(&r.join("\t"));
        text.push('\n');
    }
    let run = write(dir.path(), "tabs.csv", text);
    let out = identify(&run, &t01_mechanism());
    let at = format!("tabs.csv:{}:", first_row_line() - 1);
    refused_before_work(&out, &[&at, "tab-separated"]);
}

#[test]
fn a_mass_in_grams_is_a_warning_naming_the_key_and_line_even_with_quiet() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = std::fs::read_to_string(t01_mechanism()).expect("mechanism");
    let grams = text.replacen("mass_kg = 3.5", "mass_kg = 3500.0", 1);
    let line = 1 + grams.lines().position(|l| l.contains("3500.0")).unwrap();
    let mech = write(dir.path(), "grams.toml", &grams);
    let at = format!("grams.toml:{line}: `panel[1].mass_kg`");
    let csv = dir.path().join("out.csv");
    let sim = deploywatch(&["simulate", s(&mech), "--out", s(&csv), "--quiet"]);
    fails(&sim, 0, &[&at, "grams"]);
    // Without --quiet, the warning comes before the identification's first
    // progress line: it is raised before any simulation.
    let out = identify(&bundled_run(), &mech);
    let err = fails(&out, 0, &[&at, "grams"]);
    let lines: Vec<&str> = err.lines().collect();
    assert!(lines.len() > 1, "no progress:\n{err}");
    assert!(
        lines[0].starts_with("warning: ") && lines[0].contains("grams"),
        "{err}"
    );
}

#[test]
fn a_run_missing_an_angle_column_is_refused_naming_that_column() {
    // The bundled three-joint run saved without its `phi2_deg` column: the
    // message names the missing angle, not the last latch column as extra.
    let dir = tempfile::tempdir().expect("temp dir");
    let (meta, header, rows) = run_parts();
    let drop_second = |fields: Vec<String>| {
        let mut kept = fields;
        kept.remove(2);
        kept.join(",")
    };
    let header = drop_second(header.split(',').map(String::from).collect());
    let mut text = meta.join("\n") + "\n" + &header + "\n";
    for r in rows {
        text.push_str(&drop_second(r));
        text.push('\n');
    }
    let run = write(dir.path(), "no_phi2.csv", text);
    let out = identify(&run, &t01_mechanism());
    let at = format!("no_phi2.csv:{}:", first_row_line() - 1);
    refused_before_work(&out, &[&at, "missing column `phi2_deg`"]);
    assert!(!stderr(&out).contains("extra column"), "{}", stderr(&out));
}

#[test]
fn a_run_of_another_mechanism_is_refused_naming_the_header_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = std::fs::read_to_string(bundled_run())
        .expect("run")
        .replace(
            "# mechanism = \"seed001-T01\"",
            "# mechanism = \"seed001-T02\"",
        );
    let run = write(dir.path(), "header.csv", text);
    let out = identify(&run, &t01_mechanism());
    refused_before_work(
        &out,
        &[
            "header.csv:1:",
            "\"seed001-T02\"",
            "was not given",
            "\"seed001-T01\"",
        ],
    );
    // The run with a mechanism of other joints (swapped files) on replay.
    let case1 = data().join("mechanisms/seed000_case1.toml");
    let out = deploywatch(&[
        "replay",
        s(&bundled_run()),
        "--mechanism",
        s(&case1),
        "--target",
        "host",
        "--out",
        s(&dir.path().join("status.csv")),
    ]);
    refused_before_work(
        &out,
        &["seed001_T01.csv:1:", "\"seed001-T01\"", "was not given"],
    );
}

#[test]
fn a_latch_column_stuck_closed_is_a_warning_naming_the_column() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = transformed(|r| r[4] = "1".to_string());
    let run = write(dir.path(), "latch.csv", text);
    let out = identify(&run, &t01_mechanism());
    let at = format!("latch.csv:{}: column `latch1` (column 5)", first_row_line());
    fails(&out, 0, &[&at, "stuck closed"]);
}

#[test]
fn a_latch_column_stuck_open_on_a_latched_joint_is_a_warning() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = transformed(|r| r[5] = "0".to_string());
    let run = write(dir.path(), "open.csv", text);
    // The monitor's replay reads it (identify refuses it as ended early).
    let out = deploywatch(&[
        "replay",
        s(&run),
        "--mechanism",
        s(&t01_mechanism()),
        "--target",
        "host",
        "--out",
        s(&dir.path().join("status.csv")),
    ]);
    fails(
        &out,
        0,
        &[
            "open.csv:",
            "column `latch2` (column 6)",
            "never reads closed",
            "stuck open, or a joint stopped just short",
        ],
    );
}

#[test]
fn replay_refuses_radians_before_the_monitor_runs() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = transformed(|r| {
        for f in &mut r[1..4] {
            *f = format!("{:.6}", f.parse::<f64>().unwrap().to_radians());
        }
    });
    let run = write(dir.path(), "radians.csv", text);
    let out = deploywatch(&[
        "replay",
        s(&run),
        "--mechanism",
        s(&t01_mechanism()),
        "--target",
        "host",
        "--out",
        s(&dir.path().join("status.csv")),
    ]);
    refused_before_work(&out, &["radians.csv:", "radians"]);
    assert!(!dir.path().join("status.csv").exists());
}

/// The bundled mechanism files with the name each gives.
fn bundled_mechanisms() -> Vec<(PathBuf, Mechanism)> {
    let mut out: Vec<(PathBuf, Mechanism)> = std::fs::read_dir(data().join("mechanisms"))
        .expect("mechanisms")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| {
            let m = Mechanism::load(&p).expect("bundled mechanism");
            (p, m)
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// The bundled mechanism files named `name`.
fn mechanisms_named(name: &str) -> Vec<PathBuf> {
    bundled_mechanisms()
        .into_iter()
        .filter(|(_, m)| m.name == name)
        .map(|(p, _)| p)
        .collect()
}

#[test]
fn no_bundled_mechanism_is_implausible() {
    for (path, m) in bundled_mechanisms() {
        let w = plausibility::warnings(&m, &path);
        assert!(w.is_empty(), "{}: {w:?}", path.display());
    }
}

#[test]
fn every_bundled_example_and_reference_run_raises_no_input_warning() {
    let mut runs: Vec<PathBuf> = Vec::new();
    for dir in ["examples/a_seed001_eft", "examples/b_seed000_eft_air_drag"]
        .iter()
        .chain(&["examples/c_seed001_friction_harness", "reference"])
    {
        for e in std::fs::read_dir(data().join(dir)).expect("data folder") {
            let p = e.expect("entry").path();
            if p.extension().is_some_and(|x| x == "csv") {
                runs.push(p);
            }
        }
    }
    assert!(runs.len() >= 14, "{runs:?}");
    for run in &runs {
        let r = Run::load(run).expect("bundled run");
        let mechs = mechanisms_named(r.mechanism().expect("mechanism metadata"));
        let mut args = vec!["identify", "--method", "direct", "--quiet"];
        for m in &mechs {
            args.extend(["--mechanism", s(m)]);
        }
        args.push(s(run));
        let out = deploywatch(&args);
        let err = fails(&out, 0, &[]);
        let mut files: Vec<&Path> = mechs.iter().map(PathBuf::as_path).collect();
        files.push(run);
        assert_eq!(input_warnings(&err, &files), Vec::<String>::new());
    }
}

#[test]
fn the_truss_reference_runs_agree_with_their_mechanisms() {
    // The truss references hold angles and knees but no latch columns (no
    // command reads them): their angles and times are checked against
    // their mechanisms through the same check, the switches read closed at
    // the last sample only (a reference ends at the last latch, formats.md).
    for stem in [
        "seed000_case2_truss_eft",
        "seed000_case2_truss_nominal",
        "seed000_case3_truss_eft",
        "seed000_case3_truss_nominal",
    ] {
        let text =
            std::fs::read_to_string(data().join(format!("reference/truss/{stem}.csv"))).unwrap();
        let mut run = Run::default();
        let mut lines = text.lines();
        for l in lines.by_ref() {
            if let Some(rest) = l.strip_prefix("# ") {
                let (k, v) = rest.split_once(" = ").expect("metadata");
                run.set_meta(k, v.trim_matches('"'));
            } else {
                break;
            }
        }
        run.phi_deg = vec![Vec::new(), Vec::new()];
        run.latch = vec![Vec::new(), Vec::new()];
        for l in lines {
            let f: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            run.t_s.push(f[0]);
            for j in 0..2 {
                run.phi_deg[j].push(f[1 + j]);
                run.latch[j].push(false);
            }
        }
        for latch in &mut run.latch {
            *latch.last_mut().expect("samples") = true;
        }
        let name = run.mechanism().expect("mechanism").to_string();
        let paths = mechanisms_named(&name);
        assert!(!paths.is_empty(), "{name}");
        for p in paths {
            let m = Mechanism::load(&p).unwrap();
            let w = consistency::check(&run, &m, stem).expect("consistent");
            assert!(w.is_empty(), "{stem}: {w:?}");
        }
    }
}

#[test]
fn the_readme_commands_raise_no_warning_about_their_inputs() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = |p: &str| data().join(p);
    let (t01, t02) = (
        d("mechanisms/seed001_T01.toml"),
        d("mechanisms/seed001_T02.toml"),
    );
    let eft = dir.path().join("eft.json");
    let (a1, a2) = (
        d("examples/a_seed001_eft/seed001_T01.csv"),
        d("examples/a_seed001_eft/seed001_T02.csv"),
    );
    let t02csv = dir.path().join("t02.csv");
    let (c1, c2) = (
        d("examples/c_seed001_friction_harness/seed001_T01.csv"),
        d("examples/c_seed001_friction_harness/seed001_T02.csv"),
    );
    let diagnosis = dir.path().join("diagnosis.json");
    let commands: Vec<Vec<String>> = vec![
        vec![
            "diagnose",
            "--mechanism",
            s(&t01),
            "--mechanism",
            s(&t02),
            "--json",
            s(&diagnosis),
            s(&c1),
            s(&c2),
        ],
        vec![
            "simulate",
            s(&t02),
            "--out",
            s(&t02csv),
            "--effect",
            "coulomb_friction:joint=1:value=2.63",
            "--seed",
            "1",
        ],
        vec![
            "identify",
            "--mechanism",
            s(&t01),
            "--mechanism",
            s(&t02),
            s(&a1),
            s(&a2),
            "--method",
            "direct",
            "--json",
            s(&eft),
        ],
        vec![
            "margin",
            "--mechanism",
            s(&t01),
            "--from",
            s(&eft),
            "--standard",
            "ecss-e-st-33-01c",
        ],
        vec![
            "margin",
            "--mechanism",
            s(&d("mechanisms/seed000_case1.toml")),
            "--friction",
            "0.54,0.472",
        ],
        vec![
            "replay",
            s(&bundled_run()),
            "--mechanism",
            s(&t01),
            "--target",
            "host",
            "--out",
            s(&dir.path().join("status.csv")),
        ],
    ]
    .into_iter()
    .map(|c| c.into_iter().map(String::from).collect())
    .collect();
    for c in &commands {
        let args: Vec<&str> = c.iter().map(String::as_str).collect();
        let out = deploywatch(&args);
        let err = fails(&out, 0, &[]);
        assert!(!err.contains("warning"), "{c:?}:\n{err}");
    }
}
