//! Bad mechanism files are rejected with an error naming the file, the line
//! or key, and what was expected.

use super::*;

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
             expected one of: length_m, mass_kg, com_m, inertia_kgm2, \
             mass_tolerance_pct, inertia_tolerance_pct"
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
            "stowed_deg = -90.0",
            "stowed_deg = -90.0\nfree_play_deg = -0.1",
            "joint[1].free_play_deg",
            "≥ 0 [deg], found -0.1",
        ),
        (
            "stowed_deg = -90.0",
            "stowed_deg = -90.0\nfree_play_deg = 12.0",
            "joint[1].free_play_deg",
            "at most 5 [deg]",
        ),
        (
            "inertia_kgm2 = 0.27",
            "inertia_kgm2 = 0.27\nmass_tolerance_pct = -0.5",
            "panel[1].mass_tolerance_pct",
            "≥ 0 [%], found -0.5",
        ),
        (
            "inertia_kgm2 = 0.27",
            "inertia_kgm2 = 0.27\ninertia_tolerance_pct = 25",
            "panel[1].inertia_tolerance_pct",
            "0 to 20 [%]",
        ),
        (
            "stowed_deg = -90.0",
            "stowed_deg = -90.0\nspring_tolerance_pct = -2",
            "joint[1].spring_tolerance_pct",
            "≥ 0 [%], found -2",
        ),
        (
            "stowed_deg = -90.0",
            "stowed_deg = -90.0\nspring_tolerance_pct = 21",
            "joint[1].spring_tolerance_pct",
            "0 to 20 [%] of the drawn spring torque",
        ),
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
        let changed = to.lines().last().unwrap_or(to);
        let line = line_of(&text, changed.split(" = ").next().unwrap_or(changed));
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

    // Joint 1 is stowed at -90 deg: its points in the joint's signed angle
    // would all clamp to the last one, a constant torque.
    let text = curve("[[-90.0, 1.5], [-45.0, 1.0], [0.0, 0.5]]");
    let e = bad_mech(&text);
    assert_eq!(e.key(), Some("joint[1].spring.unfold[1]"));
    assert_eq!(e.line(), Some(line_of(&text, "unfold")));
    assert!(e.to_string().contains("an angle ≥ 0"), "{e}");
    assert!(e.to_string().contains("|φ|"), "{e}");

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

#[test]
fn a_sub_table_above_its_joint_or_numbered_is_named_at_its_header() {
    // `[joint.latch]` above the first `[[joint]]`: TOML reads `joint`
    // defined twice; the error is at the sub-table's header.
    let latch = "[joint.latch]\nkind = \"plunger\"\n";
    let text = t01_with("[[joint]]", &format!("{latch}[[joint]]"));
    let e = bad_mech(&text);
    let line = line_of(&text, "[joint.latch]");
    assert_eq!(e.line(), Some(line), "{e}");
    let msg = e.to_string();
    assert!(
        msg.contains("`[joint.latch]` comes before any [[joint]]"),
        "{msg}"
    );
    // `[joint.2.latch]`: TOML does not number tables; the error is at the
    // header's line (its first key's), naming the number.
    let text = format!("{}\n[joint.2.latch]\nkind = \"plunger\"\n", t01_text());
    let e = bad_mech(&text);
    let header = line_of(&text, "[joint.2.latch]");
    assert!(
        e.line() == Some(header) || e.line() == Some(header + 1),
        "{e}"
    );
    let msg = e.to_string();
    assert!(
        msg.contains("`joint[3].2`") && msg.contains("does not number the [[joint]] tables"),
        "{msg}"
    );
}
