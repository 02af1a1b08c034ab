//! What a new user runs into at the command line with outputs: `margin
//! --from`, help texts, words instead of Rust debug output, `--quiet`,
//! plots, identify's residual warning. The `deploywatch` binary is run as a black box on the
//! bundled data; every test checks the exit code, the message and that
//! nothing panicked.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use deploywatch_sim::effect::EffectKind;
use serde_json::Value;

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(rel)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

fn deploywatch(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_deploywatch"))
        .args(args)
        .output()
        .expect("run deploywatch")
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts success without a panic; returns stdout.
fn succeeds(out: &Output) -> String {
    let err = stderr(out);
    assert!(!err.contains("panicked"), "panic:\n{err}");
    assert!(
        out.status.success(),
        "exit {:?}; stderr:\n{err}",
        out.status
    );
    stdout(out)
}

/// Asserts a clean failure with exit code `code` and stderr containing
/// every one of `says`; returns stderr.
fn fails(out: &Output, code: i32, says: &[&str]) -> String {
    let err = stderr(out);
    assert!(!err.contains("panicked"), "panic:\n{err}");
    assert_eq!(out.status.code(), Some(code), "exit code; stderr:\n{err}");
    for w in says {
        assert!(err.contains(w), "stderr lacks {w:?}:\n{err}");
    }
    err
}

const T01: &str = "mechanisms/seed001_T01.toml";
const T02: &str = "mechanisms/seed001_T02.toml";

/// The identify arguments of the bundled EFT campaign (example a).
fn identify_a(extra: &[&str]) -> Output {
    let (m1, m2) = (data(T01), data(T02));
    let (r1, r2) = (
        data("examples/a_seed001_eft/seed001_T01.csv"),
        data("examples/a_seed001_eft/seed001_T02.csv"),
    );
    let mut args = vec![
        "identify",
        "--mechanism",
        s(&m1),
        "--mechanism",
        s(&m2),
        s(&r1),
        s(&r2),
    ];
    args.extend_from_slice(extra);
    deploywatch(&args)
}

/// The height [px] of a PNG, from its IHDR chunk.
fn png_height(path: &Path) -> u32 {
    let bytes = std::fs::read(path).expect("png written");
    assert_eq!(&bytes[1..4], b"PNG", "{} is not a PNG", path.display());
    u32::from_be_bytes(bytes[20..24].try_into().expect("IHDR"))
}

// ---------------------------------------------------------------------------
// Outputs are checked before the work.

#[test]
fn simulate_plot_into_a_missing_folder_is_refused_before_the_run_is_written() {
    let dir = tempfile::tempdir().expect("tempdir");
    let csv = dir.path().join("t01.csv");
    let png = dir.path().join("no_such_folder").join("t01.png");
    let out = deploywatch(&[
        "simulate",
        s(&data(T01)),
        "--out",
        s(&csv),
        "--plot",
        s(&png),
    ]);
    fails(
        &out,
        2,
        &[
            "--plot",
            "no_such_folder",
            "does not exist",
            "create it first",
        ],
    );
    assert!(!stderr(&out).contains("ImageError"));
    assert!(
        !csv.exists(),
        "the run was written although the plot cannot be"
    );
    assert!(
        !png.parent().expect("folder").exists(),
        "a folder was created"
    );
}

#[test]
fn every_command_refuses_an_output_in_a_missing_folder_before_any_work() {
    let dir = tempfile::tempdir().expect("tempdir");
    let missing = dir.path().join("missing");
    let cases = [
        ("--out", "simulate M1 --out DIR/r.csv"),
        (
            "--json",
            "identify --mechanism M1 --mechanism M2 R1 R2 --json DIR/eft.json",
        ),
        ("--json", "margin --mechanism M1 --json DIR/m.json"),
        (
            "--json",
            "diagnose --mechanism M1 --mechanism M2 --json DIR/d.json R1 R2",
        ),
        ("--plot", "replay R1 --mechanism M1 --plot DIR/r.png"),
    ];
    for (flag, line) in cases {
        // The paths (data/ and the temporary folder) hold no spaces.
        let line = line
            .replace("M1", s(&data(T01)))
            .replace("M2", s(&data(T02)))
            .replace("R1", s(&data("examples/a_seed001_eft/seed001_T01.csv")))
            .replace("R2", s(&data("examples/a_seed001_eft/seed001_T02.csv")))
            .replace("DIR", s(&missing));
        let args: Vec<&str> = line.split_whitespace().collect();
        let out = deploywatch(&args);
        let err = fails(&out, 2, &[flag, "missing", "does not exist"]);
        assert!(
            stdout(&out).is_empty(),
            "{}: worked before refusing its output:\n{}\n{err}",
            args[0],
            stdout(&out)
        );
        assert!(!missing.exists(), "{}: created the folder", args[0]);
    }
}

#[test]
fn an_output_that_is_a_folder_is_refused_with_its_name() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = deploywatch(&["simulate", s(&data(T01)), "--out", s(dir.path())]);
    fails(&out, 2, &["--out", "is a folder"]);
}

// ---------------------------------------------------------------------------
// margin reads what identify and diagnose found.

/// `margin --mechanism seed001_T01 --from FILE --json OUT`: its stdout and
/// the margins JSON it wrote (beside FILE).
fn margin_from(file: &Path, extra: &[&str]) -> (String, Value) {
    let text = succeeds(&run_margin_from(file, extra));
    let margins = file.with_file_name("margins.json");
    let m = serde_json::from_str(&std::fs::read_to_string(&margins).expect("margins"))
        .expect("margins JSON");
    (text, m)
}

/// Runs `margin --mechanism seed001_T01 --from FILE --json margins.json`
/// (beside FILE).
fn run_margin_from(file: &Path, extra: &[&str]) -> Output {
    let margins = file.with_file_name("margins.json");
    let mech = data(T01);
    let mut args = vec![
        "margin",
        "--mechanism",
        s(&mech),
        "--from",
        s(file),
        "--json",
        s(&margins),
    ];
    args.extend_from_slice(extra);
    deploywatch(&args)
}

#[test]
fn margin_from_an_identify_json_uses_the_identified_friction() {
    let dir = tempfile::tempdir().expect("tempdir");
    let eft = dir.path().join("eft.json");
    succeeds(&identify_a(&["--quiet", "--json", s(&eft)]));
    let (text, m) = margin_from(&eft, &[]);
    assert!(text.contains("identify"), "{text}");
    let id: Value = serde_json::from_str(&std::fs::read_to_string(&eft).expect("eft")).unwrap();
    let joints = m["joints"].as_array().expect("joints");
    assert_eq!(joints.len(), 3);
    for found in id["joints"].as_array().expect("identified joints") {
        let j = found["joint"].as_u64().expect("joint") as usize;
        let row = &joints[j - 1];
        let t_r = row["coulomb_nm"].as_f64().expect("T_R");
        // seed001_T01 has no friction of its own: T_R is the EFT found.
        assert_eq!(t_r, found["coulomb_nm"].as_f64().expect("EFT"));
        let t_d = row["driving_torque_nm"].as_f64().expect("T_D");
        let tm = row["torque_margin_pct"].as_f64().expect("finite margin");
        assert!((tm - (t_d / t_r - 1.0) * 100.0).abs() < 1e-9 * tm.abs().max(1.0));
    }
}

#[test]
fn margin_from_a_diagnose_json_takes_friction_and_damping_and_counts_the_rest() {
    let dir = tempfile::tempdir().expect("tempdir");
    // The diagnosis format of docs/spec/formats.md.
    let diagnosis = dir.path().join("diagnosis.json");
    std::fs::write(
        &diagnosis,
        r#"{
  "mechanism": "seed001-T01",
  "runs": ["t01.csv"],
  "baseline": { "rms_deg": 6.41, "trajectory_error_pct": [31.2, 18.0, 4.1] },
  "effects": [
    { "name": "coulomb_friction", "joint": 1, "value": 0.8, "unit": "N·m", "ci95": [0.79, 0.81], "evidence": "..." },
    { "name": "viscous_damping", "joint": 2, "value": 0.05, "unit": "N·m·s/rad", "ci95": [0.04, 0.06], "evidence": "..." },
    { "name": "harness_stiffness", "joint": 3, "value": 0.1, "unit": "N·m/rad", "ci95": [0.09, 0.11], "evidence": "..." }
  ],
  "extended": { "rms_deg": 0.031, "trajectory_error_pct": [0.4, 0.3, 0.2] },
  "gain": { "rms_ratio": 206.8, "held_out_rms_deg": null }
}"#,
    )
    .expect("write");
    let (text, m) = margin_from(&diagnosis, &["--quiet"]);
    // The harness is a resistance: counted under its joint with its factor.
    assert!(
        text.contains("harness_stiffness 0.1 N·m/rad (harness"),
        "{text}"
    );
    let j = &m["joints"];
    assert_eq!(j[0]["coulomb_nm"].as_f64(), Some(0.8));
    assert_eq!(j[1]["viscous_nms"].as_f64(), Some(0.05));
    let e_visc = j[1]["viscous_energy_j"].as_f64().expect("E_visc");
    assert!(e_visc > 0.0, "the damping dissipates energy on the way");
    assert_eq!(j[0]["viscous_energy_j"].as_f64(), Some(0.0));
    // E_R = T_R · stroke + E_visc.
    for row in j.as_array().expect("joints") {
        let stroke = row["stowed_deg"].as_f64().unwrap().abs().to_radians();
        let want = row["coulomb_nm"].as_f64().unwrap() * stroke
            + row["viscous_energy_j"].as_f64().unwrap();
        let got = row["resisting_energy_j"].as_f64().unwrap();
        assert!((got - want).abs() < 1e-12 + 1e-12 * want, "{got} vs {want}");
    }
    // Every effect found is counted: nothing is left out.
    let left_out = m["not_included"].as_array().map_or(0, Vec::len);
    assert_eq!(left_out, 0, "{}", m["not_included"]);
}

#[test]
fn margin_from_a_file_that_is_neither_says_what_it_expected() {
    let run = data("examples/a_seed001_eft/seed001_T01.csv");
    let out = deploywatch(&["margin", "--mechanism", s(&data(T01)), "--from", s(&run)]);
    fails(&out, 2, &["--from", "seed001_T01.csv", "not JSON"]);
    let dir = tempfile::tempdir().expect("tempdir");
    let other = dir.path().join("other.json");
    std::fs::write(&other, r#"{"joints": 3}"#).expect("write");
    let out = deploywatch(&["margin", "--mechanism", s(&data(T01)), "--from", s(&other)]);
    fails(&out, 2, &["deploywatch identify", "deploywatch diagnose"]);
    let far = dir.path().join("far.json");
    std::fs::write(
        &far,
        r#"{"method": "direct", "joints": [{"joint": 4, "coulomb_nm": 1.0}]}"#,
    )
    .expect("write");
    let out = deploywatch(&["margin", "--mechanism", s(&data(T01)), "--from", s(&far)]);
    fails(&out, 2, &["joint 4", "joints 1 to 3"]);
}

// ---------------------------------------------------------------------------
// Help texts.

#[test]
fn margin_help_lists_the_standards() {
    let help = succeeds(&deploywatch(&["margin", "--help"]));
    for name in ["none", "nasa-std-5017", "ecss-e-st-33-01c"] {
        assert!(
            help.lines()
                .any(|l| l.trim_start().starts_with(&format!("- {name}:"))),
            "--standard does not list {name}:\n{help}"
        );
    }
    let out = deploywatch(&["margin", "--mechanism", s(&data(T01)), "--standard", "mil"]);
    fails(&out, 2, &["nasa-std-5017", "ecss-e-st-33-01c"]);
}

#[test]
fn simulate_help_gives_every_effect_with_its_unit() {
    let help = succeeds(&deploywatch(&["simulate", "--help"]));
    for k in EffectKind::ALL {
        let unit = match k.unit() {
            "1" => "V dimensionless".to_string(),
            u => format!("V in {u} "),
        };
        assert!(
            help.lines()
                .any(|l| l.contains(k.name()) && l.contains(&unit)),
            "{} with its unit {unit} is missing:\n{help}",
            k.name()
        );
    }
    assert!(
        help.lines()
            .any(|l| l.contains("torque_table:joint=J:angle_deg=A1")
                && l.contains("rate_torque_nm=")
                && l.contains("N·m")),
        "torque_table with its syntax is missing:\n{help}"
    );
}

// ---------------------------------------------------------------------------
// Words, not Rust debug output.

#[test]
fn identify_prints_words_not_rust_debug_output() {
    for method in ["direct", "rsm"] {
        let out = identify_a(&["--quiet", "--method", method]);
        let text = succeeds(&out) + &stderr(&out);
        for debug in ["{", "}", "Converged", "SCAN_GRID", "Circumscribed"] {
            assert!(!text.contains(debug), "{method}: {debug:?} in\n{text}");
        }
        assert!(text.contains("EFT"), "{text}");
    }
    let out = identify_a(&["--method", "direct"]);
    let progress = stderr(&out);
    assert!(
        !progress.contains('{') && !progress.contains("SCAN_GRID"),
        "{progress}"
    );
    // diagnose: progress lines name sets in words (no `{a j1}`), and a
    // dimensionless value is not followed by a unit `1`.
    let dir = tempfile::tempdir().expect("tempdir");
    let out = deploywatch(&[
        "diagnose",
        "--mechanism",
        s(&data(T01)),
        "--mechanism",
        s(&data(T02)),
        "--json",
        s(&dir.path().join("d.json")),
        s(&data("examples/c_seed001_friction_harness/seed001_T01.csv")),
        s(&data("examples/c_seed001_friction_harness/seed001_T02.csv")),
    ]);
    let text = succeeds(&out) + &stderr(&out);
    assert!(!text.contains('{') && !text.contains('}'), "{text}");
    assert!(!text.contains(" j1") && !text.contains(" j2"), "{text}");
    assert!(text.contains("at joint"), "{text}");
    for l in text.lines() {
        assert!(
            !l.trim_end().ends_with(" 1") && !l.contains(" 1 (95 %"),
            "unit `1` in {l:?}"
        );
    }
    let md = std::fs::read_to_string(dir.path().join("d.md")).expect("report");
    for d in 0..=9 {
        assert!(
            !md.contains(&format!("{d} 1 |")),
            "unit `1` in
{md}"
        );
    }
}

// ---------------------------------------------------------------------------
// --quiet on every command.

#[test]
fn quiet_silences_progress_and_chatter_on_every_command() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = |name: &str| dir.path().join(name);
    let (m1, m2) = (data(T01), data(T02));
    let run1 = data("examples/a_seed001_eft/seed001_T01.csv");
    let run2 = data("examples/a_seed001_eft/seed001_T02.csv");
    let sim = deploywatch(&[
        "simulate",
        s(&m1),
        "--out",
        s(&p("t01.csv")),
        "--plot",
        s(&p("t01.png")),
        "-q",
    ]);
    let id = identify_a(&["-q", "--json", s(&p("eft.json"))]);
    let margin = run_margin_from(&p("eft.json"), &["--quiet"]);
    let diag = deploywatch(&[
        "diagnose",
        "-q",
        "--mechanism",
        s(&m1),
        "--mechanism",
        s(&m2),
        "--json",
        s(&p("d.json")),
        s(&run1),
        s(&run2),
    ]);
    let (status_csv, status_png) = (p("status.csv"), p("status.png"));
    let replay = deploywatch(&[
        "replay",
        s(&run1),
        "--quiet",
        "--mechanism",
        s(&m1),
        "--out",
        s(&status_csv),
        "--plot",
        s(&status_png),
    ]);
    for (name, out) in [
        ("simulate", &sim),
        ("identify", &id),
        ("margin", &margin),
        ("diagnose", &diag),
        ("replay", &replay),
    ] {
        succeeds(out);
        let (o, e) = (stdout(out), stderr(out));
        assert!(e.is_empty(), "{name} -q wrote to stderr:\n{e}");
        for chatter in ["plot:", "json:", "status CSV:", "frames", "worker threads"] {
            assert!(!o.contains(chatter), "{name} -q says {chatter:?}:\n{o}");
        }
    }
    for f in [
        "t01.csv",
        "t01.png",
        "eft.json",
        "eft.png",
        "margins.json",
        "d.json",
        "d.md",
        "status.csv",
        "status.png",
    ] {
        assert!(p(f).exists(), "{f} was not written with --quiet");
    }
    // Without --quiet the same commands do report progress and files.
    let loud = identify_a(&["--json", s(&p("eft2.json"))]);
    assert!(stderr(&loud).contains("scan"), "{}", stderr(&loud));
    assert!(stdout(&loud).contains("json:"), "{}", stdout(&loud));
}

// ---------------------------------------------------------------------------
// identify warns when friction leaves a residual above the noise.

#[test]
fn identify_warns_when_friction_alone_leaves_residuals_above_the_noise() {
    // Example c: friction at joint 1 and a harness at joint 2; friction
    // alone leaves joint 2 well above the noise.
    let (r1, r2) = (
        data("examples/c_seed001_friction_harness/seed001_T01.csv"),
        data("examples/c_seed001_friction_harness/seed001_T02.csv"),
    );
    let out = deploywatch(&[
        "identify",
        "--quiet",
        "--mechanism",
        s(&data(T01)),
        "--mechanism",
        s(&data(T02)),
        s(&r1),
        s(&r2),
    ]);
    succeeds(&out);
    let err = stderr(&out);
    for says in [
        "warning:",
        "times the noise",
        "seed001_T01.csv joint 2",
        "in the stroke",
        "deploywatch diagnose",
    ] {
        assert!(err.contains(says), "lacks {says:?}:\n{err}");
    }
    // Example a is friction only: no warning.
    let out = identify_a(&["--quiet"]);
    succeeds(&out);
    assert!(!stderr(&out).contains("warning"), "{}", stderr(&out));
}

// ---------------------------------------------------------------------------
// Plots.

#[test]
fn identify_plot_has_a_residual_panel_per_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let png = dir.path().join("eft.png");
    succeeds(&identify_a(&["--quiet", "--plot", s(&png)]));
    // One panel per run and joint, plus one residual panel per run, each
    // 300 px high under a 40 px title (report/plot.rs).
    let (runs, joints) = (2, 3);
    assert_eq!(png_height(&png), 40 + 300 * runs * (joints + 1));
}

#[test]
fn simulate_and_replay_write_their_plots_quietly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let csv = dir.path().join("t02.csv");
    let png = dir.path().join("t02.png");
    succeeds(&deploywatch(&[
        "simulate",
        s(&data(T02)),
        "--out",
        s(&csv),
        "--plot",
        s(&png),
        "-q",
    ]));
    assert_eq!(png_height(&png), 40 + 300);
    let status_png = dir.path().join("status.png");
    succeeds(&deploywatch(&[
        "replay",
        s(&csv),
        "--mechanism",
        s(&data(T02)),
        "--plot",
        s(&status_png),
        "-q",
    ]));
    assert_eq!(png_height(&status_png), 40 + 3 * 300);
}

// What a new user hits on the release binary.

/// `deploywatch simulate … --plot x.png | true`: the reader of stdout is
/// gone before the first line. The command neither panics nor stops: the
/// run and the plot are written and it exits 0.
#[test]
fn a_closed_stdout_neither_panics_nor_stops_the_outputs() {
    use std::process::Stdio;
    let dir = tempfile::tempdir().expect("temp dir");
    let (csv, png) = (dir.path().join("t02.csv"), dir.path().join("t02.png"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_deploywatch"))
        .args([
            "simulate",
            s(&data(T02)),
            "--out",
            s(&csv),
            "--plot",
            s(&png),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run deploywatch");
    // Close the pipe's reading end at once, as `| true` does.
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("wait");
    let err = stderr(&out);
    assert!(!err.contains("panicked"), "panic:\n{err}");
    assert_eq!(out.status.code(), Some(0), "stderr:\n{err}");
    assert!(csv.is_file(), "the run is not written");
    assert!(png_height(&png) > 0, "the plot is not written");
}

/// The bundled run of example c at T01, diagnosed alone (about a second).
fn diagnose_t01(json: &Path) -> Output {
    let run = data("examples/c_seed001_friction_harness/seed001_T01.csv");
    deploywatch(&[
        "diagnose",
        "-q",
        "--mechanism",
        s(&data(T01)),
        "--json",
        s(json),
        s(&run),
    ])
}

/// A `diagnose` that fails half-way through its outputs (here a plot's
/// name is taken by a folder, found only when the plots are written)
/// leaves the old JSON and report as they were, not a new JSON beside an
/// old report, and no staging folder.
#[test]
fn a_diagnose_that_fails_half_way_leaves_the_old_outputs_as_they_were() {
    let dir = tempfile::tempdir().expect("temp dir");
    let json = dir.path().join("diagnosis.json");
    std::fs::write(&json, "old json").unwrap();
    std::fs::write(dir.path().join("diagnosis.md"), "old report").unwrap();
    let blocker = dir.path().join("diagnosis_seed001_T01_residuals.png");
    std::fs::create_dir(&blocker).unwrap();
    let out = diagnose_t01(&json);
    fails(&out, 2, &["diagnosis_seed001_T01_residuals.png", "folder"]);
    assert_eq!(std::fs::read_to_string(&json).unwrap(), "old json");
    let md = std::fs::read_to_string(dir.path().join("diagnosis.md")).unwrap();
    assert_eq!(md, "old report");
    let mut left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        [
            "diagnosis.json",
            "diagnosis.md",
            "diagnosis_seed001_T01_residuals.png"
        ]
    );
}

/// The image links of a Markdown report: the targets of `![alt](target)`.
fn image_links(md: &str) -> Vec<String> {
    md.split("![")
        .skip(1)
        .filter_map(|rest| {
            let open = rest.find("](")?;
            let tail = &rest[open + 2..];
            Some(tail[..tail.find(')')?].to_string())
        })
        .collect()
}

/// A link target percent-decoded (ASCII bytes and UTF-8).
fn percent_decoded(t: &str) -> String {
    let b = t.as_bytes();
    let (mut out, mut i) = (Vec::new(), 0);
    while i < b.len() {
        if b[i] == b'%' && i + 3 <= b.len() {
            let hex = std::str::from_utf8(&b[i + 1..i + 3]).unwrap();
            out.push(u8::from_str_radix(hex, 16).unwrap());
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).unwrap()
}

/// Splits a shell line into words: plain words and '…' quotes.
fn shell_words(line: &str) -> Vec<String> {
    let (mut words, mut cur, mut quoted, mut any) = (Vec::new(), String::new(), false, false);
    for c in line.chars() {
        match c {
            '\'' => {
                quoted = !quoted;
                any = true;
            }
            ' ' if !quoted => {
                if any {
                    words.push(std::mem::take(&mut cur));
                }
                any = false;
            }
            c => {
                cur.push(c);
                any = true;
            }
        }
    }
    if any {
        words.push(cur);
    }
    words
}

/// A report written where the path holds spaces: every image link is one
/// Markdown link (no bare space) to a file that exists, the residual-torque
/// figures among them; the report ends with the next step, a `margin
/// --from` command that runs as written.
#[test]
fn the_diagnosis_report_links_files_with_spaces_and_ends_with_a_next_step_that_runs() {
    let dir = tempfile::tempdir().expect("temp dir");
    let folder = dir.path().join("rig runs");
    std::fs::create_dir(&folder).unwrap();
    let json = folder.join("my diagnosis.json");
    succeeds(&diagnose_t01(&json));
    let md = std::fs::read_to_string(folder.join("my diagnosis.md")).unwrap();
    let links = image_links(&md);
    assert!(
        links.iter().filter(|l| l.contains("torque_")).count() >= 2,
        "{links:?}"
    );
    for l in &links {
        assert!(!l.contains(' ') && !l.contains('('), "broken link {l:?}");
        let file = folder.join(percent_decoded(l));
        assert!(file.is_file(), "link {l:?}: no file {}", file.display());
    }
    let next = md.rfind("## Next step").expect("a next step section");
    let tail = &md[next..];
    assert!(
        !tail[13..].contains("\n## "),
        "not the last section:\n{tail}"
    );
    let command = tail
        .lines()
        .find(|l| l.starts_with("deploywatch margin"))
        .expect("a margin command");
    let words = shell_words(command);
    assert!(words.iter().any(|w| w == s(&json)), "{words:?}");
    let args: Vec<&str> = words[1..].iter().map(String::as_str).collect();
    let out = succeeds(&deploywatch(&args));
    let from = format!("resistances from: diagnose ({})", json.display());
    assert!(out.contains(&from), "{out}");
}

/// A joint the monitor saw latch, leave the latched state and latch again
/// (example `latch_escape_never`, joints 1 and 3): replay names the first
/// latch and the one for good, as the status stream it wrote shows them.
#[test]
fn replay_names_the_first_and_the_final_latch() {
    let dir = tempfile::tempdir().expect("temp dir");
    let status = dir.path().join("status.csv");
    let run = data("examples/latch_escape_never/seed001_T01.csv");
    let mech = data("mechanisms/seed001_T01_physical_latch.toml");
    let out = succeeds(&deploywatch(&[
        "replay",
        s(&run),
        "--mechanism",
        s(&mech),
        "-q",
        "--out",
        s(&status),
    ]));
    let text = std::fs::read_to_string(&status).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let mut relatched = 0;
    for j in 1..=3 {
        let col = header
            .iter()
            .position(|h| *h == format!("latch{j}"))
            .unwrap();
        let latched: Vec<(f32, bool)> = rows
            .iter()
            .map(|r| (r[0].parse().unwrap(), r[col] == "latched"))
            .collect();
        let first = latched.iter().find(|x| x.1).map(|x| x.0);
        let end = latched.iter().rposition(|x| !x.1).map_or(0, |i| i + 1);
        let last = latched.get(end).map(|x| x.0);
        let line = out
            .lines()
            .find(|l| l.trim_start().starts_with(&format!("joint {j}:")))
            .unwrap();
        match (first, last) {
            (Some(a), Some(b)) if a != b => {
                relatched += 1;
                let want = format!("latched first at {a:.3} s, for good at {b:.3} s");
                assert!(line.contains(&want), "{line}\nlacks {want:?}");
            }
            (Some(a), Some(_)) => assert!(line.contains(&format!("latched at {a:.3} s")), "{line}"),
            (Some(a), None) => {
                let want = format!("latched first at {a:.3} s, not at the end");
                assert!(line.contains(&want), "{line}");
            }
            (None, _) => assert!(line.contains("not latched"), "{line}"),
        }
    }
    assert!(
        relatched > 0,
        "no joint latched twice: the case is not tested\n{out}"
    );
}
