//! Bad input to the host tools (docs/robustness.md): a
//! truncated or corrupt run file, a mechanism whose joint count does not
//! match the run, angles out of physical range, a run that never moves,
//! missing samples, bad `--fault` options. Each gives a clear error (exit
//! code 2, the file named, what was expected) or a clear finding, never a
//! panic and never a silent default.
//!
//! The command-line tests run the `deploywatch` binary as a black box.

mod common;

use std::path::Path;

use common::{data, deploywatch, fails, s, t01_mechanism, t01_run_text, write};

use deploywatch_sim::deployment::{simulate, SimOptions};
use deploywatch_sim::fault_injection::{self, SensorFault};
use deploywatch_sim::mechanism::Mechanism;
use deploywatch_sim::run::{
    check_analysable, ReadOptions, Run, RunErrorKind, MAX_ANGLE_DEG, MISSING_SAMPLES_KEY,
};
use deploywatch_sim::sensor::{measure, SensorModel};

/// `diagnose` and `identify` on one run of seed001 T01: both must refuse it
/// with exit code 2 and the same message parts.
fn both_refuse(run: &Path, says: &[&str]) {
    let dir = run.parent().expect("dir");
    let json = dir.join("out.json");
    let out = deploywatch(&[
        "diagnose",
        "--quiet",
        "--mechanism",
        s(&t01_mechanism()),
        "--json",
        s(&json),
        s(run),
    ]);
    fails(&out, 2, says);
    assert!(!json.exists(), "diagnose wrote a result for a refused run");
    let out = deploywatch(&[
        "identify",
        "--quiet",
        "--mechanism",
        s(&t01_mechanism()),
        s(run),
    ]);
    fails(&out, 2, says);
}

// ---------------------------------------------------------------------------
// Run files the reader must refuse.

#[test]
fn a_run_truncated_mid_row_is_refused_with_its_line() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = t01_run_text();
    // Cut in the middle of the 40th data row.
    let cut = text.match_indices('\n').nth(42).expect("rows").0 + 12;
    let run = write(dir.path(), "truncated.csv", &text[..cut]);
    let line = text[..cut].lines().count().to_string();
    both_refuse(
        &run,
        &[
            &format!("truncated.csv:{line}:"),
            "expected 7 comma-separated fields (as in the header), found 2",
        ],
    );
}

#[test]
fn binary_garbage_is_not_a_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    // Bytes no UTF-8 text has (0xFF never occurs), with zeros and controls.
    let bytes: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8 | 0x80)
        .collect();
    let run = write(dir.path(), "garbage.csv", &bytes);
    both_refuse(
        &run,
        &["garbage.csv: not a text file (invalid UTF-8 at byte 0); expected a run CSV"],
    );
}

#[test]
fn text_garbage_and_an_empty_file_are_refused_at_the_header() {
    let dir = tempfile::tempdir().expect("tempdir");
    let run = write(
        dir.path(),
        "text.csv",
        "PK\u{3}\u{4} this is a zip file, not a run\n",
    );
    both_refuse(&run, &["text.csv:1:", "expected the header"]);
    let run = write(dir.path(), "empty.csv", "");
    both_refuse(&run, &["empty.csv:1: expected a header line"]);
}

#[test]
fn a_run_of_another_joint_count_than_its_mechanism_is_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    // Drop joint 3 from a seed001 T01 run: 2 joints, named for a 3-joint mechanism.
    let mut run = Run::parse(&t01_run_text(), "t01.csv").expect("bundled run");
    run.phi_deg.pop();
    run.latch.pop();
    let path = dir.path().join("two_joints.csv");
    run.write(&path).expect("write");
    both_refuse(
        &path,
        &[
            "two_joints.csv: the run has 2 joints but mechanism \"seed001-T01\" has 3",
            "expected equal joint counts",
        ],
    );
}

#[test]
fn angles_beyond_the_physical_range_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = t01_run_text();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let row = lines
        .iter()
        .position(|l| l.starts_with("0.400,"))
        .expect("row at 0.4 s");
    let mut fields: Vec<String> = lines[row].split(',').map(str::to_string).collect();
    fields[2] = "1000.5".to_string();
    lines[row] = fields.join(",");
    let run = write(dir.path(), "range.csv", lines.join("\n") + "\n");
    both_refuse(
        &run,
        &[
            &format!("range.csv:{}: column `phi2_deg`", row + 1),
            "expected an angle within ±720 deg, found 1000.5",
        ],
    );
    // The file's bound is the monitor's.
    assert_eq!(
        MAX_ANGLE_DEG,
        f64::from(deploywatch_core::monitor::ENCODER_RANGE_DEG)
    );
    // The same bound on writing, and at the bound itself a run is fine.
    let mut r = Run::parse(&text, "t01.csv").expect("bundled run");
    r.phi_deg[0][3] = MAX_ANGLE_DEG;
    r.validate("edge.csv").expect("720 deg is in range");
    r.phi_deg[0][3] = -MAX_ANGLE_DEG - 0.001;
    let e = r.validate("out.csv").expect_err("beyond 720 deg");
    assert!(
        e.to_string()
            .contains("sample 4: phi1_deg = -720.001; expected an angle within ±720 deg"),
        "{e}"
    );
}

/// A joint with no spring, flung by its neighbours, spins past two turns
/// (no stop on the stowed side): `simulate` writes the run up to the
/// sample before the first angle past ±720 deg, says where it cut, and the
/// file reads back.
#[test]
fn a_joint_that_spins_past_two_turns_is_written_up_to_there() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = std::fs::read_to_string(t01_mechanism()).expect("T01");
    let spring = "spring = { kind = \"tape\", type = \"TS-3\", count = 2 }";
    assert!(text.contains(spring), "T01's joint 3 spring");
    let limp = text
        .replace(
            spring,
            "spring = { kind = \"linear\", preload_nm = 0.0, stiffness_nm_per_rad = 0.0, count = 1 }",
        )
        .replace("duration_s = 6.0", "duration_s = 20.0");
    assert!(limp.contains("duration_s = 20.0"), "T01's duration");
    let mech = write(dir.path(), "limp.toml", limp);
    let csv = dir.path().join("limp.csv");
    let out = deploywatch(&["simulate", s(&mech), "--out", s(&csv)]);
    let said = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{said}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let run = Run::parse(&std::fs::read_to_string(&csv).expect("run"), "limp.csv").expect("reads");
    let last = *run.t_s.last().expect("samples");
    assert!(last > 1.0 && last < 20.0, "cut at {last} s");
    let line = said.lines().find(|l| l.contains("two turns")).expect(&said);
    assert!(line.contains("joint 3"), "{line}");
    assert!(line.contains(&format!("written to {last:.6} s")), "{line}");
    assert!(run
        .phi_deg
        .iter()
        .flatten()
        .all(|a| a.abs() <= MAX_ANGLE_DEG));
}

#[test]
fn missing_samples_are_refused_by_the_analyses_with_the_reason() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut run = Run::parse(&t01_run_text(), "t01.csv").expect("bundled run");
    let f: SensorFault = "dropout:joint=2:start=0.3:duration=0.05:mode=missing"
        .parse()
        .expect("fault");
    fault_injection::apply(&mut run, &[f], 1).expect("apply");
    let path = dir.path().join("dropout.csv");
    run.write(&path)
        .expect("a run that declares its missing samples is written");
    let row = 1
        + run.metadata.len()
        + 1
        + run
            .t_s
            .iter()
            .position(|&t| t >= 0.3 - 1e-9)
            .expect("0.3 s");
    both_refuse(
        &path,
        &[
            &format!("dropout.csv:{row}: column `phi2_deg`: a missing sample"),
            "this command needs every angle",
        ],
    );
}

// ---------------------------------------------------------------------------
// The reader's missing-sample encoding.

fn missing_text(declared: Option<&str>) -> String {
    let mut t = String::from("# mechanism = \"m\"\n");
    if let Some(v) = declared {
        t += &format!("# missing_samples = \"{v}\"\n");
    }
    t + "t_s,phi1_deg,phi2_deg,latch1,latch2\n0.000,-90.0,180.0,0,0\n0.010,NaN,179.9,0,0\n0.020,-89.8,NaN,0,1\n"
}

#[test]
fn nan_is_a_missing_sample_only_when_declared_and_asked_for() {
    let allow = ReadOptions {
        allow_missing: true,
    };
    // Declared and asked for: read, NaN where the file says.
    let r = Run::parse_with(&missing_text(Some("NaN")), "m.csv", allow).expect("declared");
    assert!(r.phi_deg[0][1].is_nan() && r.phi_deg[1][2].is_nan());
    assert_eq!(r.phi_deg[0][2], -89.8);
    // It writes back as it was read.
    assert_eq!(
        r.to_csv_string(),
        Run::parse_with(&r.to_csv_string(), "w.csv", allow)
            .expect("again")
            .to_csv_string()
    );
    // Declared, not asked for (every analysis): refused, the reason given.
    let e = Run::parse(&missing_text(Some("NaN")), "m.csv").expect_err("strict");
    assert!(
        matches!(e.kind, RunErrorKind::MissingSample { ref column, .. } if e.line == Some(5) && column == "phi1_deg"),
        "{e}"
    );
    assert!(
        e.to_string()
            .starts_with("m.csv:5: column `phi1_deg`: a missing sample"),
        "{e}"
    );
    // Not declared: a bad number whatever the caller asks.
    for options in [ReadOptions::default(), allow] {
        let e = Run::parse_with(&missing_text(None), "m.csv", options).expect_err("undeclared");
        assert!(
            matches!(e.kind, RunErrorKind::BadNumber { .. } if e.line == Some(4)),
            "{e}"
        );
    }
    // Another spelling of the declaration, or of the missing field, is refused.
    let e =
        Run::parse_with(&missing_text(Some("nan")), "m.csv", allow).expect_err("bad declaration");
    assert!(
        matches!(e.kind, RunErrorKind::BadMetadata { .. } if e.line == Some(2)),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("`# missing_samples = \"NaN\"` (the only value)"),
        "{e}"
    );
    let e = Run::parse_with(
        &missing_text(Some("NaN")).replace("0.010,NaN", "0.010,nan"),
        "m.csv",
        allow,
    )
    .expect_err("lower-case nan");
    assert!(
        matches!(e.kind, RunErrorKind::BadNumber { .. } if e.line == Some(5)),
        "{e}"
    );
    // Time stamps and switches are never missing.
    let e = Run::parse_with(
        &missing_text(Some("NaN")).replace("0.020,", "NaN,"),
        "m.csv",
        allow,
    )
    .expect_err("missing time");
    assert!(
        matches!(e.kind, RunErrorKind::BadNumber { ref column, .. } if column == "t_s"),
        "{e}"
    );
    // A run in memory with NaN and no declaration is not written.
    let mut r = r;
    r.metadata.retain(|(k, _)| k != MISSING_SAMPLES_KEY);
    assert!(r
        .validate("x.csv")
        .unwrap_err()
        .to_string()
        .contains("expected a finite angle"));
}

// ---------------------------------------------------------------------------
// Runs the format accepts but an analysis cannot use.

#[test]
fn the_bundled_runs_are_analysable() {
    let mechs: Vec<Mechanism> = [
        "seed000_case1",
        "seed000_case3",
        "seed001_T01",
        "seed001_T02",
    ]
    .iter()
    .map(|n| Mechanism::load(&data().join(format!("mechanisms/{n}.toml"))).expect("mechanism"))
    .collect();
    let mut seen = 0;
    for dir in [
        "reference",
        "examples/a_seed001_eft",
        "examples/b_seed000_eft_air_drag",
        "examples/c_seed001_friction_harness",
    ] {
        for e in std::fs::read_dir(data().join(dir)).expect("dir") {
            let p = e.expect("entry").path();
            if p.extension().is_some_and(|x| x == "csv") {
                let run = Run::load(&p).expect("bundled run");
                let m = deploywatch_sim::run::pair_runs(&mechs, &run, s(&p)).expect("paired");
                check_analysable(&run, m, s(&p)).unwrap_or_else(|e| panic!("{e}"));
                seen += 1;
            }
        }
    }
    assert!(seen >= 14, "{seen} runs");
}

#[test]
fn a_run_that_never_moves_is_a_clear_finding() {
    let mech = Mechanism::load(&t01_mechanism()).expect("mechanism");
    let mut run = Run::parse(&t01_run_text(), "t01.csv").expect("bundled run");
    // GIVEN every joint reading its stowed angle with the reference noise
    for (j, series) in run.phi_deg.iter_mut().enumerate() {
        let stowed = series[0];
        for (i, x) in series.iter_mut().enumerate() {
            *x = stowed + if (i + j) % 3 == 0 { 0.022 } else { 0.0 };
        }
    }
    run.latch
        .iter_mut()
        .for_each(|l| l.iter_mut().for_each(|x| *x = false));
    // WHEN it is checked for analysis THEN it is refused as never moving
    let e = check_analysable(&run, &mech, "still.csv").expect_err("still");
    assert!(matches!(e.kind, RunErrorKind::NeverMoves { .. }), "{e}");
    let msg = e.to_string();
    assert!(
        msg.starts_with(
            "still.csv: the run never moves (no joint's angle changes by more than 0.022 deg"
        ),
        "{msg}"
    );
    assert!(
        msg.contains("expected a deployment, at least one joint moving by 1 deg or more"),
        "{msg}"
    );
    // A run with one joint moving is analysable (the others are findings).
    let mut one = run.clone();
    for (i, x) in one.phi_deg[0].iter_mut().enumerate() {
        *x += i as f64 * 0.01;
    }
    assert!(!matches!(
        check_analysable(&one, &mech, "one.csv").map_err(|e| e.kind),
        Err(RunErrorKind::NeverMoves { .. })
    ));
}

#[test]
fn a_run_truncated_at_a_line_end_is_a_clear_finding() {
    let mech = Mechanism::load(&t01_mechanism()).expect("mechanism");
    let text = t01_run_text();
    let full = Run::parse(&text, "t01.csv").expect("bundled run");
    check_analysable(&full, &mech, "t01.csv").expect("the whole run");
    // GIVEN the file cut after the row of 1.0 s (no joint latched yet)
    let cut = text.find("\n1.010,").expect("row") + 1;
    let run = Run::parse(&text[..cut], "cut.csv").expect("the format cannot tell");
    // THEN the analysis check can
    let e = check_analysable(&run, &mech, "cut.csv").expect_err("truncated");
    assert_eq!(
        e.to_string(),
        "cut.csv: the run ends at 1 s with joint(s) 1, 2, 3 not latched, before the mechanism's duration_s = 6 s: truncated? expected a run to go on until every joint latched or to duration_s (docs/spec/formats.md)"
    );
    // A run that goes on to duration_s without latching (a stall) is fine.
    let mut stall = run.clone();
    let n = stall.len();
    for i in 0..500 {
        stall.t_s.push(1.0 + 0.01 * (i + 1) as f64);
        for j in 0..3 {
            let x = stall.phi_deg[j][n - 1];
            stall.phi_deg[j].push(x);
            stall.latch[j].push(false);
        }
    }
    check_analysable(&stall, &mech, "stall.csv").expect("a stall to duration_s");
}

/// `Campaign::push` calls `run::check_analysable`: `diagnose` and `identify`
/// refuse a run that never moves, or one cut before its joints latched.
#[test]
fn diagnose_refuses_a_run_that_never_moves_and_a_run_cut_at_a_line_end() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = t01_run_text();
    let mut still = Run::parse(&text, "t01.csv").expect("bundled run");
    for series in still.phi_deg.iter_mut() {
        let x0 = series[0];
        series.iter_mut().for_each(|x| *x = x0);
    }
    still
        .latch
        .iter_mut()
        .for_each(|l| l.iter_mut().for_each(|x| *x = false));
    let path = dir.path().join("still.csv");
    still.write(&path).expect("write");
    both_refuse(&path, &["still.csv: the run never moves"]);
    let cut = text.find("\n1.010,").expect("row") + 1;
    let path = write(dir.path(), "cut.csv", &text[..cut]);
    both_refuse(&path, &["cut.csv: the run ends at 1 s", "truncated?"]);
}

// ---------------------------------------------------------------------------
// Mechanism files.

#[test]
fn a_corrupt_mechanism_is_refused_by_every_command() {
    let dir = tempfile::tempdir().expect("tempdir");
    let bad = write(
        dir.path(),
        "bad.toml",
        "name = \"x\"\n[[panel]\nlength_m = 0.8\n",
    );
    let run = write(dir.path(), "run.csv", t01_run_text());
    let out = deploywatch(&["simulate", s(&bad), "--out", s(&dir.path().join("o.csv"))]);
    fails(&out, 2, &["bad.toml:2"]);
    let out = deploywatch(&[
        "diagnose",
        "--quiet",
        "--mechanism",
        s(&bad),
        "--json",
        s(&dir.path().join("o.json")),
        s(&run),
    ]);
    fails(&out, 2, &["bad.toml:2"]);
    let out = deploywatch(&["margin", "--mechanism", s(&bad)]);
    fails(&out, 2, &["bad.toml:2"]);
    let bin = write(dir.path(), "bin.toml", [0xffu8, 0xfe, 0x00, 0x41]);
    let out = deploywatch(&["simulate", s(&bin), "--out", s(&dir.path().join("o.csv"))]);
    fails(&out, 2, &["bin.toml"]);
}

// ---------------------------------------------------------------------------
// `simulate --fault`.

#[test]
fn bad_fault_options_say_what_was_expected() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out_csv = dir.path().join("o.csv");
    let m = t01_mechanism();
    for (spec, says) in [
        (
            "dropout:joint=1:start=0.5",
            "missing duration=...; dropout needs joint, start, duration",
        ),
        (
            "spike:joint=4:t=1:magnitude=3",
            "spike: joint 4 does not exist (expected a joint from 1 to 3)",
        ),
        (
            "chatter:joint=1:bounce=0.5",
            "expected a bounce time in seconds, more than 0 and at most 0.02",
        ),
        ("freeze:joint=1", "unknown fault `freeze`"),
        (
            "parity:joint=1:rate=2",
            "expected a fraction of the samples from 0 to 1",
        ),
    ] {
        let out = deploywatch(&["simulate", s(&m), "--out", s(&out_csv), "--fault", spec]);
        fails(&out, 2, &[says]);
        assert!(!out_csv.exists(), "{spec}: a run was written");
    }
    let out = deploywatch(&[
        "simulate",
        s(&m),
        "--out",
        s(&out_csv),
        "--fault",
        "gap:start=0:duration=100",
    ]);
    fails(
        &out,
        2,
        &["--fault: the gaps remove every sample of the run"],
    );
}

#[test]
fn simulate_with_faults_writes_a_declared_reproducible_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = t01_mechanism();
    let specs = [
        "dropout:joint=1:start=0.5:duration=0.1:mode=missing",
        "chatter:joint=3:bounce=0.02",
        "parity:joint=2:rate=0.02",
        "jitter:sigma=0.001",
        "gap:start=1:duration=0.2",
    ];
    let mut args = vec!["simulate", s(&m), "--seed", "5"];
    for f in &specs {
        args.extend(["--fault", f]);
    }
    let a = dir.path().join("a.csv");
    let b = dir.path().join("b.csv");
    for p in [&a, &b] {
        let mut v = args.clone();
        v.extend(["--out", s(p)]);
        let out = deploywatch(&v);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            stdout.contains(
                "fault dropout:joint=1:start=0.5:duration=0.1:mode=missing: 10 sample(s) affected"
            ),
            "{stdout}"
        );
        assert!(
            stdout.contains("fault gap:start=1:duration=0.2: 20 sample(s) affected"),
            "{stdout}"
        );
    }
    let text = std::fs::read_to_string(&a).expect("a");
    assert_eq!(
        text,
        std::fs::read_to_string(&b).expect("b"),
        "same seed, same file"
    );
    let run = Run::load_with(
        &a,
        ReadOptions {
            allow_missing: true,
        },
    )
    .expect("faulted run reads back");
    assert_eq!(run.meta("faults"), Some(specs.join("; ").as_str()));
    assert_eq!(run.meta(MISSING_SAMPLES_KEY), Some("NaN"));
    assert!(run.phi_deg[0].iter().filter(|x| x.is_nan()).count() >= 10);
    // With a fault the run goes on after the last latch, to duration_s.
    assert!(*run.t_s.last().expect("samples") > 5.9);
    // No missing reading, no declaration: any command reads it.
    let c = dir.path().join("c.csv");
    let out = deploywatch(&[
        "simulate",
        s(&m),
        "--out",
        s(&c),
        "--fault",
        "spike:joint=1:t=0.5:magnitude=20",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let run = Run::load(&c).expect("strict reader");
    assert!(run.meta(MISSING_SAMPLES_KEY).is_none());
}

#[test]
fn faults_apply_to_a_simulated_run_of_every_reference_mechanism() {
    for name in [
        "seed000_case1",
        "seed000_case3",
        "seed001_T01",
        "seed001_T02",
    ] {
        let mech =
            Mechanism::load(&data().join(format!("mechanisms/{name}.toml"))).expect("mechanism");
        let opts = SimOptions {
            stop_when_deployed: false,
            ..SimOptions::default()
        };
        let traj = simulate(&mech, &[], &opts).expect("simulate");
        let n = mech.joint_count();
        for kind in fault_injection::KINDS {
            let spec = match kind {
                "dropout" => format!("dropout:joint={n}:start=0.5:duration=0.2:mode=stale"),
                "spike" => format!("spike:joint={n}:t=0.7:magnitude=-15"),
                "stuck" => format!("stuck:joint={n}:start=1"),
                "parity" => format!("parity:joint={n}:rate=0.1:bits=2"),
                "chatter" => format!("chatter:joint={n}:bounce=0.02"),
                "switch_stuck" => format!("switch_stuck:joint={n}:state=open"),
                "jitter" => "jitter:sigma=0.003".to_string(),
                _ => "gap:start=0.3:duration=0.25".to_string(),
            };
            let fault: SensorFault = spec.parse().expect("spec");
            let mut run = measure(&traj, &vec![0.0; n], &SensorModel::REFERENCE, 9);
            let clean = run.clone();
            let report = fault_injection::apply(&mut run, &[fault], 9)
                .unwrap_or_else(|e| panic!("{name} {spec}: {e}"));
            assert!(report[0].samples > 0, "{name} {spec}: nothing happened");
            assert_ne!(run, clean, "{name} {spec}");
            run.validate(name)
                .unwrap_or_else(|e| panic!("{name} {spec}: {e}"));
        }
    }
}
