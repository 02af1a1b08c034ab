//! The bundled runs read, write and read back unchanged, pair with their
//! mechanisms, and a written run is checked and formatted.

use super::*;

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
         0.333333,0.000000,1\n\
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
