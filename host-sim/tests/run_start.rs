//! A run that does not start with a sample at the release, `t = 0`, as
//! loggers write them (`docs/spec/formats.md`, "Run"): rows before the
//! release with the wing at rest (a pre-trigger) are left out, a first
//! sample one interval after the release is taken as it is, each said in a
//! warning, and `identify` finds the friction it finds on the run from
//! `t = 0`; rows before `t = 0` where the wing moves, or a first sample
//! long after it (a logger's clock), are refused with what to do.
//!
//! `cargo test -p deploywatch-sim --test run_start`

mod common;

use common::{data, deploywatch, fails, s, t01_mechanism, write};
use serde_json::Value;
use std::path::Path;

/// The bundled run of seed 001 T01 (example campaign a): its metadata and
/// header lines, and its rows split into fields.
fn parts() -> (Vec<String>, Vec<Vec<String>>) {
    let path = data().join("examples/a_seed001_eft/seed001_T01.csv");
    let text = std::fs::read_to_string(path).expect("bundled run");
    let head: Vec<String> = text
        .lines()
        .take_while(|l| l.starts_with('#') || l.starts_with("t_s"))
        .map(String::from)
        .collect();
    let rows = text
        .lines()
        .skip(head.len())
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (head, rows)
}

fn text(head: &[String], rows: &[Vec<String>]) -> String {
    let mut out = head.join("\n") + "\n";
    for r in rows {
        out.push_str(&r.join(","));
        out.push('\n');
    }
    out
}

/// `identify --json` of `run`: the JSON's joints and stderr.
fn identified(dir: &Path, run: &Path) -> (Value, String) {
    let json = dir.join(format!(
        "{}.json",
        run.file_stem().unwrap().to_string_lossy()
    ));
    let out = deploywatch(&[
        "identify",
        "--mechanism",
        s(&t01_mechanism()),
        "--json",
        s(&json),
        "-q",
        s(run),
    ]);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{err}");
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    (doc["joints"].clone(), err)
}

/// Each joint's EFT [N·m] and its 95 % interval.
fn eft(joints: &Value) -> Vec<(f64, f64, f64)> {
    joints
        .as_array()
        .unwrap()
        .iter()
        .map(|j| {
            let ci = j["ci95"].as_array().unwrap();
            (
                j["coulomb_nm"].as_f64().unwrap(),
                ci[0].as_f64().unwrap(),
                ci[1].as_f64().unwrap(),
            )
        })
        .collect()
}

#[test]
fn a_pre_trigger_at_rest_and_a_lost_first_sample_are_runs_from_the_release() {
    let dir = tempfile::tempdir().unwrap();
    let (head, rows) = parts();
    let dt: f64 = rows[1][0].parse::<f64>().unwrap() - rows[0][0].parse::<f64>().unwrap();
    let original = write(dir.path(), "original.csv", text(&head, &rows));
    let (want, quiet) = identified(dir.path(), &original);
    assert!(!quiet.contains("t = 0"), "{quiet}");

    // Ten rows of the stowed pose before the release, a little noise on them.
    let mut pre: Vec<Vec<String>> = (1..=10)
        .rev()
        .map(|k| {
            let mut r = rows[0].clone();
            r[0] = format!("{:.3}", -(k as f64) * dt);
            let angle: f64 = r[1].parse().unwrap();
            r[1] = format!("{:.4}", angle + if k % 2 == 0 { 0.03 } else { -0.02 });
            r
        })
        .collect();
    pre.extend(rows.iter().cloned());
    let triggered = write(dir.path(), "triggered.csv", text(&head, &pre));
    let (got, said) = identified(dir.path(), &triggered);
    assert_eq!(got, want, "the same samples from the release: the same fit");
    assert!(
        said.contains("triggered.csv: 10 rows before t = 0") && said.contains("pre-trigger"),
        "{said}"
    );

    // The sample at the release lost: the same friction, within intervals.
    let lost = write(dir.path(), "lost.csv", text(&head, &rows[1..]));
    let (got, said) = identified(dir.path(), &lost);
    assert!(
        said.contains("lost.csv: the first sample is at t = 0.01 s"),
        "{said}"
    );
    for (j, (g, w)) in eft(&got).iter().zip(eft(&want)).enumerate() {
        assert!(
            w.1 <= g.0 && g.0 <= w.2 && g.1 <= w.0 && w.0 <= g.2,
            "joint {}: {g:?} against {w:?}",
            j + 1
        );
    }

    // Rows before t = 0 where the wing moves: the release is not at 0.
    let mut moving = rows.clone();
    for r in &mut moving {
        r[0] = format!("{:.3}", r[0].parse::<f64>().unwrap() - 0.5);
    }
    let shifted = write(dir.path(), "shifted.csv", text(&head, &moving));
    let out = deploywatch(&["identify", "--mechanism", s(&t01_mechanism()), s(&shifted)]);
    fails(
        &out,
        2,
        &[
            "shifted.csv:",
            "t = -0.5 s",
            "rows before t = 0 where the wing moves",
            "add 0.5 s",
        ],
    );
}
