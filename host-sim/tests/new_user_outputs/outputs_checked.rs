//! Outputs are checked before the work, and written all or none; a closed
//! stdout stops neither.

use super::*;

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

/// A plot whose name gives no format the plots are written in (`run.out`)
/// is refused by its flag before any work, the extensions listed, and
/// nothing is written: every command with a plot.
#[test]
fn a_plot_name_without_an_image_extension_is_refused_before_any_work() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let t01 = data(T01);
    let run = data("examples/a_seed001_eft/seed001_T01.csv");
    let cases: [Vec<String>; 4] = [
        vec![
            "simulate".into(),
            s(&t01).into(),
            "--out".into(),
            d("r.csv"),
            "--plot".into(),
            d("r.out"),
        ],
        vec![
            "margin".into(),
            "--mechanism".into(),
            s(&t01).into(),
            "--json".into(),
            d("m.json"),
            "--plot".into(),
            d("m.txt"),
        ],
        vec![
            "replay".into(),
            s(&run).into(),
            "--mechanism".into(),
            s(&t01).into(),
            "--out".into(),
            d("s.csv"),
            "--plot".into(),
            d("s.svg"),
        ],
        vec![
            "identify".into(),
            "--mechanism".into(),
            s(&t01).into(),
            s(&run).into(),
            "--json".into(),
            d("e.json"),
            "--plot".into(),
            d("e"),
        ],
    ];
    for args in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = deploywatch(&args);
        let err = fails(&out, 2, &["--plot", ".png", ".jpg", "format"]);
        assert!(!err.contains("ImageError"), "{}: {err}", args[0]);
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert!(left.is_empty(), "{}: wrote {left:?}", args[0]);
    }
    // The extension's case does not matter.
    let out = deploywatch(&[
        "simulate",
        s(&t01),
        "--out",
        &d("r.csv"),
        "--plot",
        &d("r.PNG"),
        "-q",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(png_height(&dir.path().join("r.PNG")) > 0);
}

/// Two outputs of one command on one file (by any path to it) would leave
/// only the one written last: refused by the second's flag, naming the
/// first, before any work.
#[test]
fn two_outputs_on_one_file_are_refused_before_any_work() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    // The same file by another path: `./sub/../x.png`.
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    let other = |name: &str| {
        dir.path()
            .join("sub")
            .join("..")
            .join(name)
            .to_string_lossy()
            .into_owned()
    };
    let t01 = data(T01);
    let run = data("examples/a_seed001_eft/seed001_T01.csv");
    let cases: [(Vec<String>, [&str; 2]); 3] = [
        (
            vec![
                "simulate".into(),
                s(&t01).into(),
                "--out".into(),
                p("same.png"),
                "--plot".into(),
                other("same.png"),
            ],
            ["--plot", "--out"],
        ),
        (
            vec![
                "margin".into(),
                "--mechanism".into(),
                s(&t01).into(),
                "--json".into(),
                p("m.png"),
                "--plot".into(),
                p("m.png"),
            ],
            ["--plot", "--json"],
        ),
        (
            vec![
                "diagnose".into(),
                "--mechanism".into(),
                s(&t01).into(),
                "--json".into(),
                p("rep.md"),
                s(&run).into(),
            ],
            ["the report beside --json", "--json"],
        ),
    ];
    for (args, [second, first]) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = deploywatch(&args);
        let err = fails(&out, 2, &[second, first, "replace"]);
        assert!(stdout(&out).is_empty(), "{}: worked first: {err}", args[0]);
        let left: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n != "sub")
            .collect();
        assert!(left.is_empty(), "{}: wrote {left:?}", args[0]);
    }
}

#[test]
fn replay_keep_on_a_file_is_refused_as_not_a_folder_and_the_file_kept() {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("kept");
    std::fs::write(&file, "mine").expect("write");
    let out = deploywatch(&[
        "replay",
        s(&data("examples/a_seed001_eft/seed001_T01.csv")),
        "--mechanism",
        s(&data(T01)),
        "--keep",
        s(&file),
    ]);
    fails(&out, 2, &["--keep", "a file; expected a folder"]);
    assert_eq!(std::fs::read_to_string(&file).expect("kept"), "mine");
}
