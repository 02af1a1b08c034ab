//! Bad run files are rejected with an error naming the file, the line and
//! column, and what was expected.

use super::*;

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
