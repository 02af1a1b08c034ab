//! More of what a new user runs into, checked on the `deploywatch` binary
//! as a black box: a spreadsheet's run with a `;` at the end of its rows,
//! files saved in Latin-1 or UTF-16, a joint key written below
//! `[joint.latch]`, a rig wire in millimetres, two joints' columns swapped,
//! a bad entry in a `--from` findings file, a tolerance typed as a
//! fraction, a run written under an image's name, a range of one joint,
//! and two mechanism files of one name. Each is refused (exit 2) or warned
//! of at its file and line with what was expected, not with the hint of
//! another mistake.
//!
//! `cargo test -p deploywatch-sim --test new_user_more`

mod common;

use std::path::Path;
use std::process::Output;

use common::{data, deploywatch, fails, s, t01_mechanism, t01_run_text, write};

/// `identify` of `run` on seed 001 T01, as a user starts it.
fn identify(run: &Path) -> Output {
    deploywatch(&["identify", "-q", "--mechanism", s(&t01_mechanism()), s(run)])
}

/// Stderr of a command that succeeded (exit 0, no panic).
fn warned(out: &Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!err.contains("panicked"), "panic:\n{err}");
    assert_eq!(out.status.code(), Some(0), "exit code; stderr:\n{err}");
    err
}

/// The 1-based line of the first line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    1 + text
        .lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("no line with {needle:?}"))
}

/// The bundled run in the spreadsheet dialect: `;` between fields and a
/// decimal comma, each row (and the header, with `header_too`) ending
/// with a `;`.
fn semicolon_run(header_too: bool) -> String {
    let mut out = String::new();
    for l in t01_run_text().lines() {
        if l.starts_with('#') {
            out.push_str(l);
        } else if l.starts_with("t_s") {
            out.push_str(&l.replace(',', ";"));
            if header_too {
                out.push(';');
            }
        } else {
            out.push_str(&l.replace(',', ";").replace('.', ","));
            out.push(';');
        }
        out.push('\n');
    }
    out
}

#[test]
fn a_semicolon_ending_every_row_of_a_spreadsheet_run_is_named_as_such() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = semicolon_run(false);
    let run = write(dir.path(), "semi.csv", &text);
    let first_row = line_of(&text, "t_s;") + 1;
    let err = fails(
        &identify(&run),
        2,
        &[
            &format!("semi.csv:{first_row}:"),
            "`;`-separated fields",
            "ends with `;`",
            "trailing separator",
        ],
    );
    assert!(!err.contains("comma-separated"), "{err}");
    assert!(!err.contains("decimal commas"), "{err}");
    let text = semicolon_run(true);
    let run = write(dir.path(), "header.csv", &text);
    let header = line_of(&text, "t_s;");
    let err = fails(
        &identify(&run),
        2,
        &[
            &format!("header.csv:{header}:"),
            "without a `;` at its end",
            "latch3;`",
        ],
    );
    assert!(!err.contains("a comma"), "{err}");
}

#[test]
fn a_run_saved_in_latin1_or_utf16_names_the_line_and_the_encoding() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = t01_run_text().replacen(
        "# source = \"",
        "# bench = \"Pr\u{fc}fstand 3\"\n# source = \"",
        1,
    );
    let line = line_of(&text, "# bench");
    let latin1: Vec<u8> = text.chars().map(|c| c as u32 as u8).collect();
    let run = write(dir.path(), "latin1.csv", latin1);
    let err = fails(
        &identify(&run),
        2,
        &[
            &format!("latin1.csv:{line}:"),
            "column 14",
            "0xFC",
            "Latin-1",
            "expected a run CSV in UTF-8",
        ],
    );
    assert!(!err.contains("not a text file"), "{err}");
    let utf16: Vec<u8> = [0xFF, 0xFE]
        .into_iter()
        .chain(t01_run_text().encode_utf16().flat_map(u16::to_le_bytes))
        .collect();
    let run = write(dir.path(), "utf16.csv", utf16);
    let err = fails(
        &identify(&run),
        2,
        &["utf16.csv:1:", "UTF-16", "FF FE", "save it as UTF-8"],
    );
    assert!(!err.contains("not a text file"), "{err}");
}

#[test]
fn a_mechanism_saved_in_latin1_names_the_line_and_the_encoding() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = format!(
        "# Pr\u{fc}fstand 3\n{}",
        std::fs::read_to_string(t01_mechanism()).expect("T01")
    );
    let latin1: Vec<u8> = text.chars().map(|c| c as u32 as u8).collect();
    let mech = write(dir.path(), "latin1.toml", latin1);
    let out = dir.path().join("out.csv");
    fails(
        &deploywatch(&["simulate", s(&mech), "-o", s(&out)]),
        2,
        &[
            "latin1.toml:1:",
            "column 5",
            "Latin-1",
            "expected a mechanism TOML in UTF-8",
        ],
    );
}

#[test]
fn a_joint_key_below_the_latch_header_is_told_to_move_above_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let t01 = std::fs::read_to_string(t01_mechanism()).expect("T01");
    let first_joint = t01.find("[[joint]]").expect("a joint");
    let spring = first_joint + t01[first_joint..].find("spring").expect("its spring");
    let end = spring + t01[spring..].find('\n').expect("end of line");
    let text = format!(
        "{}\n[joint.latch]\nmodel = \"ideal\"\nfriction = {{ coulomb_nm = 0.3 }}{}",
        &t01[..end],
        &t01[end..]
    );
    let line = line_of(&text, "friction = { coulomb_nm = 0.3 }");
    let mech = write(dir.path(), "latch.toml", &text);
    let out = dir.path().join("out.csv");
    fails(
        &deploywatch(&["simulate", s(&mech), "-o", s(&out)]),
        2,
        &[
            &format!("latch.toml:{line}:"),
            "`joint[1].latch.friction`",
            "a key of the [[joint]]",
            "above the `[joint.latch]` line",
        ],
    );
}

#[test]
fn a_rig_wire_in_millimetres_is_warned_of_at_its_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let rig = data().join("mechanisms/seed001_T01_rig.toml");
    let text =
        std::fs::read_to_string(rig)
            .expect("rig")
            .replacen("wire_m = 1.5", "wire_m = 1500", 1);
    let line = line_of(&text, "wire_m = 1500");
    let mech = write(dir.path(), "rig.toml", &text);
    let out = dir.path().join("out.csv");
    let err = warned(&deploywatch(&["simulate", s(&mech), "-o", s(&out)]));
    for says in [
        &format!("rig.toml:{line}:") as &str,
        "`rig.trolley[1].wire_m`",
        "millimetres",
    ] {
        assert!(err.contains(says), "stderr lacks {says:?}:\n{err}");
    }
}

/// The bundled run with the fields `a` and `b` (0-based, `t_s` is 0) of
/// its header's columns swapped in every data row.
fn swapped(pairs: &[(usize, usize)]) -> String {
    let mut out = String::new();
    let mut header_seen = false;
    for l in t01_run_text().lines() {
        if l.starts_with('#') || !header_seen {
            header_seen |= !l.starts_with('#');
            out.push_str(l);
        } else {
            let mut f: Vec<&str> = l.split(',').collect();
            for &(a, b) in pairs {
                f.swap(a, b);
            }
            out.push_str(&f.join(","));
        }
        out.push('\n');
    }
    out
}

#[test]
fn two_joints_columns_swapped_are_named_as_swapped_not_mirrored() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = swapped(&[(1, 2), (4, 5)]);
    let run = write(dir.path(), "swap12.csv", &text);
    let first_row = line_of(&text, "t_s,") + 1;
    let err = fails(
        &identify(&run),
        2,
        &[
            &format!("swap12.csv:{first_row}:"),
            "`phi1_deg` (column 2) and `phi2_deg` (column 3)",
            "swapped",
            "swap the columns",
        ],
    );
    assert!(!err.contains("negate"), "{err}");
    // At ±180 deg each reading is also its own joint's pose a turn off,
    // until the joints move towards 0 on the side they started: refused,
    // naming the swap and two mirrored encoders.
    let text = swapped(&[(2, 3), (5, 6)]);
    let run = write(dir.path(), "swap23.csv", &text);
    fails(
        &identify(&run),
        2,
        &[
            &format!("swap23.csv:{first_row}:"),
            "`phi2_deg` (column 3) and `phi3_deg` (column 4)",
            "the columns swapped, or both encoders mounted mirrored",
        ],
    );
}

#[test]
fn a_bad_entry_of_a_from_file_names_the_file_and_the_entry() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out.csv");
    let cases = [
        (
            r#"{"effects": [{"name": "coulomb_friction", "joint": 7, "value": 0.5}]}"#,
            "effects[0] (coulomb_friction)",
        ),
        (
            r#"{"method": "direct", "joints": [{"joint": 7, "coulomb_nm": 0.5}]}"#,
            "joints[0] (coulomb_friction)",
        ),
    ];
    for (json, entry) in cases {
        let from = write(dir.path(), "found.json", json);
        let err = fails(
            &deploywatch(&[
                "simulate",
                s(&t01_mechanism()),
                "-o",
                s(&out),
                "--from",
                s(&from),
            ]),
            2,
            &[
                &format!("--from {}: {entry}", s(&from)),
                "joint 7 does not exist",
            ],
        );
        assert!(!err.contains("--effect"), "{err}");
    }
}

#[test]
fn a_spring_tolerance_below_one_per_cent_is_asked_about() {
    let out = deploywatch(&[
        "margin",
        "--mechanism",
        s(&t01_mechanism()),
        "--spring-tolerance",
        "0.05",
    ]);
    let err = warned(&out);
    for says in [
        "--spring-tolerance 0.05",
        "fraction",
        "`--spring-tolerance 5`",
    ] {
        assert!(err.contains(says), "stderr lacks {says:?}:\n{err}");
    }
    let err = warned(&deploywatch(&[
        "margin",
        "--mechanism",
        s(&t01_mechanism()),
        "--spring-tolerance",
        "5",
    ]));
    assert!(!err.contains("fraction"), "{err}");
}

#[test]
fn a_run_written_under_an_image_name_is_refused_before_the_work() {
    let dir = tempfile::tempdir().expect("temp dir");
    let png = dir.path().join("run.png");
    fails(
        &deploywatch(&["simulate", s(&t01_mechanism()), "-o", s(&png)]),
        2,
        &[
            &format!("--out {}", s(&png)),
            "not as an image",
            ".png",
            "--plot",
        ],
    );
    assert!(!png.exists());
}

#[test]
fn a_joint_beyond_a_one_joint_wing_is_not_told_a_range_of_1_to_1() {
    let dir = tempfile::tempdir().expect("temp dir");
    let one = "name = \"one\"\n[[panel]]\nlength_m = 1.0\nmass_kg = 2.0\ncom_m = 0.5\n\
               inertia_kgm2 = 0.17\n[[joint]]\nstowed_deg = -90.0\n\
               spring = { kind = \"linear\", preload_nm = 1.0, stiffness_nm_per_rad = 0.0, count = 1 }\n\
               [run]\nduration_s = 6.0\n";
    let mech = write(dir.path(), "one.toml", one);
    let out = dir.path().join("out.csv");
    let err = fails(
        &deploywatch(&[
            "simulate",
            s(&mech),
            "-o",
            s(&out),
            "--effect",
            "coulomb_friction:joint=2:value=0.1",
        ]),
        2,
        &["joint 2 does not exist", "only joint 1"],
    );
    assert!(!err.contains("1 to 1"), "{err}");
}

#[test]
fn two_mechanism_files_of_one_name_are_both_named() {
    let dir = tempfile::tempdir().expect("temp dir");
    let t01 = std::fs::read_to_string(t01_mechanism()).expect("T01");
    let edited = t01.replacen("mass_kg = 3.5", "mass_kg = 3.6", 1);
    assert_ne!(edited, t01);
    let first = write(dir.path(), "first.toml", &t01);
    let second = write(dir.path(), "second.toml", &edited);
    let run = write(dir.path(), "run.csv", t01_run_text());
    fails(
        &deploywatch(&[
            "identify",
            "-q",
            "--mechanism",
            s(&first),
            "--mechanism",
            s(&second),
            s(&run),
        ]),
        2,
        &[
            &format!("{}: mechanism \"seed001-T01\"", s(&second)),
            &format!("also the name of {}", s(&first)),
        ],
    );
}
