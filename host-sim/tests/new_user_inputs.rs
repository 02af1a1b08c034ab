//! What a new user runs into at the command line with bad input, each
//! checked on the `deploywatch` binary as a black box: a clear error (exit
//! code 2, the file, line and key named, what is allowed) and never a panic,
//! or, for unusual input that is valid (a huge duration, a run file ending in
//! blank lines), the right result.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{data, deploywatch, fails, s, t01_mechanism, t01_run_text, write};

use deploywatch_sim::run::Run;

fn t01_text() -> String {
    std::fs::read_to_string(t01_mechanism()).expect("bundled mechanism")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts a clean input error: exit code 2, no panic, and stderr containing
/// every one of `says`.
fn refused(out: &Output, says: &[&str]) {
    fails(out, 2, says);
}

/// Asserts success, no panic.
fn succeeded(out: &Output) {
    let err = stderr(out);
    assert!(!err.contains("panicked"), "panic:\n{err}");
    assert_eq!(out.status.code(), Some(0), "exit code; stderr:\n{err}");
}

/// The 1-based line of the first line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    1 + text
        .lines()
        .position(|l| l.contains(needle))
        .expect("needle in text")
}

/// `deploywatch simulate` of a mechanism text with extra arguments.
fn simulate(dir: &Path, mechanism: &str, extra: &[&str]) -> (Output, PathBuf) {
    let toml = write(dir, "m.toml", mechanism);
    let csv = dir.join("run.csv");
    let mut args = vec!["simulate", s(&toml), "--out", s(&csv)];
    args.extend_from_slice(extra);
    (deploywatch(&args), csv)
}

#[test]
fn a_huge_duration_simulates_until_the_wing_latched_with_memory_for_what_is_simulated() {
    // GIVEN seed001 T01 (latches after about 2.4 s) with `duration_s = 1e9`
    let dir = tempfile::tempdir().expect("temp dir");
    let text = t01_text().replace("duration_s = 6.0", "duration_s = 1e9");
    assert!(text.contains("duration_s = 1e9"));
    // WHEN it is simulated
    let (out, csv) = simulate(dir.path(), &text, &["--no-noise"]);
    // THEN it ends after the last latch, with a run of a few seconds
    succeeded(&out);
    let run = Run::load(&csv).expect("the run written");
    let end = *run.t_s.last().expect("samples");
    assert!(end < 10.0, "the run goes on to {end} s");
    assert!(run.latch.iter().all(|l| l.last() == Some(&true)));
}

#[test]
fn a_huge_duration_to_be_written_whole_is_refused_before_the_work() {
    // GIVEN `duration_s = 1e9` and a fault (which makes the run go on to
    // duration_s)
    let dir = tempfile::tempdir().expect("temp dir");
    let text = t01_text().replace("duration_s = 6.0", "duration_s = 1e9");
    let fault = "dropout:joint=1:start=0.5:duration=0.1";
    let (out, csv) = simulate(dir.path(), &text, &["--fault", fault]);
    // THEN a clear error, not an allocation failure
    let err = stderr(&out);
    assert!(!err.contains("panicked") && !err.contains("memory allocation"));
    assert!(matches!(out.status.code(), Some(1 | 2)), "{err}");
    assert!(
        err.contains("samples") && err.contains("duration_s"),
        "{err}"
    );
    assert!(!csv.exists());
}

#[test]
fn a_run_that_cannot_be_written_names_the_output_given() {
    // GIVEN T01 run for 0.1 s at 3 MHz: stamps 0.33 µs apart, which the
    // run file's 6 decimals cannot keep apart
    let dir = tempfile::tempdir().expect("temp dir");
    let text = t01_text().replace("duration_s = 6.0", "duration_s = 0.1");
    assert!(text.contains("duration_s = 0.1"));
    let (out, csv) = simulate(dir.path(), &text, &["--rate", "3000000"]);
    // THEN refused, naming `--out` and not the staging folder
    refused(
        &out,
        &[&format!("{}: cannot write the run", csv.display()), "1 µs"],
    );
    assert!(
        !stderr(&out).contains(".deploywatch-partial"),
        "{}",
        stderr(&out)
    );
    assert!(!csv.exists());
    let left: Vec<_> = std::fs::read_dir(dir.path()).expect("the folder").collect();
    assert_eq!(left.len(), 1, "only the mechanism left: {left:?}");
}

#[test]
fn effect_values_that_change_what_the_effect_is_are_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    for (effect, allowed) in [
        ("coulomb_friction:joint=1:value=-1", "≥ 0 [N·m]"),
        ("spring_softening:joint=1:value=1", "< 1"),
        ("spring_softening:joint=2:value=1.5", "< 1"),
        ("harness_stiffness:joint=1:value=-0.5", "≥ 0 [N·m/rad]"),
    ] {
        let (out, csv) = simulate(dir.path(), &t01_text(), &["--effect", effect]);
        let name = effect.split(':').next().unwrap_or_default();
        refused(&out, &["--effect", name, allowed]);
        assert!(!csv.exists(), "{effect}: a run was written");
    }
}

#[test]
fn mechanism_values_no_panel_can_have_are_refused_with_file_line_and_key() {
    let dir = tempfile::tempdir().expect("temp dir");
    for (from, to, says) in [
        // A centre of mass beyond the panel.
        (
            "com_m = 0.4",
            "com_m = 0.9",
            ["panel[1].com_m", "0 to length_m = 0.8", "found 0.9"],
        ),
        // A hinge folded more than one turn.
        (
            "stowed_deg = -90.0",
            "stowed_deg = -450.0",
            ["joint[1].stowed_deg", "±360", "found -450.0"],
        ),
    ] {
        let text = t01_text().replacen(from, to, 1);
        let (out, _) = simulate(dir.path(), &text, &[]);
        let toml = dir.path().join("m.toml");
        let at = format!("{}:{}:", toml.display(), line_of(&text, to));
        let mut all = vec![at.as_str()];
        all.extend(says);
        refused(&out, &all);
    }
}

#[test]
fn a_fault_that_starts_after_the_run_ends_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (out, csv) = simulate(
        dir.path(),
        &t01_text(),
        &[
            "--fault",
            "dropout:joint=1:start=100:duration=0.1:mode=stale",
        ],
    );
    refused(
        &out,
        &[
            "--fault",
            "after the run ends",
            "expected a start from 0 to",
        ],
    );
    assert!(!csv.exists(), "a run was written");
}

#[test]
fn a_run_file_ending_in_blank_lines_is_read() {
    let dir = tempfile::tempdir().expect("temp dir");
    let run = write(dir.path(), "run.csv", format!("{}\n\n\n", t01_run_text()));
    let out = deploywatch(&["replay", "--mechanism", s(&t01_mechanism()), s(&run)]);
    succeeded(&out);
}

/// The mechanism and the run swapped, or a command's JSON given as the
/// mechanism: each loader says what the file it met reads as, with the
/// file and line, whatever command it is (`model::file_kind`).
#[test]
fn a_file_of_the_wrong_kind_is_named_as_what_it_is() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mech = t01_mechanism();
    let run = write(dir.path(), "run.csv", t01_run_text());
    // A mechanism with a comment first: the comment is not the header.
    let commented = write(
        dir.path(),
        "wing.toml",
        format!("# my wing, from the drawing\n{}", t01_text()),
    );
    let json = write(dir.path(), "found.json", "{\"effects\": []}\n");
    let json_out = dir.path().join("d.json");
    let header_at = line_of(&t01_run_text(), "t_s,");
    let run_where = format!("{}:{header_at}:", run.display());
    let as_run = "reads as a run CSV (its header starts `t_s,`), not a mechanism TOML";
    let as_toml =
        "reads as a mechanism TOML (`key = value` lines, `[table]` headers), not a run CSV";
    let cases: Vec<(Vec<&str>, Vec<String>)> = vec![
        (
            vec![
                "diagnose",
                "--mechanism",
                s(&run),
                "--json",
                s(&json_out),
                s(&mech),
            ],
            vec![run_where.clone(), as_run.into()],
        ),
        (
            vec!["margin", "--mechanism", s(&run)],
            vec![run_where.clone(), as_run.into()],
        ),
        (
            vec!["identify", "--mechanism", s(&mech), s(&mech)],
            vec![format!("{}:1:", mech.display()), as_toml.into()],
        ),
        (
            vec!["replay", "--mechanism", s(&mech), s(&commented)],
            vec![format!("{}:2:", commented.display()), as_toml.into()],
        ),
        (
            vec!["margin", "--mechanism", s(&json)],
            vec![
                format!("{}:1:", json.display()),
                "reads as a JSON document".into(),
            ],
        ),
    ];
    for (args, says) in cases {
        let says: Vec<&str> = says.iter().map(String::as_str).collect();
        refused(&deploywatch(&args), &says);
    }
}

#[test]
fn a_wrong_header_is_told_for_the_joint_count_the_file_seems_to_have() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = t01_run_text();
    let header = "t_s,phi1_deg,phi2_deg,phi3_deg,latch1,latch2,latch3";
    let at = line_of(&text, header);
    let bad = text.replace(header, "time,a1,a2,a3,s1,s2,s3");
    let run = write(dir.path(), "run.csv", bad);
    let out = deploywatch(&["replay", "--mechanism", s(&t01_mechanism()), s(&run)]);
    let where_ = format!("{}:{at}:", run.display());
    refused(
        &out,
        &[
            &where_,
            "unknown column `time` (column 1): expected `t_s` there",
            header,
            "3 joint(s)",
        ],
    );
    assert!(!stderr(&out).contains("extra column"), "{}", stderr(&out));
}

#[test]
fn an_undeclared_nan_says_how_to_declare_missing_samples() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = t01_run_text();
    // The first data row after the header: its first angle becomes NaN.
    let header_at = line_of(&text, "t_s,phi1_deg");
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let row = &mut lines[header_at];
    let fields: Vec<&str> = row.split(',').collect();
    *row = format!("{},NaN,{}", fields[0], fields[2..].join(","));
    let run = write(dir.path(), "run.csv", lines.join("\n") + "\n");
    let out = deploywatch(&["replay", "--mechanism", s(&t01_mechanism()), s(&run)]);
    let where_ = format!("{}:{}:", run.display(), header_at + 1);
    refused(
        &out,
        &[
            &where_,
            "phi1_deg",
            "# missing_samples = \"NaN\"",
            "formats.md",
        ],
    );
}

#[test]
fn replay_errors_name_the_run_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    // A run of seed000 case 1 (2 joints) against the 3-joint T01 mechanism.
    let other = std::fs::read_to_string(data().join("reference/seed000_case1_nominal.csv"))
        .expect("bundled golden run");
    let other = other.replace("seed000-case1-open", "seed001-T01");
    let run = write(dir.path(), "two_joints.csv", other);
    let out = deploywatch(&["replay", "--mechanism", s(&t01_mechanism()), s(&run)]);
    refused(&out, &[s(&run), "2 joints", "3"]);
}

/// The first time at which every switch reads closed.
fn deployed_at(run: &Run) -> f64 {
    let i = (0..run.len())
        .find(|&i| run.latch.iter().all(|l| l[i]))
        .expect("every joint latches");
    run.t_s[i]
}

#[test]
fn a_simulated_run_records_settle_s_after_the_last_latch() {
    let dir = tempfile::tempdir().expect("temp dir");
    // The default settle_s = 0.2 s, then one given in the file.
    for (text, settle_s) in [
        (t01_text(), 0.2),
        (
            t01_text().replace("sample_hz = 100.0", "sample_hz = 100.0\nsettle_s = 0.5"),
            0.5,
        ),
    ] {
        let (out, csv) = simulate(dir.path(), &text, &[]);
        succeeded(&out);
        let run = Run::load(&csv).expect("the run written");
        let latched = deployed_at(&run);
        let end = *run.t_s.last().expect("samples");
        assert!(
            end >= latched + settle_s - 1e-9,
            "settle_s = {settle_s}: last latch at {latched} s, run ends at {end} s"
        );
        assert!(end < latched + settle_s + 0.02, "ends at {end} s");
        // Every switch stays closed after the latch: the joints stay latched.
        let i = run.t_s.iter().position(|&t| t >= latched).unwrap_or(0);
        assert!(run.latch.iter().all(|l| l[i..].iter().all(|&x| x)));
    }
}

/// An effect with nothing to act on is refused, never simulated as if it
/// acted: a rig cause on a physical-latch wing (no rig), a magnet's
/// weakening on a pawl (no magnet). On a latch that has one, it acts.
#[test]
fn an_effect_with_nothing_to_act_on_is_refused_on_a_physical_latch_wing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let pawl = std::fs::read_to_string(data().join("mechanisms/one_panel_pawl.toml")).unwrap();
    for (effect, says) in [
        ("rig_friction:value=0.5", "has no active [rig]"),
        ("wire_length:value=0.01", "has no active [rig]"),
        (
            "magnet_weakening:joint=1:value=0.5",
            "the joint's latch has no magnet",
        ),
    ] {
        let (out, _) = simulate(dir.path(), &pawl, &["--effect", effect, "-q"]);
        refused(&out, &[says]);
    }
    let magnet =
        std::fs::read_to_string(data().join("mechanisms/seed001_T01_physical_latch.toml")).unwrap();
    let (out, _) = simulate(
        dir.path(),
        &magnet,
        &["--effect", "magnet_weakening:joint=1:value=0.5", "-q"],
    );
    succeeded(&out);
}

/// A run given twice (a shell glob that matches it twice, or a copy) is
/// refused: counted twice it would narrow every interval as new evidence.
#[test]
fn a_run_given_twice_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let run = write(dir.path(), "t01.csv", t01_run_text());
    let copy = write(dir.path(), "t01_copy.csv", t01_run_text());
    let mech = t01_mechanism();
    for second in [&run, &copy] {
        for command in ["identify", "diagnose"] {
            let json = dir.path().join("out.json");
            let out = deploywatch(&[
                command,
                "--mechanism",
                s(&mech),
                "--json",
                s(&json),
                "-q",
                s(&run),
                s(second),
            ]);
            refused(&out, &["the same samples as", "give each run once"]);
            assert!(!json.exists(), "{command}: nothing written");
        }
    }
}

/// A physical latch that would engage beyond its joint's stroke (a crest
/// or a switch farther from the stop than the panel is stowed) is refused
/// with the file, the line and the mark, never simulated as latched while
/// stowed.
#[test]
fn a_latch_beyond_the_stroke_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = std::fs::read_to_string(data().join("mechanisms/seed001_T01_physical_latch.toml"))
        .expect("bundled mechanism");
    for (from, to, mark) in [
        ("crest_deg = 0.6", "crest_deg = 95.0", "its crest"),
        (
            "switch_travel_deg = 0.05",
            "switch_travel_deg = 120.0",
            "its switch",
        ),
    ] {
        let bad = text.replacen(from, to, 1);
        let line = line_of(&bad, "[joint.latch]");
        let (out, csv) = simulate(dir.path(), &bad, &["-q"]);
        refused(
            &out,
            &[
                &format!("m.toml:{line}"),
                "joint[1].latch",
                "within the joint's stroke of 90 deg",
                mark,
            ],
        );
        assert!(!csv.exists(), "nothing written");
    }
    // The stroke typed in radians leaves no room for the latch either: the
    // refusal says what the number reads as, as the ideal latch's warning
    // does.
    let bad = text.replacen("stowed_deg = -90.0", "stowed_deg = -1.5708", 1);
    assert_ne!(bad, text, "the bundled wing stows joint 1 at -90 deg");
    let (out, csv) = simulate(dir.path(), &bad, &["-q"]);
    refused(
        &out,
        &[
            "joint[1].latch",
            "-1.5708 deg is π/2 in radians",
            "expected degrees (-90.0)",
        ],
    );
    assert!(!csv.exists(), "nothing written");
}

#[test]
fn a_factor_given_twice_is_refused_naming_both() {
    let m = t01_mechanism();
    let margin = |factors: &[&str]| {
        let mut args = vec!["margin", "--mechanism", s(&m)];
        for f in factors {
            args.extend(["--factor", f]);
        }
        deploywatch(&args)
    };
    let twice = margin(&["friction=2", "spring=1.2", "friction=3"]);
    refused(&twice, &["--factor friction=3", "friction=2 before"]);
    succeeded(&margin(&["friction=2", "spring=1.2"]));
    // A factor below 1 weakens the margin: run, and said.
    let weak = margin(&["friction=0.5"]);
    succeeded(&weak);
    assert!(
        stderr(&weak).contains("warning: --factor friction=0.5: below 1"),
        "{}",
        stderr(&weak)
    );
}

/// Options that would be ignored are refused or said: `--standard` beside
/// `--all-standards` (which prints every standard), `--flight` on a wing
/// without a rig and without findings (nothing to take out).
#[test]
fn options_that_would_change_nothing_are_said() {
    let m = t01_mechanism();
    let out = deploywatch(&[
        "margin",
        "--mechanism",
        s(&m),
        "--all-standards",
        "--standard",
        "ecss-e-st-33-01c",
    ]);
    refused(&out, &["--standard", "cannot be used with"]);
    let out = deploywatch(&["margin", "--mechanism", s(&m), "--flight"]);
    succeeded(&out);
    assert!(stderr(&out).contains("--flight: "), "{}", stderr(&out));
    assert!(stderr(&out).contains("has no [rig]"), "{}", stderr(&out));
    let rig = data().join("mechanisms/seed001_T01_rig.toml");
    let out = deploywatch(&["margin", "--mechanism", s(&rig), "--flight"]);
    succeeded(&out);
    assert!(!stderr(&out).contains("has no [rig]"), "{}", stderr(&out));
}

/// A list of numbers given with spaces (`--start 0.1 0.2 0.3`) leaves its
/// second value where a run file belongs: refused saying so (not "No such
/// file"); a list starting with a negative number is read as the option's
/// value, not as a flag, and judged as one (here: friction below 0).
#[test]
fn numbers_given_apart_and_negative_lists_are_read_as_meant() {
    let mech = t01_mechanism();
    let dir = tempfile::tempdir().expect("temp dir");
    let run = write(dir.path(), "t01.csv", t01_run_text());
    let out = deploywatch(&[
        "identify",
        "--mechanism",
        s(&mech),
        s(&run),
        "--start",
        "0.1",
        "0.2",
        "0.3",
        "-q",
    ]);
    refused(
        &out,
        &[
            "0.2: no such file",
            "reads as a number",
            "--start 0.1,0.2,0.3",
        ],
    );
    let out = deploywatch(&[
        "identify",
        "--mechanism",
        s(&mech),
        s(&run),
        "--start",
        "-0.1,0.2,0.3",
        "-q",
    ]);
    refused(&out, &["--start -0.1: expected friction torques ≥ 0"]);
    let out = deploywatch(&[
        "margin",
        "--mechanism",
        s(&mech),
        "--friction",
        "-0.1,0.2,0.3",
    ]);
    refused(&out, &["--friction: -0.1 is not a friction torque"]);
}

/// One campaign of runs of a one-panel wing and of a three-panel wing:
/// the effects a diagnosis finds are common to every run by joint number,
/// so "joint 1" would be two different hinges. Said before any work.
#[test]
fn runs_of_wings_of_different_joint_counts_in_one_campaign_are_said() {
    let dir = tempfile::tempdir().expect("temp dir");
    let one = data().join("mechanisms/reliability_one_panel.toml");
    let three = t01_mechanism();
    let mut runs = Vec::new();
    for (m, name) in [(&one, "one.csv"), (&three, "three.csv")] {
        let csv = dir.path().join(name);
        let out = deploywatch(&["simulate", s(m), "--seed", "1", "-o", s(&csv), "-q"]);
        assert!(out.status.success(), "{}", stderr(&out));
        runs.push(csv);
    }
    let json = dir.path().join("d.json");
    let out = deploywatch(&[
        "diagnose",
        "--mechanism",
        s(&one),
        "--mechanism",
        s(&three),
        "--json",
        s(&json),
        "--max-seconds",
        "1",
        "-q",
        s(&runs[0]),
        s(&runs[1]),
    ]);
    let err = stderr(&out);
    assert!(!err.contains("panicked"), "{err}");
    for said in [
        "warning: the runs are of wings of different joint counts",
        "one.csv (reliability-one-panel, 1 joint)",
        "three.csv (seed001-T01, 3 joints)",
    ] {
        assert!(err.contains(said), "{said:?} not in:\n{err}");
    }
}

/// A hinge that runs with less friction than its mechanism file gives
/// (wing4_ideal's joint 1: 0.5 N·m measured, 0.8 drawn): `identify` adds
/// its EFT to the file's friction, at least 0, so the table says what the
/// EFTs are added to, and the joint fixed at 0 is warned of with the way
/// to its whole EFT.
#[test]
fn less_friction_than_the_file_gives_is_said() {
    let dir = tempfile::tempdir().expect("temp dir");
    let drawn = std::fs::read_to_string(data().join("mechanisms/wing4_ideal.toml")).unwrap();
    let built = drawn.replacen("coulomb_nm = 0.8", "coulomb_nm = 0.5", 1);
    assert_ne!(built, drawn);
    let (out, run) = simulate(dir.path(), &built, &["-q", "--seed", "3"]);
    succeeded(&out);
    let mech = write(dir.path(), "drawn.toml", &drawn);
    let out = deploywatch(&["identify", "--mechanism", s(&mech), s(&run), "-q"]);
    succeeded(&out);
    let said = String::from_utf8_lossy(&out.stdout);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains("added to the mechanism's own Coulomb friction (joint 1 0.8 N·m"),
        "{said}"
    );
    assert!(
        err.contains("fixed at 0 on top of the mechanism's own friction: joint 1 (0.8 N·m")
            && err.contains("its `coulomb_nm` at 0"),
        "{err}"
    );
    // The same run against the mechanism as built raises neither.
    let as_built = write(dir.path(), "built.toml", &built);
    let out = deploywatch(&["identify", "--mechanism", s(&as_built), s(&run), "-q"]);
    succeeded(&out);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("fixed at 0 on top"));
}

/// A hinge that never moves (seized at its stowed angle: T01 simulated
/// with 50 N·m at joint 3, its readings then held at -180 deg against the
/// swing of the others) fits any friction that holds it: `identify` says
/// its EFT is no measurement.
#[test]
fn a_joint_that_never_moves_has_no_measured_friction() {
    let dir = tempfile::tempdir().expect("temp dir");
    let run = dir.path().join("seized.csv");
    let out = deploywatch(&[
        "simulate",
        s(&t01_mechanism()),
        "--out",
        s(&run),
        "-q",
        "--effect",
        "coulomb_friction:joint=3:value=50",
    ]);
    succeeded(&out);
    let text = std::fs::read_to_string(&run).unwrap();
    let mut column = None;
    let held: Vec<String> = text
        .lines()
        .enumerate()
        .map(|(i, line)| {
            let mut f: Vec<String> = line.split(',').map(String::from).collect();
            match column {
                _ if line.starts_with('#') => return line.to_string(),
                None => column = f.iter().position(|c| c == "phi3_deg"),
                Some(c) => f[c] = format!("{:.3}", -180.0 + 0.02 * (i % 3) as f64),
            }
            f.join(",")
        })
        .collect();
    std::fs::write(&run, held.join("\n") + "\n").unwrap();
    let out = deploywatch(&[
        "identify",
        "--mechanism",
        s(&t01_mechanism()),
        s(&run),
        "-q",
    ]);
    succeeded(&out);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("never moves by 1 deg in these runs: joint 3 (")
            && err.contains("not a measurement")
            && !err.contains("joint 1 ("),
        "{err}"
    );
}
