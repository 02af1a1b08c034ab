//! The interchange formats of `docs/spec/formats.md`: the bundled mechanisms
//! and runs read, write and read back unchanged; every kind of bad input is
//! rejected with an error naming the file, the line or key, and what was
//! expected.

use std::path::{Path, PathBuf};

use deploywatch_core::spring::Interp;
use deploywatch_sim::mechanism::{Mechanism, SpringSpec};
use deploywatch_sim::mechanism_toml::{MechanismError, MechanismErrorKind};
use deploywatch_sim::run::{pair_runs, Run, RunError, RunErrorKind};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data")
}

/// The files of `dir` with extension `ext`, sorted.
fn files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == ext))
        .collect();
    v.sort();
    v
}

fn mechanisms() -> Vec<Mechanism> {
    // The truss wings (`*_truss*.toml`) are tested in tests/truss.rs and
    // host-sim/tests/truss_cli.rs; the project's own
    // `reliability_one_panel.toml` (not a seed mechanism) in tests/reliability.rs;
    // the physical-latch examples (`*_physical_latch.toml`) in tests/physical_latch.rs;
    // the rig examples (`*_rig.toml`) in host-sim/tests/rig.rs;
    // the pawl examples (`*_pawl.toml`) in tests/latch_pawl.rs.
    files(&data().join("mechanisms"), "toml")
        .iter()
        .filter(|p| !p.to_string_lossy().contains("_truss"))
        .filter(|p| !p.to_string_lossy().contains("_physical_latch"))
        .filter(|p| !p.to_string_lossy().ends_with("_rig.toml"))
        .filter(|p| !p.to_string_lossy().ends_with("_pawl.toml"))
        .filter(|p| {
            p.file_name()
                .is_some_and(|f| f.to_string_lossy().starts_with("seed"))
        })
        .map(|p| Mechanism::load(p).unwrap_or_else(|e| panic!("{e}")))
        .collect()
}

/// `data/reference/*.csv` and `data/examples/*/*.csv` (but the
/// physical-latch runs `data/examples/latch_*`, tested in
/// tests/physical_latch.rs with their own mechanisms).
fn bundled_runs() -> Vec<PathBuf> {
    let mut v = files(&data().join("reference"), "csv");
    for d in std::fs::read_dir(data().join("examples")).expect("examples") {
        let d = d.expect("entry").path();
        let latch = d
            .file_name()
            .is_some_and(|f| f.to_string_lossy().starts_with("latch_"));
        if d.is_dir() && !latch {
            v.extend(files(&d, "csv"));
        }
    }
    v.sort();
    v
}

/// 1-based line of the first line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle:?} not in text"))
        + 1
}

// ---------------------------------------------------------------------------
// Mechanisms.

fn t01_text() -> String {
    std::fs::read_to_string(data().join("mechanisms/seed001_T01.toml")).expect("T01")
}

/// T01 with the first `from` replaced by `to`.
fn t01_with(from: &str, to: &str) -> String {
    let text = t01_text();
    assert!(text.contains(from), "{from:?} not in T01");
    text.replacen(from, to, 1)
}

fn bad_mech(text: &str) -> MechanismError {
    match Mechanism::from_toml_str(text, "bad.toml") {
        Ok(m) => panic!("accepted: {m:?}"),
        Err(e) => e,
    }
}

#[test]
fn the_four_bundled_mechanisms_load() {
    let ms = mechanisms();
    let names: Vec<&str> = ms.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "seed000-case1-open",
            "seed000-case3-open",
            "seed001-T01",
            "seed001-T02"
        ]
    );
    let case3 = &ms[1];
    assert_eq!(case3.joint_count(), 2);
    assert_eq!(case3.panels[1].mass_kg, 4.28);
    assert_eq!(case3.joints[0].stowed_deg, 90.0);
    assert_eq!(
        case3.joints[1].spring,
        SpringSpec::Linear {
            preload_nm: 0.711942,
            stiffness_nm_per_rad: 0.909758,
            count: 1
        }
    );
    let t02 = &ms[3];
    assert_eq!(t02.joint_count(), 3);
    assert_eq!(t02.duration_s, 12.0);
    assert_eq!(t02.sample_hz, 100.0);
    assert_eq!(t02.joints[2].stowed_deg, -180.0);
    let SpringSpec::Tape {
        type_name,
        points,
        count,
    } = &t02.joints[0].spring
    else {
        panic!("T02 joint 1 is a tape spring")
    };
    assert_eq!((type_name.as_str(), *count), ("TS-3", 2));
    assert_eq!(points.a, (1.08, 33.43));
    assert_eq!(points.b, (1.15, 0.46));
    assert_eq!(points.d, (0.29, 11.07));
    assert_eq!((points.m_90, points.c_180), (0.385, 0.74));
    for m in &ms {
        assert_eq!(m.joints.len(), m.panels.len());
        for j in &m.joints {
            assert_eq!(
                j.friction,
                Default::default(),
                "{}: nominal, no friction",
                m.name
            );
        }
    }
}

#[test]
fn bundled_mechanisms_round_trip() {
    for m in mechanisms() {
        let text = m.to_toml_string();
        let back = Mechanism::from_toml_str(&text, "written.toml")
            .unwrap_or_else(|e| panic!("{}: {e}\n{text}", m.name));
        assert_eq!(back, m, "{}", m.name);
        assert_eq!(back.to_toml_string(), text, "{}: writing is stable", m.name);
    }
}

#[test]
fn mechanism_with_curve_spring_friction_and_defaults_round_trips() {
    let text = r#"
name = "one panel"

[[panel]]
length_m = 1
mass_kg = 2.0
com_m = 0.5
inertia_kgm2 = 0.2

[[joint]]
stowed_deg = 120
spring = { kind = "curve", unfold = [[0.0, 0.0], [10.0, 1.5], [180.0, 2.0]], fold = [[0, 0], [5, 3], [180, 2.5]], interp = "linear", count = 2 }
friction = { coulomb_nm = 0.3, viscous_nms = 0.01, breakaway_nm = 0.5, stribeck_rad_s = 0.02 }
"#;
    let m = Mechanism::from_toml_str(text, "curve.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.description, "");
    assert_eq!(m.duration_s, 6.0, "default duration");
    assert_eq!(m.sample_hz, 100.0, "default sample rate");
    assert_eq!(m.panels[0].length_m, 1.0, "integers read as numbers");
    let j = &m.joints[0];
    assert_eq!(
        j.spring,
        SpringSpec::Curve {
            unfold: vec![(0.0, 0.0), (10.0, 1.5), (180.0, 2.0)],
            fold: Some(vec![(0.0, 0.0), (5.0, 3.0), (180.0, 2.5)]),
            interp: Interp::Linear,
            count: 2
        }
    );
    assert_eq!(j.friction.coulomb_nm, 0.3);
    assert_eq!(j.friction.viscous_nms, 0.01);
    assert_eq!(
        j.friction.coulomb_threshold_rad_s, 0.01,
        "default threshold"
    );
    assert_eq!(j.friction.stribeck, Some((0.5, 0.02)));
    let back =
        Mechanism::from_toml_str(&m.to_toml_string(), "w.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back, m);

    // A curve spring without fold or interp: no hysteresis, Akima.
    let plain = text
        .replace(", fold = [[0, 0], [5, 3], [180, 2.5]]", "")
        .replace(", interp = \"linear\"", "");
    let m = Mechanism::from_toml_str(&plain, "plain.toml").unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(
        m.joints[0].spring,
        SpringSpec::Curve {
            fold: None,
            interp: Interp::Akima,
            ..
        }
    ));
}

#[test]
fn mechanism_written_to_a_file_reads_back() {
    let dir = tempfile::tempdir().expect("tempdir");
    for m in mechanisms() {
        let path = dir.path().join("m.toml");
        m.write(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(Mechanism::load(&path).unwrap_or_else(|e| panic!("{e}")), m);
    }
}

#[test]
fn unknown_spring_kind_names_joint_line_key_and_kinds() {
    let text = t01_with(
        r#"spring = { kind = "tape", type = "TS-2", count = 2 }"#,
        r#"spring = { kind = "torsion", type = "TS-2", count = 2 }"#,
    );
    let e = bad_mech(&text);
    let file = &e.file;
    let line = e.line;
    let MechanismErrorKind::UnknownSpringKind {
        ref key,
        joint,
        ref found,
    } = e.kind
    else {
        panic!("wrong error: {e}")
    };
    let want_line = line_of(&text, "torsion");
    assert_eq!(file, "bad.toml");
    assert_eq!(line, Some(want_line));
    assert_eq!(key, "joint[2].spring.kind");
    assert_eq!(joint, 2);
    assert_eq!(found, "torsion");
    assert_eq!(
        e.to_string(),
        format!(
            "bad.toml:{want_line}: `joint[2].spring.kind`: unknown spring kind \"torsion\" for joint 2; \
             expected one of \"linear\", \"tape\", \"curve\""
        )
    );
}

#[test]
fn missing_tape_type_lists_the_defined_ones() {
    let text = t01_with(r#"type = "TS-3""#, r#"type = "TS-9""#);
    let e = bad_mech(&text);
    assert!(
        matches!(e.kind, MechanismErrorKind::UnknownTapeType { .. }),
        "{e}"
    );
    assert_eq!(e.line(), Some(line_of(&text, "TS-9")));
    assert_eq!(e.key(), Some("joint[3].spring.type"));
    let msg = e.to_string();
    assert!(msg.contains(r#"tape type "TS-9" is not defined"#), "{msg}");
    assert!(msg.contains(r#"expected a [tape."TS-9"] table"#), "{msg}");
    assert!(
        msg.contains(r#"(defined: "TS-1", "TS-2", "TS-3")"#),
        "{msg}"
    );
}

#[test]
fn tape_spring_without_type_is_a_missing_key() {
    let text = t01_with(r#"type = "TS-1", "#, "");
    let e = bad_mech(&text);
    assert!(
        matches!(e.kind, MechanismErrorKind::MissingKey { .. }),
        "{e}"
    );
    assert_eq!(e.key(), Some("joint[1].spring.type"));
    assert_eq!(
        e.line(),
        Some(line_of(&text, r#"kind = "tape", count = 3"#))
    );
    assert!(
        e.to_string()
            .contains("the name of a [tape.\"NAME\"] table"),
        "{e}"
    );
}

#[test]
fn unknown_keys_are_rejected_with_the_allowed_ones() {
    let text = t01_with("com_m = 0.4", "com_m = 0.4\ncentre_m = 0.4");
    let e = bad_mech(&text);
    assert!(
        matches!(e.kind, MechanismErrorKind::UnknownKey { .. }),
        "{e}"
    );
    assert_eq!(e.key(), Some("panel[1].centre_m"));
    let line = line_of(&text, "centre_m");
    assert_eq!(e.line(), Some(line));
    assert_eq!(
        e.to_string(),
        format!(
            "bad.toml:{line}: unknown key `panel[1].centre_m`; \
             expected one of: length_m, mass_kg, com_m, inertia_kgm2"
        )
    );

    let e = bad_mech(&t01_with("name =", "colour = \"red\"\nname ="));
    assert_eq!(e.key(), Some("colour"));
    assert_eq!(e.line(), Some(1));
    assert!(
        e.to_string()
            .contains("name, description, panel, joint, tape, run"),
        "{e}"
    );

    let text = t01_with("count = 3 }", "count = 3, preload_nm = 1.0 }");
    let e = bad_mech(&text);
    assert_eq!(e.key(), Some("joint[1].spring.preload_nm"));
    assert_eq!(e.line(), Some(line_of(&text, "preload_nm")));
    assert!(
        e.to_string().contains("expected one of: kind, type, count"),
        "{e}"
    );

    let e = bad_mech(&t01_with("m_90 = 1.20", "m_90 = 1.20\nm_45 = 1.0"));
    assert_eq!(e.key(), Some("tape.TS-1.m_45"));

    let e = bad_mech(&t01_with(
        "sample_hz = 100.0",
        "sample_hz = 100.0\nseed = 3",
    ));
    assert_eq!(e.key(), Some("run.seed"));

    let e = bad_mech(&t01_with(
        "stowed_deg = -90.0",
        "stowed_deg = -90.0\nfriction = { coulomb_nm = 1.0, static_nm = 2.0 }",
    ));
    assert_eq!(e.key(), Some("joint[1].friction.static_nm"));
}

#[test]
fn non_finite_and_out_of_range_numbers_are_rejected() {
    for (from, to, key, expected) in [
        (
            "stowed_deg = -90.0",
            "stowed_deg = nan",
            "joint[1].stowed_deg",
            "a finite non-zero number [deg], found nan",
        ),
        (
            "stowed_deg = -90.0",
            "stowed_deg = 0.0",
            "joint[1].stowed_deg",
            "a finite non-zero number [deg], found 0.0",
        ),
        (
            "length_m = 0.8",
            "length_m = -0.8",
            "panel[1].length_m",
            "a finite number > 0 [m], found -0.8",
        ),
        (
            "mass_kg = 3.5",
            "mass_kg = inf",
            "panel[1].mass_kg",
            "> 0 [kg], found inf",
        ),
        (
            "inertia_kgm2 = 0.27",
            "inertia_kgm2 = 0",
            "panel[1].inertia_kgm2",
            "> 0 [kg·m²]",
        ),
        (
            "com_m = 0.4",
            "com_m = -inf",
            "panel[1].com_m",
            "a finite number [m]",
        ),
        (
            "duration_s = 6.0",
            "duration_s = 0.0",
            "run.duration_s",
            "> 0 [s]",
        ),
        (
            "sample_hz = 100.0",
            "sample_hz = -100.0",
            "run.sample_hz",
            "> 0 [Hz]",
        ),
        (
            "sample_hz = 100.0",
            "sample_hz = 2e6",
            "run.sample_hz",
            "≤ 1e6 [Hz]",
        ),
        (
            "count = 3",
            "count = 0",
            "joint[1].spring.count",
            "an integer ≥ 1",
        ),
        ("m_90 = 1.20", "m_90 = -1.20", "tape.TS-1.m_90", "≥ 0"),
        (
            "d = [0.52, 37.0]",
            "d = [1.5, 37.0]",
            "tape.TS-1.b",
            "d's deg < deg < 90",
        ),
    ] {
        let text = t01_with(from, to);
        let e = bad_mech(&text);
        assert!(
            matches!(e.kind, MechanismErrorKind::InvalidValue { .. }),
            "{to}: {e}"
        );
        assert_eq!(e.key(), Some(key), "{to}: {e}");
        let msg = e.to_string();
        assert!(msg.contains(expected), "{to}: {msg}");
        let line = line_of(&text, to.split(" = ").next().unwrap_or(to));
        if key.starts_with("tape") && key.ends_with(".b") {
            assert!(msg.starts_with("bad.toml:"), "{to}: {msg}");
        } else {
            assert!(
                msg.starts_with(&format!("bad.toml:{line}: `{key}`")),
                "{to}: {msg}"
            );
        }
    }
}

#[test]
fn wrong_types_are_rejected() {
    let text = t01_with("count = 3", "count = 2.5");
    let e = bad_mech(&text);
    assert!(
        matches!(e.kind, MechanismErrorKind::WrongType { .. }),
        "{e}"
    );
    assert_eq!(e.key(), Some("joint[1].spring.count"));
    assert_eq!(e.line(), Some(line_of(&text, "count = 2.5")));
    assert!(e.to_string().contains("expected an integer ≥ 1"), "{e}");
    assert!(e.to_string().contains("found a float"), "{e}");

    let e = bad_mech(&t01_with("mass_kg = 3.5", "mass_kg = \"3.5\""));
    assert_eq!(e.key(), Some("panel[1].mass_kg"));
    assert!(e.to_string().contains("found a string"), "{e}");

    let e = bad_mech(&t01_with("a = [1.10, 69.39]", "a = [1.10]"));
    assert_eq!(e.key(), Some("tape.TS-1.a"));
    assert!(e.to_string().contains("a pair of finite numbers"), "{e}");

    let e = bad_mech(&t01_with("name = \"seed001-T01\"", "name = 1979-05-27"));
    assert_eq!(e.key(), Some("name"));
    assert!(e.to_string().contains("found a date-time"), "{e}");
}

#[test]
fn panel_and_joint_counts_are_checked() {
    let text = t01_with(
        "[[joint]]\nstowed_deg = -180.0",
        "[[jointx]]\nstowed_deg = -180.0",
    );
    let e = bad_mech(&text);
    assert_eq!(e.key(), Some("jointx"), "unknown table: {e}");

    // Drop the third joint: 3 panels, 2 joints.
    let text = t01_text();
    let start = text.rfind("[[joint]]").expect("joint");
    let end = text.find("[tape.").expect("tape");
    let two = format!("{}{}", &text[..start], &text[end..]);
    let e = bad_mech(&two);
    assert!(
        matches!(
            e.kind,
            MechanismErrorKind::JointCount {
                panels: 3,
                joints: 2,
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        "bad.toml: expected one [[joint]] table per [[panel]] table (3), found 2 [[joint]] tables"
    );

    let panel = "[[panel]]\nlength_m = 0.8\nmass_kg = 3.5\ncom_m = 0.4\ninertia_kgm2 = 0.27\n\n";
    let nine = t01_with("[[panel]]", &format!("{}[[panel]]", panel.repeat(6)));
    let e = bad_mech(&nine);
    assert!(
        matches!(e.kind, MechanismErrorKind::PanelCount { found: 9, .. }),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("expected 1 to 8 [[panel]] tables, found 9"),
        "{e}"
    );

    let e = bad_mech("name = \"x\"\njoint = []\n");
    assert!(
        matches!(e.kind, MechanismErrorKind::MissingKey { .. }),
        "{e}"
    );
    assert_eq!(e.key(), Some("panel"));
}

#[test]
fn friction_breakaway_needs_stribeck() {
    let text = t01_with(
        "stowed_deg = 180.0",
        "stowed_deg = 180.0\nfriction = { coulomb_nm = 0.2, breakaway_nm = 0.4 }",
    );
    let e = bad_mech(&text);
    assert!(
        matches!(e.kind, MechanismErrorKind::MissingKey { .. }),
        "{e}"
    );
    assert_eq!(e.key(), Some("joint[2].friction.stribeck_rad_s"));
    assert_eq!(e.line(), Some(line_of(&text, "breakaway_nm")));
    assert!(e.to_string().contains("both or neither"), "{e}");

    let ok = t01_with(
        r#"spring = { kind = "tape", type = "TS-2", count = 2 }"#,
        "spring = { kind = \"tape\", type = \"TS-2\", count = 2 }\n\
         [joint.friction]\ncoulomb_nm = 0.2\ncoulomb_threshold_rad_s = 0.05",
    );
    let m = Mechanism::from_toml_str(&ok, "ok.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.joints[1].friction.coulomb_nm, 0.2);
    assert_eq!(m.joints[1].friction.coulomb_threshold_rad_s, 0.05);
}

#[test]
fn bad_curves_are_rejected_by_key() {
    let curve = |unfold: &str| {
        t01_with(
            r#"{ kind = "tape", type = "TS-1", count = 3 }"#,
            &format!(r#"{{ kind = "curve", unfold = {unfold}, count = 1 }}"#),
        )
    };
    let text = curve("[[0, 0], [10, 1], [5, 2]]");
    let e = bad_mech(&text);
    assert!(matches!(e.kind, MechanismErrorKind::BadCurve { .. }), "{e}");
    assert_eq!(e.key(), Some("joint[1].spring.unfold"));
    assert_eq!(e.line(), Some(line_of(&text, "unfold")));
    assert!(e.to_string().contains("strictly increasing"), "{e}");

    let many: Vec<String> = (0..17).map(|i| format!("[{i}, 1]")).collect();
    let e = bad_mech(&curve(&format!("[{}]", many.join(", "))));
    assert!(e.to_string().contains("at most 16"), "{e}");

    let e = bad_mech(&curve("[[0, 0], [10, nan]]"));
    assert_eq!(e.key(), Some("joint[1].spring.unfold[2][2]"));

    let e = bad_mech(&t01_with(
        r#"{ kind = "tape", type = "TS-1", count = 3 }"#,
        r#"{ kind = "curve", unfold = [[0, 0], [10, 1]], interp = "cubic", count = 1 }"#,
    ));
    assert_eq!(e.key(), Some("joint[1].spring.interp"));
    assert!(e.to_string().contains("\"akima\" or \"linear\""), "{e}");
}

#[test]
fn toml_syntax_errors_give_the_line() {
    let text = t01_with("mass_kg = 3.5", "mass_kg = = 3.5");
    let e = bad_mech(&text);
    assert!(matches!(e.kind, MechanismErrorKind::Syntax { .. }), "{e}");
    let line = line_of(&text, "mass_kg = = 3.5");
    assert_eq!(e.line(), Some(line));
    let msg = e.to_string();
    assert!(
        msg.starts_with(&format!("bad.toml:{line}: invalid TOML at column 11: ")),
        "{msg}"
    );
    assert!(!msg.contains('\n'), "one line: {msg}");
}

#[test]
fn mechanism_file_errors_name_the_path() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("wing.toml");
    let text = t01_with("count = 3", "count = -3");
    std::fs::write(&path, &text).expect("write");
    let e = Mechanism::load(&path).expect_err("count = -3");
    let line = line_of(&text, "count = -3");
    assert!(
        e.to_string().starts_with(&format!(
            "{}:{line}: `joint[1].spring.count`",
            path.display()
        )),
        "{e}"
    );
    let e = Mechanism::load(&dir.path().join("absent.toml")).expect_err("absent");
    assert!(matches!(e.kind, MechanismErrorKind::Io { .. }), "{e}");
    assert!(e.to_string().contains("absent.toml"), "{e}");
}

// ---------------------------------------------------------------------------
// Runs.

#[test]
fn bundled_runs_round_trip() {
    let runs = bundled_runs();
    assert_eq!(runs.len(), 18, "8 reference + 10 example runs: {runs:?}");
    for path in runs {
        let text = std::fs::read_to_string(&path).expect("read");
        let run = Run::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(run.len() > 100, "{}", path.display());
        assert_eq!(run.latch.len(), run.joints());
        let written = run.to_csv_string();
        let back = Run::parse(&written, "written.csv").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(back, run, "{}", path.display());
        assert_eq!(
            back.to_csv_string(),
            written,
            "{}: writing is stable",
            path.display()
        );
        if path.parent().is_some_and(|p| p.ends_with("reference")) {
            // Written as shared/reference writes it: byte for byte.
            assert!(written == text, "{}: not byte-identical", path.display());
        }
    }
}

#[test]
fn reference_run_content() {
    let run = Run::load(&data().join("reference/seed001_T01_nominal.csv"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(run.mechanism(), Some("seed001-T01"));
    assert_eq!(run.meta("effects"), Some("none"));
    assert_eq!(run.joints(), 3);
    assert_eq!(run.t_s[0], 0.0);
    assert_eq!(run.t_s[1], 0.001);
    assert_eq!(*run.t_s.last().expect("samples"), 2.357);
    assert_eq!(run.phi_deg[0][0], -90.0);
    assert_eq!(run.phi_deg[1][0], 180.0);
    assert!(run
        .latch
        .iter()
        .all(|l| !l[0] && *l.last().expect("samples")));
}

#[test]
fn runs_pair_with_their_mechanisms() {
    // The seed mechanisms and the four- and six-panel test wings.
    let mut ms = mechanisms();
    ms.extend(
        files(&data().join("mechanisms"), "toml")
            .iter()
            .filter(|p| {
                p.file_name()
                    .is_some_and(|f| f.to_string_lossy().starts_with("wing"))
            })
            .map(|p| Mechanism::load(p).unwrap_or_else(|e| panic!("{e}"))),
    );
    for path in bundled_runs() {
        let run = Run::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let m = pair_runs(&ms, &run, &path.display().to_string()).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(Some(m.name.as_str()), run.mechanism());
        assert_eq!(m.joint_count(), run.joints());
    }
}

const GOOD: &str = "# mechanism = \"seed000-case1-open\"\n\
# source = \"hand-written, \\\"quoted\\\" \\u00b0\"\n\
t_s,phi1_deg,phi2_deg,latch1,latch2\n\
0.000,90.0,-180.0,0,0\n\
0.010,89.5,-179.0,0,0\n\
0.020,89.0,-178.5,0,0\n";

fn bad_run(text: &str) -> RunError {
    match Run::parse(text, "bad.csv") {
        Ok(r) => panic!("accepted: {r:?}"),
        Err(e) => e,
    }
}

#[test]
fn metadata_values_are_json_strings() {
    let run = Run::parse(GOOD, "good.csv").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(run.meta("source"), Some("hand-written, \"quoted\" °"));
    let written = run.to_csv_string();
    assert!(
        written.starts_with(
            "# mechanism = \"seed000-case1-open\"\n# source = \"hand-written, \\\"quoted\\\" °\"\n"
        ),
        "{written}"
    );
    assert_eq!(
        Run::parse(&written, "w.csv").unwrap_or_else(|e| panic!("{e}")),
        run
    );
    // Accepted variations: CRLF, no final newline.
    let crlf = GOOD.replace('\n', "\r\n");
    assert_eq!(
        Run::parse(&crlf, "crlf.csv").unwrap_or_else(|e| panic!("{e}")),
        run
    );
    assert_eq!(
        Run::parse(GOOD.trim_end(), "x.csv").unwrap_or_else(|e| panic!("{e}")),
        run
    );

    let e = bad_run(&GOOD.replace("\"seed000-case1-open\"", "seed000-case1-open"));
    assert!(
        matches!(e.kind, RunErrorKind::BadMetadata { .. } if e.line == Some(1)),
        "{e}"
    );
    assert!(
        e.to_string().starts_with("bad.csv:1: bad metadata line"),
        "{e}"
    );
    assert!(e.to_string().contains("JSON string"), "{e}");

    let e = bad_run(&GOOD.replace("# source =", "# mechanism ="));
    assert!(
        matches!(e.kind, RunErrorKind::DuplicateMetadata {
                first: 1,
                ..
            } if e.line == Some(2)),
        "{e}"
    );

    let e = bad_run(&GOOD.replace("# source =", "# a comment, not metadata"));
    assert!(
        matches!(e.kind, RunErrorKind::BadMetadata { .. } if e.line == Some(2)),
        "{e}"
    );
}

#[test]
fn missing_column() {
    let e = bad_run(&GOOD.replace("latch1,latch2", "latch1"));
    let file = &e.file;
    let line = e.line.unwrap_or(0);
    let RunErrorKind::MissingColumn {
        ref column,
        ref expected_header,
    } = e.kind
    else {
        panic!("wrong error: {e}")
    };
    assert_eq!(
        (file.as_str(), line, column.as_str()),
        ("bad.csv", 3, "latch2")
    );
    assert_eq!(expected_header, "t_s,phi1_deg,phi2_deg,latch1,latch2");
    assert_eq!(
        e.to_string(),
        "bad.csv:3: missing column `latch2`; expected the header `t_s,phi1_deg,phi2_deg,latch1,latch2`"
    );

    let e = bad_run(&GOOD.replace("t_s,", "time,"));
    assert!(
        matches!(e.kind, RunErrorKind::UnknownColumn { position: 1, .. }),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        "bad.csv:3: unknown column `time` (column 1): expected `t_s` there; expected the header \
         `t_s,phi1_deg,phi2_deg,latch1,latch2` (for 2 joint(s))"
    );
    // No column spelt right: the joint count comes from the header's width.
    let e = bad_run(&GOOD.replace("t_s,phi1_deg,phi2_deg,latch1,latch2", "time,a1,a2,s1,s2"));
    assert!(
        e.to_string().contains(
            "unknown column `time` (column 1): expected `t_s` there; expected the header \
             `t_s,phi1_deg,phi2_deg,latch1,latch2` (for 2 joint(s))"
        ),
        "{e}"
    );

    let e = bad_run(&GOOD.replace("t_s,phi1_deg,phi2_deg", "t_s,phi1_deg,phi3_deg"));
    assert!(
        matches!(e.kind, RunErrorKind::MissingColumn { ref column, .. } if column == "phi2_deg"),
        "{e}"
    );
}

#[test]
fn wrong_column_order() {
    let e = bad_run(&GOOD.replace("latch1,latch2", "latch2,latch1"));
    assert!(
        matches!(e.kind, RunErrorKind::ColumnOrder { position: 4, ref found, ref expected, .. } if e.line == Some(3) && found == "latch2" && expected == "latch1"),
        "{e}"
    );
    assert!(
        e.to_string()
            .starts_with("bad.csv:3: wrong column order: column 4 is `latch2`, expected `latch1`"),
        "{e}"
    );

    let e = bad_run(&GOOD.replace(
        "t_s,phi1_deg,phi2_deg,latch1",
        "phi1_deg,t_s,phi2_deg,latch1",
    ));
    assert!(
        matches!(e.kind, RunErrorKind::ColumnOrder { position: 1, .. }),
        "{e}"
    );
}

#[test]
fn extra_and_duplicate_columns() {
    let e = bad_run(&GOOD.replace("latch2\n", "latch2,latch3\n"));
    assert!(
        matches!(e.kind, RunErrorKind::ExtraColumn { position: 6, ref column, .. } if e.line == Some(3) && column == "latch3"),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("expected the header `t_s,phi1_deg,phi2_deg,latch1,latch2`"),
        "{e}"
    );

    let e = bad_run(&GOOD.replace("latch2\n", "latch2,temp_c\n"));
    assert!(
        matches!(e.kind, RunErrorKind::ExtraColumn { position: 6, .. }),
        "{e}"
    );

    let e = bad_run(&GOOD.replace("latch1,latch2", "latch1,latch1"));
    assert!(
        matches!(
            e.kind,
            RunErrorKind::DuplicateColumn {
                first: 4,
                position: 5,
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn too_many_joints() {
    let phi: Vec<String> = (1..=9).map(|j| format!("phi{j}_deg")).collect();
    let latch: Vec<String> = (1..=9).map(|j| format!("latch{j}")).collect();
    let header = format!("t_s,{},{}", phi.join(","), latch.join(","));
    let row = format!("0.0,{},{}", ["1"; 9].join(","), ["0"; 9].join(","));
    let e = bad_run(&format!("{header}\n{row}\n"));
    assert!(
        matches!(e.kind, RunErrorKind::TooManyJoints {
                found: 9,
                ..
            } if e.line == Some(1)),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        "bad.csv:1: 9 joints in the header; expected 1 to 8"
    );
}

#[test]
fn non_monotonic_time() {
    let e = bad_run(&GOOD.replace("0.020,", "0.010,"));
    let file = &e.file;
    let line = e.line.unwrap_or(0);
    let RunErrorKind::NonMonotonicTime {
        ref found,
        ref previous,
    } = e.kind
    else {
        panic!("wrong error: {e}")
    };
    assert_eq!((file.as_str(), line), ("bad.csv", 6));
    assert_eq!((found.as_str(), previous.as_str()), ("0.010", "0.010"));
    assert_eq!(
        e.to_string(),
        "bad.csv:6: column `t_s`: expected a time after 0.010 s (strictly increasing), found 0.010 s"
    );
    let e = bad_run(&GOOD.replace("0.010,", "0.030,"));
    assert!(
        matches!(e.kind, RunErrorKind::NonMonotonicTime { .. } if e.line == Some(6)),
        "{e}"
    );
}

#[test]
fn nan_inf_and_garbage_numbers() {
    let e = bad_run(&GOOD.replace("89.5,-179.0", "89.5,NaN"));
    let file = &e.file;
    let line = e.line.unwrap_or(0);
    let RunErrorKind::BadNumber {
        ref column,
        ref found,
        ..
    } = e.kind
    else {
        panic!("wrong error: {e}")
    };
    assert_eq!(
        (file.as_str(), line, column.as_str(), found.as_str()),
        ("bad.csv", 5, "phi2_deg", "NaN")
    );
    assert_eq!(
        e.to_string(),
        "bad.csv:5: column `phi2_deg`: expected a finite number, found `NaN`; a missing reading \
         may be written `NaN` only in a file that declares it: add the line \
         `# missing_samples = \"NaN\"` before the header (docs/spec/formats.md)"
    );

    let e = bad_run(&GOOD.replace("89.0,", "inf,"));
    assert!(
        matches!(e.kind, RunErrorKind::BadNumber { ref column, .. } if e.line == Some(6) && column == "phi1_deg"),
        "{e}"
    );
    let e = bad_run(&GOOD.replace("0.010,", "0.01s,"));
    assert!(
        matches!(e.kind, RunErrorKind::BadNumber { ref column, .. } if e.line == Some(5) && column == "t_s"),
        "{e}"
    );
    let e = bad_run(&GOOD.replace("89.0,", ","));
    assert!(
        matches!(e.kind, RunErrorKind::BadNumber { ref found, .. } if e.line == Some(6) && found.is_empty()),
        "{e}"
    );
}

#[test]
fn latch_must_be_0_or_1() {
    for bad in ["2", "0.0", "true", ""] {
        let e = bad_run(&GOOD.replace("89.0,-178.5,0,0", &format!("89.0,-178.5,0,{bad}")));
        assert!(
            matches!(e.kind, RunErrorKind::BadLatch { ref column, ref found, .. } if e.line == Some(6) && column == "latch2" && found == bad),
            "{bad}: {e}"
        );
        assert_eq!(
            e.to_string(),
            format!("bad.csv:6: column `latch2`: expected 0 or 1, found `{bad}`")
        );
    }
}

#[test]
fn rows_with_the_wrong_field_count() {
    let e = bad_run(&GOOD.replace("89.5,-179.0,0,0", "89.5,-179.0,0"));
    assert!(
        matches!(e.kind, RunErrorKind::FieldCount {
                expected: 5,
                found: 4,
                ..
            } if e.line == Some(5)),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        "bad.csv:5: expected 5 comma-separated fields (as in the header), found 4"
    );
}

#[test]
fn empty_file_and_header_only() {
    let e = bad_run("");
    assert!(
        matches!(e.kind, RunErrorKind::NoHeader if e.line == Some(1)),
        "{e}"
    );
    assert!(
        e.to_string()
            .starts_with("bad.csv:1: expected a header line"),
        "{e}"
    );

    let e = bad_run("# mechanism = \"x\"\n");
    assert!(
        matches!(e.kind, RunErrorKind::NoHeader if e.line == Some(2)),
        "{e}"
    );

    let header_only: String = GOOD.lines().take(3).map(|l| format!("{l}\n")).collect();
    let e = bad_run(&header_only);
    assert!(
        matches!(e.kind, RunErrorKind::NoSamples if e.line == Some(4)),
        "{e}"
    );
    assert!(
        e.to_string().contains("expected at least one data row"),
        "{e}"
    );
}

#[test]
fn blank_lines_and_late_metadata() {
    let e = bad_run(&GOOD.replace("0.010,", "\n0.010,"));
    assert!(
        matches!(e.kind, RunErrorKind::BadLine { .. } if e.line == Some(5)),
        "{e}"
    );
    let e = bad_run(&format!("{GOOD}# note = \"late\"\n"));
    assert!(
        matches!(e.kind, RunErrorKind::BadLine { .. } if e.line == Some(7)),
        "{e}"
    );
}

#[test]
fn run_file_errors_name_the_path() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("t03.csv");
    std::fs::write(&path, GOOD.replace("0.020,", "0.005,")).expect("write");
    let e = Run::load(&path).expect_err("non-monotonic");
    assert!(
        e.to_string()
            .starts_with(&format!("{}:6: column `t_s`", path.display())),
        "{e}"
    );
    let e = Run::load(&dir.path().join("absent.csv")).expect_err("absent");
    assert!(matches!(e.kind, RunErrorKind::Io { .. }), "{e}");
    assert!(e.to_string().contains("absent.csv"), "{e}");
}

#[test]
fn pair_runs_errors() {
    let ms = mechanisms();
    let run = Run::parse(GOOD, "good.csv").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        pair_runs(&ms, &run, "good.csv")
            .map(|m| m.name.as_str())
            .ok(),
        Some("seed000-case1-open")
    );

    // Joint count mismatch: a 2-joint run naming a 3-joint mechanism.
    let mut wrong = run.clone();
    wrong.set_meta("mechanism", "seed001-T01");
    let e = pair_runs(&ms, &wrong, "t01.csv").expect_err("2 vs 3 joints");
    assert!(
        matches!(
            e.kind,
            RunErrorKind::JointCountMismatch {
                run_joints: 2,
                mechanism_joints: 3,
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        "t01.csv: the run has 2 joints but mechanism \"seed001-T01\" has 3; expected equal joint counts"
    );

    // Mechanism not given.
    let e = pair_runs(&ms[2..], &run, "good.csv").expect_err("not given");
    assert!(
        matches!(e.kind, RunErrorKind::UnknownMechanism { .. }),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        "good.csv:1: mechanism \"seed000-case1-open\" (from the run's metadata) was not given; \
         expected one of: \"seed001-T01\", \"seed001-T02\""
    );

    // No metadata.
    let mut anonymous = run.clone();
    anonymous.metadata.clear();
    let e = pair_runs(&ms, &anonymous, "anon.csv").expect_err("no metadata");
    assert!(matches!(e.kind, RunErrorKind::NoMechanism), "{e}");
    assert!(
        e.to_string().starts_with("anon.csv: no `# mechanism"),
        "{e}"
    );

    // Two different mechanisms of that name.
    let mut twin = ms[0].clone();
    twin.duration_s = 9.0;
    let two = [ms[0].clone(), twin];
    let e = pair_runs(&two, &run, "good.csv").expect_err("ambiguous");
    assert!(
        matches!(e.kind, RunErrorKind::AmbiguousMechanism { count: 2, .. }),
        "{e}"
    );
    // The same mechanism given twice is fine.
    let same = [ms[0].clone(), ms[0].clone()];
    assert!(pair_runs(&same, &run, "good.csv").is_ok());
}

#[test]
fn writing_formats_numbers_and_checks_the_run() {
    let run = Run {
        metadata: vec![("mechanism".into(), "m".into())],
        t_s: vec![0.0, 0.0125, 1.0 / 3.0, 2.5],
        phi_deg: vec![vec![-90.0, -89.1234567, -0.0, 1e-9]],
        latch: vec![vec![false, false, true, true]],
        extra: Vec::new(),
    };
    assert_eq!(
        run.to_csv_string(),
        "# mechanism = \"m\"\n\
         t_s,phi1_deg,latch1\n\
         0.000,-90.000000,0\n\
         0.0125,-89.123457,0\n\
         0.333333,-0.000000,1\n\
         2.500,0.000000,1\n"
    );
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("w.csv");
    run.write(&path).unwrap_or_else(|e| panic!("{e}"));
    let back = Run::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back.t_s[2], 0.333333);
    assert_eq!(back.phi_deg[0][1], -89.123457);
    assert_eq!(back.latch, run.latch);

    let mut nan = run.clone();
    nan.phi_deg[0][1] = f64::NAN;
    let e = nan.write(&path).expect_err("NaN angle");
    assert!(matches!(e.kind, RunErrorKind::Invalid { .. }), "{e}");
    assert!(
        e.to_string()
            .contains("sample 2: phi1_deg = NaN; expected a finite angle"),
        "{e}"
    );

    let mut close = run.clone();
    close.t_s[1] = 1e-7;
    let e = close.validate("c.csv").expect_err("too close");
    assert!(e.to_string().contains("at least 1 µs apart"), "{e}");

    let mut ragged = run;
    ragged.latch[0].pop();
    assert!(ragged.validate("r.csv").is_err());
    // Never panics, even on a ragged run.
    assert!(ragged.to_csv_string().ends_with("2.500,0.000000,NaN\n"));
}

/// A small deterministic generator (64-bit LCG) for the mutation test.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 33) as usize) % n.max(1)
    }
}

/// `text` with a few characters deleted, inserted or replaced.
fn mutate(text: &str, rng: &mut Lcg) -> String {
    const ALPHABET: &[char] = &[
        '0', '1', '9', '.', ',', '-', '#', '=', '"', '[', ']', '{', '}', '\n', ' ', 'e', 'n', 'a',
        '_', '°',
    ];
    let mut chars: Vec<char> = text.chars().collect();
    for _ in 0..1 + rng.below(3) {
        let i = rng.below(chars.len() + 1);
        let c = ALPHABET[rng.below(ALPHABET.len())];
        match rng.below(3) {
            0 if i < chars.len() => {
                chars.remove(i);
            }
            1 if i < chars.len() => chars[i] = c,
            _ => chars.insert(i, c),
        }
    }
    chars.into_iter().collect()
}

#[test]
fn mutated_inputs_are_accepted_or_rejected_with_a_located_error_never_a_panic() {
    let mut rng = Lcg(2026);
    let t01 = t01_text();
    let mut rejected = (0, 0);
    for _ in 0..3000 {
        let text = mutate(GOOD, &mut rng);
        if let Err(e) = Run::parse(&text, "bad.csv") {
            rejected.0 += 1;
            assert!(e.to_string().starts_with("bad.csv:"), "{e}");
            assert!(e.line().is_some(), "{e}");
        }
        let text = mutate(&t01, &mut rng);
        if let Err(e) = Mechanism::from_toml_str(&text, "bad.toml") {
            rejected.1 += 1;
            assert!(e.to_string().starts_with("bad.toml"), "{e}");
            assert!(e.line().is_some() || e.key().is_some(), "{e}");
        }
    }
    // The mutations do break most files.
    assert!(rejected.0 > 1000 && rejected.1 > 1000, "{rejected:?}");
}

#[test]
fn run_settle_s_defaults_to_two_tenths_is_read_checked_and_written_back() {
    use deploywatch_sim::mechanism_toml::DEFAULT_SETTLE_S;
    let m = Mechanism::from_toml_str(&t01_text(), "t01.toml").expect("T01");
    assert_eq!(m.settle_s, DEFAULT_SETTLE_S);
    assert_eq!(DEFAULT_SETTLE_S, 0.2);
    let text = t01_with("sample_hz = 100.0", "sample_hz = 100.0\nsettle_s = 0.0");
    let m = Mechanism::from_toml_str(&text, "t01.toml").expect("settle_s = 0");
    assert_eq!(m.settle_s, 0.0);
    let back = Mechanism::from_toml_str(&m.to_toml_string(), "back.toml").expect("written");
    assert_eq!(back, m);
    let text = t01_with("sample_hz = 100.0", "sample_hz = 100.0\nsettle_s = -1");
    let e = bad_mech(&text);
    assert_eq!(e.line, Some(line_of(&text, "settle_s")));
    assert_eq!(e.key(), Some("run.settle_s"));
    assert!(e.to_string().contains("a finite number ≥ 0 [s]"), "{e}");
}
