//! Help texts, words instead of Rust debug output, `--quiet` on every
//! command, identify's residual warning, and replay's latch in words.

use super::*;

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

/// A ball plunger that holds its joint past the crest with the switch
/// open: `simulate` says the joint is not latched (its switch, as the
/// run's `latch` column reads it) and that its latch holds it, and the run
/// agrees on both; the joints whose switch and latch agree get no clause.
#[test]
fn simulate_says_when_a_latch_holds_with_its_switch_open() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mech = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/five_mixed_latches.toml");
    let csv = dir.path().join("run.csv");
    let out = succeeds(&deploywatch(&[
        "simulate",
        s(&mech),
        "--out",
        s(&csv),
        "--no-noise",
    ]));
    let line = |j: usize| {
        out.lines()
            .find(|l| l.trim_start().starts_with(&format!("joint {j}:")))
            .unwrap_or_else(|| panic!("no line for joint {j}:\n{out}"))
    };
    let two = line(2);
    assert!(
        two.contains("NOT latched by")
            && two.contains("its switch open at the end, though its latch holds it (held past its ball plunger's crest)"),
        "{out}"
    );
    for j in [1, 3, 4, 5] {
        assert!(!line(j).contains("though"), "{out}");
    }
    let text = std::fs::read_to_string(&csv).expect("the run");
    let header: Vec<&str> = text
        .lines()
        .find(|l| l.starts_with("t_s"))
        .expect("a header")
        .split(',')
        .collect();
    let last: Vec<&str> = text.lines().last().expect("rows").split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    // The switch open, the joint past the plunger's crest (0.6°) and short
    // of the switch's travel (0.05°).
    assert_eq!(last[col("latch2")], "0", "{out}");
    let phi: f64 = last[col("phi2_deg")].parse().expect("an angle");
    assert!(
        phi.abs() > 0.05 && phi.abs() < 0.6,
        "joint 2 ends at {phi} deg"
    );
}
